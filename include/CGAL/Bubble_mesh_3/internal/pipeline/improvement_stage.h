// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_IMPROVEMENT_STAGE_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_IMPROVEMENT_STAGE_H

// Stage 4 of the pipeline (paper, section 4, and beyond it): metric flips,
// smoothing (boundary vertices sliding on the input surface and its curves),
// edge collapses and splits where those are stuck, in place on the mesh.

#include <CGAL/Bubble_mesh_3/Meshing_report.h>
#include <CGAL/Bubble_mesh_3/improve_mesh.h>
#include <CGAL/Bubble_mesh_3/internal/boundary_self_intersections.h>
#include <CGAL/Bubble_mesh_3/internal/improve/input_projections.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/boundary_stage.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/domain_mesh.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/run_control.h>

#include <algorithm>
#include <limits>
#include <string>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

/// Stage 4: improves `out` in place. A run time limit cuts the improvement to
/// the time left (the mesh stays valid) instead of throwing.
template <typename MetricField>
void improvement_stage(const MetricField& field, const Domain_boundary& boundary, const Meshing_settings& s,
                       const Run_control& control, Meshing_report& rep, Domain_mesh& out)
{
  control.advance(0.8);
  Indexed_tet_mesh_3& m = out.mesh;
  Improvement_options io;
  io.time_limit_seconds = s.improve_time_limit;
  if(control.has_time_limit()) {
    const double own = s.improve_time_limit < 0 ? 2.0 + 1e-4 * double(m.tets.size()) : s.improve_time_limit;
    io.time_limit_seconds = std::max(0.0, std::min(own, control.remaining()));
  }
  install_stop_check(io, control, "the improvement", false);
  // boundary vertices inside curved patches and curved feature curves slide
  // on the input surface and on its feature polylines
  const improve::Input_projections projections(boundary.surface, boundary.chains, boundary.chain_curves);
  io.surface_projection = [&projections](int ref, const std::array<double, 3>& p, std::array<double, 3>& q) {
    return projections.surface(ref, p, q);
  };
  io.curve_projection = [&projections](int ref, const std::array<double, 3>& p, std::array<double, 3>& q) {
    return projections.curve(ref, p, q);
  };
  // where flips and moves are stuck, collapse short edges and split others
  // (vertices removed and added: the locations follow below)
  io.edge_splits = true;
  io.edge_collapses = true;
  io.keep_edges_in_range = true;
  // the packing's gaps and clusters where the metric grades fast
  io.edge_lengths = true;
  // the surface-approximation bound: chords that the packing's nodes leave
  // farther than it from the input are split
  io.surface_distance = rep.surface_distance_bound;
  // Boundary moves, curved flips, splits and collapses each keep the boundary
  // embedded, but should a thin part (a tip thinner than the sizes) still
  // fold, the improvement is done again on the front's mesh with the
  // boundary fixed.
  Indexed_tet_mesh_3 front_mesh = m;
  rep.improvement = improve_mesh(m, field, io);
  if(boundary_self_intersections(m) > 0) {
    control.say("improvement: the boundary it changed intersects itself at a thin part; improving again with the "
                "boundary fixed");
    m = std::move(front_mesh);
    io.boundary_smoothing = false; // no projections either: only interior moves, flips and splits
    if(control.has_time_limit())
      io.time_limit_seconds = std::max(0.0, std::min(io.time_limit_seconds, control.remaining()));
    rep.improvement = improve_mesh(m, field, io);
    rep.improvement_boundary_fixed = true;
  }
  rep.improved = true;
  relocate_after_improvement(m, rep.improvement.new_vertex_index, out.locations);
  control.say("improvement: worst metric min dihedral " + std::to_string(rep.improvement.worst_before) + " -> " +
              std::to_string(rep.improvement.worst_after) + " deg, " + std::to_string(rep.improvement.seconds) +
              " s");
}

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_IMPROVEMENT_STAGE_H
