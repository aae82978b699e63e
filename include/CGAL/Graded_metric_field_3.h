// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_GRADED_METRIC_FIELD_3_H
#define CGAL_GRADED_METRIC_FIELD_3_H

#include <CGAL/Bbox_3.h>
#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/recover_hessians.h>
#include <CGAL/Interpolated_metric_field_3.h>
#include <CGAL/Realizable_metric_field_3.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <deque>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace CGAL {

namespace Bubble_mesh_3 {
namespace internal {

/// A box split into `n` x `n` x `n` cubes of 6 tets each (Kuhn's
/// subdivision, all tets around the cube's main diagonal: conforming): the
/// background on which a field without a mesh of its own is graded.
inline Indexed_tet_mesh_3 box_tet_mesh(const CGAL::Bbox_3& box, int n)
{
  if(n < 1)
    throw Invalid_input("box_tet_mesh: at least one cell per axis");
  const double lo[3] = {box.xmin(), box.ymin(), box.zmin()}, hi[3] = {box.xmax(), box.ymax(), box.zmax()};
  for(int k = 0; k < 3; ++k)
    if(!(std::isfinite(lo[k]) && std::isfinite(hi[k]) && hi[k] > lo[k]))
      throw Invalid_input("box_tet_mesh: the box must be finite and have a positive extent along each axis");
  Indexed_tet_mesh_3 mesh;
  const int m = n + 1;
  for(int k = 0; k < m; ++k)
    for(int j = 0; j < m; ++j)
      for(int i = 0; i < m; ++i)
        mesh.points.push_back({{lo[0] + (hi[0] - lo[0]) * i / n, lo[1] + (hi[1] - lo[1]) * j / n,
                                lo[2] + (hi[2] - lo[2]) * k / n}});
  auto id = [m](int i, int j, int k) { return (k * m + j) * m + i; };
  // the six paths from corner 000 to corner 111 along the cube's edges
  const int paths[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for(int k = 0; k < n; ++k)
    for(int j = 0; j < n; ++j)
      for(int i = 0; i < n; ++i)
        for(const auto& path : paths) {
          std::array<int, 3> c = {{i, j, k}};
          std::array<int, 4> t;
          t[0] = id(c[0], c[1], c[2]);
          for(int s = 0; s < 3; ++s) {
            ++c[std::size_t(path[s])];
            t[std::size_t(s + 1)] = id(c[0], c[1], c[2]);
          }
          // odd permutations of the axes give negatively oriented tets
          const bool odd = (path[0] == 0 && path[1] == 2) || (path[0] == 1 && path[1] == 0) ||
                           (path[0] == 2 && path[1] == 1);
          if(odd)
            std::swap(t[2], t[3]);
          mesh.tets.push_back(t);
        }
  mesh.tet_refs.assign(mesh.tets.size(), 1);
  return mesh;
}

} // namespace internal
} // namespace Bubble_mesh_3

/// \ingroup PkgBubbleMesh3MetricFields
/// A metric field whose growth between points is bounded: anisotropic size
/// gradation in the metric space (Alauzet, "Size gradation control of
/// anisotropic meshes", 2010), as an adaptor over any `MetricField_3`.
///
/// From a point `p` to a point `q` at metric length `l = |pq|_{M(p)}`, the
/// sizes may grow by at most the factor `1 + l ln(beta)` (`beta` the
/// gradation, > 1): the metric at `q` must contain `M(p) / (1 + l ln beta)^2`,
/// the metric of `p` scaled, not made isotropic, so the directions and the
/// anisotropy of a layer spread with it (MMG's isotropic size clamp is known
/// to destroy anisotropic patterns). Where the field asks for a size that
/// cannot be reached from its neighbourhood at that rate (a layer of size
/// 0.001 next to a size 1 a hundredth away), the metric is intersected with
/// the grown metrics (`Bubble_mesh_3::intersection()`): sizes are only
/// reduced, never enlarged.
///
/// The correction is computed once, at construction, on a background tet
/// mesh: the field is sampled at its vertices and the bound is enforced
/// along its edges until no vertex metric is clipped by more than
/// `tolerance()` (a work list: each clipped vertex re-checks its
/// neighbours). In a background tet with no clipped vertex the field is
/// returned as it is, bitwise (so a field that is already graded is
/// unchanged); in one with a clipped vertex, the field's metric intersected
/// with the log-Euclidean interpolation of the graded vertex metrics, which
/// keeps the field's own finer variation inside the tet. Outside the
/// background mesh, the nearest background vertex plays that role.
///
/// The bound holds along the background's edges (to `tolerance()`) and,
/// between arbitrary points, up to the interpolation of the graded vertex
/// metrics, provided the background resolves the field: a feature of the
/// field thinner than the background's spacing, between its vertices, is
/// not seen (a Hessian field's own mesh resolves it; for an analytic field,
/// use a box grid with several vertices across its smallest feature).
///
/// \cgalModels `MetricField_3`
template <typename MetricField>
class Graded_metric_field_3 {
public:
  typedef typename MetricField::Kernel Kernel;
  typedef typename Kernel::FT FT;
  typedef typename Kernel::Point_3 Point_3;
  typedef Bubble_mesh_3::Metric_3 Metric;
  typedef Metric::Matrix Matrix;
  typedef MetricField Base_field;

