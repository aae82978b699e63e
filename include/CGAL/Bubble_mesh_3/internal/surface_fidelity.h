// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// How faithfully a tet mesh's boundary follows the input surface: the
// largest distance from the boundary triangles to the input (sampled over
// each triangle, not only at its vertices: a chord strays most inside), the
// largest distance from the input's vertices to the boundary (a cut-off tip
// or a missed thin part), and the relative volume error.
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_SURFACE_FIDELITY_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_SURFACE_FIDELITY_H

#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/internal/front/boundary_front.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

struct Surface_fidelity {
  double mesh_to_surface = 0;  ///< largest distance of a boundary sample to the input surface
  double surface_to_mesh = 0;  ///< largest distance of an input vertex to the mesh boundary
  double volume_error = 0;     ///< |mesh volume - enclosed input volume| / enclosed input volume
  double diagonal = 0;         ///< of the input's bounding box
};

namespace surface_fidelity_detail {

typedef CGAL::Exact_predicates_inexact_constructions_kernel EK;
typedef std::vector<EK::Triangle_3> Triangles;
typedef CGAL::AABB_triangle_primitive<EK, Triangles::const_iterator> Primitive;
typedef CGAL::AABB_tree<CGAL::AABB_traits<EK, Primitive>> Tree;

inline EK::Point_3 point(const std::array<double, 3>& p) { return EK::Point_3(p[0], p[1], p[2]); }

// signed volume enclosed by triangles, relative to o (exact cancellation far from the origin)
inline double enclosed_volume(const std::vector<std::array<double, 3>>& points,
                              const std::vector<std::array<int, 3>>& triangles)
{
  if(points.empty())
    return 0;
  const std::array<double, 3> o = points.front();
  double v = 0;
  for(const auto& t : triangles) {
    std::array<std::array<double, 3>, 3> p;
    for(int k = 0; k < 3; ++k)
      for(int i = 0; i < 3; ++i)
        p[k][i] = points[std::size_t(t[k])][i] - o[i];
    const auto &a = p[0], &b = p[1], &c = p[2];
    v += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
          a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
  }
  return v;
}

} // namespace surface_fidelity_detail

/// Compares the boundary triangles of `mesh` with `surface`; each boundary
/// triangle is sampled at the points of a barycentric grid of `subdivisions`
/// steps per edge.
inline Surface_fidelity surface_fidelity(const front::Boundary_surface& surface, const Indexed_tet_mesh_3& mesh,
                                         int subdivisions = 4)
{
  using namespace surface_fidelity_detail;
  Surface_fidelity r;
  if(surface.triangles.empty() || mesh.triangles.empty())
    return r;
  std::array<double, 3> lo{{HUGE_VAL, HUGE_VAL, HUGE_VAL}}, hi{{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}};
  for(const auto& p : surface.points)
    for(int i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], p[i]);
      hi[i] = std::max(hi[i], p[i]);
    }
  r.diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                         (hi[2] - lo[2]) * (hi[2] - lo[2]));

  Triangles input, boundary;
  for(const auto& t : surface.triangles)
    input.emplace_back(point(surface.points[std::size_t(t[0])]), point(surface.points[std::size_t(t[1])]),
                       point(surface.points[std::size_t(t[2])]));
  for(const auto& t : mesh.triangles)
    boundary.emplace_back(point(mesh.points[std::size_t(t[0])]), point(mesh.points[std::size_t(t[1])]),
                          point(mesh.points[std::size_t(t[2])]));
  Tree input_tree(input.begin(), input.end());
  input_tree.accelerate_distance_queries();
  Tree boundary_tree(boundary.begin(), boundary.end());
  boundary_tree.accelerate_distance_queries();

  const int n = std::max(1, subdivisions);
  double d2 = 0;
  for(const auto& t : boundary)
    for(int i = 0; i <= n; ++i)
      for(int j = 0; i + j <= n; ++j) {
        const double a = double(i) / n, b = double(j) / n, c = 1 - a - b;
        const EK::Point_3 q(a * t[0].x() + b * t[1].x() + c * t[2].x(), a * t[0].y() + b * t[1].y() + c * t[2].y(),
                            a * t[0].z() + b * t[1].z() + c * t[2].z());
        d2 = std::max(d2, input_tree.squared_distance(q));
      }
  r.mesh_to_surface = std::sqrt(d2);
  d2 = 0;
  for(const auto& p : surface.points)
    d2 = std::max(d2, boundary_tree.squared_distance(point(p)));
  r.surface_to_mesh = std::sqrt(d2);

  const double vin = std::abs(enclosed_volume(surface.points, surface.triangles));
  const double vmesh = std::abs(enclosed_volume(mesh.points, mesh.triangles));
  r.volume_error = vin > 0 ? std::abs(vmesh - vin) / vin : 0;
  return r;
}

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_SURFACE_FIDELITY_H
