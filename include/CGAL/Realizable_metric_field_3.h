// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_REALIZABLE_METRIC_FIELD_3_H
#define CGAL_REALIZABLE_METRIC_FIELD_3_H

#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Constant_metric_field_3.h>
#include <CGAL/Interpolated_metric_field_3.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace CGAL {

/// \ingroup PkgBubbleMesh3MetricFields
///
/// A model of `MetricField_3`: a metric field with its large sizes reduced
/// where its frame turns faster than straight edges of those sizes can
/// follow.
///
/// An anisotropic metric whose small-size direction turns along a long edge
/// cannot be met by that edge: a chord of length `h_t` across a boundary
/// layer wrapped around a cylinder of radius `r` leaves the layer's frame by
/// the angle `h_t / (2 r)` at its ends, where it measures about
/// `sqrt(1 + (h_t^2 / (2 r h_n))^2)` in the metric (`h_n` the layer's normal
/// size). On UGAWG's polar-1 metric (`h_t = 0.1`, `h_n = 0.001`, `r = 0.5`)
/// that is 10: no mesh with straight edges of the asked sizes conforms to
/// the field, and a mesher that honours it must shorten the tangential edges
/// near the wall, as edge-based remeshers do when they split the chords the
/// metric measures long.
///
/// At a point `x` where the smallest size `h_n` (direction `n`) is below
/// half the two others (directions `e_1`, `e_2`), the turn of `n` along the
/// plane of `e_1` and `e_2` is measured by central differences over the
/// segments of the sizes asked along them (`S(a, b) = e_a . dn/ds_b`); its
/// principal rates `w_k` and directions `t_k` (those of the symmetric part
/// of `S`, so a degenerate pair of large sizes, as in any boundary layer,
/// gives the same result for any choice of `e_1` and `e_2`) bound the size
/// along `t_k`: a chord of length `h` turns by `w_k h / 2` at its ends,
/// where it measures `(w_k h^2 / (2 h_n))^2` more (squared) across the
/// layer, and that excess is kept within `turn_tolerance()`, so
/// `h_k = sqrt(2 sqrt(turn_tolerance()) h_n / w_k)`. The metric is then
/// intersected with those sizes (never below `h_n`). A metric whose frame
/// does not turn (constant, or graded along fixed directions) is returned
/// unchanged. Each query costs one eigen-solve more than the field's own,
/// and four field evaluations and eigen-solves more where the field is
/// anisotropic.
///
/// Thread-safe if the field is.
///
/// \tparam MetricField a model of `MetricField_3`
template <typename MetricField>
class Realizable_metric_field_3 {
public:
  typedef typename MetricField::Kernel Kernel;
  typedef typename Kernel::FT FT;
  typedef typename Kernel::Point_3 Point_3;
  typedef Bubble_mesh_3::Metric_3 Metric;
  typedef MetricField Base_field;

  /// `field` checked as described above; with `enabled` false, `field` as it is
  explicit Realizable_metric_field_3(const MetricField& field, bool enabled = true) : field_(field), enabled_(enabled)
  {}

  /// the largest turn excess accepted at a segment's ends (a squared metric
  /// length, see the class description): with 0.5, the sagitta of a chord
  /// along a wall wrapped around the layer stays within about a sixth of the
  /// layer's normal size
  static constexpr double turn_tolerance() { return 0.5; }
  /// sizes within this factor of the smallest are not checked
  static constexpr double checked_ratio() { return 2; }

  const MetricField& base_field() const { return field_; }
  bool enabled() const { return enabled_; }

