// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_HESSIAN_METRIC_FIELD_3_H
#define CGAL_HESSIAN_METRIC_FIELD_3_H

#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/parameters.h>
#include <CGAL/Bubble_mesh_3/recover_hessians.h>
#include <CGAL/Graded_metric_field_3.h>
#include <CGAL/Interpolated_metric_field_3.h>
#include <CGAL/Realizable_metric_field_3.h>
#include <CGAL/Named_function_parameters.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace CGAL {

namespace Bubble_mesh_3 {
namespace internal {

// The mean over a tet of exp(a), a linear with values `a` at its vertices:
// 3! times the divided difference of exp at the four values, summed as
// exp(min) sum_k h_k(d) 3! / (k + 3)! with d = a - min and h_k the complete
// homogeneous symmetric polynomials (stable for equal values, where the
// textbook quotient formula cancels); spreads above 16 are first halved by
// midpoint subdivision (8 equal children) to keep the terms in range.
// exp(mean) alone missed 9 % of a tanh layer thinner than the tets.
inline double mean_exp_over_tet(const std::array<double, 4>& a)
{
  const double lo = (std::min)((std::min)(a[0], a[1]), (std::min)(a[2], a[3]));
  const double hi = (std::max)((std::max)(a[0], a[1]), (std::max)(a[2], a[3]));
  if(hi - lo > 16) {
    auto mid = [&](int i, int j) { return 0.5 * (a[std::size_t(i)] + a[std::size_t(j)]); };
    const double m01 = mid(0, 1), m02 = mid(0, 2), m03 = mid(0, 3), m12 = mid(1, 2), m13 = mid(1, 3),
                 m23 = mid(2, 3);
    // four corner tets, and the inner octahedron cut along m02-m13
    const std::array<double, 4> children[8] = {{{a[0], m01, m02, m03}}, {{m01, a[1], m12, m13}},
                                               {{m02, m12, a[2], m23}}, {{m03, m13, m23, a[3]}},
                                               {{m02, m13, m01, m03}}, {{m02, m13, m03, m23}},
                                               {{m02, m13, m23, m12}}, {{m02, m13, m12, m01}}};
    double sum = 0;
    for(const auto& c : children)
      sum += mean_exp_over_tet(c);
    return sum / 8;
  }
  const double d[4] = {a[0] - lo, a[1] - lo, a[2] - lo, a[3] - lo};
  // h[j]: h_k of the first j values, updated from k - 1 to k
  double h[5] = {1, 1, 1, 1, 1};
  double sum = 1, coefficient = 1; // 3! / (k + 3)!
  for(int k = 1; k < 200; ++k) {
    h[0] = 0;
    for(int j = 1; j <= 4; ++j)
      h[j] = h[j - 1] + d[j - 1] * h[j];
    coefficient /= (k + 3);
    const double term = coefficient * h[4];
    sum += term;
    if(k > hi - lo && term <= 1e-17 * sum)
      break;
  }
  return std::exp(lo) * sum;
}

} // namespace internal
} // namespace Bubble_mesh_3

