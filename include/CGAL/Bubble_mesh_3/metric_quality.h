// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_METRIC_QUALITY_H
#define CGAL_BUBBLE_MESH_3_METRIC_QUALITY_H

#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/enum.h>
#include <CGAL/number_utils.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <type_traits>

/// \file metric_quality.h
/// Shape and size measures of tetrahedra and edges, in the Euclidean metric
/// and in a Riemannian metric (paper, section 6).
///
/// Every measure "in the metric `m`" is the Euclidean measure of the tet whose
/// vertices are mapped by `Q`, where `m.matrix() = Q^T Q` (`Metric_3::Q()`).
/// Such a measure does not depend on the choice of the factor `Q` (two factors
/// differ by a rotation) and, being translation invariant, only the edge
/// vectors `Q (p_i - p_0)` are mapped, which keeps full precision for meshes
/// far from the origin.
///
/// Points may be given as `Eigen::Vector3d` (the primary overloads), as
/// `std::array<double, 3>`, or as any type with `x()`, `y()`, `z()` (a CGAL
/// `Point_3` of any kernel; coordinates go through `CGAL::to_double`).
///
/// Orientation and degeneracy conventions:
/// - dihedral angles, radius ratio and mean ratio do not depend on the
///   orientation of the tet (an inverted tet has the angles of its mirror
///   image); use `CGAL::orientation` (exact) to detect inverted tets.
/// - a flat tet (four coplanar points, or a degenerate face) has minimum
///   dihedral angle 0, radius ratio 0 and mean ratio 0, never NaN. When a
///   floating-point result is small enough to come from rounding, exact
///   coplanarity of the (double) input points is decided with Epick's exact
///   `CGAL::orientation`, so exactly flat tets give exactly 0 even after the
///   mapping by `Q`; their six angles are then exactly 0 or 180.
/// - signed volumes are positive when `CGAL::orientation(p0, p1, p2, p3)`
///   is `CGAL::POSITIVE`, i.e. `(p1-p0) . ((p2-p0) x (p3-p0)) > 0`.
///
/// Edge order of the six dihedral angles (the edge where the angle sits):
/// `(0,1), (0,2), (0,3), (1,2), (1,3), (2,3)`.

