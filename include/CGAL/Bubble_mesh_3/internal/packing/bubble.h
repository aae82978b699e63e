// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Contract: the packer's working record of one bubble, and the small
// closed-form metric computations of the hot loop (no Eigen solvers, no
// allocation). A metric is cached per bubble as its six entries; the largest
// principal size `h_max` bounds the bubble's Euclidean extent.
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_BUBBLE_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_BUBBLE_H

#include <CGAL/Bubble_mesh_3/Metric_3.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {
namespace packing {

typedef Eigen::Vector3d Vec3;

/// symmetric matrix by its upper triangle m00 m01 m02 m11 m12 m22
struct Sym3 {
  double a00 = 1, a01 = 0, a02 = 0, a11 = 1, a12 = 0, a22 = 1;

  Sym3() = default;
  explicit Sym3(const Metric_3& m)
      : a00(m(0, 0)), a01(m(0, 1)), a02(m(0, 2)), a11(m(1, 1)), a12(m(1, 2)), a22(m(2, 2))
  {}

  /// d^T M d
  double squared_length(const Vec3& d) const
  {
    const double x = d[0], y = d[1], z = d[2];
    return a00 * x * x + a11 * y * y + a22 * z * z + 2 * (a01 * x * y + a02 * x * z + a12 * y * z);
  }
  double length(const Vec3& d) const { return std::sqrt(squared_length(d)); }

  Vec3 operator*(const Vec3& d) const
  {
    return Vec3(a00 * d[0] + a01 * d[1] + a02 * d[2], a01 * d[0] + a11 * d[1] + a12 * d[2],
                a02 * d[0] + a12 * d[1] + a22 * d[2]);
  }

  double determinant() const
  {
    return a00 * (a11 * a22 - a12 * a12) - a01 * (a01 * a22 - a12 * a02) + a02 * (a01 * a12 - a11 * a02);
  }

  Sym3 inverse() const
  {
    Sym3 r;
    const double det = determinant();
    r.a00 = (a11 * a22 - a12 * a12) / det;
    r.a01 = (a02 * a12 - a01 * a22) / det;
    r.a02 = (a01 * a12 - a02 * a11) / det;
    r.a11 = (a00 * a22 - a02 * a02) / det;
    r.a12 = (a01 * a02 - a00 * a12) / det;
    r.a22 = (a00 * a11 - a01 * a01) / det;
    return r;
  }

  /// largest eigenvalue (closed form, accurate relative to the norm)
  double largest_eigenvalue() const
  {
    const double p1 = a01 * a01 + a02 * a02 + a12 * a12;
    const double q = (a00 + a11 + a22) / 3;
    const double p2 = (a00 - q) * (a00 - q) + (a11 - q) * (a11 - q) + (a22 - q) * (a22 - q) + 2 * p1;
    if(!(p2 > 1e-30 * q * q))
      return std::max(a00, std::max(a11, a22));
    const double p = std::sqrt(p2 / 6);
    Sym3 b;
    b.a00 = (a00 - q) / p;
    b.a11 = (a11 - q) / p;
    b.a22 = (a22 - q) / p;
    b.a01 = a01 / p;
    b.a02 = a02 / p;
    b.a12 = a12 / p;
    const double r = std::clamp(b.determinant() / 2, -1.0, 1.0);
    return q + 2 * p * std::cos(std::acos(r) / 3);
  }

