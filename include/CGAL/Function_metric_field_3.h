// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_FUNCTION_METRIC_FIELD_3_H
#define CGAL_FUNCTION_METRIC_FIELD_3_H

#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/number_utils.h>

#include <sstream>
#include <type_traits>
#include <utility>

namespace CGAL {

/// \ingroup PkgBubbleMesh3MetricFields
/// A metric field defined by a callable: `F(const K::Point_3&)` returning
/// either an `Eigen::Matrix3d` or a `Bubble_mesh_3::Metric_3`.
///
/// Every value is validated when it is evaluated: a NaN, non-symmetric or
/// non-positive-definite matrix throws `Bubble_mesh_3::Invalid_metric`
/// naming the point where it happened. The callable must be thread-safe
/// (the packer evaluates the field concurrently).
/// \cgalModels `MetricField_3`
template <typename K, typename F>
class Function_metric_field_3 {
public:
  typedef K Kernel;
  typedef typename K::FT FT;
  typedef typename K::Point_3 Point_3;
  typedef Bubble_mesh_3::Metric_3 Metric;
  typedef F Function;

  explicit Function_metric_field_3(F f) : f_(std::move(f)) {}

  /// the metric at `p`
  Metric operator()(const Point_3& p) const
  {
    typedef std::decay_t<decltype(f_(p))> Result;
    static_assert(std::is_same<Result, Metric>::value || std::is_convertible<Result, Metric::Matrix>::value,
                  "the metric function must return Eigen::Matrix3d or CGAL::Bubble_mesh_3::Metric_3");
    if constexpr(std::is_same<Result, Metric>::value) {
      return f_(p);
    } else {
      const Metric::Matrix m = f_(p);
      try {
        return Metric(m);
      } catch(const Bubble_mesh_3::Invalid_metric& e) {
        // Build the location only on failure: this is the packer's hot path.
        std::ostringstream where;
        where.precision(17);
        where << "metric function at point (" << CGAL::to_double(p.x()) << " " << CGAL::to_double(p.y()) << " "
              << CGAL::to_double(p.z()) << "): " << e.what();
        throw Bubble_mesh_3::Invalid_metric(where.str());
      }
    }
  }

  const F& function() const { return f_; }

private:
  F f_;
};

/// \ingroup PkgBubbleMesh3MetricFields
/// `Function_metric_field_3<K, F>(f)` without naming `F` (e.g. for a lambda)
template <typename K, typename F>
Function_metric_field_3<K, F> make_function_metric_field_3(F f)
{
  return Function_metric_field_3<K, F>(std::move(f));
}

} // namespace CGAL

#endif // CGAL_FUNCTION_METRIC_FIELD_3_H
