// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Symbolic perturbation of the metric in-sphere predicate.
//
// The point with id k gets the lifting w_M(x) + eps^(rank of k), where the
// largest id has rank 1 (the largest perturbation), the next one rank 2, and
// so on, for an infinitesimal eps > 0. The predicate is
// -sign det[x, y, z, w, 1] over the rows p, q, r, s, t; it is linear in the
// lifted column, so the perturbed determinant is
//
//     D + sum_k eps^rank(k) C_k,   C_k the cofactor of the lifted entry of row k,
//
// and C_k = +-orientation of the four other points: the perturbation does not
// involve M at all. Working out the signs, when D = 0 the answer is, for the
// point of largest id first:
//   - t:               -orientation(p, q, r, s)
//   - one of p,q,r,s:  orientation(p, q, r, s) with that point replaced by t
// and the first non-zero one wins. The t term is non-zero unless p, q, r, s
// are coplanar, so 0 is returned only when all five points are coplanar.
// Because the perturbation is a fixed perturbation of each point, the result
// keeps the alternating property of the determinant under any permutation of
// the five (point, id) pairs.
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PREDICATES_SOS_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PREDICATES_SOS_H

#include <CGAL/Bubble_mesh_3/internal/predicates/side_of_oriented_metric_sphere_3.h>

#include <CGAL/assertions.h>
#include <CGAL/enum.h>

#include <cstddef>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

/// Sign of the perturbed determinant when the unperturbed one is zero.
/// `points` and `ids` are in the argument order p, q, r, s, t; ids must be distinct.
template <class Point_3, class Orientation_3>
CGAL::Oriented_side
perturbed_side_of_oriented_metric_sphere_3(const Point_3* const (&points)[5],
                                           const std::size_t (&ids)[5],
                                           const Orientation_3& orientation)
{
  // positions sorted by decreasing id (insertion sort of five)
  int order[5] = {0, 1, 2, 3, 4};
  for(int i = 1; i < 5; ++i) {
    const int k = order[i];
    int j = i;
    for(; j > 0 && ids[order[j - 1]] < ids[k]; --j)
      order[j] = order[j - 1];
    order[j] = k;
  }
  for(int i = 0; i < 5; ++i) {
    const int k = order[i];
    CGAL::Orientation o;
    if(k == 4) {
      o = -orientation(*points[0], *points[1], *points[2], *points[3]);
    } else {
      const Point_3* a[4] = {points[0], points[1], points[2], points[3]};
      a[k] = points[4];
      o = orientation(*a[0], *a[1], *a[2], *a[3]);
    }
    if(o != CGAL::ZERO)
      return o;
  }
  return CGAL::ON_ORIENTED_BOUNDARY; // all five points are coplanar
}

/// Model of the traits' `Side_of_oriented_metric_sphere_SOS_3`.
template <class K>
class Side_of_oriented_metric_sphere_SOS_3 {
public:
  typedef typename K::Point_3 Point_3;
  typedef typename K::Orientation_3 Orientation_3;
  typedef CGAL::Bubble_mesh_3::Metric_3 Metric_3;
  typedef Side_of_oriented_metric_sphere_3<K> Side_of_oriented_metric_sphere_3_;
  typedef CGAL::Oriented_side result_type;

  explicit Side_of_oriented_metric_sphere_SOS_3(const Orientation_3& orientation = Orientation_3(),
                                                const Side_of_oriented_metric_sphere_3_& side =
                                                    Side_of_oriented_metric_sphere_3_())
    : orientation_(orientation), side_(side)
  {}

  result_type operator()(const Point_3& p, const Point_3& q, const Point_3& r, const Point_3& s,
                         const Point_3& t, const Metric_3& metric,
                         std::size_t id_p, std::size_t id_q, std::size_t id_r, std::size_t id_s,
                         std::size_t id_t) const
  {
    CGAL_precondition_msg(id_p != id_q && id_p != id_r && id_p != id_s && id_p != id_t &&
                          id_q != id_r && id_q != id_s && id_q != id_t &&
                          id_r != id_s && id_r != id_t && id_s != id_t,
                          "the five vertex ids must be distinct");
    const result_type unperturbed = side_(p, q, r, s, t, metric);
    if(unperturbed != CGAL::ON_ORIENTED_BOUNDARY)
      return unperturbed;
    const Point_3* const points[5] = {&p, &q, &r, &s, &t};
    const std::size_t ids[5] = {id_p, id_q, id_r, id_s, id_t};
    return perturbed_side_of_oriented_metric_sphere_3(points, ids, orientation_);
  }

private:
  Orientation_3 orientation_;
  Side_of_oriented_metric_sphere_3_ side_;
};

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PREDICATES_SOS_H