  /// upper Cholesky factor Q (M = Q^T Q), stored row-major
  Eigen::Matrix3d cholesky_upper() const
  {
    Eigen::Matrix3d q = Eigen::Matrix3d::Zero();
    q(0, 0) = std::sqrt(a00);
    q(0, 1) = a01 / q(0, 0);
    q(0, 2) = a02 / q(0, 0);
    q(1, 1) = std::sqrt(std::max(a11 - q(0, 1) * q(0, 1), 1e-300));
    q(1, 2) = (a12 - q(0, 1) * q(0, 2)) / q(1, 1);
    q(2, 2) = std::sqrt(std::max(a22 - q(0, 2) * q(0, 2) - q(1, 2) * q(1, 2), 1e-300));
    return q;
  }
  double sqrt_determinant() const { return std::sqrt(std::max(determinant(), 0.0)); }
};

/// largest principal size 1/sqrt(lambda_min(M)) = sqrt(lambda_max(M^-1)),
/// inflated by 0.1% against rounding (it only decides search radii)
inline double largest_principal_size(const Sym3& m)
{
  return 1.001 * std::sqrt(m.inverse().largest_eigenvalue());
}

/// The packer's working record of one bubble (internal).
struct Bubble_record {
  Vec3 x = Vec3::Zero();      // centre
  Vec3 v = Vec3::Zero();      // last displacement (the velocity times the time step)
  Vec3 n = Vec3::Zero();      // surface bubbles: unit normal of the face they lie on
  double step_scale = 1;      // factor of the force in the integrator (below 1 while it swings)
  Sym3 m;                     // metric at x (cached, refreshed with the neighbour lists)
  double h_max = 1;           // largest principal size of m
  double s = 0;               // curve bubbles: arc length from the curve start
  double clearance = 0;       // volume bubbles: Euclidean distance to the boundary known to be free
  int dimension = 3;          // 0 corner, 1 curve, 2 patch, 3 interior
  int entity = 0;             // slot of the corner / curve / patch / subdomain in the domain oracle
  bool fixed = false;         // does not move in the current stage
  bool gap_free = false;      // the last gap search around it found nothing...
  Vec3 probed_at = Vec3::Zero(); // ...from here
};

/// The normalized distance w = l / l0 of two bubbles: l0 = l_i + l_j with
/// l_i = (1/2) l / |d|_{M_i} the distance from centre i to the boundary of its
/// own bubble (metric ball of radius 1/2) along the segment. So
/// w = 2 a b / (a + b), the harmonic mean of the two metric lengths a, b of d.
inline double normalized_distance(double a, double b) { return (a + b > 0) ? 2 * a * b / (a + b) : 0.0; }

/// Two patch bubbles whose normals are within 25 degrees of opposite
/// (cosine below `opposite_sides_cosine`) lie on the two sides of a part
/// thinner than the metric's size (or of a thin gap between parts, or of a
/// wedge sharper than 25 degrees): each side's surface needs its own full
/// set of nodes, so such bubbles ignore each other (no force, no overlap, no
/// blocking of gaps) unless they are closer than a quarter of an element
/// (where the two sides of a crease that is not a feature curve meet, they
/// must not coincide). Otherwise the two sides' bubbles repel each other
/// across the part and population control deletes one of each close pair:
/// on the rotor's thin blades at a 1:3 metric, boundary edges 5.7 times the
/// metric's size and slivers spanning the blade. (Within 60 degrees, the
/// sides of the triceratops' 53-degree wedges crowded their edges: 14.5 ->
/// 5.0 degrees.)
constexpr double opposite_sides_cosine = -0.9;

inline bool on_opposite_sides(const Bubble_record& a, const Bubble_record& b)
{
  if(a.dimension != 2 || b.dimension != 2 || !(a.n.dot(b.n) < opposite_sides_cosine))
    return false;
  const Vec3 d = b.x - a.x;
  return normalized_distance(a.m.length(d), b.m.length(d)) >= 0.25;
}



/// Evaluates a MetricField_3 at internal points (thread-safe if the field is).
template <typename MetricField>
class Metric_refresh {
public:
  explicit Metric_refresh(const MetricField& field) : field_(field) {}
  Sym3 at(const Vec3& p) const
  {
    typedef typename MetricField::Point_3 Point_3;
    return Sym3(field_(Point_3(p[0], p[1], p[2])));
  }
  void operator()(Bubble_record& b) const
  {
    b.m = at(b.x);
    b.h_max = largest_principal_size(b.m);
  }

private:
  const MetricField& field_;
};

/// smallest principal size 1/sqrt(lambda_max(M))
inline double smallest_principal_size(const Sym3& m) { return 1 / std::sqrt(m.largest_eigenvalue()); }

/// x = Q^{-1} y for the upper-triangular Q
inline Vec3 solve_upper(const Eigen::Matrix3d& q, const Vec3& y)
{
  Vec3 x;
  x[2] = y[2] / q(2, 2);
  x[1] = (y[1] - q(1, 2) * x[2]) / q(1, 1);
  x[0] = (y[0] - q(0, 1) * x[1] - q(0, 2) * x[2]) / q(0, 0);
  return x;
}

/// A portable uniform double in [0, 1) from a 32-bit generator (std::mt19937
/// is specified bit-exactly by the standard; the distributions are not).
template <typename Generator>
double uniform_01(Generator& g)
{
  return double(g() & 0xffffffffu) / 4294967296.0;
}

} // namespace packing
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_BUBBLE_H
