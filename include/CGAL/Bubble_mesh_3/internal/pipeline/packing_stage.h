// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_PACKING_STAGE_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_PACKING_STAGE_H

// Stage 1 of the pipeline: the bubbles packed on the corners, curves,
// patches and interior of the domain (paper, section 2); their centres are
// the mesh's nodes.

#include <CGAL/Bubble_mesh_3/Meshing_report.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/run_control.h>
#include <CGAL/Bubble_packer_3.h>

#include <cmath>
#include <string>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

/// The packed nodes, stage by stage (corners first). Refuses a metric asking
/// for more than `s.maximum_bubbles` nodes (`Too_many_nodes`) before packing.
template <typename MeshDomain, typename MetricField>
std::vector<typename CGAL::Bubble_packer_3<MeshDomain, MetricField>::Node>
pack_nodes(const MeshDomain& domain, const MetricField& field, const Meshing_settings& s, const Run_control& control,
           Meshing_report& rep)
{
  typedef CGAL::Bubble_packer_3<MeshDomain, MetricField> Packer;
  typename Packer::Parameters pp;
  pp.seed = s.seed;
  pp.number_of_threads = s.threads;
  pp.maximum_iterations = s.iterations;
  pp.maximum_number_of_bubbles = s.maximum_bubbles;
  install_stop_check(pp, control, "the packing");
  Packer packer(domain, field, pp);
  rep.estimated_nodes = packer.estimated_number_of_bubbles();
  control.say("estimated nodes: " + std::to_string(std::llround(rep.estimated_nodes)));
  control.check("the packing");
  const char* stage_names[4] = {"corners", "curves", "surfaces", "volume"};
  // the share of the run each stage starts at (for `callback`)
  const double advancement[4] = {0.02, 0.05, 0.15, 0.3};
  for(int d = 0; d < 4; ++d) {
    control.advance(advancement[d]);
    switch(d) {
    case 0: packer.pack_corners(); break;
    case 1: packer.pack_curves(); break;
    case 2: packer.pack_surfaces(); break;
    default: packer.pack_volume(); break;
    }
    const auto& st = packer.statistics().stages[d];
    rep.nodes[d] = st.bubbles;
    rep.packing_seconds[d] = st.seconds;
    rep.packing_iterations[d] = st.iterations;
    rep.packing_converged[d] = st.converged;
    rep.packing_settled[d] = st.settled;
    rep.packing_still_moving[d] = st.still_moving;
    control.say(std::string("packed ") + stage_names[d] + ": " + std::to_string(st.bubbles) + " bubbles, " +
                std::to_string(st.iterations) + " iterations" +
                (st.settled ? " (settled: " + std::to_string(st.still_moving) + " still creeping)" : "") + ", " +
                std::to_string(st.seconds) + " s");
    control.check(std::string("the packing (after the ") + stage_names[d] + ")");
  }
  return packer.nodes();
}

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_PACKING_STAGE_H