  /// relative clipping below which a vertex metric counts as unchanged
  static constexpr double tolerance() { return 1e-3; }

  /// Grades `field` with the gradation `gradation` (> 1; e.g. 1.5) on the
  /// vertices and edges of `background` (its points and tets). Throws
  /// `Bubble_mesh_3::Invalid_input` for a gradation not above 1 or a
  /// background without tets.
  Graded_metric_field_3(MetricField field, const Bubble_mesh_3::Indexed_tet_mesh_3& background, double gradation)
    : field_(std::move(field)), data_(build(field_, background, gradation))
  {}

  /// the graded metric at `p` (see the class description)
  Metric operator()(const Point_3& p) const
  {
    const Metric m = field_(p);
    const Data& d = *data_;
    if(d.clipped_vertices == 0)
      return m;
    std::array<int, 4> v;
    std::array<double, 4> w;
    if(d.locator.locate(p, v, w) < 0) {
      const std::size_t k = d.locator.nearest_vertex(p);
      return d.clipped[k] ? Bubble_mesh_3::intersection(m, d.locator.metric_at_vertex(k)) : m;
    }
    bool any = false;
    for(int k = 0; k < 4; ++k)
      any = any || (w[std::size_t(k)] > 0 && d.clipped[std::size_t(v[std::size_t(k)])]);
    return any ? Bubble_mesh_3::intersection(m, d.locator(p)) : m;
  }

  /// the field graded
  const MetricField& base_field() const { return field_; }
  /// the gradation `beta`
  double gradation() const { return data_->gradation; }
  /// how many background vertices had their metric reduced
  std::size_t number_of_clipped_vertices() const { return data_->clipped_vertices; }
  /// the graded metric at background vertex `i`
  const Metric& vertex_metric(std::size_t i) const { return data_->locator.metric_at_vertex(i); }
  /// the background mesh the field was graded on (points and tets)
  Bubble_mesh_3::Indexed_tet_mesh_3 background_mesh() const { return data_->locator.background_mesh(); }
  /// the graded metrics at the background vertices
  std::vector<Metric> vertex_metrics() const
  {
    std::vector<Metric> out;
    out.reserve(data_->clipped.size());
    for(std::size_t i = 0; i < data_->clipped.size(); ++i)
      out.push_back(data_->locator.metric_at_vertex(i));
    return out;
  }
  /// vertex relaxations done by the grading (its cost)
  std::size_t number_of_relaxations() const { return data_->relaxations; }

private:
  struct Data {
    double gradation = 0;
    Interpolated_metric_field_3<Kernel> locator; // the graded vertex metrics
    std::vector<char> clipped;
    std::size_t clipped_vertices = 0;
    std::size_t relaxations = 0;
    explicit Data(Interpolated_metric_field_3<Kernel> l) : locator(std::move(l)) {}
  };

  // the largest eigenvalue of Q_b^-T A Q_b^-1: how much A asks beyond B
  // along its most demanding direction (<= 1: B contains A)
  static double excess(const Matrix& a, const Metric& b)
  {
    const Matrix qi = b.Q_inverse();
    const Matrix c = qi.transpose() * a * qi;
    if(c.trace() <= 1) // the largest eigenvalue is at most the trace
      return c.trace();
    Eigen::SelfAdjointEigenSolver<Matrix> es;
    es.computeDirect(0.5 * (c + c.transpose()), Eigen::EigenvaluesOnly);
    return es.eigenvalues()[2];
  }