/// \ingroup PkgBubbleMesh3MetricFields
/// The metric of a scalar field's P1 interpolation error: from values at the
/// vertices of a tetrahedral mesh (a solution on the previous mesh of an
/// adaptation loop), or from a callable sampled there, the metric asking for
/// the mesh on which the field's piecewise linear interpolation is best.
///
/// 1. The Hessian `H_i` at each vertex is recovered by
///    `Bubble_mesh_3::recover_hessians()` (a least-squares quadratic fit on
///    the vertex's neighbours; exact for quadratics).
/// 2. Its absolute value `|H_i|` (same eigenvectors, absolute eigenvalues)
///    becomes the metric, in one of two ways:
///    - `interpolation_error(e)`: `M_i = (c / e) |H_i|` with `c = 9/32`, the
///      constant of the L-infinity bound of the P1 interpolation error on a
///      tetrahedron (Frey and Alauzet 2005): a mesh whose edges have unit
///      length in `M` interpolates the field to about `e`;
///    - `target_number_of_vertices(n)`: the metric minimising the L^p norm of
///      the interpolation error for that complexity (Loseille and Alauzet's
///      continuous mesh), `M_i = s det|H_i|^(-1/(2p+3)) |H_i|` with `p` given
///      by `error_norm(p)` (default 2) and the scale `s` chosen so that the
///      estimated vertex count, after the size bounds below, is `n`.
/// 3. Sizes are bounded to [`minimum_size`, `maximum_size`] (defaults: the
///    mesh's bounding box diagonal over 10^4 and over 10: where the field is
///    nearly linear, elements larger than that would not resolve the domain
///    and the pipeline's small-feature refinement adds nodes the vertex
///    estimate does not count: 10 % more on a unit box at the diagonal) and their
///    ratio at a point to `maximum_anisotropy` (default 1000); where the
///    field is linear (`H_i = 0`) the size is `maximum_size`.
/// 4. Between the vertices the metrics are interpolated log-Euclidean, by an
///    `Interpolated_metric_field_3` on the same mesh (outside it: the nearest
///    vertex's).
///
/// The estimated vertex count of a mesh of the background mesh's domain (by
/// `make_anisotropic_mesh_3()` with its defaults; on a unit box at 4,000 and
/// 15,000 vertices: -2 to +5 %, test `HessianField.TargetNumberOfVerticesIsMet`) is
/// `vertices_per_unit_metric_volume()` times the complexity
/// `C = integral of sqrt(det M)` over the mesh (the metric's volume in its
/// own units) plus `extra_vertices_per_unit_metric_area()` times the metric
/// area of its boundary (the faces of one tetrahedron only): the nodes
/// packed on a boundary come on top of the interior's.
///
/// Throws `Bubble_mesh_3::Invalid_input` for a bad mesh or values (see
/// `recover_hessians()`), for neither or both of `interpolation_error` and
/// `target_number_of_vertices`, for a non-positive or non-finite parameter,
/// and for a target the size bounds cannot reach (the message gives the
/// range they allow).
/// \cgalModels `MetricField_3`
template <typename K>
class Hessian_metric_field_3 {
public:
  typedef K Kernel;
  typedef typename K::FT FT;
  typedef typename K::Point_3 Point_3;
  typedef Bubble_mesh_3::Metric_3 Metric;
  typedef Metric::Matrix Matrix;
  typedef Metric::Vector Vector;

  /// the constant `c` of the L-infinity interpolation error bound in 3D
  static constexpr double interpolation_constant() { return 9.0 / 32.0; }
  /// mesh vertices per unit of metric volume inside the package's meshes
  /// (about the density of a face-centred cubic packing of unit spheres,
  /// sqrt(2)); fitted with `extra_vertices_per_unit_metric_area()` to the
  /// isotropic unit cube at 1,867, 13,054 and 41,975 vertices (to 0.1 %)
  static constexpr double vertices_per_unit_metric_volume() { return 1.40; }
  /// the boundary's extra vertices per unit of its metric area
  static constexpr double extra_vertices_per_unit_metric_area() { return 0.78; }

  /// Builds the field from the mesh `mesh` (its points and tetrahedra) and the
  /// field's value at each of its vertices. Named parameters:
  /// `interpolation_error` or `target_number_of_vertices` (one of them),
  /// `error_norm`, `minimum_size`, `maximum_size`, `maximum_anisotropy`.
  template <typename NamedParameters = CGAL::parameters::Default_named_parameters>
  Hessian_metric_field_3(const Bubble_mesh_3::Indexed_tet_mesh_3& mesh, const std::vector<double>& values,
                         const NamedParameters& np = CGAL::parameters::default_values(),
                         const std::string& name = "Hessian metric")
    : data_(build(mesh, Bubble_mesh_3::recover_hessians(mesh, values, name), np, name)),
      field_(mesh, data_->metrics, name)
  {}

  /// Builds the field from Hessians already recovered at the vertices of
  /// `mesh` (e.g. `hessians()` of another field of the same values, to
  /// rescale it without fitting again); same named parameters.
  template <typename NamedParameters = CGAL::parameters::Default_named_parameters>
  static Hessian_metric_field_3 from_hessians(const Bubble_mesh_3::Indexed_tet_mesh_3& mesh,
                                              std::vector<Matrix> hessians,
                                              const NamedParameters& np = CGAL::parameters::default_values(),
                                              const std::string& name = "Hessian metric")
  {
    if(hessians.size() != mesh.points.size())
      throw Bubble_mesh_3::Invalid_input(name + ": " + std::to_string(hessians.size()) + " Hessians for " +
                                         std::to_string(mesh.points.size()) + " vertices");
    return Hessian_metric_field_3(build(mesh, std::move(hessians), np, name), mesh, name);
  }

