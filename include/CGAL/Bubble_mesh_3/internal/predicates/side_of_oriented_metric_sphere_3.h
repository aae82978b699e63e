// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// The exact metric in-sphere predicate.
//
// For a fixed symmetric positive definite M (six doubles) and d_i = p_i - t,
//
//   side_M(p,q,r,s,t) = sign det | d_p  w(d_p) |     w(d) = d^T M d
//                                | d_r  w(d_r) |
//                                | d_q  w(d_q) |     (rows p, r, q, s: the
//                                | d_s  w(d_s) |      order of CGAL's
//                                                     side_of_oriented_sphereC3)
//
// It equals -sign det[x, y, z, x^T M x, 1] over the rows p, q, r, s, t, and
// is the Euclidean in-sphere test of the points mapped by any Q with
// M = Q^T Q, det Q > 0 (the determinant gains the factor det Q > 0), without
// ever computing Q. Degree 3 in the coordinate differences plus 2 in the
// lifting: 5, linear in M.
//
// Evaluation: semi-static filter in plain doubles, then interval arithmetic
// and an exact ring type through CGAL::Filtered_predicate.
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PREDICATES_SIDE_OF_ORIENTED_METRIC_SPHERE_3_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PREDICATES_SIDE_OF_ORIENTED_METRIC_SPHERE_3_H

#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/internal/predicates/static_filter.h>

#include <CGAL/Filtered_predicate.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/Kernel/Same_uncertainty.h>
#include <CGAL/Mpzf.h>
#include <CGAL/enum.h>
#include <CGAL/number_utils.h>
#ifndef CGAL_HAS_MPZF
#include <CGAL/MP_Float.h>
#endif

#include <cmath>
#include <type_traits>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

/// The three coordinates of a point in number type `NT`.
template <class NT>
struct Coordinates_3 {
  NT x, y, z;
};

/// The six independent entries of a symmetric matrix in number type `NT`,
/// in the order of `Metric_3::entries()` (the off-diagonals are not doubled).
template <class NT>
struct Metric_coefficients_3 {
  NT m11, m12, m13, m22, m23, m33;
};

/// The lifted 4x4 determinant of the rows `(d[i], w(d[i]))`, `w(d) = d^T M d`,
/// given the diagonal of `M` and its *doubled* off-diagonal entries.
///
/// This one expression is evaluated in doubles by the semi-static filter, in
/// `Interval_nt` and in the exact type by the dynamic filter, and on error
/// bounds by `Side_of_oriented_metric_sphere_3_static_filter::compute_epsilon()`,
/// so the filter constant is derived from the very operation sequence it guards.
/// Do not reorder the operations without recomputing the constant.
template <class NT>
NT metric_lifted_determinant(const NT (&d)[4][3],
                             const NT& m11, const NT& m22, const NT& m33,
                             const NT& m12x2, const NT& m13x2, const NT& m23x2)
{
  // Lifting in Horner form: 9 products instead of 12. Written out (not as a
  // loop) so that -O2 schedules the four rows together.
  auto lift = [&](const NT (&r)[3]) -> NT {
    return r[0] * (m11 * r[0] + m12x2 * r[1] + m13x2 * r[2]) + r[1] * (m22 * r[1] + m23x2 * r[2]) +
           r[2] * (m33 * r[2]);
  };
  const NT w0 = lift(d[0]);
  const NT w1 = lift(d[1]);
  const NT w2 = lift(d[2]);
  const NT w3 = lift(d[3]);
  // 2x2 minors on the x and y columns
  const NT m01 = d[0][0] * d[1][1] - d[1][0] * d[0][1];
  const NT m02 = d[0][0] * d[2][1] - d[2][0] * d[0][1];
  const NT m03 = d[0][0] * d[3][1] - d[3][0] * d[0][1];
  const NT m12 = d[1][0] * d[2][1] - d[2][0] * d[1][1];
  const NT m13 = d[1][0] * d[3][1] - d[3][0] * d[1][1];
  const NT m23 = d[2][0] * d[3][1] - d[3][0] * d[2][1];
  // 3x3 minors on the x, y, z columns, named by their rows
  const NT m012 = m01 * d[2][2] - m02 * d[1][2] + m12 * d[0][2];
  const NT m013 = m01 * d[3][2] - m03 * d[1][2] + m13 * d[0][2];
  const NT m023 = m02 * d[3][2] - m03 * d[2][2] + m23 * d[0][2];
  const NT m123 = m12 * d[3][2] - m13 * d[2][2] + m23 * d[1][2];
  // expansion along the lifted column
  return w3 * m012 - w2 * m013 + w1 * m023 - w0 * m123;
}

/// The predicate over any ring number type: exact for an exact `NT`,
/// `Uncertain<Oriented_side>` for `Interval_nt`.
template <class NT>
class Side_of_oriented_metric_sphere_3_nt {
public:
  typedef typename CGAL::Same_uncertainty_nt<CGAL::Oriented_side, NT>::type result_type;

