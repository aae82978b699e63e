// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_METRIC_STAGE_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_METRIC_STAGE_H

// Stage 0 of the pipeline: the field the later stages mesh. The user's
// metric with its large sizes reduced where its frame turns too fast for them
// (unless turned off), intersected near the surface with the curvature sizes of the
// surface-distance bound (if any), refined where corners and curves are
// closer than its sizes (unless turned off). It is always a
// `Feature_size_metric_field_3`, so the stages are instantiated once; a field
// the caller built as either kind is used as it is.

#include <CGAL/Bubble_mesh_3/Meshing_report.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/run_control.h>
#include <CGAL/Feature_size_metric_field_3.h>
#include <CGAL/Realizable_metric_field_3.h>
#include <CGAL/Surface_approximation_metric_field_3.h>

#include <chrono>
#include <sstream>
#include <string>
#include <type_traits>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

template <typename F>
struct Is_surface_approximation_field : std::false_type {};
template <typename F>
struct Is_surface_approximation_field<CGAL::Surface_approximation_metric_field_3<F>> : std::true_type {};
template <typename F>
struct Is_feature_size_field : std::false_type {};
template <typename F>
struct Is_feature_size_field<CGAL::Feature_size_metric_field_3<F>> : std::true_type {};

template <typename MetricField>
void report_feature_sizes(const CGAL::Feature_size_metric_field_3<MetricField>& field, const Run_control& control,
                          Meshing_report& rep)
{
  const auto& st = field.statistics();
  rep.small_feature_samples = st.refined_samples;
  rep.smallest_feature_size = field.refines() ? st.smallest_size : 0;
  rep.feature_size_seconds = st.seconds;
  if(control.says() && field.refines()) {
    std::ostringstream m;
    m << "small features: " << (st.refined_samples - st.thin_samples - st.near_patch_refined) << " of " << st.samples
      << " corner and curve samples closer than the metric's size, " << st.thin_samples << " of "
      << st.thickness_samples << " surface samples across thinner parts, " << st.near_patch_refined << " of "
      << st.near_patch_samples << " curve samples near a patch they do not bound, sizes down to " << st.smallest_size
      << " (" << st.smallest_ratio << " of the metric's)";
    if(st.floored_samples > 0)
      m << ", " << st.floored_samples << " raised to " << field.smallest_relative_size() << " of it";
    m << ", " << rep.feature_size_seconds << " s";
    control.say(m.str());
  }
}

/// Stage 0: calls `mesh(prepared_field)` and returns what it returns.
template <typename MeshDomain, typename MetricField, typename Mesh>
auto with_prepared_metric(const MeshDomain& domain, const MetricField& field, const Meshing_settings& s,
                          const Run_control& control, Meshing_report& rep, const Mesh& mesh)
{
  control.advance(0.01);
  auto with_feature_sizes = [&](const auto& f) {
    typedef std::decay_t<decltype(f)> F;
    const auto refined = s.small_feature_refinement ? CGAL::make_feature_size_metric_field_3(domain, f)
                                                    : CGAL::Feature_size_metric_field_3<F>(f);
    report_feature_sizes(refined, control, rep);
    control.check("the feature sizes");
    return mesh(refined);
  };
  if constexpr(Is_feature_size_field<MetricField>::value) {
    if constexpr(Is_surface_approximation_field<typename MetricField::Base_field>::value)
      rep.surface_distance_bound = field.base_field().bounded() ? field.base_field().distance() : 0;
    report_feature_sizes(field, control, rep);
    return mesh(field);
  } else if constexpr(Is_surface_approximation_field<MetricField>::value) {
    rep.surface_distance_bound = field.bounded() ? field.distance() : 0;
    return with_feature_sizes(field);
  } else {
    // without a bound the field passes the user's metric through
    const auto t0 = std::chrono::steady_clock::now();
    // unqualified: the overloads of the fields interpolated from a mesh
    // (Interpolated_, Hessian_metric_field_3) are found by ADL
    using CGAL::make_realizable_metric_field_3;
    const auto realizable = make_realizable_metric_field_3(field, s.realizable_metric);
    const auto approximating = CGAL::make_surface_approximation_metric_field_3(domain, realizable, s.surface_distance);
    rep.surface_distance_bound = approximating.bounded() ? approximating.distance() : 0;
    rep.surface_metric_seconds = seconds_since(t0);
    if(approximating.bounded())
      control.say("surface metric: curvature sizes for a distance bound of " +
                  std::to_string(rep.surface_distance_bound) + ", " + std::to_string(rep.surface_metric_seconds) +
                  " s");
    return with_feature_sizes(approximating);
  }
}

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_METRIC_STAGE_H
