// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_INTERSECTION_METRIC_FIELD_3_H
#define CGAL_INTERSECTION_METRIC_FIELD_3_H

#include <CGAL/Bubble_mesh_3/Metric_3.h>

#include <type_traits>
#include <utility>

namespace CGAL {

/// \ingroup PkgBubbleMesh3MetricFields
/// The intersection of two metric fields: at every point the largest metric
/// whose unit ball lies in both (`Bubble_mesh_3::intersection()`, by
/// simultaneous reduction), i.e. the smaller of the two sizes in every
/// direction. Combines, e.g., a boundary-layer field, the Hessian metrics of
/// several solution fields and a maximum size; nest it for more than two.
/// Commutative, and the intersection of a field with itself is that field.
/// \cgalModels `MetricField_3`
template <typename Field1, typename Field2>
class Intersection_metric_field_3 {
public:
  typedef typename Field1::Kernel Kernel;
  typedef typename Kernel::FT FT;
  typedef typename Kernel::Point_3 Point_3;
  typedef Bubble_mesh_3::Metric_3 Metric;
  static_assert(std::is_same<Point_3, typename Field2::Kernel::Point_3>::value,
                "Intersection_metric_field_3: both fields must have the same kernel point type");

  Intersection_metric_field_3(Field1 first, Field2 second) : first_(std::move(first)), second_(std::move(second)) {}

  /// the intersection of the two fields' metrics at `p`
  Metric operator()(const Point_3& p) const { return Bubble_mesh_3::intersection(first_(p), second_(p)); }

  const Field1& first() const { return first_; }
  const Field2& second() const { return second_; }

private:
  Field1 first_;
  Field2 second_;
};

/// \ingroup PkgBubbleMesh3MetricFields
/// `Intersection_metric_field_3<Field1, Field2>(first, second)` without naming the types
template <typename Field1, typename Field2>
Intersection_metric_field_3<Field1, Field2> make_intersection_metric_field_3(Field1 first, Field2 second)
{
  return Intersection_metric_field_3<Field1, Field2>(std::move(first), std::move(second));
}

} // namespace CGAL

#endif // CGAL_INTERSECTION_METRIC_FIELD_3_H
