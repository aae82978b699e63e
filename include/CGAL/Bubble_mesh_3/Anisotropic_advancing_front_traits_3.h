// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_ANISOTROPIC_ADVANCING_FRONT_TRAITS_3_H
#define CGAL_BUBBLE_MESH_3_ANISOTROPIC_ADVANCING_FRONT_TRAITS_3_H

#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/internal/predicates/side_of_oriented_metric_sphere_3.h>
#include <CGAL/Bubble_mesh_3/internal/predicates/sos.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

namespace CGAL {
namespace Bubble_mesh_3 {

/// \ingroup PkgBubbleMesh3Classes
///
/// The default geometric traits of the anisotropic advancing front: the
/// kernel `K` plus exact predicates that measure in a Riemannian metric.
///
/// The metric in-sphere predicate decides on which side of the
/// *M-circumsphere* of four points a fifth point lies: the ellipsoid
/// `{x : (x-c)^T M (x-c) = rho^2}` through `p, q, r, s`, i.e. the circumsphere
/// of the four points mapped by any `Q` with `M = Q^T Q`. It is evaluated
/// exactly from the point coordinates and the six entries of `M` as given
/// (doubles), as the sign of the 4x4 lifted determinant with rows
/// `(d_i, d_i^T M d_i)`, `d_i = p_i - t`: a semi-static filter in doubles, then
/// interval arithmetic, then an exact ring type (`CGAL::Mpzf`). `Q` is never
/// computed, so rounding in a Cholesky factor cannot change an answer. A
/// front decision must use one metric for all its tests (freeze `M` per
/// decision) for the answers to be mutually consistent.
///
/// \tparam K a model of `Kernel` with `double` coordinates, by default
/// `CGAL::Exact_predicates_inexact_constructions_kernel`. Its predicates
/// and constructions are inherited.
///
/// \cgalModels `AnisotropicAdvancingFrontTraits_3`
///
/// To extend the traits, add a functor type, its `*_object()` accessor, and
/// its line in the concept `AnisotropicAdvancingFrontTraits_3`.
template <class K = CGAL::Exact_predicates_inexact_constructions_kernel>
class Anisotropic_advancing_front_traits_3 : public K {
public:
  /// \name Types
  /// @{

  /// the kernel
  typedef K Kernel;
  /// the number type of the coordinates (`double`)
  typedef typename K::FT FT;
  /// the point type
  typedef typename K::Point_3 Point_3;
  /// a symmetric positive definite matrix stored as doubles, the exact input
  /// of the metric predicates
  typedef CGAL::Bubble_mesh_3::Metric_3 Metric_3;

  /// the kernel's exact orientation predicate:
  /// `CGAL::Orientation operator()(p, q, r, s)`, `POSITIVE` when `s` lies on
  /// the positive side of the plane through `p, q, r` (counterclockwise seen
  /// from `s`).
  typedef typename K::Orientation_3 Orientation_3;

  /// A function object with the operator
  ///
  /// `CGAL::Oriented_side operator()(const Point_3& p, const Point_3& q, const Point_3& r, const Point_3& s, const Point_3& t, const Metric_3& M) const`
  ///
  /// which returns, exactly, the side of the oriented M-circumsphere of
  /// `p, q, r, s` on which `t` lies, with the convention of
  /// `K::Side_of_oriented_sphere_3`: when `orientation(p, q, r, s) == POSITIVE`,
  /// `ON_POSITIVE_SIDE` means `t` is strictly inside,
  /// `ON_NEGATIVE_SIDE` strictly outside and `ON_ORIENTED_BOUNDARY` on the
  /// ellipsoid; the answer is reversed for a negative orientation. It is
  /// the Euclidean `side_of_oriented_sphere` of the five points mapped by `Q`.
  /// With `M` the identity it equals `K::Side_of_oriented_sphere_3`. When
  /// `p, q, r, s` are coplanar the result is, as for `Side_of_oriented_sphere_3`,
  /// the sign of the degenerate lifted determinant (no sphere exists).
  typedef internal::Side_of_oriented_metric_sphere_3<K> Side_of_oriented_metric_sphere_3;

  /// A function object with the operator
  ///
  /// `CGAL::Oriented_side operator()(const Point_3& p, const Point_3& q, const Point_3& r, const Point_3& s, const Point_3& t, const Metric_3& M, std::size_t id_p, std::size_t id_q, std::size_t id_r, std::size_t id_s, std::size_t id_t) const`
  ///
  /// the same test under symbolic perturbation: it returns the result of
  /// `Side_of_oriented_metric_sphere_3` when that is not `ON_ORIENTED_BOUNDARY`,
  /// and otherwise the sign obtained by adding `epsilon^k` to the lifting
  /// `d^T M d` of the point with the `k`-th **largest** id (the point with
  /// the largest id is perturbed the most), for an infinitely
  /// small `epsilon > 0`. The perturbation only depends on the ids, never on the
  /// argument order or on `M`; the answer is then the first non-zero of:
  /// for the largest id, if it is `t`, `-orientation(p, q, r, s)`, otherwise
  /// `orientation(p, q, r, s)` with that point replaced by `t`; then the same for
  /// the next largest id, and so on.
  ///
  /// Properties: it never returns `ON_ORIENTED_BOUNDARY` unless the five
  /// points are coplanar, in particular never when `p, q, r, s` are not
  /// coplanar; permuting the five (point, id) pairs multiplies the result by
  /// the sign of the permutation; it is consistent over all the tests that use
  /// the same ids and the same `M`.
  /// \pre the five ids are distinct, and the same point always carries the same id.
  typedef internal::Side_of_oriented_metric_sphere_SOS_3<K> Side_of_oriented_metric_sphere_SOS_3;

  /// @}

  /// \name Creation
  /// @{

  /// constructs the traits from a kernel object
  Anisotropic_advancing_front_traits_3(const K& kernel = K()) : K(kernel) {}

  /// @}

  /// \name Operations
  /// @{

  /// returns an `Orientation_3` object
  Orientation_3 orientation_3_object() const { return K::orientation_3_object(); }

  /// returns a `Side_of_oriented_metric_sphere_3` object
  Side_of_oriented_metric_sphere_3 side_of_oriented_metric_sphere_3_object() const
  {
    return Side_of_oriented_metric_sphere_3();
  }

  /// returns a `Side_of_oriented_metric_sphere_SOS_3` object
  Side_of_oriented_metric_sphere_SOS_3 side_of_oriented_metric_sphere_SOS_3_object() const
  {
    return Side_of_oriented_metric_sphere_SOS_3(orientation_3_object(), side_of_oriented_metric_sphere_3_object());
  }

  /// @}
};

} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_ANISOTROPIC_ADVANCING_FRONT_TRAITS_3_H