  static std::shared_ptr<const Data> build(const MetricField& field, const Bubble_mesh_3::Indexed_tet_mesh_3& bg,
                                          double beta)
  {
    if(!(beta > 1) || !std::isfinite(beta))
      throw Bubble_mesh_3::Invalid_input("Graded_metric_field_3: the gradation must be a finite number above 1");
    if(bg.tets.empty())
      throw Bubble_mesh_3::Invalid_input("Graded_metric_field_3: the background mesh has no tetrahedra");
    const std::size_t n = bg.points.size();
    for(const auto& t : bg.tets)
      for(int v : t)
        if(v < 0 || std::size_t(v) >= n)
          throw Bubble_mesh_3::Invalid_input("Graded_metric_field_3: a background tet has a vertex index out of range");
    std::vector<Metric> graded;
    graded.reserve(n);
    for(const auto& p : bg.points)
      graded.push_back(field(Point_3(p[0], p[1], p[2])));
    // neighbours through the tets' edges (the Hessian fit's adjacency)
    const std::vector<std::vector<int>> neighbours = Bubble_mesh_3::internal::vertex_neighbours(bg);
    const double log_beta = std::log(beta);
    std::vector<char> clipped(n, 0), queued(n, 1);
    std::deque<int> work;
    for(std::size_t i = 0; i < n; ++i)
      work.push_back(int(i));
    std::size_t relaxations = 0;
    while(!work.empty()) {
      const std::size_t p = std::size_t(work.front());
      work.pop_front();
      queued[p] = 0;
      const Metric& mp = graded[p];
      const auto& xp = bg.points[p];
      for(const int neighbour : neighbours[p]) {
        const std::size_t q = std::size_t(neighbour);
        const auto& xq = bg.points[q];
        const Metric::Vector pq(xq[0] - xp[0], xq[1] - xp[1], xq[2] - xp[2]);
        const double grow = 1 + mp.length(pq) * log_beta;
        const Matrix reachable = mp.matrix() / (grow * grow);
        ++relaxations;
        if(excess(reachable, graded[q]) <= 1 + tolerance())
          continue;
        graded[q] = Bubble_mesh_3::intersection(graded[q], Metric(reachable, "graded metric"));
        clipped[q] = 1;
        if(!queued[q]) {
          queued[q] = 1;
          work.push_back(int(q));
        }
      }
    }
    const std::size_t count = std::size_t(std::count(clipped.begin(), clipped.end(), char(1)));
    Bubble_mesh_3::Indexed_tet_mesh_3 background;
    background.points = bg.points;
    background.tets = bg.tets;
    auto d = std::make_shared<Data>(Interpolated_metric_field_3<Kernel>(background, std::move(graded), "graded metric"));
    d->gradation = beta;
    d->clipped = std::move(clipped);
    d->clipped_vertices = count;
    d->relaxations = relaxations;
    return d;
  }

  MetricField field_;
  std::shared_ptr<const Data> data_;
};

/// \ingroup PkgBubbleMesh3MetricFields
/// `Graded_metric_field_3<MetricField>(field, background, gradation)`
template <typename MetricField>
Graded_metric_field_3<MetricField> make_graded_metric_field_3(MetricField field,
                                                             const Bubble_mesh_3::Indexed_tet_mesh_3& background,
                                                             double gradation)
{
  return Graded_metric_field_3<MetricField>(std::move(field), background, gradation);
}

/// \ingroup PkgBubbleMesh3MetricFields
/// `field` graded on a grid of `box` with `cells_per_axis` cubes along each
/// axis (6 tets per cube): for fields without a mesh of their own
template <typename MetricField>
Graded_metric_field_3<MetricField> make_graded_metric_field_3(MetricField field, const CGAL::Bbox_3& box,
                                                             double gradation, int cells_per_axis = 32)
{
  return Graded_metric_field_3<MetricField>(std::move(field), Bubble_mesh_3::internal::box_tet_mesh(box, cells_per_axis),
                                            gradation);
}

/// \ingroup PkgBubbleMesh3MetricFields
/// The realizable version of a graded field (what the pipeline meshes): its
/// base field made realizable (`make_realizable_metric_field_3()`, found by
/// ADL: a field interpolated on a mesh is checked once per vertex), graded
/// again on the same background with the same gradation (the realizable
/// reduction can only shrink sizes, so grading after it keeps the bound)
template <typename MetricField>
auto make_realizable_metric_field_3(const Graded_metric_field_3<MetricField>& field, bool enabled = true)
{
  using CGAL::make_realizable_metric_field_3;
  auto base = make_realizable_metric_field_3(field.base_field(), enabled);
  return Graded_metric_field_3<decltype(base)>(std::move(base), field.background_mesh(), field.gradation());
}

} // namespace CGAL

#endif // CGAL_GRADED_METRIC_FIELD_3_H
