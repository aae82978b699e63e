// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Named parameters of make_anisotropic_mesh_3. The package's own tags live in
// CGAL::Bubble_mesh_3::internal_np; a thin class derived from CGAL's
// Named_function_parameters chains them with the CGAL tags the package reuses
// (CGAL 5.5 has no public way to add tags to its own class), so
//   CGAL::Bubble_mesh_3::parameters::number_of_threads(2).random_seed(7)
// and CGAL::parameters::random_seed(7) both work.
#ifndef CGAL_BUBBLE_MESH_3_PARAMETERS_H
#define CGAL_BUBBLE_MESH_3_PARAMETERS_H

#include <CGAL/Named_function_parameters.h>

namespace CGAL {
namespace Bubble_mesh_3 {

/// \ingroup PkgBubbleMesh3Ref
/// The default of `maximum_number_of_bubbles` (and of the tool's
/// `--max-nodes`), chosen for a 24 GB machine: the measured peak memory of a
/// whole run of the tool (packing, front, improvement) is about 2 kB per
/// node, less for large runs (unit cube, one thread: 57 MB at 24k nodes,
/// 231 MB at 110k, 719 MB at 435k; doc/Bubble_mesh_3/input_checks.md), so
/// 5e6 nodes need about 10 GB, leaving room for the C3T3 of
/// `make_anisotropic_mesh_3()` and a second thread.
constexpr double default_maximum_number_of_nodes = 5e6;
/// the default bound of `surface_distance`, as a fraction of the domain's
/// bounding box diagonal
constexpr double default_relative_surface_distance = 1.0 / 200;

namespace internal_np {
enum number_of_threads_t { number_of_threads };
enum maximum_number_of_bubbles_t { maximum_number_of_bubbles };
enum allow_steiner_points_t { allow_steiner_points };
enum meshing_report_t { meshing_report };
enum mesh_improvement_t { mesh_improvement };
enum improvement_time_limit_t { improvement_time_limit };
enum time_limit_t { time_limit };
enum should_stop_t { should_stop };
enum surface_distance_t { surface_distance };
enum feature_angle_t { feature_angle };
enum minimum_feature_length_t { minimum_feature_length };
enum small_feature_refinement_t { small_feature_refinement };
enum realizable_metric_t { realizable_metric };
enum progress_messages_t { progress_messages };
// the improver's (improve_mesh(), improve_anisotropic_mesh_3())
enum target_angle_t { target_angle };
enum flips_t { flips };
enum smoothing_t { smoothing };
enum boundary_smoothing_t { boundary_smoothing };
enum boundary_flips_t { boundary_flips };
enum curved_boundary_flips_t { curved_boundary_flips };
enum sliver_moves_t { sliver_moves };
enum edge_splits_t { edge_splits };
enum split_below_angle_t { split_below_angle };
enum edge_collapses_t { edge_collapses };
enum keep_edges_in_range_t { keep_edges_in_range };
enum flips_keep_edges_in_range_t { flips_keep_edges_in_range };
enum edge_lengths_t { edge_lengths };
enum maximum_ring_size_t { maximum_ring_size };
enum smoothing_iterations_t { smoothing_iterations };
enum surface_projection_t { surface_projection };
enum curve_projection_t { curve_projection };
// Hessian_metric_field_3's
enum interpolation_error_t { interpolation_error };
enum target_number_of_vertices_t { target_number_of_vertices };
enum error_norm_t { error_norm };
enum minimum_size_t { minimum_size };
enum maximum_size_t { maximum_size };
enum maximum_anisotropy_t { maximum_anisotropy };
} // namespace internal_np

/// Named parameters: CGAL's, plus the package's own options as chaining members.
template <typename T, typename Tag, typename Base = CGAL::internal_np::No_property>
struct Named_function_parameters : CGAL::Named_function_parameters<T, Tag, Base> {
  typedef CGAL::Named_function_parameters<T, Tag, Base> Cgal_base;
  typedef Named_function_parameters<T, Tag, Base> self;
  Named_function_parameters() : Cgal_base() {}
  Named_function_parameters(const T& v) : Cgal_base(v) {}
  Named_function_parameters(const T& v, const Base& b) : Cgal_base(v, b) {}

#define CGAL_BUBBLE_MESH_3_MEMBER(NS, TAG)                                                                        \
  template <typename K>                                                                                          \
  Named_function_parameters<K, NS::TAG##_t, self> TAG(const K& k) const                                          \
  {                                                                                                              \
    return Named_function_parameters<K, NS::TAG##_t, self>(k, *this);                                            \
  }
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, number_of_threads)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, maximum_number_of_bubbles)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, allow_steiner_points)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, meshing_report)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, mesh_improvement)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, improvement_time_limit)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, time_limit)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, should_stop)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, surface_distance)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, feature_angle)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, minimum_feature_length)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, small_feature_refinement)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, realizable_metric)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, progress_messages)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, target_angle)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, flips)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, smoothing)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, boundary_smoothing)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, boundary_flips)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, curved_boundary_flips)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, sliver_moves)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, edge_splits)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, split_below_angle)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, edge_collapses)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, keep_edges_in_range)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, flips_keep_edges_in_range)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, edge_lengths)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, maximum_ring_size)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, smoothing_iterations)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, surface_projection)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, curve_projection)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, interpolation_error)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, target_number_of_vertices)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, error_norm)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, minimum_size)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, maximum_size)
  CGAL_BUBBLE_MESH_3_MEMBER(Bubble_mesh_3::internal_np, maximum_anisotropy)
  CGAL_BUBBLE_MESH_3_MEMBER(CGAL::internal_np, random_seed)
  CGAL_BUBBLE_MESH_3_MEMBER(CGAL::internal_np, number_of_iterations)
  CGAL_BUBBLE_MESH_3_MEMBER(CGAL::internal_np, callback)
  CGAL_BUBBLE_MESH_3_MEMBER(CGAL::internal_np, verbose)
