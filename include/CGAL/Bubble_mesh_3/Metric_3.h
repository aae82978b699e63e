// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_METRIC_3_H
#define CGAL_BUBBLE_MESH_3_METRIC_3_H

#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/number_utils.h>

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {

/// \ingroup PkgBubbleMesh3Classes
/// A Riemannian metric at one point: a symmetric positive definite 3x3
/// matrix `M`, together with a factor `Q` such that `M = Q^T Q`.
///
/// The metric length of a vector `v` is `sqrt(v^T M v)`; the unit bubble of
/// the metric centred at `p` is the ellipsoid `{x : (x-p)^T M (x-p) <= 1}`,
/// whose semi-axes are the principal sizes `h_i = 1/sqrt(lambda_i)` along the
/// eigenvectors of `M`. Mapping points by `Q` turns that ellipsoid into the
/// unit sphere, which is how the paper measures quality "in the metric".
///
/// `Q` is the upper-triangular Cholesky factor (positive diagonal, so
/// `det Q > 0`). Any other factor differs from it by a rotation, so every
/// quantity the package computes after mapping by `Q` (lengths, angles,
/// volumes) does not depend on the choice. Exact predicates never use `Q`:
/// they take the six entries of `M` (see `Anisotropic_advancing_front_traits_3`).
///
/// Every constructor that takes user values validates them and throws
/// `Invalid_metric` when they are not finite, not symmetric, not positive
/// definite, or more anisotropic than `maximum_eigenvalue_ratio()`.
class Metric_3 {
public:
  typedef Eigen::Matrix3d Matrix;
  typedef Eigen::Vector3d Vector;

  /// The largest accepted ratio lambda_max / lambda_min (a size ratio of
  /// 1e6 between the longest and the shortest axis). Beyond it double
  /// arithmetic on metric lengths loses every significant digit.
  static constexpr double maximum_eigenvalue_ratio() { return 1e12; }

  /// the identity metric (unit size, isotropic)
  Metric_3() : m_(Matrix::Identity()), q_(Matrix::Identity()) {}

  /// validates `m` and stores it. `where` is prepended to error messages
  /// (e.g. "bg.sol, vertex 12").
  explicit Metric_3(const Matrix& m, const std::string& where = std::string())
  {
    set(m, where);
  }

  /// from the six independent entries of a symmetric matrix
  static Metric_3 from_entries(double m11, double m12, double m13, double m22,
                               double m23, double m33,
                               const std::string& where = std::string())
  {
    Matrix m;
    m << m11, m12, m13, m12, m22, m23, m13, m23, m33;
    return Metric_3(m, where);
  }

  /// isotropic metric of size `h`: `M = I / h^2`
  static Metric_3 isotropic(double h, const std::string& where = std::string())
  {
    if(!(std::isfinite(h) && h > 0))
      throw Invalid_metric(prefix(where) + "isotropic size must be finite and positive, got " + to_string(h));
    return Metric_3(Matrix::Identity() / (h * h), where);
  }

  /// `M = R diag(1/h_u^2, 1/h_v^2, 1/h_w^2) R^T` where the columns of `R` are
  /// the principal directions u, v, w (orthonormalised here) and `sizes` the
  /// wanted element sizes along them.
  static Metric_3 from_directions_and_sizes(const Matrix& directions, const Vector& sizes,
                                            const std::string& where = std::string())
  {
    for(int i = 0; i < 3; ++i)
      if(!(std::isfinite(sizes[i]) && sizes[i] > 0))
        throw Invalid_metric(prefix(where) + "principal size " + std::to_string(i) +
                             " must be finite and positive, got " + to_string(sizes[i]));
    if(!directions.allFinite() || std::abs(directions.determinant()) < 1e-12 * std::max(1.0, directions.norm()))
      throw Invalid_metric(prefix(where) + "principal directions are not finite and independent");
    // Orthonormalise so that slightly non-orthogonal user input still gives
    // the intended ellipsoid axes.
    Eigen::HouseholderQR<Matrix> qr(directions);
    Matrix r = qr.householderQ();
    for(int i = 0; i < 3; ++i)
      if(r.col(i).dot(directions.col(i)) < 0)
        r.col(i) = -r.col(i);
    Vector lambda = sizes.cwiseProduct(sizes).cwiseInverse();
    Matrix m = r * lambda.asDiagonal() * r.transpose();
    return Metric_3(Matrix(0.5 * (m + m.transpose())), where);
  }

  /// the symmetric positive definite matrix `M`
  const Matrix& matrix() const { return m_; }

  /// entry (i, j) of `M`
  double operator()(int i, int j) const { return m_(i, j); }

  /// upper-triangular factor with positive diagonal, `M = Q^T Q`
  const Matrix& Q() const { return q_; }

  /// inverse of `Q`: maps the unit sphere onto the metric's unit ellipsoid
  Matrix Q_inverse() const
  {
    return q_.triangularView<Eigen::Upper>().solve(Matrix::Identity());
  }

  /// the six independent entries m11 m12 m13 m22 m23 m33 (row-major upper triangle)
  std::array<double, 6> entries() const
  {
    return {{m_(0, 0), m_(0, 1), m_(0, 2), m_(1, 1), m_(1, 2), m_(2, 2)}};
  }

  /// `v^T M v`
  double squared_length(const Vector& v) const { return v.dot(m_ * v); }
  /// metric length `sqrt(v^T M v)`
  double length(const Vector& v) const { return std::sqrt(squared_length(v)); }

  /// metric length of a CGAL vector (anything with x(), y(), z())
  template <typename Vector_3>
  double length_of(const Vector_3& v) const
  {
    return length(Vector(CGAL::to_double(v.x()), CGAL::to_double(v.y()), CGAL::to_double(v.z())));
  }

  /// `Q v`: the image of a vector (or of a point, as a position vector) in
  /// the space where the metric is Euclidean
  Vector map(const Vector& v) const { return q_.triangularView<Eigen::Upper>() * v; }

  /// `det M`
  double determinant() const
  {
    const double d = q_(0, 0) * q_(1, 1) * q_(2, 2);
    return d * d;
  }
  /// `sqrt(det M) = det Q`: the number of unit bubbles per unit volume, up
  /// to the bubble volume constant
  double sqrt_determinant() const { return q_(0, 0) * q_(1, 1) * q_(2, 2); }

  /// eigenvalues of `M`, ascending, and the matching unit eigenvectors as
  /// columns of `directions`
  void eigen_decomposition(Vector& eigenvalues, Matrix& directions) const
  {
    Eigen::SelfAdjointEigenSolver<Matrix> es(m_);
    eigenvalues = es.eigenvalues();
    directions = es.eigenvectors();
  }

  /// principal sizes `h_i = 1/sqrt(lambda_i)`, descending (longest axis first),
  /// matching the columns of `principal_directions()`
  Vector principal_sizes() const
  {
    Vector l;
    Matrix r;
    eigen_decomposition(l, r);
    return Vector(1 / std::sqrt(l[0]), 1 / std::sqrt(l[1]), 1 / std::sqrt(l[2]));
  }
  /// unit principal directions as columns, longest axis first
  Matrix principal_directions() const
  {
    Vector l;
    Matrix r;
    eigen_decomposition(l, r);
    return r;
  }

  /// ratio of the longest to the shortest principal size (1 when isotropic)
  double anisotropy_ratio() const
  {
    Vector h = principal_sizes();
    return h.maxCoeff() / h.minCoeff();
  }

  /// matrix logarithm `R diag(log lambda) R^T` (symmetric, any sign)
  Matrix log() const
  {
    Vector l;
    Matrix r;
    eigen_decomposition(l, r);
    return r * l.array().log().matrix().asDiagonal() * r.transpose();
  }

  /// matrix exponential of a symmetric matrix: always SPD. Only the
  /// anisotropy bound can fail, which is checked on the eigenvalues at hand
  /// (this is the hot path of interpolated fields: one eigen solve, one LLT).
  static Metric_3 exp(const Matrix& symmetric, const std::string& where = std::string())
  {
    return exp(symmetric, where.c_str());
  }

  /// as above; `where` is only turned into a string for an error message
  static Metric_3 exp(const Matrix& symmetric, const char* where)
  {
    if(!symmetric.allFinite())
      throw Invalid_metric(prefix(where) + "logarithm of the metric is not finite");
    // One eigen solve and one LLT: this is the hot path of interpolated
    // fields. Eigen's closed-form 3x3 solver (computeDirect) took a third
    // fewer instructions here but loses digits near repeated eigenvalues,
    // the common case of boundary-layer metrics (1e-7 relative to the metric
    // at a 1:10 size ratio; this solver: 1e-13); exact Jacobi polishing or a
    // Taylor series with scaling and squaring cost as much as this solver.
    Eigen::SelfAdjointEigenSolver<Matrix> es(0.5 * (symmetric + symmetric.transpose()));
    const Vector& l = es.eigenvalues(); // ascending
    if(!(l[2] - l[0] <= std::log(maximum_eigenvalue_ratio())) || !(std::abs(l[2]) < 700 && std::abs(l[0]) < 700))
      throw Invalid_metric(prefix(where) + "metric is too anisotropic or out of range: log-eigenvalues " +
                           to_string(l[0]) + " .. " + to_string(l[2]));
    const Matrix& r = es.eigenvectors();
    const Matrix m = r * l.array().exp().matrix().asDiagonal() * r.transpose();
    Metric_3 result;
    result.m_ = 0.5 * (m + m.transpose());
    Eigen::LLT<Matrix> llt(result.m_);
    if(llt.info() != Eigen::Success)
      throw Invalid_metric(prefix(where) + "exponential is not positive definite " + to_string(result.m_));
    result.q_ = llt.matrixU();
    return result;
  }

  bool operator==(const Metric_3& other) const { return m_ == other.m_; }
  bool operator!=(const Metric_3& other) const { return !(*this == other); }

  /// throws `Invalid_metric` (message prefixed by `where`) unless `m` is a
  /// finite, symmetric, positive definite matrix within the anisotropy bound
  static void validate(const Matrix& m, const std::string& where = std::string())
  {
    Matrix q;
    check_and_factor(m, where, q);
  }

private:
  static std::string prefix(const std::string& where)
  {
    return where.empty() ? std::string("metric: ") : where + ": ";
  }
  static std::string to_string(double x)
  {
    std::ostringstream os;
    os.precision(17);
    os << x;
    return os.str();
  }
  static std::string to_string(const Matrix& m)
  {
    std::ostringstream os;
    os.precision(6);
    os << "[" << m(0, 0) << " " << m(0, 1) << " " << m(0, 2) << "; " << m(1, 0) << " " << m(1, 1) << " "
       << m(1, 2) << "; " << m(2, 0) << " " << m(2, 1) << " " << m(2, 2) << "]";
    return os.str();
  }

  // Returns the symmetrised matrix and fills its upper Cholesky factor.
  static Matrix check_and_factor(const Matrix& m, const std::string& where, Matrix& q)
  {
    if(!m.allFinite())
      throw Invalid_metric(prefix(where) + "metric has a NaN or infinite entry " + to_string(m));
    const double scale = m.cwiseAbs().maxCoeff();
    if(!(scale > 0))
      throw Invalid_metric(prefix(where) + "metric is the zero matrix");
    for(int i = 0; i < 3; ++i)
      for(int j = i + 1; j < 3; ++j)
        if(std::abs(m(i, j) - m(j, i)) > 1e-9 * scale)
          throw Invalid_metric(prefix(where) + "metric is not symmetric " + to_string(m));
    Matrix s = 0.5 * (m + m.transpose());
    Eigen::LLT<Matrix> llt(s);
    Vector eigenvalues = Eigen::SelfAdjointEigenSolver<Matrix>(s, Eigen::EigenvaluesOnly).eigenvalues();
    if(llt.info() != Eigen::Success || !(eigenvalues[0] > 0))
      throw Invalid_metric(prefix(where) + "metric is not positive definite " + to_string(m) +
                           " (smallest eigenvalue " + to_string(eigenvalues[0]) + ")");
    if(eigenvalues[2] > maximum_eigenvalue_ratio() * eigenvalues[0])
      throw Invalid_metric(prefix(where) + "metric is too anisotropic: eigenvalue ratio " +
                           to_string(eigenvalues[2] / eigenvalues[0]) + " exceeds " +
                           to_string(maximum_eigenvalue_ratio()));
    q = llt.matrixU();
    return s;
  }

  void set(const Matrix& m, const std::string& where) { m_ = check_and_factor(m, where, q_); }

  Matrix m_;
  Matrix q_;
};

/// \ingroup PkgBubbleMesh3Functions
/// Log-Euclidean weighted mean `exp(sum_i w_i log M_i)` of metrics. Weights
/// are normalised to sum 1 (they must be non-negative, not all zero). It
/// reproduces `M_i` exactly when one weight is 1 and the others 0, and its
/// determinant is the weighted geometric mean of the determinants, so
/// interpolated sizes never swell as with linear interpolation.
template <typename MetricRange, typename WeightRange>
Metric_3 log_euclidean_interpolation(const MetricRange& metrics, const WeightRange& weights)
{
  Metric_3::Matrix sum = Metric_3::Matrix::Zero();
  double total = 0;
  auto w = std::begin(weights);
  const Metric_3* only = nullptr;
  int nonzero = 0;
  for(const Metric_3& m : metrics) {
    if(w == std::end(weights))
      throw Invalid_input("log_euclidean_interpolation: fewer weights than metrics");
    const double wi = *w++;
    if(!(std::isfinite(wi) && wi >= 0))
      throw Invalid_input("log_euclidean_interpolation: weights must be finite and non-negative");
    if(wi == 0)
      continue;
    ++nonzero;
    only = &m;
    sum += wi * m.log();
    total += wi;
  }
  if(!(total > 0))
    throw Invalid_input("log_euclidean_interpolation: weights sum to zero");
  if(nonzero == 1)
    return *only; // exact at the data points
  return Metric_3::exp(sum / total, "log-Euclidean interpolation");
}

/// Log-Euclidean weighted mean of precomputed logarithms (the hot path of
/// interpolated fields, which store `log M` per vertex).
template <int N>
Metric_3 log_euclidean_interpolation_of_logs(const std::array<const Metric_3::Matrix*, N>& logs,
                                             const std::array<double, N>& weights)
{
  Metric_3::Matrix sum = Metric_3::Matrix::Zero();
  double total = 0;
  for(int i = 0; i < N; ++i) {
    sum += weights[i] * (*logs[i]);
    total += weights[i];
  }
  return Metric_3::exp(sum / total, "log-Euclidean interpolation");
}

/// \ingroup PkgBubbleMesh3Functions
/// Metric intersection (simultaneous reduction): the largest metric whose
/// unit ellipsoid lies inside both unit ellipsoids, i.e. it asks for the
/// smaller size in every direction. Commutative, and `intersection(M, M) == M`.
inline Metric_3 intersection(const Metric_3& a, const Metric_3& b)
{
  // Generalised eigenvectors P of (B, A) with P^T A P = I, P^T B P = diag(mu).
  Eigen::GeneralizedSelfAdjointEigenSolver<Metric_3::Matrix> ges(b.matrix(), a.matrix());
  const Metric_3::Matrix& p = ges.eigenvectors();
  Metric_3::Vector mu = ges.eigenvalues().cwiseMax(1.0);
  Metric_3::Matrix p_inv = p.inverse();
  Metric_3::Matrix m = p_inv.transpose() * mu.asDiagonal() * p_inv;
  return Metric_3(Metric_3::Matrix(0.5 * (m + m.transpose())), "metric intersection");
}

} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_METRIC_3_H
