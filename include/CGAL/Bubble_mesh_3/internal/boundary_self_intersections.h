// Copyright (c) 2026 The Bubble_mesh_3 authors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
//
// Whether the boundary of a tet mesh intersects itself: the boundary of
// each subdomain (the faces of its tets that no other tet of it shares), as
// a Surface_mesh, through PMP::self_intersections. A tet mesh that passes
// the validity check (positive tets, faces shared by at most two tets,
// volume) can still fold over itself at a thin part if its boundary
// vertices moved; this is the check that catches it.

#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_BOUNDARY_SELF_INTERSECTIONS_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_BOUNDARY_SELF_INTERSECTIONS_H

#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <iterator>
#include <map>
#include <utility>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

/// The number of pairs of intersecting triangles on the boundaries of the
/// subdomains of `mesh` (each subdomain's boundary on its own; triangles of
/// two subdomains are not compared). A subdomain boundary that cannot be
/// built as a Surface_mesh (a pinched edge, inconsistent orientations: what
/// the validity check reports on its own) is not checked and is counted in
/// `unchecked_subdomains` if given.
inline std::size_t boundary_self_intersections(const Indexed_tet_mesh_3& mesh,
                                               std::size_t* unchecked_subdomains = nullptr)
{
  if(unchecked_subdomains)
    *unchecked_subdomains = 0;
  typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
  typedef CGAL::Surface_mesh<K::Point_3> Surface;
  // the faces of each subdomain's tets, all oriented alike (inward for a
  // positively oriented tet: only consistency matters to the Surface_mesh)
  std::map<int, std::map<std::array<int, 3>, std::pair<int, std::array<int, 3>>>> faces;
  static constexpr int opposite[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};
  for(std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const int ref = mesh.tet_refs.empty() ? 0 : mesh.tet_refs[t];
    auto& of_ref = faces[ref];
    for(int k = 0; k < 4; ++k) {
      const std::array<int, 3> f{{mesh.tets[t][std::size_t(opposite[k][0])], mesh.tets[t][std::size_t(opposite[k][1])],
                                  mesh.tets[t][std::size_t(opposite[k][2])]}};
      std::array<int, 3> key = f;
      std::sort(key.begin(), key.end());
      auto it = of_ref.find(key);
      if(it == of_ref.end())
        of_ref.emplace(key, std::make_pair(1, f));
      else
        ++it->second.first;
    }
  }
  std::size_t pairs = 0;
  for(const auto& kv : faces) {
    Surface surface;
    std::map<int, Surface::Vertex_index> vertex;
    auto add = [&](int v) {
      auto it = vertex.find(v);
      if(it != vertex.end())
        return it->second;
      const auto& p = mesh.points[std::size_t(v)];
      const Surface::Vertex_index x = surface.add_vertex(K::Point_3(p[0], p[1], p[2]));
      vertex.emplace(v, x);
      return x;
    };
    bool manifold = true;
    for(const auto& face : kv.second) {
      if(face.second.first != 1)
        continue;
      const std::array<int, 3>& f = face.second.second;
      if(surface.add_face(add(f[0]), add(f[1]), add(f[2])) == Surface::null_face()) {
        manifold = false;
        break;
      }
    }
    if(!manifold) {
      if(unchecked_subdomains)
        ++*unchecked_subdomains;
      continue;
    }
    std::vector<std::pair<Surface::Face_index, Surface::Face_index>> found;
    CGAL::Polygon_mesh_processing::self_intersections(surface, std::back_inserter(found));
    pairs += found.size();
  }
  return pairs;
}

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_BOUNDARY_SELF_INTERSECTIONS_H