#undef CGAL_BUBBLE_MESH_3_MEMBER
};

namespace parameters {
#define CGAL_BUBBLE_MESH_3_FREE(NS, TAG)                                                                          \
  template <typename K>                                                                                          \
  Named_function_parameters<K, NS::TAG##_t> TAG(const K& k)                                                      \
  {                                                                                                              \
    return Named_function_parameters<K, NS::TAG##_t>(k);                                                         \
  }
/// number of threads of the packing (0: all, 1: serial); the mesh does not depend on it
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, number_of_threads)
/// refuse (`Too_many_nodes`) when the estimated node count exceeds this (default: `default_maximum_number_of_nodes`)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, maximum_number_of_bubbles)
/// whether the front may add Steiner points strictly inside cavities it cannot close (default true)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, allow_steiner_points)
/// a `Bubble_mesh_3::Meshing_report*` filled with counts and times of every stage
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, meshing_report)
/// improve the front's mesh by metric flips and smoothing (`improve_mesh()`; default true)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, mesh_improvement)
/// seconds for the improvement (default: none, bounded by passes and reproducible; negative: automatic)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, improvement_time_limit)
/// seconds for the whole run (default: none); when reached at a check point before the mesh is complete,
/// `Time_limit_exceeded` is thrown; the improvement is cut to the time left instead
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, time_limit)
/// a `std::function<bool()>` polled at check points; when it returns true, `Interrupted` is thrown
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, should_stop)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, surface_distance)
/// `detect_features()`: an edge is sharp when its faces' normals differ by more than this (degrees, default 60)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, feature_angle)
/// `detect_features()`: chains with a free end shorter than this metric length are dropped, and patches narrower than a tenth of an element merged (default 1; 0 keeps all)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, minimum_feature_length)
/// refine the metric where the domain's corners and feature curves are closer than its sizes (default true;
/// `CGAL::Feature_size_metric_field_3`)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, small_feature_refinement)
/// reduce the metric's large sizes where its frame turns faster than straight edges of those sizes can follow
/// (default true; `CGAL::Realizable_metric_field_3`)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, realizable_metric)
/// a `std::function<void(const std::string&)>` receiving a line per stage (nodes, tets, seconds)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, progress_messages)
/// `improve_mesh()`: tets whose metric minimum dihedral angle (degrees) is below this are worked on (default 40)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, target_angle)
/// `improve_mesh()`: 2-3 flips and edge removals (default true)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, flips)
/// `improve_mesh()`: vertex moves (default true)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, smoothing)
/// `improve_mesh()`: boundary vertices move too, where that cannot change the domain, or on the projections (default true)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, boundary_smoothing)
/// `improve_mesh()`: flips of boundary edges inside planar regions of one patch (default true)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, boundary_flips)
/// `improve_mesh()`: with a `surface_projection`, also boundary flips and cap removals on curved patches (default true)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, curved_boundary_flips)
/// `improve_mesh()`: push a sliver's vertex that smoothing could not move off its opposite face (default true)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, sliver_moves)
/// `improve_mesh()`: split an edge of the tets still bad when flips and moves are stuck (adds vertices; default false)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, edge_splits)
/// `improve_mesh()`: the angle (degrees) below which splits and collapses are tried (default 15)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, split_below_angle)
/// `improve_mesh()`: collapse a short edge of those tets (removes vertices; default false)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, edge_collapses)
/// `improve_mesh()`: interior moves keep the vertex's edges that are in [1/sqrt(2), sqrt(2)] in the metric in that range (default false)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, keep_edges_in_range)
/// `improve_mesh()`: flips of tets not below `split_below_angle` create no edge outside [1/sqrt(2), sqrt(2)] in the metric (default false)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, flips_keep_edges_in_range)
/// `improve_mesh()`: rounds of removals, splits and collapses of the edges outside [1/sqrt(2), sqrt(2)] in the metric (default false)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, edge_lengths)
/// `improve_mesh()`: largest number of tets around an edge that edge removal considers (default 10)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, maximum_ring_size)
/// `improve_mesh()`: steepest-ascent steps per vertex move (default 8)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, smoothing_iterations)
/// `improve_mesh()`: a `std::function<bool(int, const std::array<double, 3>&, std::array<double, 3>&)>` giving the point of patch `ref` closest to a point: vertices of curved patches slide on it (default none)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, surface_projection)
/// `improve_mesh()`: the same for the feature curves (edge refs): vertices of curved curves slide on it (default none)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, curve_projection)
/// `Hessian_metric_field_3`: the P1 interpolation error asked (L-infinity), in the field's units
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, interpolation_error)
/// `Hessian_metric_field_3`: the number of mesh vertices asked instead of an error (the metric minimising the
/// L^p error for that many vertices)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, target_number_of_vertices)
/// `Hessian_metric_field_3`: the p of the L^p norm that `target_number_of_vertices` minimises (default 2;
/// infinity for L-infinity)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, error_norm)
/// `Hessian_metric_field_3`: the smallest edge length the metric asks (default: the mesh's bounding box diagonal / 10^4)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, minimum_size)
/// `Hessian_metric_field_3`: the largest edge length the metric asks (default: the bounding box diagonal / 10)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, maximum_size)
/// `Hessian_metric_field_3`: the largest ratio of the metric's sizes at a point (default 1000)
CGAL_BUBBLE_MESH_3_FREE(Bubble_mesh_3::internal_np, maximum_anisotropy)
CGAL_BUBBLE_MESH_3_FREE(CGAL::internal_np, random_seed)
CGAL_BUBBLE_MESH_3_FREE(CGAL::internal_np, number_of_iterations)
/// CGAL's meaning: a `std::function<bool(double)>` called at every check point with the advancement of the
/// run (0 to 1); when it returns false, `Interrupted` is thrown
CGAL_BUBBLE_MESH_3_FREE(CGAL::internal_np, callback)
/// the stage messages and the final summary to `std::cerr` (default false)
CGAL_BUBBLE_MESH_3_FREE(CGAL::internal_np, verbose)
#undef CGAL_BUBBLE_MESH_3_FREE
} // namespace parameters

} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_PARAMETERS_H