namespace CGAL {
namespace Bubble_mesh_3 {

namespace internal {

// Detects std::array<T, 3> without requiring value_type from other types.
template <typename T>
struct Is_std_array_3 : std::false_type {};
template <typename T>
struct Is_std_array_3<std::array<T, 3>> : std::true_type {};

/// Converts a point or vector to `Eigen::Vector3d`: Eigen vectors and
/// expressions, `std::array<T, 3>`, or anything with `x()`, `y()`, `z()`.
template <typename Point_>
Eigen::Vector3d to_vector_3(const Point_& p)
{
  if constexpr(std::is_base_of<Eigen::MatrixBase<Point_>, Point_>::value) {
    return Eigen::Vector3d(p);
  } else if constexpr(Is_std_array_3<Point_>::value) {
    return Eigen::Vector3d(static_cast<double>(p[0]), static_cast<double>(p[1]), static_cast<double>(p[2]));
  } else {
    return Eigen::Vector3d(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
  }
}

constexpr double radians_to_degrees() { return 57.295779513082320876798154814105; }

/// `Q v` for an upper-triangular `Q` (9 flops instead of 15)
inline Eigen::Vector3d map_by_upper(const Eigen::Matrix3d& q, const Eigen::Vector3d& v)
{
  return Eigen::Vector3d(q(0, 0) * v[0] + q(0, 1) * v[1] + q(0, 2) * v[2],
                         q(1, 1) * v[1] + q(1, 2) * v[2],
                         q(2, 2) * v[2]);
}

// The three edge vectors p1-p0, p2-p0, p3-p0 mapped by Q of `m`: every metric
// measure of a tet is the Euclidean measure of these.
inline std::array<Eigen::Vector3d, 3> metric_edge_vectors(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                                          const Eigen::Vector3d& p2, const Eigen::Vector3d& p3,
                                                          const Metric_3& m)
{
  const Eigen::Matrix3d& q = m.Q();
  return {{map_by_upper(q, p1 - p0), map_by_upper(q, p2 - p0), map_by_upper(q, p3 - p0)}};
}

/// Face normals (twice the area, outward when `a . (b x c) > 0`) of the tet
/// `p0, p0+a, p0+b, p0+c`; `n[k]` belongs to the face opposite vertex `k`.
inline void face_normals(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                         Eigen::Vector3d n[4])
{
  n[1] = c.cross(b);
  n[2] = a.cross(c);
  n[3] = b.cross(a);
  // The area vectors of a closed surface sum to zero.
  n[0] = -(n[1] + n[2] + n[3]);
}

/// Interior dihedral angle (radians) between the faces of outward normals
/// `nk`, `nl`; 0 when one face is degenerate.
inline double dihedral_angle_from_normals(const Eigen::Vector3d& nk, const Eigen::Vector3d& nl)
{
  const double s = nk.cross(nl).norm();
  const double c = -nk.dot(nl);
  if(s == 0 && c <= 0)
    return 0; // parallel normals of a flat tet, or a degenerate (zero) normal
  // atan2 keeps full relative precision for angles near 0 and 180 degrees,
  // where acos of a normalised dot product would not.
  return std::atan2(s, c);
}

// Faces opposite the two vertices that are not on edge e, for the edge order
// (0,1), (0,2), (0,3), (1,2), (1,3), (2,3).
constexpr int edge_opposite_faces[6][2] = {{2, 3}, {1, 3}, {1, 2}, {0, 3}, {0, 2}, {0, 1}};

/// the six dihedral angles (degrees) of the tet spanned by edge vectors a, b, c
inline std::array<double, 6> dihedral_angles_of_edge_vectors(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                                             const Eigen::Vector3d& c)
{
  Eigen::Vector3d n[4];
  face_normals(a, b, c, n);
  std::array<double, 6> angles;
  for(int e = 0; e < 6; ++e)
    angles[e] = radians_to_degrees() *
                dihedral_angle_from_normals(n[edge_opposite_faces[e][0]], n[edge_opposite_faces[e][1]]);
  return angles;
}

/// the minimum dihedral angle (degrees) of the tet spanned by edge vectors a, b, c
inline double minimum_dihedral_angle_of_edge_vectors(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                                     const Eigen::Vector3d& c)
{
  const std::array<double, 6> angles = dihedral_angles_of_edge_vectors(a, b, c);
  return *std::min_element(angles.begin(), angles.end());
}

/// `3 r / R` of the tet spanned by edge vectors a, b, c
inline double radius_ratio_of_edge_vectors(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                           const Eigen::Vector3d& c)
{
  // det = 6 V; inradius r = 3 V / S = |det| / sum|n_k| (|n_k| = twice the
  // face area); circumcentre offset from p0 = (|a|^2 b x c + |b|^2 c x a +
  // |c|^2 a x b) / (2 det), so R = |w| / (2 |det|).
  const double det = a.dot(b.cross(c));
  Eigen::Vector3d n[4];
  face_normals(a, b, c, n);
  const double area_sum = n[0].norm() + n[1].norm() + n[2].norm() + n[3].norm();
  const Eigen::Vector3d w = a.squaredNorm() * b.cross(c) + b.squaredNorm() * c.cross(a) + c.squaredNorm() * a.cross(b);
  const double denominator = area_sum * w.norm();
  if(!(denominator > 0) || det == 0)
    return 0;
  const double ratio = 6 * det * det / denominator;
  return std::min(ratio, 1.0); // 1 is the supremum; clamp rounding above it
}

/// `12 (3|V|)^(2/3) / sum l^2` of the tet spanned by edge vectors a, b, c
inline double mean_ratio_of_edge_vectors(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                         const Eigen::Vector3d& c)
{
  const double three_v = std::abs(a.dot(b.cross(c))) / 2; // 3 |V|
  const double sum_l2 = a.squaredNorm() + b.squaredNorm() + c.squaredNorm() + (b - a).squaredNorm() +
                        (c - a).squaredNorm() + (c - b).squaredNorm();
  if(!(sum_l2 > 0) || three_v == 0)
    return 0;
  return std::min(12 * std::cbrt(three_v * three_v) / sum_l2, 1.0);
}

/// Below these values a result may be rounding noise of a flat tet: the
/// exact coplanarity test decides.
constexpr double suspicious_angle_degrees() { return 1e-4; }
constexpr double suspicious_ratio() { return 1e-6; }

/// exact: the four points (as doubles) are coplanar
inline bool is_exactly_coplanar(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                                const Eigen::Vector3d& p3)
{
  typedef CGAL::Exact_predicates_inexact_constructions_kernel::Point_3 Point;
  return CGAL::orientation(Point(p0[0], p0[1], p0[2]), Point(p1[0], p1[1], p1[2]), Point(p2[0], p2[1], p2[2]),
                           Point(p3[0], p3[1], p3[2])) == CGAL::COPLANAR;
}

/// snaps the angles of an exactly flat tet to 0 or 180
inline std::array<double, 6> snap_flat_angles(std::array<double, 6> angles, const Eigen::Vector3d& p0,
                                              const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                                              const Eigen::Vector3d& p3)
{
  const double smallest = *std::min_element(angles.begin(), angles.end());
  if(smallest < suspicious_angle_degrees() && is_exactly_coplanar(p0, p1, p2, p3))
    for(double& a : angles)
      a = a < 90 ? 0.0 : 180.0;
  return angles;
}

inline double snap_flat_angle(double smallest, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                              const Eigen::Vector3d& p2, const Eigen::Vector3d& p3)
{
  if(smallest < suspicious_angle_degrees() && smallest > 0 && is_exactly_coplanar(p0, p1, p2, p3))
    return 0;
  return smallest;
}

inline double snap_flat_ratio(double ratio, const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                              const Eigen::Vector3d& p2, const Eigen::Vector3d& p3)
{
  if(ratio < suspicious_ratio() && ratio > 0 && is_exactly_coplanar(p0, p1, p2, p3))
    return 0;
  return ratio;
}

} // namespace internal

/// \ingroup PkgBubbleMesh3Functions
/// \name Tetrahedron measures
/// @{

/// Euclidean signed volume `(p1-p0) . ((p2-p0) x (p3-p0)) / 6`; positive for
/// a positively oriented tet. It is a floating-point value: to decide whether
/// a tet is inverted use `CGAL::orientation` (exact with Epick).
inline double signed_volume(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                            const Eigen::Vector3d& p3)
{
  return (p1 - p0).dot((p2 - p0).cross(p3 - p0)) / 6;
}

/// signed volume in the metric `m`: `sqrt(det M) * signed_volume(p0, p1, p2, p3)`
inline double metric_signed_volume(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                                   const Eigen::Vector3d& p3, const Metric_3& m)
{
  return m.sqrt_determinant() * signed_volume(p0, p1, p2, p3);
}

/// the six Euclidean dihedral angles, in degrees, in the edge order
/// (0,1), (0,2), (0,3), (1,2), (1,3), (2,3); each in [0, 180]
inline std::array<double, 6> dihedral_angles(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                             const Eigen::Vector3d& p2, const Eigen::Vector3d& p3)
{
  return internal::snap_flat_angles(internal::dihedral_angles_of_edge_vectors(p1 - p0, p2 - p0, p3 - p0), p0, p1,
                                    p2, p3);
}

/// the six dihedral angles, in degrees, after mapping the vertices by `Q`
/// (`m.matrix() = Q^T Q`): the paper's anisotropic dihedral angles. Same edge
/// order as `dihedral_angles()`.
inline std::array<double, 6> metric_dihedral_angles(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                                    const Eigen::Vector3d& p2, const Eigen::Vector3d& p3,
                                                    const Metric_3& m)
{
  const std::array<Eigen::Vector3d, 3> e = internal::metric_edge_vectors(p0, p1, p2, p3, m);
  return internal::snap_flat_angles(internal::dihedral_angles_of_edge_vectors(e[0], e[1], e[2]), p0, p1, p2, p3);
}

/// smallest Euclidean dihedral angle, in degrees: `acos(1/3) = 70.53` for the
/// regular tet (the largest possible value), 0 for a flat tet
inline double minimum_dihedral_angle(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                                     const Eigen::Vector3d& p3)
{
  return internal::snap_flat_angle(internal::minimum_dihedral_angle_of_edge_vectors(p1 - p0, p2 - p0, p3 - p0), p0,
                                   p1, p2, p3);
}

/// smallest dihedral angle in the metric `m`, in degrees (the paper's
/// quality measure, section 6, with `m` the metric at the centroid)
inline double metric_minimum_dihedral_angle(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                            const Eigen::Vector3d& p2, const Eigen::Vector3d& p3, const Metric_3& m)
{
  const std::array<Eigen::Vector3d, 3> e = internal::metric_edge_vectors(p0, p1, p2, p3, m);
  return internal::snap_flat_angle(internal::minimum_dihedral_angle_of_edge_vectors(e[0], e[1], e[2]), p0, p1, p2, p3);
}

/// Euclidean radius ratio `3 r / R` (inradius over circumradius, normalised):
/// 1 for the regular tet, in [0, 1), 0 for a flat tet
inline double radius_ratio(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                           const Eigen::Vector3d& p3)
{
  return internal::snap_flat_ratio(internal::radius_ratio_of_edge_vectors(p1 - p0, p2 - p0, p3 - p0), p0, p1, p2, p3);
}

/// radius ratio `3 r / R` in the metric `m`
inline double metric_radius_ratio(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                                  const Eigen::Vector3d& p3, const Metric_3& m)
{
  const std::array<Eigen::Vector3d, 3> e = internal::metric_edge_vectors(p0, p1, p2, p3, m);
  return internal::snap_flat_ratio(internal::radius_ratio_of_edge_vectors(e[0], e[1], e[2]), p0, p1, p2, p3);
}

/// Euclidean mean ratio `12 (3|V|)^(2/3) / sum of the six squared edge
/// lengths`: 1 for the regular tet, in [0, 1), 0 for a flat tet
inline double mean_ratio(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                         const Eigen::Vector3d& p3)
{
  return internal::snap_flat_ratio(internal::mean_ratio_of_edge_vectors(p1 - p0, p2 - p0, p3 - p0), p0, p1, p2, p3);
}

/// mean ratio in the metric `m`
inline double metric_mean_ratio(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                                const Eigen::Vector3d& p3, const Metric_3& m)
{
  const std::array<Eigen::Vector3d, 3> e = internal::metric_edge_vectors(p0, p1, p2, p3, m);
  return internal::snap_flat_ratio(internal::mean_ratio_of_edge_vectors(e[0], e[1], e[2]), p0, p1, p2, p3);
}

/// @}

/// \name Edge measures
/// @{

/// length of the edge `pq` in the single metric `m`: `sqrt((q-p)^T M (q-p))`
inline double metric_edge_length(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Metric_3& m)
{
  return m.length(q - p);
}

/// Variant (a): mean of the lengths of `pq` in the metrics of its two end
/// points, `(|q-p|_{M_p} + |q-p|_{M_q}) / 2`. Exact for a constant metric;
/// second-order accurate for a smooth field (what the quality report uses,
/// since it needs one field evaluation per vertex only).
inline double metric_edge_length(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Metric_3& m_p,
                                 const Metric_3& m_q)
{
  const Eigen::Vector3d v = q - p;
  return 0.5 * (m_p.length(v) + m_q.length(v));
}

/// Variant (b): the Riemannian length of the straight segment `pq`,
/// `integral_0^1 sqrt(v^T M(p + t v) v) dt` with `v = q - p`, by composite
/// 3-point Gauss-Legendre quadrature on `number_of_segments` equal pieces
/// (`3 * number_of_segments` evaluations of `field`, never at the end
/// points). The quadrature is exact for integrands of degree 5 per piece;
/// its error decreases as `number_of_segments^-6` for smooth fields.
/// `field` is a model of `MetricField_3`; its `Point_3` is built from doubles.
/// Throws `Invalid_input` if `number_of_segments < 1`.
template <typename MetricField_3>
double integrated_metric_edge_length(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const MetricField_3& field,
                                     int number_of_segments = 8)
{
  typedef typename MetricField_3::Point_3 Point_3;
  if(number_of_segments < 1)
    throw Invalid_input("integrated_metric_edge_length: number_of_segments must be at least 1, got " +
                        std::to_string(number_of_segments));
  // Gauss-Legendre nodes on [0, 1]: 1/2 -+ sqrt(3/5)/2, weights 5/18, 8/18, 5/18.
  static constexpr double half_offset = 0.38729833462074168851792653997824; // sqrt(3/5)/2
  const double nodes[3] = {0.5 - half_offset, 0.5, 0.5 + half_offset};
  const double weights[3] = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};
  const Eigen::Vector3d v = q - p;
  const double h = 1.0 / number_of_segments;
  double sum = 0;
  for(int s = 0; s < number_of_segments; ++s) {
    double piece = 0;
    for(int g = 0; g < 3; ++g) {
      const double t = (s + nodes[g]) * h;
      const Eigen::Vector3d x = p + t * v;
      const auto& m = field(Point_3(x[0], x[1], x[2]));
      piece += weights[g] * m.length(v);
    }
    sum += piece;
  }
  return sum * h;
}

/// @}

// Thin overloads for `std::array<double, 3>` and CGAL points (anything with
// x(), y(), z()), forwarding to the `Eigen::Vector3d` versions.

template <typename Point_>
double signed_volume(const Point_& p0, const Point_& p1, const Point_& p2, const Point_& p3)
{
  return signed_volume(internal::to_vector_3(p0), internal::to_vector_3(p1), internal::to_vector_3(p2),
                       internal::to_vector_3(p3));
}

template <typename Point_>
double metric_signed_volume(const Point_& p0, const Point_& p1, const Point_& p2, const Point_& p3,
                            const Metric_3& m)
{
  return metric_signed_volume(internal::to_vector_3(p0), internal::to_vector_3(p1), internal::to_vector_3(p2),
                              internal::to_vector_3(p3), m);
}

template <typename Point_>
std::array<double, 6> dihedral_angles(const Point_& p0, const Point_& p1, const Point_& p2, const Point_& p3)
{
  return dihedral_angles(internal::to_vector_3(p0), internal::to_vector_3(p1), internal::to_vector_3(p2),
                         internal::to_vector_3(p3));
}

template <typename Point_>
std::array<double, 6> metric_dihedral_angles(const Point_& p0, const Point_& p1, const Point_& p2, const Point_& p3,
                                             const Metric_3& m)
{
  return metric_dihedral_angles(internal::to_vector_3(p0), internal::to_vector_3(p1), internal::to_vector_3(p2),
                                internal::to_vector_3(p3), m);
}

template <typename Point_>
double minimum_dihedral_angle(const Point_& p0, const Point_& p1, const Point_& p2, const Point_& p3)
{
  return minimum_dihedral_angle(internal::to_vector_3(p0), internal::to_vector_3(p1), internal::to_vector_3(p2),
                                internal::to_vector_3(p3));
}

template <typename Point_>
double metric_minimum_dihedral_angle(const Point_& p0, const Point_& p1, const Point_& p2, const Point_& p3,
                                     const Metric_3& m)
{
  return metric_minimum_dihedral_angle(internal::to_vector_3(p0), internal::to_vector_3(p1),
                                       internal::to_vector_3(p2), internal::to_vector_3(p3), m);
}

template <typename Point_>
double radius_ratio(const Point_& p0, const Point_& p1, const Point_& p2, const Point_& p3)
{
  return radius_ratio(internal::to_vector_3(p0), internal::to_vector_3(p1), internal::to_vector_3(p2),
                      internal::to_vector_3(p3));
}

template <typename Point_>
double metric_radius_ratio(const Point_& p0, const Point_& p1, const Point_& p2, const Point_& p3, const Metric_3& m)
{
  return metric_radius_ratio(internal::to_vector_3(p0), internal::to_vector_3(p1), internal::to_vector_3(p2),
                             internal::to_vector_3(p3), m);
}

template <typename Point_>
double mean_ratio(const Point_& p0, const Point_& p1, const Point_& p2, const Point_& p3)
{
  return mean_ratio(internal::to_vector_3(p0), internal::to_vector_3(p1), internal::to_vector_3(p2),
                    internal::to_vector_3(p3));
}

template <typename Point_>
double metric_mean_ratio(const Point_& p0, const Point_& p1, const Point_& p2, const Point_& p3, const Metric_3& m)
{
  return metric_mean_ratio(internal::to_vector_3(p0), internal::to_vector_3(p1), internal::to_vector_3(p2),
                           internal::to_vector_3(p3), m);
}

template <typename Point_>
double metric_edge_length(const Point_& p, const Point_& q, const Metric_3& m)
{
  return metric_edge_length(internal::to_vector_3(p), internal::to_vector_3(q), m);
}

template <typename Point_>
double metric_edge_length(const Point_& p, const Point_& q, const Metric_3& m_p, const Metric_3& m_q)
{
  return metric_edge_length(internal::to_vector_3(p), internal::to_vector_3(q), m_p, m_q);
}

template <typename Point_, typename MetricField_3>
double integrated_metric_edge_length(const Point_& p, const Point_& q, const MetricField_3& field,
                                     int number_of_segments = 8)
{
  return integrated_metric_edge_length(internal::to_vector_3(p), internal::to_vector_3(q), field,
                                       number_of_segments);
}

} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_METRIC_QUALITY_H