  result_type operator()(const Coordinates_3<NT>& p, const Coordinates_3<NT>& q,
                         const Coordinates_3<NT>& r, const Coordinates_3<NT>& s,
                         const Coordinates_3<NT>& t, const Metric_coefficients_3<NT>& m) const
  {
    const Coordinates_3<NT>* rows[4] = {&p, &r, &q, &s};
    NT d[4][3];
    for(int i = 0; i < 4; ++i) {
      d[i][0] = rows[i]->x - t.x;
      d[i][1] = rows[i]->y - t.y;
      d[i][2] = rows[i]->z - t.z;
    }
    const NT two(2);
    return CGAL::sign(metric_lifted_determinant(d, m.m11, m.m22, m.m33,
                                                two * m.m12, two * m.m13, two * m.m23));
  }
};

/// Converts the double inputs of the predicate to `NT` (exactly for the
/// exact type, as point intervals for `Interval_nt`). `CGAL::Filtered_predicate`
/// applies it to every argument, points and metric alike.
template <class NT>
struct To_metric_sphere_nt {
  Coordinates_3<NT> operator()(const Coordinates_3<double>& p) const
  {
    return Coordinates_3<NT>{NT(p.x), NT(p.y), NT(p.z)};
  }
  Metric_coefficients_3<NT> operator()(const Metric_coefficients_3<double>& m) const
  {
    return Metric_coefficients_3<NT>{NT(m.m11), NT(m.m12), NT(m.m13), NT(m.m22), NT(m.m23), NT(m.m33)};
  }
};

/// The exact ring type of the last stage (`Mpzf` where CGAL has it).
#ifdef CGAL_HAS_MPZF
typedef CGAL::Mpzf Metric_sphere_exact_nt;
#else
typedef CGAL::MP_Float Metric_sphere_exact_nt;
#endif

/// Interval arithmetic, then the exact ring type.
typedef CGAL::Filtered_predicate<Side_of_oriented_metric_sphere_3_nt<Metric_sphere_exact_nt>,
                                 Side_of_oriented_metric_sphere_3_nt<CGAL::Interval_nt_advanced>,
                                 To_metric_sphere_nt<Metric_sphere_exact_nt>,
                                 To_metric_sphere_nt<CGAL::Interval_nt_advanced> >
    Side_of_oriented_metric_sphere_3_dynamic_filter;

/// The semi-static filter: the determinant in plain doubles and the bound
///
///     |det' - det| <= epsilon() * X * Y * Z * A^2 * m
///
/// where `X, Y, Z` are the largest |x, y, z differences| over the four rows,
/// `A = max(X, Y, Z)` and `m` the largest |entry| of `M` (off-diagonals not
/// doubled). The lifting of a row is at most `9 m A^2`.
/// Ranges are checked so that nothing overflows and underflow errors stay far
/// below the bound; outside them the filter abstains.
struct Side_of_oriented_metric_sphere_3_static_filter {
  /// The hard-coded constant: `compute_epsilon()` rounded up (a unit test
  /// recomputes it).
  static constexpr double epsilon() { return 4.3232125808233011e-13; }

  /// Derives the constant by running `metric_lifted_determinant()` on
  /// `Static_error_bound`s: differences `|d| <= 1` with error `u` (one rounded
  /// subtraction), entries of `M` exact with bound 1, doubled off-diagonals
  /// exact with bound 2. The factor `1 + 2^-20` covers the six rounded products
  /// that scale the constant at run time (relative error <= 6u) and the
  /// absolute underflow errors allowed by the range checks (relative
  /// contribution below 1e-50).
  static double compute_epsilon()
  {
    typedef Static_error_bound F;
    const F difference(1, F::unit_roundoff());
    F d[4][3];
    for(int i = 0; i < 4; ++i)
      for(int j = 0; j < 3; ++j)
        d[i][j] = difference;
    const F entry(1);
    const F doubled_entry(2);
    const F det = metric_lifted_determinant(d, entry, entry, entry, doubled_entry, doubled_entry, doubled_entry);
    return F::up(det.error() * (1 + 1.0 / 1048576.0));
  }