  /// the metric at `p`
  Metric operator()(const Point_3& p) const
  {
    const Metric m = field_(p);
    if(!enabled_)
      return m;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(m.matrix());
    // ascending eigenvalues: column 2 is the smallest size's direction n
    const Eigen::Vector3d lambda = eig.eigenvalues();
    if(!(lambda[0] > 0) || lambda[2] <= lambda[1] * checked_ratio() * checked_ratio())
      return m;
    const Eigen::Vector3d n = eig.eigenvectors().col(2);
    const Eigen::Vector3d e[2] = {eig.eigenvectors().col(0), eig.eigenvectors().col(1)};
    // the turn of n along the plane of the large sizes: S(a, b) = e_a . dn/ds_b,
    // by central differences over the segment of the size along e_b
    Eigen::Matrix2d turn = Eigen::Matrix2d::Zero();
    for(int b = 0; b < 2; ++b) {
      const double half = 0.5 / std::sqrt(lambda[std::size_t(b)]);
      Eigen::Vector3d ends[2];
      double span = 0;
      for(int side = 0; side < 2; ++side) {
        const double offset = side == 0 ? -half : half;
        ends[side] = n;
        if(smallest_direction(p, offset * e[b], n, ends[side]))
          span += half;
      }
      if(span > 0)
        for(int a = 0; a < 2; ++a)
          turn(a, b) = e[a].dot(ends[1] - ends[0]) / span;
    }
    // principal turn rates and directions in that plane
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> principal(0.5 * (turn + turn.transpose()));
    const double normal_size = 1 / std::sqrt(lambda[2]);
    Eigen::Matrix3d limit = Eigen::Matrix3d::Zero();
    bool limited = false;
    for(int k = 0; k < 2; ++k) {
      const double rate = std::abs(principal.eigenvalues()[k]);
      const Eigen::Vector3d t =
          (principal.eigenvectors()(0, k) * e[0] + principal.eigenvectors()(1, k) * e[1]).normalized();
      const double asked = 1 / std::sqrt(t.dot(m.matrix() * t));
      // a chord of length h turns by rate h / 2 at its ends, where it
      // measures (rate h^2 / (2 h_n))^2 more (squared) across the layer
      const double size = rate > 0 ? std::sqrt(2 * std::sqrt(turn_tolerance()) * normal_size / rate)
                                   : std::numeric_limits<double>::infinity();
      const double s = std::min(asked, std::max(size, normal_size));
      limit += t * t.transpose() / (s * s);
      limited = limited || size < asked;
    }
    if(!limited)
      return m;
    return Bubble_mesh_3::intersection(m, Metric(Eigen::Matrix3d(limit + n * n.transpose() * lambda[2]),
                                                 "metric limited by its frame's turn"));
  }

private:
  // the field's smallest-size direction at p + shift, signed like n, in
  // `out`; false where the field cannot be evaluated there (a field defined
  // on the domain only, probed outside it)
  bool smallest_direction(const Point_3& p, const Eigen::Vector3d& shift, const Eigen::Vector3d& n,
                          Eigen::Vector3d& out) const
  {
    const Point_3 q(CGAL::to_double(p.x()) + shift[0], CGAL::to_double(p.y()) + shift[1],
                    CGAL::to_double(p.z()) + shift[2]);
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    try {
      eig.computeDirect(field_(q).matrix());
    } catch(const Bubble_mesh_3::Invalid_input&) {
      return false;
    }
    out = eig.eigenvectors().col(2);
    if(out.dot(n) < 0)
      out = -out;
    return true;
  }

  MetricField field_;
  bool enabled_;
};

/// \ingroup PkgBubbleMesh3MetricFields
/// `field` with its large sizes reduced where its frame turns faster than
/// straight edges of those sizes can follow: a
/// `Realizable_metric_field_3<MetricField>` that checks at every query
/// (with `enabled` false: one that passes `field` through).
template <typename MetricField>
Realizable_metric_field_3<MetricField> make_realizable_metric_field_3(const MetricField& field, bool enabled = true)
{
  return Realizable_metric_field_3<MetricField>(field, enabled);
}

/// \ingroup PkgBubbleMesh3MetricFields
/// A constant field's frame never turns: the field itself.
template <typename K>
Constant_metric_field_3<K> make_realizable_metric_field_3(const Constant_metric_field_3<K>& field, bool = true)
{
  return field;
}

/// \ingroup PkgBubbleMesh3MetricFields
/// For a field interpolated from a background mesh, the check is done once
/// per background vertex and the results are interpolated: the field at the
/// background's resolution, at the cost of the given one per query
/// (checking at every query costs five interpolations where the field is
/// anisotropic). With
/// `enabled` false: `field` itself.
template <typename K>
Interpolated_metric_field_3<K> make_realizable_metric_field_3(const Interpolated_metric_field_3<K>& field,
                                                              bool enabled = true)
{
  if(!enabled)
    return field;
  const Realizable_metric_field_3<Interpolated_metric_field_3<K>> checked(field);
  std::vector<Bubble_mesh_3::Metric_3> metrics;
  metrics.reserve(field.number_of_vertices());
  bool changed = false;
  for(std::size_t i = 0; i < field.number_of_vertices(); ++i) {
    metrics.push_back(checked(field.point_at_vertex(i)));
    changed = changed || metrics.back().matrix() != field.metric_at_vertex(i).matrix();
  }
  return changed ? field.with_vertex_metrics(std::move(metrics), field.name()) : field;
}

} // namespace CGAL

#endif // CGAL_REALIZABLE_METRIC_FIELD_3_H
