// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_CONSTANT_METRIC_FIELD_3_H
#define CGAL_CONSTANT_METRIC_FIELD_3_H

#include <CGAL/Bubble_mesh_3/Metric_3.h>

namespace CGAL {

/// \ingroup PkgBubbleMesh3MetricFields
/// The same metric everywhere.
/// \cgalModels `MetricField_3`
/// \tparam K a CGAL kernel; only `K::Point_3` and `K::FT` are used.
template <typename K>
class Constant_metric_field_3 {
public:
  typedef K Kernel;
  typedef typename K::FT FT;
  typedef typename K::Point_3 Point_3;
  typedef Bubble_mesh_3::Metric_3 Metric;

  /// the identity metric: unit-size isotropic elements
  Constant_metric_field_3() = default;
  /// the metric `m`
  explicit Constant_metric_field_3(const Metric& m) : m_(m) {}
  /// the metric of matrix `m`; throws `Bubble_mesh_3::Invalid_metric` if it
  /// is not a finite symmetric positive definite matrix
  explicit Constant_metric_field_3(const Metric::Matrix& m) : m_(m, "constant metric") {}

  /// isotropic field of element size `h`
  static Constant_metric_field_3 isotropic(double h)
  {
    return Constant_metric_field_3(Metric::isotropic(h, "constant metric"));
  }

  /// the metric at `p` (always the same)
  const Metric& operator()(const Point_3& /*p*/) const { return m_; }

  /// the metric (for callers that know the field is constant)
  const Metric& metric() const { return m_; }

private:
  Metric m_;
};

} // namespace CGAL

#endif // CGAL_CONSTANT_METRIC_FIELD_3_H
