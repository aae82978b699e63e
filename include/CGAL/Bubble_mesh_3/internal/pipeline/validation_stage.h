// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_VALIDATION_STAGE_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_VALIDATION_STAGE_H

// Stage 5 of the pipeline: never hand out an invalid mesh. The whole validity
// check, then how far the boundary strays from the input surface.

#include <CGAL/Bubble_mesh_3/Meshing_report.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/boundary_stage.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/run_control.h>
#include <CGAL/Bubble_mesh_3/internal/surface_fidelity.h>
#include <CGAL/Bubble_mesh_3/validity.h>

#include <chrono>
#include <string>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

/// Stage 5: throws `Meshing_failure` naming the first problem of an invalid
/// mesh; fills the report's validity time and surface distances.
inline void validation_stage(const Indexed_tet_mesh_3& m, const Domain_boundary& boundary,
                             bool boundary_checked_for_self_intersections, const Run_control& control,
                             Meshing_report& rep)
{
  control.advance(0.95);
  const auto t0 = std::chrono::steady_clock::now();
  Validity_options vo;
  vo.require_outward_triangles = true;
  // the improvement stage checks the boundary it changed itself
  vo.check_boundary_self_intersections = !boundary_checked_for_self_intersections;
  const Validity_report vr = check_validity(m, vo);
  rep.validity_seconds = seconds_since(t0);
  if(!vr.is_valid()) {
    const std::string first = vr.problems.empty() ? std::string() : vr.problems.front();
    throw Meshing_failure("the mesh failed the validity check (" + std::to_string(vr.number_of_problems) +
                          " problems; first: " + first + ")");
  }
  const Surface_fidelity fidelity = surface_fidelity(boundary.surface, m);
  rep.surface_distance = fidelity.mesh_to_surface;
  rep.surface_distance_relative = fidelity.diagonal > 0 ? fidelity.mesh_to_surface / fidelity.diagonal : 0;
  rep.input_to_boundary_distance = fidelity.surface_to_mesh;
  rep.volume_error = fidelity.volume_error;
}

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_VALIDATION_STAGE_H