  /// Computes the double determinant `det` and its error bound `eps`. Returns
  /// `false` (and leaves both unspecified) when the inputs are out of the
  /// range where the bound is valid.
  static bool evaluate(const Coordinates_3<double>& p, const Coordinates_3<double>& q,
                       const Coordinates_3<double>& r, const Coordinates_3<double>& s,
                       const Coordinates_3<double>& t, const Metric_coefficients_3<double>& m,
                       double& det, double& eps)
  {
    // rows in the order p, r, q, s; straight-line code for -O2
    const double d[4][3] = {{p.x - t.x, p.y - t.y, p.z - t.z},
                            {r.x - t.x, r.y - t.y, r.z - t.z},
                            {q.x - t.x, q.y - t.y, q.z - t.z},
                            {s.x - t.x, s.y - t.y, s.z - t.z}};
    const double max_x = max_of(max_of(std::abs(d[0][0]), std::abs(d[1][0])), max_of(std::abs(d[2][0]), std::abs(d[3][0])));
    const double max_y = max_of(max_of(std::abs(d[0][1]), std::abs(d[1][1])), max_of(std::abs(d[2][1]), std::abs(d[3][1])));
    const double max_z = max_of(max_of(std::abs(d[0][2]), std::abs(d[1][2])), max_of(std::abs(d[2][2]), std::abs(d[3][2])));
    const double max_m = max_of(max_of(max_of(std::abs(m.m11), std::abs(m.m22)), std::abs(m.m33)),
                                max_of(max_of(std::abs(m.m12), std::abs(m.m13)), std::abs(m.m23)));
    const double lo = min_of(min_of(max_x, max_y), max_z);
    const double hi = max_of(max_of(max_x, max_y), max_z);
    // Negated tests, so that a NaN maximum fails them (a NaN that max_of
    // dropped still reaches det, which then fails both sign tests of
    // certified_sign). With these ranges each product
    // that can underflow (X Y, X Y Z, A^2, m A, m A^2, the scale) is at least
    // 1e-250 in its own unit, and no intermediate exceeds ~1e253.
    if(!(lo >= 1e-40 && hi <= 1e40 && max_m >= 1e-150 && max_m <= 1e150))
      return false;
    const double scale = max_x * max_y * max_z * hi * hi * max_m;
    if(!(scale >= 1e-250 && scale <= 1e250))
      return false;
    det = metric_lifted_determinant(d, m.m11, m.m22, m.m33, 2 * m.m12, 2 * m.m13, 2 * m.m23);
    eps = epsilon() * scale;
    return true;
  }

  // branch-free (maxsd / minsd); a NaN operand may be dropped, but it
  // still reaches the determinant, which then fails both sign tests
  static double max_of(double a, double b) { return a > b ? a : b; }
  static double min_of(double a, double b) { return a < b ? a : b; }

  /// Returns `true` and sets `result` when the sign is certified.
  static bool certified_sign(const Coordinates_3<double>& p, const Coordinates_3<double>& q,
                             const Coordinates_3<double>& r, const Coordinates_3<double>& s,
                             const Coordinates_3<double>& t, const Metric_coefficients_3<double>& m,
                             CGAL::Oriented_side& result)
  {
    double det;
    double eps;
    if(!evaluate(p, q, r, s, t, m, det, eps))
      return false;
    if(det > eps) {
      result = CGAL::ON_POSITIVE_SIDE;
      return true;
    }
    if(det < -eps) {
      result = CGAL::ON_NEGATIVE_SIDE;
      return true;
    }
    return false;
  }
};

/// The whole filtered predicate on doubles: semi-static, interval, exact.
inline CGAL::Oriented_side
side_of_oriented_metric_sphere_3(const Coordinates_3<double>& p, const Coordinates_3<double>& q,
                                 const Coordinates_3<double>& r, const Coordinates_3<double>& s,
                                 const Coordinates_3<double>& t, const Metric_coefficients_3<double>& m)
{
  CGAL::Oriented_side result;
  if(Side_of_oriented_metric_sphere_3_static_filter::certified_sign(p, q, r, s, t, m, result))
    return result;
  return Side_of_oriented_metric_sphere_3_dynamic_filter()(p, q, r, s, t, m);
}

/// The six entries of `M` as the predicate reads them.
inline Metric_coefficients_3<double> metric_coefficients(const Metric_3& metric)
{
  const Metric_3::Matrix& a = metric.matrix();
  return Metric_coefficients_3<double>{a(0, 0), a(0, 1), a(0, 2), a(1, 1), a(1, 2), a(2, 2)};
}

/// Model of the traits' `Side_of_oriented_metric_sphere_3` for a kernel `K`
/// with double coordinates.
template <class K>
class Side_of_oriented_metric_sphere_3 {
  static_assert(std::is_same<typename K::FT, double>::value,
                "Side_of_oriented_metric_sphere_3 needs a kernel with double coordinates (e.g. Epick)");

public:
  typedef typename K::Point_3 Point_3;
  typedef CGAL::Bubble_mesh_3::Metric_3 Metric_3;
  typedef CGAL::Oriented_side result_type;

  result_type operator()(const Point_3& p, const Point_3& q, const Point_3& r, const Point_3& s,
                         const Point_3& t, const Metric_3& metric) const
  {
    return side_of_oriented_metric_sphere_3(coordinates(p), coordinates(q), coordinates(r),
                                            coordinates(s), coordinates(t), metric_coefficients(metric));
  }

private:
  static Coordinates_3<double> coordinates(const Point_3& p)
  {
    return Coordinates_3<double>{p.x(), p.y(), p.z()};
  }
};

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PREDICATES_SIDE_OF_ORIENTED_METRIC_SPHERE_3_H
