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

#include <algorithm>
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

/// The C3T3 locations after the improvement: a kept vertex keeps its own
/// (`new_vertex_index`: empty if none was removed), a split vertex gets its
/// curve if on a feature edge, its patch if in a boundary triangle, else
/// its subdomain (`point_refs`: the index).
inline void relocate_after_improvement(const Indexed_tet_mesh_3& m, const std::vector<int>& new_vertex_index,
                                       std::vector<C3t3_vertex_location>& locations)
{
  std::vector<C3t3_vertex_location> moved(m.points.size(), C3t3_vertex_location{3, 0});
  std::vector<char> known(m.points.size(), 0);
  for(std::size_t v = 0; v < locations.size(); ++v) {
    const int w = new_vertex_index.empty() ? int(v) : new_vertex_index[v];
    if(w >= 0) {
      moved[std::size_t(w)] = locations[v];
      known[std::size_t(w)] = 1;
    }
  }
  if(std::find(known.begin(), known.end(), char(0)) != known.end()) {
    std::vector<int> dimension(m.points.size(), 3);
    for(const auto& f : m.triangles)
      for(int v : f)
        dimension[std::size_t(v)] = 2;
    for(const auto& e : m.edges)
      for(int v : e)
        dimension[std::size_t(v)] = 1;
    for(std::size_t v = 0; v < m.points.size(); ++v)
      if(!known[v])
        moved[v] = C3t3_vertex_location{dimension[v], m.point_refs[v]};
  }
  locations = std::move(moved);
}

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_DOMAIN_MESH_H