  /// samples `f` (a callable `double(const Point_3&)`) at the vertices of
  /// `mesh` and builds the field from those values
  template <typename F, typename NamedParameters = CGAL::parameters::Default_named_parameters>
  static Hessian_metric_field_3 from_function(const Bubble_mesh_3::Indexed_tet_mesh_3& mesh, const F& f,
                                              const NamedParameters& np = CGAL::parameters::default_values())
  {
    std::vector<double> values;
    values.reserve(mesh.points.size());
    for(const auto& p : mesh.points)
      values.push_back(double(f(Point_3(p[0], p[1], p[2]))));
    return Hessian_metric_field_3(mesh, values, np);
  }

  /// the metric at `p`
  Metric operator()(const Point_3& p) const { return field_(p); }

  /// the recovered Hessian at each vertex of the mesh
  const std::vector<Matrix>& hessians() const { return data_->hessians; }
  /// the metric at each vertex of the mesh
  const std::vector<Metric>& vertex_metrics() const { return data_->metrics; }
  /// the integral of `sqrt(det M)` over the mesh
  double complexity() const { return data_->complexity; }
  /// the metric area of the mesh's boundary
  double boundary_metric_area() const { return data_->boundary_area; }
  /// the vertex count of a mesh of the background mesh's domain in this
  /// metric (see the class description)
  double estimated_number_of_vertices() const { return vertex_estimate(data_->complexity, data_->boundary_area); }
  /// the interpolated field that evaluates the metric
  const Interpolated_metric_field_3<K>& interpolated_field() const { return field_; }
  /// with `target_number_of_vertices`: the smallest target the size bounds
  /// allow (every size at `maximum_size` where the Hessian allows it); 0 otherwise
  double smallest_target() const { return data_->least_vertices; }

  /// the vertex count of a mesh, in the metric given by `vertex_metrics` at
  /// the vertices of `mesh` (log-Euclidean in between), of `mesh`'s domain:
  /// the estimate `estimated_number_of_vertices()` makes for this field's own
  /// metrics, for others (e.g. the same field graded)
  static double estimated_number_of_vertices(const Bubble_mesh_3::Indexed_tet_mesh_3& mesh,
                                             const std::vector<Metric>& vertex_metrics)
  {
    if(vertex_metrics.size() != mesh.points.size())
      throw Bubble_mesh_3::Invalid_input("estimated_number_of_vertices: one metric per vertex is needed");
    std::vector<double> log_root_det;
    std::vector<Matrix> matrices;
    log_root_det.reserve(vertex_metrics.size());
    matrices.reserve(vertex_metrics.size());
    for(const Metric& m : vertex_metrics) {
      log_root_det.push_back(0.5 * std::log(m.determinant()));
      matrices.push_back(m.matrix());
    }
    return vertex_estimate(complexity(mesh, log_root_det), metric_area(mesh, boundary_faces(mesh), matrices));
  }

private:
  // |H| at a vertex: eigenvectors and absolute eigenvalues
  struct Absolute_hessian {
    Matrix frame;
    Vector values;
  };

  struct Bounds {
    double min_size, max_size, anisotropy, norm;
  };

  // the metric eigenvalues of scale `s` at a vertex (the size bounds applied)
  static Vector eigenvalues(const Absolute_hessian& h, double s, const Bounds& b)
  {
    const double top = h.values.maxCoeff();
    const double lo = 1 / (b.max_size * b.max_size), hi = 1 / (b.min_size * b.min_size);
    if(!(top > 0))
      return Vector::Constant(lo);
    const double r2 = b.anisotropy * b.anisotropy;
    // the anisotropy bound first, so that det|H| > 0 for the L^p factor
    Vector mu = h.values.cwiseMax(top / r2);
    double factor = 1;
    if(std::isfinite(b.norm))
      factor = std::pow(mu.prod(), -1 / (2 * b.norm + 3));
    Vector l = (s * factor * mu).cwiseMax(lo).cwiseMin(hi);
    return l.cwiseMax(l.maxCoeff() / r2);
  }

