// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Where a metric field says where it was given (the vertices of the
// background mesh of an interpolated, Hessian or graded field, through any
// wrapper that exposes its base field), the octrees that seed and estimate
// the interior test the metric at those points as well as at each cell's
// centre and corners. A layer thinner than a cell, lying between its corners,
// is otherwise never seen: a tanh layer 0.02 wide across the unit cube
// (a Hessian metric without gradation) got 859 interior seeds where about
// 7,000 bubbles were expected, and the advancing front then stalled on the
// under-populated layer. Fields given by a formula have no such points; the
// corners are all there is to test.
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_METRIC_SAMPLES_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_METRIC_SAMPLES_H

#include <CGAL/Bubble_mesh_3/internal/packing/bubble.h>

#include <CGAL/number_utils.h>

#include <algorithm>
#include <cstddef>
#include <type_traits>
#include <utility>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {
namespace packing {

namespace sample_traits {
template <typename F, typename = void>
struct Has_vertices : std::false_type {};
template <typename F>
struct Has_vertices<F, std::void_t<decltype(std::declval<const F&>().number_of_vertices()),
                                   decltype(std::declval<const F&>().point_at_vertex(std::size_t()))>>
    : std::true_type {};
template <typename F, typename = void>
struct Has_interpolated_field : std::false_type {};
template <typename F>
struct Has_interpolated_field<F, std::void_t<decltype(std::declval<const F&>().interpolated_field())>>
    : std::true_type {};
template <typename F, typename = void>
struct Has_background_mesh : std::false_type {};
template <typename F>
struct Has_background_mesh<F, std::void_t<decltype(std::declval<const F&>().background_mesh().points)>>
    : std::true_type {};
template <typename F, typename = void>
struct Has_base_field : std::false_type {};
template <typename F>
struct Has_base_field<F, std::void_t<decltype(std::declval<const F&>().base_field())>> : std::true_type {};
template <typename F, typename = void>
struct Has_two_fields : std::false_type {};
template <typename F>
struct Has_two_fields<F, std::void_t<decltype(std::declval<const F&>().first()),
                                     decltype(std::declval<const F&>().second())>> : std::true_type {};
} // namespace sample_traits

/// appends the points where `field` was given (none for a formula)
template <typename MetricField>
void append_metric_sample_points(const MetricField& field, std::vector<Vec3>& out)
{
  namespace T = sample_traits;
  if constexpr(T::Has_vertices<MetricField>::value) {
    for(std::size_t i = 0; i < field.number_of_vertices(); ++i) {
      const auto p = field.point_at_vertex(i);
      out.emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
    }
  } else {
    if constexpr(T::Has_interpolated_field<MetricField>::value)
      append_metric_sample_points(field.interpolated_field(), out);
    if constexpr(T::Has_background_mesh<MetricField>::value)
      for(const auto& p : field.background_mesh().points)
        out.emplace_back(p[0], p[1], p[2]);
    if constexpr(T::Has_base_field<MetricField>::value)
      append_metric_sample_points(field.base_field(), out);
    if constexpr(T::Has_two_fields<MetricField>::value) {
      append_metric_sample_points(field.first(), out);
      append_metric_sample_points(field.second(), out);
    }
  }
}

/// The sample points with sqrt(det M) there, and the octree's test of a cell
/// against the samples it contains.
class Metric_samples {
public:
  Metric_samples() = default;

  template <typename Refresh>
  Metric_samples(std::vector<Vec3> points, const Refresh& refresh)
  {
    std::sort(points.begin(), points.end(), [](const Vec3& a, const Vec3& b) {
      return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
    });
    points.erase(std::unique(points.begin(), points.end()), points.end());
    points_ = std::move(points);
    density_.reserve(points_.size());
    for(const Vec3& p : points_)
      density_.push_back(refresh.at(p).sqrt_determinant());
  }

  std::size_t size() const { return points_.size(); }

  /// the indices of every sample
  std::vector<int> all() const
  {
    std::vector<int> out(points_.size());
    for(std::size_t i = 0; i < out.size(); ++i)
      out[i] = int(i);
    return out;
  }

  /// the samples of `candidates` in the closed box [lo, hi]
  void select(const std::vector<int>& candidates, const Vec3& lo, const Vec3& hi, std::vector<int>& inside) const
  {
    inside.clear();
    for(int i : candidates) {
      const Vec3& p = points_[std::size_t(i)];
      if(!(p[0] < lo[0] || p[1] < lo[1] || p[2] < lo[2] || p[0] > hi[0] || p[1] > hi[1] || p[2] > hi[2]))
        inside.push_back(i);
    }
  }

  /// `select`, and raises `finest` to the largest sqrt(det M) of the samples
  /// in the box and sets `varies` if one differs from `d0` by more than `ratio`
  void test_cell(const std::vector<int>& candidates, const Vec3& lo, const Vec3& hi, double d0, double ratio,
                 double& finest, bool& varies, std::vector<int>& inside) const
  {
    select(candidates, lo, hi, inside);
    for(int i : inside) {
      const double d = density_[std::size_t(i)];
      varies = varies || d > ratio * d0 || d0 > ratio * d;
      finest = std::max(finest, d);
    }
  }

private:
  std::vector<Vec3> points_;
  std::vector<double> density_; // sqrt(det M) at each point
};

} // namespace packing
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_METRIC_SAMPLES_H
