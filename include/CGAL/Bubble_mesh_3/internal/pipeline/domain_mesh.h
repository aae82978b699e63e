// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_DOMAIN_MESH_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_DOMAIN_MESH_H

// The mesh the pipeline's stages fill in turn (boundary, volume) and edit
// (improvement), with where each vertex lies in the domain for the C3T3.

#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/internal/c3t3/tet_soup_to_c3t3.h>

#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

/// The domain's tet mesh and the location of each of its vertices.
struct Domain_mesh {
  Indexed_tet_mesh_3 mesh;
  std::vector<C3t3_vertex_location> locations;

  /// a vertex on a corner (0), curve (1), patch (2) or in a subdomain (3) of
  /// the domain with that index; returns its number
  int add_point(double x, double y, double z, int dimension, int index)
  {
    mesh.points.push_back({{x, y, z}});
    mesh.point_refs.push_back(index);
    locations.push_back(C3t3_vertex_location{dimension, index});
    if(dimension == 0)
      mesh.corners.push_back(int(mesh.points.size()) - 1);
    return int(mesh.points.size()) - 1;
  }
};

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_DOMAIN_MESH_H