  // integral of sqrt(det M) over the mesh, log sqrt(det) linear in each tet
  // like the log-Euclidean metric's logarithm
  static double complexity(const Bubble_mesh_3::Indexed_tet_mesh_3& mesh, const std::vector<double>& log_root_det)
  {
    double total = 0;
    for(const auto& t : mesh.tets) {
      Eigen::Vector3d p[4];
      for(int k = 0; k < 4; ++k)
        p[k] = Eigen::Vector3d(mesh.points[std::size_t(t[k])][0], mesh.points[std::size_t(t[k])][1],
                               mesh.points[std::size_t(t[k])][2]);
      const double volume = std::abs((p[1] - p[0]).dot((p[2] - p[0]).cross(p[3] - p[0]))) / 6;
      total += volume * Bubble_mesh_3::internal::mean_exp_over_tet({{log_root_det[std::size_t(t[0])], log_root_det[std::size_t(t[1])],
                                   log_root_det[std::size_t(t[2])], log_root_det[std::size_t(t[3])]}});
    }
    return total;
  }

  static double vertex_estimate(double volume, double area)
  {
    return vertices_per_unit_metric_volume() * volume + extra_vertices_per_unit_metric_area() * area;
  }

  // the faces of one tet only
  static std::vector<std::array<int, 3>> boundary_faces(const Bubble_mesh_3::Indexed_tet_mesh_3& mesh)
  {
    std::vector<std::array<int, 3>> faces;
    faces.reserve(4 * mesh.tets.size());
    for(const auto& t : mesh.tets)
      for(int k = 0; k < 4; ++k) {
        std::array<int, 3> f{{t[(k + 1) % 4], t[(k + 2) % 4], t[(k + 3) % 4]}};
        std::sort(f.begin(), f.end());
        faces.push_back(f);
      }
    std::sort(faces.begin(), faces.end());
    std::vector<std::array<int, 3>> single;
    for(std::size_t i = 0; i < faces.size();) {
      std::size_t j = i;
      while(j < faces.size() && faces[j] == faces[i])
        ++j;
      if(j - i == 1)
        single.push_back(faces[i]);
      i = j;
    }
    return single;
  }

  // metric area of the faces, with the mean of their vertices' metrics
  static double metric_area(const Bubble_mesh_3::Indexed_tet_mesh_3& mesh, const std::vector<std::array<int, 3>>& faces,
                            const std::vector<Matrix>& metrics)
  {
    double total = 0;
    for(const auto& f : faces) {
      const Matrix m = (metrics[std::size_t(f[0])] + metrics[std::size_t(f[1])] + metrics[std::size_t(f[2])]) / 3;
      Vector p[3];
      for(int k = 0; k < 3; ++k)
        p[k] = Vector(mesh.points[std::size_t(f[k])][0], mesh.points[std::size_t(f[k])][1],
                      mesh.points[std::size_t(f[k])][2]);
      const Vector u = p[1] - p[0], v = p[2] - p[0];
      const double uu = u.dot(m * u), vv = v.dot(m * v), uv = u.dot(m * v);
      total += 0.5 * std::sqrt((std::max)(0.0, uu * vv - uv * uv));
    }
    return total;
  }

  // what the field computes once; copies share it (the pipeline copies fields)
  struct Data {
    std::vector<Matrix> hessians;
    std::vector<Metric> metrics;
    double complexity = 0;
    double boundary_area = 0;
    double least_vertices = 0; // the estimate with every size at the maximum (target mode)
  };

