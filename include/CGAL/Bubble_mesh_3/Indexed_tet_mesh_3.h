// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_INDEXED_TET_MESH_3_H
#define CGAL_BUBBLE_MESH_3_INDEXED_TET_MESH_3_H

#include <array>
#include <cstddef>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {

/// \ingroup PkgBubbleMesh3Classes
/// A tetrahedral mesh as plain indexed arrays: what MEDIT `.mesh` files hold
/// and what the quality report and the writers consume. Indices are 0-based
/// in memory (MEDIT files are 1-based; the reader and writer convert).
/// Each element array has a parallel array of references: the subdomain of a
/// tet, the surface patch of a triangle, the feature curve of an edge.
struct Indexed_tet_mesh_3 {
  std::vector<std::array<double, 3>> points;
  std::vector<int> point_refs;
  std::vector<std::array<int, 2>> edges;
  std::vector<int> edge_refs;
  std::vector<std::array<int, 3>> triangles;
  std::vector<int> triangle_refs;
  std::vector<std::array<int, 4>> tets;
  std::vector<int> tet_refs;
  /// vertices that are corners (MEDIT `Corners`), 0-based
  std::vector<int> corners;

  std::size_t number_of_points() const { return points.size(); }
  std::size_t number_of_tets() const { return tets.size(); }
};

} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INDEXED_TET_MESH_3_H
