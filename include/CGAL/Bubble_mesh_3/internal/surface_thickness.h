// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Where a part is thin: points of a closed, outward oriented triangle surface
// paired with the point straight inside them (along the inward normal) where
// the ray leaves the part, when it leaves through a face turned against
// theirs (normals within 25 degrees of opposite: the other side of a plate,
// a blade, a wall). The pairs are
// what `Feature_size_metric_field_3` compares with the metric's sizes: a
// part thinner than an element gets elements of about its thickness, so the
// tets spanning it are not slivers. Rays leave from sub-triangle centres of
// every face, at most half the smallest size asked there apart.
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_SURFACE_THICKNESS_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_SURFACE_THICKNESS_H

#include <CGAL/Bubble_mesh_3/internal/front/boundary_front.h>
#include <CGAL/Bubble_mesh_3/internal/packing/bubble.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

/// a surface point and the point straight inside it on the other side of the part
struct Facing_pair {
  std::array<double, 3> p, q;
};

/// The facing pairs of `surface` (outward oriented, as
/// `front::boundary_surface_from_polyhedral_domain` returns it) closer than
/// `reach(p)`. `spacing(p)` is the largest distance between the ray origins
/// near p; at most `maximum_samples` rays are cast (the spacing is widened
/// uniformly beyond that). Faces are turned against each other when the
/// cosine of their normals is below `facing_cosine` (by default the rule by
/// which the packing lets the two sides of a part ignore each other).
template <typename Spacing, typename Reach>
std::vector<Facing_pair> facing_pairs(const front::Boundary_surface& surface, const Spacing& spacing,
                                      const Reach& reach, double facing_cosine = packing::opposite_sides_cosine,
                                      std::size_t maximum_samples = 100000)
{
  typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
  typedef std::vector<K::Triangle_3>::const_iterator Iterator;
  typedef CGAL::AABB_triangle_primitive<K, Iterator> Primitive;
  typedef CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>> Tree;
  std::vector<Facing_pair> pairs;
  const std::size_t nf = surface.triangles.size();
  if(nf == 0)
    return pairs;
  auto point = [&](int i) {
    const auto& p = surface.points[std::size_t(i)];
    return K::Point_3(p[0], p[1], p[2]);
  };
  std::vector<K::Triangle_3> triangles;
  std::vector<K::Vector_3> normals;
  triangles.reserve(nf);
  normals.reserve(nf);
  for(const auto& t : surface.triangles) {
    triangles.emplace_back(point(t[0]), point(t[1]), point(t[2]));
    const K::Vector_3 n = CGAL::cross_product(triangles.back()[1] - triangles.back()[0],
                                              triangles.back()[2] - triangles.back()[0]);
    const double l = std::sqrt(CGAL::to_double(n.squared_length()));
    normals.push_back(l > 0 ? n / l : K::Vector_3(0, 0, 0));
  }
  // subdivision of each face: k x k sub-triangles, k from the spacing at its centre
  std::vector<int> divisions(nf, 1);
  double total = 0;
  for(std::size_t f = 0; f < nf; ++f) {
    const K::Triangle_3& t = triangles[f];
    const K::Point_3 c = CGAL::centroid(t[0], t[1], t[2]);
    const double longest = std::sqrt(std::max({CGAL::to_double(CGAL::squared_distance(t[0], t[1])),
                                               CGAL::to_double(CGAL::squared_distance(t[1], t[2])),
                                               CGAL::to_double(CGAL::squared_distance(t[2], t[0]))}));
    const double s = spacing(std::array<double, 3>{{c.x(), c.y(), c.z()}});
    const double k = (s > 0 && std::isfinite(s)) ? std::ceil(longest / s) : 1.0;
    divisions[f] = int(std::min(k, 1000.0));
    total += double(divisions[f]) * double(divisions[f]);
  }
  if(total > double(maximum_samples)) {
    const double shrink = std::sqrt(double(maximum_samples) / total);
    for(int& k : divisions)
      k = std::max(1, int(std::floor(double(k) * shrink)));
  }
  Tree tree(triangles.begin(), triangles.end());
  tree.build();
  std::vector<Primitive::Id> crossed;
  for(std::size_t f = 0; f < nf; ++f) {
    const K::Vector_3& n = normals[f];
    if(n == K::Vector_3(0, 0, 0))
      continue;
    const K::Triangle_3& t = triangles[f];
    const int k = divisions[f];
    const K::Vector_3 u = (t[1] - t[0]) / double(k), v = (t[2] - t[0]) / double(k);
    // the centres of the k^2 sub-triangles (upright and inverted)
    for(int i = 0; i < k; ++i)
      for(int j = 0; i + j < k; ++j)
        for(int up = 0; up < 2; ++up) {
          if(up == 1 && i + j + 1 >= k)
            continue;
          const double a = up == 0 ? i + 1.0 / 3 : i + 2.0 / 3, b = up == 0 ? j + 1.0 / 3 : j + 2.0 / 3;
          const K::Point_3 p = t[0] + a * u + b * v;
          const std::array<double, 3> pa{{p.x(), p.y(), p.z()}};
          const double r = reach(pa);
          if(!(r > 0))
            continue;
          // a segment as long as the reach, not a ray: the tree then visits
          // the faces near p only (a ray crosses the whole part)
          crossed.clear();
          tree.all_intersected_primitives(K::Segment_3(p, p - r * n), std::back_inserter(crossed));
          // the first face the segment meets is where it leaves the part: a
          // pair only if that face is turned against this one
          double first = r;
          std::size_t first_face = nf;
          for(const Iterator& id : crossed) {
            const std::size_t g = std::size_t(id - triangles.begin());
            const double towards = -(normals[g] * n);
            if(g == f || !(std::abs(towards) > 1e-12))
              continue; // its own face; a face along the segment (met again through another)
            const double along = CGAL::to_double(normals[g] * (triangles[g][0] - p)) / towards;
            if(along > 0 && along < first) {
              first = along;
              first_face = g;
            }
          }
          if(first_face == nf || !(normals[first_face] * n < facing_cosine))
            continue;
          const K::Point_3 q = p - first * n;
          pairs.push_back(Facing_pair{pa, {{q.x(), q.y(), q.z()}}});
        }
  }
  return pairs;
}

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_SURFACE_THICKNESS_H
