// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_C3T3_STAGE_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_C3T3_STAGE_H

// Stage 6 of `make_anisotropic_mesh_3()`: the domain's mesh into a
// `Mesh_complex_3_in_triangulation_3`. A triangulation fills the convex hull
// of its vertices, so the rest of a box around the domain is padded with
// cells of subdomain 0 (TetGen's constrained tetrahedralization).

#include <CGAL/Bubble_mesh_3/Meshing_report.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/internal/c3t3/exterior_padding.h>
#include <CGAL/Bubble_mesh_3/internal/c3t3/tet_soup_to_c3t3.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/domain_mesh.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/run_control.h>

#include <chrono>
#include <string>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

/// Stage 6: fills `c3t3` from `dm`. The mesh is the pipeline's, not the
/// user's: whatever the padding or the conversion refuses is a
/// `Meshing_failure`.
template <typename Indices, typename C3T3>
void c3t3_stage(const Domain_mesh& dm, const Indices& indices, const Run_control& control, Meshing_report& rep,
                C3T3& c3t3)
{
  control.advance(0.97);
  control.check("the exterior padding", false);
  const auto t0 = std::chrono::steady_clock::now();
  c3t3.clear();
  std::size_t padding_tets = 0;
  try {
    if(has_exterior_padding) {
      Padding_options padding;
      padding.should_stop = [&control] {
        control.check("the exterior padding", false);
        return false;
      };
      const Padded_tet_mesh_3 padded = pad_to_box(dm.mesh, padding);
      std::vector<C3t3_vertex_location> locations = dm.locations;
      locations.resize(padded.mesh.points.size(), C3t3_vertex_location{3, 0});
      indexed_mesh_to_c3t3(padded.mesh, locations, indices, c3t3);
      padding_tets = padded.mesh.tets.size() - dm.mesh.tets.size();
    } else {
      // without TetGen only a mesh of a convex domain fills its triangulation
      try {
        indexed_mesh_to_c3t3(dm.mesh, dm.locations, indices, c3t3);
      } catch(const Invalid_input& e) {
        throw Meshing_failure(std::string("the domain is not convex (or has several components), and this build "
                                          "has no TetGen to pad it out to a box for the C3T3 (") +
                              e.what() + "); use make_indexed_anisotropic_mesh_3 or build with TetGen");
      }
    }
  } catch(const Invalid_input& e) {
    c3t3.clear();
    throw Meshing_failure(std::string("the C3T3 of the mesh: ") + e.what());
  } catch(...) {
    c3t3.clear();
    throw;
  }
  rep.padding_tets = padding_tets;
  rep.c3t3_seconds = seconds_since(t0);
}

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_C3T3_STAGE_H