  template <typename NamedParameters>
  static std::shared_ptr<const Data> build(const Bubble_mesh_3::Indexed_tet_mesh_3& mesh,
                                           std::vector<Matrix> recovered, const NamedParameters& np,
                                           const std::string& name)
  {
    auto data = std::make_shared<Data>();
    data->hessians = std::move(recovered);
    const std::vector<Matrix>& hessians = data->hessians;
    namespace BNP = Bubble_mesh_3::internal_np;
    using parameters::choose_parameter;
    using parameters::get_parameter;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), up = -lo;
    for(const auto& p : mesh.points) {
      lo = lo.cwiseMin(Eigen::Vector3d(p[0], p[1], p[2]));
      up = up.cwiseMax(Eigen::Vector3d(p[0], p[1], p[2]));
    }
    const double diagonal = (up - lo).norm();
    const double error = choose_parameter(get_parameter(np, BNP::interpolation_error), nan);
    const double target = choose_parameter(get_parameter(np, BNP::target_number_of_vertices), nan);
    Bounds b;
    b.norm = choose_parameter(get_parameter(np, BNP::error_norm), 2.0);
    b.max_size = choose_parameter(get_parameter(np, BNP::maximum_size), diagonal / 10);
    b.min_size = choose_parameter(get_parameter(np, BNP::minimum_size), diagonal * 1e-4);
    b.anisotropy = choose_parameter(get_parameter(np, BNP::maximum_anisotropy), 1000.0);
    auto positive = [&](double v, const char* what) {
      if(!(v > 0) || !std::isfinite(v))
        throw Bubble_mesh_3::Invalid_input(name + ": " + what + " must be positive and finite, not " +
                                           std::to_string(v));
    };
    if(std::isnan(error) == std::isnan(target))
      throw Bubble_mesh_3::Invalid_input(name + ": give either interpolation_error or target_number_of_vertices");
    positive(b.max_size, "maximum_size");
    positive(b.min_size, "minimum_size");
    if(!(b.anisotropy >= 1) || !std::isfinite(b.anisotropy))
      throw Bubble_mesh_3::Invalid_input(name + ": maximum_anisotropy must be at least 1 and finite");
    if(!(b.min_size <= b.max_size))
      throw Bubble_mesh_3::Invalid_input(name + ": minimum_size is larger than maximum_size");
    if(!(b.norm >= 1))
      throw Bubble_mesh_3::Invalid_input(name + ": error_norm must be at least 1 (or infinity)");

    std::vector<Absolute_hessian> abs(hessians.size());
    for(std::size_t i = 0; i < hessians.size(); ++i) {
      Eigen::SelfAdjointEigenSolver<Matrix> es(hessians[i]);
      abs[i].frame = es.eigenvectors();
      abs[i].values = es.eigenvalues().cwiseAbs();
    }
    std::vector<double> log_root_det(abs.size());
    const std::vector<std::array<int, 3>> boundary = boundary_faces(mesh);
    std::vector<Matrix> at_vertex(abs.size());
    double area = 0;
    // complexity and boundary area at scale s (the area in `area`)
    auto complexity_of = [&](double s) {
      for(std::size_t i = 0; i < abs.size(); ++i) {
        const Vector l = eigenvalues(abs[i], s, b);
        log_root_det[i] = 0.5 * l.array().log().sum();
        at_vertex[i] = abs[i].frame * l.asDiagonal() * abs[i].frame.transpose();
      }
      area = metric_area(mesh, boundary, at_vertex);
      return complexity(mesh, log_root_det);
    };
    auto estimate_at = [&](double s) {
      const double c = complexity_of(s);
      return vertex_estimate(c, area);
    };

    double scale;
    if(!std::isnan(error)) {
      positive(error, "interpolation_error");
      b.norm = std::numeric_limits<double>::infinity(); // the L-infinity bound: M proportional to |H|
      scale = interpolation_constant() / error;
    } else {
      positive(target, "target_number_of_vertices");
      // the estimate grows with the scale from all-maximum to all-minimum sizes
      const double least = estimate_at(0), most = estimate_at(std::numeric_limits<double>::max());
      data->least_vertices = least;
      if(!(target >= least && target <= most))
        throw Bubble_mesh_3::Invalid_input(name + ": target_number_of_vertices " +
                                           std::to_string(std::llround(target)) +
                                           " is outside what the size bounds allow (" +
                                           std::to_string(std::llround(least)) + " to " +
                                           std::to_string(std::llround(most)) + ")");
      // bisection on log(scale), between scales that put every size at a bound
      double low = -700, high = 700;
      for(int it = 0; it < 200 && high - low > 1e-9; ++it) {
        const double mid = 0.5 * (low + high);
        (estimate_at(std::exp(mid)) < target ? low : high) = mid;
      }
      scale = std::exp(0.5 * (low + high));
    }
    data->complexity = complexity_of(scale);
    data->boundary_area = area;
    std::vector<Metric>& metrics = data->metrics;
    metrics.reserve(abs.size());
    for(std::size_t i = 0; i < abs.size(); ++i) {
      const Vector l = eigenvalues(abs[i], scale, b);
      metrics.push_back(Metric::from_directions_and_sizes(abs[i].frame, l.cwiseSqrt().cwiseInverse()));
    }
    return data;
  }

  Hessian_metric_field_3(std::shared_ptr<const Data> data, const Bubble_mesh_3::Indexed_tet_mesh_3& mesh,
                         const std::string& name)
    : data_(std::move(data)), field_(mesh, data_->metrics, name)
  {}

  std::shared_ptr<const Data> data_;
  Interpolated_metric_field_3<K> field_;
};

