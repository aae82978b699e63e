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
#include <map>
#include <utility>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

/// a surface point and the point straight inside it on the other side of the part
struct Facing_pair {
  std::array<double, 3> p, q;
};

/// the faces of `surface` as triangles, with their unit normals (zero for a
/// degenerate face)
inline void surface_triangles(const front::Boundary_surface& surface,
                              std::vector<CGAL::Exact_predicates_inexact_constructions_kernel::Triangle_3>& triangles,
                              std::vector<CGAL::Exact_predicates_inexact_constructions_kernel::Vector_3>& normals)
{
  typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
  auto point = [&](int i) {
    const auto& p = surface.points[std::size_t(i)];
    return K::Point_3(p[0], p[1], p[2]);
  };
  triangles.clear();
  normals.clear();
  triangles.reserve(surface.triangles.size());
  normals.reserve(surface.triangles.size());
  for(const auto& t : surface.triangles) {
    triangles.emplace_back(point(t[0]), point(t[1]), point(t[2]));
    const K::Vector_3 n = CGAL::cross_product(triangles.back()[1] - triangles.back()[0],
                                              triangles.back()[2] - triangles.back()[0]);
    const double l = std::sqrt(CGAL::to_double(n.squared_length()));
    normals.push_back(l > 0 ? n / l : K::Vector_3(0, 0, 0));
  }
}

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
  std::vector<K::Triangle_3> triangles;
  std::vector<K::Vector_3> normals;
  surface_triangles(surface, triangles, normals);
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

/// The points of the feature curves of `surface` (its sharp edges) paired
/// with the nearest point of a patch that does not bound them, where the
/// perpendicular from the curve point falls inside a face of that patch
/// closer than `reach(p)`: a curve running along a wall it is not part of
/// (the cheese's CSG walls leave a hole's rim 0.00012 from the face of
/// another hole; every tet below 10 degrees there joined a node of that rim
/// with a face of that wall). Neither the thickness rays (a curve is near)
/// nor the curve and corner samples (no curve on the wall there) see such a
/// pair. Curve points are `spacing(p)` apart at most; at most
/// `maximum_samples` of them (the spacing is widened uniformly beyond that).
template <typename Spacing, typename Reach>
std::vector<Facing_pair> curve_patch_pairs(const front::Boundary_surface& surface, const Spacing& spacing,
                                           const Reach& reach, std::size_t maximum_samples = 100000)
{
  typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
  typedef std::vector<K::Triangle_3>::const_iterator Iterator;
  typedef CGAL::AABB_triangle_primitive<K, Iterator> Primitive;
  typedef CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>> Tree;
  typedef std::array<double, 3> Point;
  std::vector<Facing_pair> pairs;
  if(surface.triangles.empty() || surface.feature_edges.empty())
    return pairs;
  // the patches on either side of each edge
  std::map<std::pair<int, int>, std::array<int, 2>> sides;
  for(std::size_t f = 0; f < surface.triangles.size(); ++f)
    for(int k = 0; k < 3; ++k) {
      const int a = surface.triangles[f][std::size_t(k)], b = surface.triangles[f][std::size_t((k + 1) % 3)];
      auto it = sides.emplace(std::make_pair(std::min(a, b), std::max(a, b)), std::array<int, 2>{{-1, -1}}).first;
      it->second[it->second[0] < 0 ? 0 : 1] = surface.patches[f];
    }
  std::vector<K::Triangle_3> triangles;
  std::vector<K::Vector_3> normals;
  surface_triangles(surface, triangles, normals);
  // points per edge, from the spacing at its midpoint
  std::vector<int> pieces;
  double total = 0;
  for(const auto& e : surface.feature_edges) {
    const Point &a = surface.points[std::size_t(e[0])], &b = surface.points[std::size_t(e[1])];
    const double length = std::sqrt(CGAL::square(b[0] - a[0]) + CGAL::square(b[1] - a[1]) + CGAL::square(b[2] - a[2]));
    const double s = spacing(Point{{(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2}});
    pieces.push_back(int(std::min(1000.0, (s > 0 && std::isfinite(s)) ? std::max(1.0, std::ceil(length / s)) : 1.0)));
    total += pieces.back();
  }
  if(total > double(maximum_samples))
    for(int& k : pieces)
      k = std::max(1, int(std::floor(double(k) * double(maximum_samples) / total)));
  Tree tree(triangles.begin(), triangles.end());
  tree.build();
  std::vector<Primitive::Id> near;
  for(std::size_t i = 0; i < surface.feature_edges.size(); ++i) {
    const auto& e = surface.feature_edges[i];
    const auto it = sides.find(std::make_pair(std::min(e[0], e[1]), std::max(e[0], e[1])));
    if(it == sides.end())
      continue;
    const K::Point_3 a(surface.points[std::size_t(e[0])][0], surface.points[std::size_t(e[0])][1],
                       surface.points[std::size_t(e[0])][2]);
    const K::Vector_3 ab = K::Point_3(surface.points[std::size_t(e[1])][0], surface.points[std::size_t(e[1])][1],
                                      surface.points[std::size_t(e[1])][2]) - a;
    for(int j = 0; j < pieces[i]; ++j) {
      const K::Point_3 p = a + ((j + 0.5) / pieces[i]) * ab;
      const Point pa{{p.x(), p.y(), p.z()}};
      const double r = reach(pa);
      if(!(r > 0))
        continue;
      near.clear();
      tree.all_intersected_primitives(K::Iso_cuboid_3(p.x() - r, p.y() - r, p.z() - r, p.x() + r, p.y() + r, p.z() + r),
                                      std::back_inserter(near));
      double best = r;
      K::Point_3 foot = p;
      for(const Iterator& id : near) {
        const std::size_t g = std::size_t(id - triangles.begin());
        const int patch = surface.patches[g];
        if(patch == it->second[0] || patch == it->second[1] || normals[g] == K::Vector_3(0, 0, 0))
          continue;
        const K::Triangle_3& t = triangles[g];
        const double d = CGAL::to_double(normals[g] * (p - t[0]));
        if(!(std::abs(d) < best))
          continue;
        const K::Point_3 q = p - d * normals[g];
        // inside the face: q on the inner side of its three edges
        bool inside = true;
        for(int k = 0; k < 3 && inside; ++k)
          inside = CGAL::cross_product(t[(k + 1) % 3] - t[k], q - t[k]) * normals[g] > 0;
        if(inside) {
          best = std::abs(d);
          foot = q;
        }
      }
      if(best < r)
        pairs.push_back(Facing_pair{pa, {{foot.x(), foot.y(), foot.z()}}});
    }
  }
  return pairs;
}

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_SURFACE_THICKNESS_H