/// \ingroup PkgBubbleMesh3MetricFields
/// A Hessian field is interpolated from its mesh's vertices: the realizability
/// check is done once per vertex, as for `Interpolated_metric_field_3` (the
/// generic adaptor's five evaluations per query made meshing 10 times slower).
template <typename K>
Interpolated_metric_field_3<K> make_realizable_metric_field_3(const Hessian_metric_field_3<K>& field,
                                                              bool enabled = true)
{
  return make_realizable_metric_field_3(field.interpolated_field(), enabled);
}

/// \ingroup PkgBubbleMesh3MetricFields
/// The Hessian metric of `values` (one per vertex of `mesh`) graded with
/// `gradation` on `mesh` (`Graded_metric_field_3`). With
/// `target_number_of_vertices`, the graded field meets the target: gradation
/// only adds vertices, so the Hessian's target is lowered (a bracketed
/// secant search on its logarithm, the Hessians fitted once) until the graded
/// field's estimate is within 3 % of the target (at most 12 rounds; the
/// closest is kept), but not below the smallest target the size bounds allow: a
/// target too small for the graded field gives the smallest graded field
/// (its `Hessian_metric_field_3::estimated_number_of_vertices(mesh,
/// vertex_metrics())` says how many vertices it asks). Named parameters as
/// `Hessian_metric_field_3`.
template <typename K, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Graded_metric_field_3<Hessian_metric_field_3<K>>
make_graded_hessian_metric_field_3(const Bubble_mesh_3::Indexed_tet_mesh_3& mesh, const std::vector<double>& values,
                                   double gradation, const NamedParameters& np = CGAL::parameters::default_values(),
                                   const std::string& name = "Hessian metric")
{
  typedef Hessian_metric_field_3<K> Hessian;
  const double target = parameters::choose_parameter(
      parameters::get_parameter(np, Bubble_mesh_3::internal_np::target_number_of_vertices),
      std::numeric_limits<double>::quiet_NaN());
  const Hessian first(mesh, values, np, name);
  Graded_metric_field_3<Hessian> graded(first, mesh, gradation);
  if(std::isnan(target))
    return graded;
  auto estimate_of = [&](const Graded_metric_field_3<Hessian>& g) {
    return Hessian::estimated_number_of_vertices(mesh, g.vertex_metrics());
  };
  // the graded estimate grows with the Hessian's target: a search on
  // log(target) between a target giving too few and one giving too many
  // (secant steps, bisection when they leave the bracket)
  const double lowest = first.smallest_target() * (1 + 1e-9);
  double best_error = std::abs(std::log(estimate_of(graded) / target));
  double low = std::log(lowest), high = std::log(target), at = high;
  double f_at = std::log(estimate_of(graded) / target), f_low = std::numeric_limits<double>::quiet_NaN(), f_high = f_at;
  if(f_at <= 0)
    return graded; // gradation only adds vertices: at the target already
  for(int round = 0; round < 12 && best_error > std::log(1.03); ++round) {
    double next = at - f_at; // estimate roughly proportional to the target
    if(!std::isnan(f_low) && f_high != f_low)
      next = low - f_low * (high - low) / (f_high - f_low);
    if(!(next > low && next < high))
      next = std::isnan(f_low) ? low : 0.5 * (low + high);
    const Bubble_mesh_3::Named_function_parameters<double, Bubble_mesh_3::internal_np::target_number_of_vertices_t,
                                                   NamedParameters>
        lowered(std::exp(next), np);
    Graded_metric_field_3<Hessian> g(Hessian::from_hessians(mesh, first.hessians(), lowered, name), mesh, gradation);
    const double f = std::log(estimate_of(g) / target);
    if(std::abs(f) < best_error) {
      best_error = std::abs(f);
      graded = g;
    }
    at = next;
    f_at = f;
    if(f > 0) {
      high = next;
      f_high = f;
    } else {
      low = next;
      f_low = f;
    }
    if(std::isnan(f_low) && next <= std::log(lowest) * (1 + 1e-12))
      break; // even the smallest target asks too many: the smallest graded field
  }
  return graded;
}

} // namespace CGAL

#endif // CGAL_HESSIAN_METRIC_FIELD_3_H
