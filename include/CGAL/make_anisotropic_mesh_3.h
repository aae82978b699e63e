// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_MAKE_ANISOTROPIC_MESH_3_H
#define CGAL_MAKE_ANISOTROPIC_MESH_3_H

#include <CGAL/Anisotropic_advancing_front_3.h>
#include <CGAL/Bubble_mesh_3/IO/read_triangle_surface.h>
#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/improve_mesh.h>
#include <CGAL/Bubble_mesh_3/internal/boundary_self_intersections.h>
#include <CGAL/Bubble_mesh_3/internal/c3t3/exterior_padding.h>
#include <CGAL/Bubble_mesh_3/internal/c3t3/tet_soup_to_c3t3.h>
#include <CGAL/Bubble_mesh_3/internal/front/boundary_front.h>
#include <CGAL/Bubble_mesh_3/internal/front/feature_chains.h>
#include <CGAL/Bubble_mesh_3/internal/improve/input_projections.h>
#include <CGAL/Bubble_mesh_3/internal/json.h>
#include <CGAL/Bubble_mesh_3/internal/surface_fidelity.h>
#include <CGAL/Bubble_mesh_3/parameters.h>
#include <CGAL/Bubble_mesh_3/validity.h>
#include <CGAL/Bubble_packer_3.h>
#include <CGAL/Feature_size_metric_field_3.h>
#include <CGAL/Surface_approximation_metric_field_3.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Triangulation_3.h>
#include <CGAL/boost/graph/copy_face_graph.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <memory>
#include <ostream>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace CGAL {

/// \ingroup PkgBubbleMesh3Classes
/// The triangulation type to put in the `Mesh_complex_3_in_triangulation_3`
/// filled by `make_anisotropic_mesh_3()`: a plain `Triangulation_3` over
/// Mesh_3's geometric traits and data structure. A regular triangulation
/// (Mesh_3's default) asserts in debug builds when it holds a mesh that is not
/// regular, which an anisotropic mesh is not (cgal_conventions.md 6); this
/// type holds any valid mesh and works with `output_to_medit()`,
/// `output_to_vtu()` and the C3T3 iterators.
template <typename MeshDomain>
struct Anisotropic_mesh_triangulation_3 {
  typedef typename CGAL::Mesh_triangulation_3<MeshDomain>::type Mesh_3_triangulation;
  typedef CGAL::Triangulation_3<typename Mesh_3_triangulation::Geom_traits,
                                typename Mesh_3_triangulation::Triangulation_data_structure>
      type;
};

namespace Bubble_mesh_3 {

/// \ingroup PkgBubbleMesh3Classes
/// What `make_anisotropic_mesh_3()` did: counts and seconds per stage.
struct Meshing_report {
  std::array<std::size_t, 4> nodes{{0, 0, 0, 0}}; ///< packed nodes per dimension (corner, curve, patch, interior)
  std::array<double, 4> packing_seconds{{0, 0, 0, 0}};
  std::array<int, 4> packing_iterations{{0, 0, 0, 0}};
  std::array<bool, 4> packing_converged{{true, true, true, true}};
  double estimated_nodes = 0;
  std::size_t boundary_triangles = 0;
  double boundary_seconds = 0;
  std::size_t tets = 0; ///< made by the front (the final count: `final_tets`)
  std::size_t final_tets = 0;
  Advancing_front_statistics front; ///< how the front made them (recoveries, Steiner points)
  /// interior nodes not used: outside the boundary front (between a chord
  /// and a curved wall), or within metric distance 0.25 of it
  std::size_t dropped_outside = 0, dropped_near_boundary = 0;
  /// patch nodes not used: on, or within metric distance 0.1 of, a feature
  /// curve bounding their patch (they would make sliver boundary triangles)
  std::size_t dropped_patch_nodes = 0;
  /// nodes the boundary front added where the packed nodes could not
  /// represent the surface (tips, thin parts, short closed curves)
  std::size_t added_boundary_nodes = 0;
  int boundary_repair_rounds = 0; ///< rebuilds of the boundary front to keep more of them
  double front_seconds = 0;
  bool improved = false;           ///< whether `improve_mesh()` ran
  /// whether its first run made the boundary intersect itself (at a thin
  /// part), so that the improvement was redone with the boundary fixed
  bool improvement_boundary_fixed = false;
  Improvement_report improvement;  ///< its report (quality before and after, flips, moves)
  double validity_seconds = 0;
  /// how far the boundary strays from the input surface: the largest distance
  /// of the boundary triangles to it (sampled over each triangle), the
  /// largest distance of an input vertex to the boundary (absolute, and over
  /// the bounding box diagonal), and |mesh volume - input volume| / input volume
  double surface_distance = 0, surface_distance_relative = 0;
  double input_to_boundary_distance = 0;
  double volume_error = 0;
  /// the bound D the metric was intersected with near the surface
  /// (`surface_distance`; 0: none) and the seconds its curvature estimate took
  double surface_distance_bound = 0, surface_metric_seconds = 0;
  /// small features (`small_feature_refinement`): the corner and curve
  /// samples where the features are closer than the metric's sizes, the
  /// smallest size they ask (0: none), and the seconds their search took
  std::size_t small_feature_samples = 0;
  double smallest_feature_size = 0, feature_size_seconds = 0;
  double c3t3_seconds = 0; ///< padding and conversion (make_anisotropic_mesh_3 only)
  std::size_t padding_tets = 0;
  double total_seconds = 0;
};

/// \ingroup PkgBubbleMesh3Functions
/// The report as a JSON object.
inline std::string to_json(const Meshing_report& r)
{
  using internal::format_json_number;
  auto num = [](double x) { return format_json_number(x); };
  auto arr = [&](const auto& a) {
    std::string s = "[";
    for(std::size_t i = 0; i < a.size(); ++i)
      s += (i ? ", " : "") + num(double(a[i]));
    return s + "]";
  };
  std::string conv = "[";
  for(std::size_t i = 0; i < 4; ++i)
    conv += std::string(i ? ", " : "") + (r.packing_converged[i] ? "true" : "false");
  conv += "]";
  std::ostringstream o;
  o << "{\n    \"estimated_nodes\": " << num(r.estimated_nodes) << ",\n    \"nodes_per_dimension\": " << arr(r.nodes)
    << ",\n    \"packing_seconds\": " << arr(r.packing_seconds) << ",\n    \"packing_iterations\": "
    << arr(r.packing_iterations) << ",\n    \"packing_converged\": " << conv
    << ",\n    \"boundary_triangles\": " << r.boundary_triangles << ",\n    \"added_boundary_nodes\": "
    << r.added_boundary_nodes << ",\n    \"boundary_repair_rounds\": " << r.boundary_repair_rounds << ",\n    \"boundary_seconds\": "
    << num(r.boundary_seconds) << ",\n    \"tets\": " << r.tets << ",\n    \"delaunay_tets\": " << r.front.delaunay_tets
    << ",\n    \"best_quality_tets\": " << r.front.best_quality_tets << ",\n    \"undo_rounds\": " << r.front.undo_rounds
    << ",\n    \"undone_tets\": " << r.front.undone_tets << ",\n    \"search_tets\": " << r.front.search_tets
    << ",\n    \"cavities\": " << r.front.cavities << ",\n    \"cavity_tets\": " << r.front.cavity_tets
    << ",\n    \"vertex_star_fills\": " << r.front.vertex_star_fills << ",\n    \"steiner_star_fills\": "
    << r.front.steiner_star_fills << ",\n    \"tetgen_fills\": " << r.front.tetgen_fills
    << ",\n    \"cavity_enlargements\": " << r.front.cavity_enlargements
    << ",\n    \"removability_tests\": " << r.front.removability_tests
    << ",\n    \"front_work_limit_reached\": " << (r.front.work_limit_reached ? "true" : "false")
    << ",\n    \"steiner_points\": " << r.front.steiner_points << ",\n    \"dropped_interior_nodes_outside\": "
    << r.dropped_outside << ",\n    \"dropped_interior_nodes_near_boundary\": " << r.dropped_near_boundary << ",\n    \"dropped_patch_nodes_near_curves\": " << r.dropped_patch_nodes << ",\n    \"front_seconds\": " << num(r.front_seconds)
    << ",\n    \"final_tets\": " << r.final_tets << ",\n    \"improved\": " << (r.improved ? "true" : "false")
    << ",\n    \"improvement_boundary_fixed\": " << (r.improvement_boundary_fixed ? "true" : "false") << ",\n    \"improvement\": {\"worst_before\": "
    << num(r.improvement.worst_before) << ", \"worst_after\": " << num(r.improvement.worst_after)
    << ", \"p01_before\": " << num(r.improvement.p01_before) << ", \"p01_after\": " << num(r.improvement.p01_after)
    << ", \"flips_2_3\": " << r.improvement.flips_2_3 << ", \"flips_3_2\": " << r.improvement.flips_3_2
    << ", \"flips_4_4\": " << r.improvement.flips_4_4 << ", \"edge_removals\": " << r.improvement.edge_removals
    << ", \"smoothing_moves\": " << r.improvement.smoothing_moves << ", \"edge_splits\": " << r.improvement.edge_splits
    << ", \"boundary_edge_splits\": " << r.improvement.boundary_edge_splits
    << ", \"feature_edge_splits\": " << r.improvement.feature_edge_splits
    << ", \"edge_collapses\": " << r.improvement.edge_collapses
    << ", \"boundary_edge_collapses\": " << r.improvement.boundary_edge_collapses << ", \"seconds\": " << num(r.improvement.seconds)
    << ", \"time_limit_reached\": " << (r.improvement.time_limit_reached ? "true" : "false") << "}"
    << ",\n    \"validity_seconds\": " << num(r.validity_seconds) << ",\n    \"surface_distance\": "
    << num(r.surface_distance) << ",\n    \"surface_distance_relative\": " << num(r.surface_distance_relative)
    << ",\n    \"input_to_boundary_distance\": " << num(r.input_to_boundary_distance)
    << ",\n    \"volume_error\": " << num(r.volume_error) << ",\n    \"surface_distance_bound\": "
    << num(r.surface_distance_bound) << ",\n    \"small_feature_samples\": " << r.small_feature_samples
    << ",\n    \"smallest_feature_size\": " << num(r.smallest_feature_size)
    << ",\n    \"feature_size_seconds\": " << num(r.feature_size_seconds) << ",\n    \"total_seconds\": "
    << num(r.total_seconds) << "\n  }";
  return o.str();
}

/// \ingroup PkgBubbleMesh3Functions
/// A few lines: nodes, tets, how the front made them, seconds per stage.
inline void print_meshing_summary(std::ostream& out, const Meshing_report& r)
{
  std::ostringstream o;
  o.setf(std::ios::fixed);
  o.precision(2);
  o << "nodes:    " << r.nodes[0] + r.nodes[1] + r.nodes[2] + r.nodes[3] << " (corners " << r.nodes[0] << ", curves "
    << r.nodes[1] << ", surfaces " << r.nodes[2] << ", interior " << r.nodes[3] << "; estimate "
    << std::llround(r.estimated_nodes) << ")\n";
  o << "packing:  " << r.packing_seconds[1] << " s curves, " << r.packing_seconds[2] << " s surfaces, "
    << r.packing_seconds[3] << " s interior (iterations " << r.packing_iterations[1] << "/" << r.packing_iterations[2]
    << "/" << r.packing_iterations[3] << (r.packing_converged[1] && r.packing_converged[2] && r.packing_converged[3]
                                               ? ", converged"
                                               : ", iteration cap reached")
    << ")\n";
  o << "boundary: " << r.boundary_triangles << " triangles, " << r.boundary_seconds << " s";
  if(r.added_boundary_nodes > 0)
    o << " (" << r.added_boundary_nodes << " nodes added where the packed ones could not represent the surface, "
      << r.boundary_repair_rounds
      << " repair rounds)";
  o << "\n";
  o << "front:    " << r.tets << " tets, " << r.front_seconds << " s (modified Delaunay " << r.front.delaunay_tets
    << ", best quality " << r.front.best_quality_tets << ", undo rounds " << r.front.undo_rounds << ", cavities " << r.front.cavities
    << ", Steiner points " << r.front.steiner_points << ")\n";
  if(r.front.work_limit_reached)
    o << "front:    stopped at its work budget (" << r.front.removability_tests
      << " removability tests); the cavity fillers closed the rest\n";
  if(r.front.cavities > 0)
    o << "cavities: " << r.front.vertex_star_fills << " closed from a vertex, " << r.front.steiner_star_fills
      << " from a Steiner point, " << r.front.tetgen_fills << " TetGen runs, " << r.front.cavity_enlargements
      << " enlarged and refilled\n";
  if(r.dropped_outside + r.dropped_near_boundary > 0)
    o << "dropped:  " << r.dropped_outside << " interior nodes outside the boundary front, "
      << r.dropped_near_boundary << " too close to it\n";
  if(r.dropped_patch_nodes > 0)
    o << "dropped:  " << r.dropped_patch_nodes << " surface nodes on or next to a feature curve\n";
  if(r.improved) {
    const Improvement_report& i = r.improvement;
    o << "improve:  worst " << i.worst_before << " -> " << i.worst_after << " deg, p01 " << i.p01_before << " -> "
      << i.p01_after << " deg, " << i.tets_after << " tets, " << i.seconds << " s (2-3 " << i.flips_2_3 << ", 3-2 "
      << i.flips_3_2 << ", 4-4 " << i.flips_4_4 << ", edge removals " << i.edge_removals << ", boundary flips "
      << i.boundary_flips << ", moves " << i.smoothing_moves << " of which " << i.boundary_moves << " on the boundary"
      << (i.edge_splits > 0 ? ", edge splits " + std::to_string(i.edge_splits) + " of which " +
                                  std::to_string(i.boundary_edge_splits) + " on the boundary (" +
                                  std::to_string(i.feature_edge_splits) + " on feature curves)"
                            : std::string())
      << (i.edge_collapses > 0 ? ", edge collapses " + std::to_string(i.edge_collapses) + " of which " +
                                     std::to_string(i.boundary_edge_collapses) + " on the boundary"
                               : std::string())
      << (i.time_limit_reached ? ", time limit reached" : "") << ")\n";
    if(r.improvement_boundary_fixed)
      o << "improve:  its first run made the boundary intersect itself at a thin part: redone with the boundary "
           "fixed\n";
  }
  o.precision(3);
  o << "surface:  boundary within " << r.surface_distance;
  if(r.surface_distance_bound > 0)
    o << " (bound " << r.surface_distance_bound << ")";
  o << " of the input (" << 100 * r.surface_distance_relative
    << " % of the diagonal), input within " << r.input_to_boundary_distance << " of the boundary, volume error "
    << 100 * r.volume_error << " %\n";
  o.precision(2);
  o << "total:    " << r.total_seconds << " s\n";
  out << o.str();
}

/// \ingroup PkgBubbleMesh3Functions
/// `field` intersected near the surface of `domain` (a
/// `Polyhedral_mesh_domain_with_features_3` after `detect_features()`: its
/// patches) with the metric that keeps the boundary within `distance` of it
/// (`CGAL::Surface_approximation_metric_field_3`). A negative `distance` is
/// the default, the bounding box diagonal times
/// `default_relative_surface_distance`; 0 or infinity: no bound (the field
/// returned is then `field` itself). This is the field
/// `make_anisotropic_mesh_3()` meshes with its `surface_distance` parameter:
/// measure the mesh's quality in it.
template <typename MeshDomain, typename MetricField>
CGAL::Surface_approximation_metric_field_3<MetricField>
make_surface_approximation_metric_field_3(const MeshDomain& domain, const MetricField& field, double distance = -1)
{
  if(std::isnan(distance))
    throw Invalid_input("surface distance: not a number");
  if(distance == 0 || std::isinf(distance))
    return CGAL::Surface_approximation_metric_field_3<MetricField>(field, {}, {}, {},
                                                                   std::numeric_limits<double>::infinity());
  const internal::front::Boundary_surface surface = internal::front::boundary_surface_from_polyhedral_domain(domain);
  if(surface.points.empty())
    throw Invalid_input("domain: the polyhedral surface has no faces");
  if(distance < 0) {
    std::array<double, 3> lo = surface.points.front(), hi = lo;
    for(const auto& p : surface.points)
      for(int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], p[k]);
        hi[k] = std::max(hi[k], p[k]);
      }
    distance = default_relative_surface_distance * std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
                                                             (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                                             (hi[2] - lo[2]) * (hi[2] - lo[2]));
  }
  return CGAL::Surface_approximation_metric_field_3<MetricField>(field, surface.points, surface.triangles,
                                                                 surface.patches, distance);
}

namespace internal {

inline double seconds_since(std::chrono::steady_clock::time_point t0)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The settings resolved from the named parameters.
struct Meshing_settings {
  unsigned int seed = 0;
  int threads = 0;
  int iterations = 400;
  double maximum_bubbles = default_maximum_number_of_nodes;
  double time_limit = std::numeric_limits<double>::infinity();
  std::function<bool()> should_stop;
  bool allow_steiner = true;
  bool verbose = false;
  bool improve = true;
  double improve_time_limit = std::numeric_limits<double>::infinity();
  std::function<void(const std::string&)> progress;
  Meshing_report* report = nullptr;
  /// the surface-approximation bound: 0 or infinite for none (the default),
  /// negative for a fraction of the bounding box diagonal
  double surface_distance = 0;
  /// refine the metric where corners and curves are closer than its sizes
  bool small_feature_refinement = true;
};

template <typename NP>
Meshing_settings resolve_settings(const NP& np)
{
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  Meshing_settings s;
  s.seed = choose_parameter(get_parameter(np, CGAL::internal_np::random_seed), 0u);
  s.threads = choose_parameter(get_parameter(np, Bubble_mesh_3::internal_np::number_of_threads), 0);
  s.iterations = choose_parameter(get_parameter(np, CGAL::internal_np::number_of_iterations), 400);
  s.maximum_bubbles = choose_parameter(get_parameter(np, Bubble_mesh_3::internal_np::maximum_number_of_bubbles),
                                       default_maximum_number_of_nodes);
  s.time_limit = choose_parameter(get_parameter(np, Bubble_mesh_3::internal_np::time_limit),
                                  std::numeric_limits<double>::infinity());
  s.should_stop = choose_parameter(get_parameter(np, Bubble_mesh_3::internal_np::should_stop),
                                   std::function<bool()>());
  s.allow_steiner = choose_parameter(get_parameter(np, Bubble_mesh_3::internal_np::allow_steiner_points), true);
  s.verbose = choose_parameter(get_parameter(np, CGAL::internal_np::verbose), false);
  s.improve = choose_parameter(get_parameter(np, Bubble_mesh_3::internal_np::mesh_improvement), true);
  s.improve_time_limit =
      choose_parameter(get_parameter(np, Bubble_mesh_3::internal_np::improvement_time_limit),
                       std::numeric_limits<double>::infinity());
  s.progress = choose_parameter(get_parameter(np, CGAL::internal_np::callback),
                                std::function<void(const std::string&)>());
  s.report = choose_parameter(get_parameter(np, Bubble_mesh_3::internal_np::meshing_report),
                              static_cast<Meshing_report*>(nullptr));
  s.surface_distance = choose_parameter(get_parameter(np, Bubble_mesh_3::internal_np::surface_distance), 0.0);
  if(std::isnan(s.surface_distance))
    throw Invalid_input("surface_distance: not a number");
  s.small_feature_refinement =
      choose_parameter(get_parameter(np, Bubble_mesh_3::internal_np::small_feature_refinement), true);
  return s;
}

/// The check points of a run: throws `Interrupted` once `should_stop` returns
/// true and `Time_limit_exceeded` once the time limit has passed (the time is
/// not checked after the improvement, which is cut to the time left instead).
class Stop_check {
public:
  Stop_check(const Meshing_settings& s, std::chrono::steady_clock::time_point start)
    : limit_(s.time_limit), should_stop_(s.should_stop), start_(start)
  {}
  bool active() const { return bool(should_stop_) || limit_ < std::numeric_limits<double>::infinity(); }
  /// seconds left before the limit (infinite without one)
  double remaining() const { return limit_ - seconds_since(start_); }
  void operator()(const std::string& stage, bool check_time = true) const
  {
    if(should_stop_ && should_stop_())
      throw Interrupted("interrupted during " + stage);
    if(check_time && limit_ < std::numeric_limits<double>::infinity() && remaining() < 0) {
      std::ostringstream o;
      o << "time limit of " << limit_ << " s reached during " << stage;
      throw Time_limit_exceeded(o.str());
    }
  }

private:
  double limit_;
  std::function<bool()> should_stop_;
  std::chrono::steady_clock::time_point start_;
};

// A stage's parameters get the check as `should_stop` when they have that
// member (the packer, front and improver may offer it); the check throws.
template <typename P, typename = void>
struct Has_should_stop : std::false_type {};
template <typename P>
struct Has_should_stop<P, std::void_t<decltype(std::declval<P&>().should_stop = std::function<bool()>())>>
    : std::true_type {};
template <typename P>
void install_stop_check(P& parameters, const Stop_check& check, const std::string& stage, bool check_time = true)
{
  if constexpr(Has_should_stop<P>::value) {
    if(check.active())
      parameters.should_stop = [check, stage, check_time]() {
        check(stage, check_time);
        return false;
      };
  } else {
    (void)parameters, (void)check, (void)stage, (void)check_time;
  }
}

/// Refuses a domain whose boundary cannot be meshed (`check_triangle_surface()`
/// on all its polyhedra together), before any expensive work.
template <typename MeshDomain>
void check_domain_surface(const MeshDomain& domain)
{
  typedef typename std::decay_t<decltype(domain.polyhedra().front())>::Traits::Point_3 Point;
  CGAL::Surface_mesh<Point> sm;
  for(const auto& poly : domain.polyhedra())
    CGAL::copy_face_graph(poly, sm);
  if(num_faces(sm) == 0)
    throw Invalid_input("domain: the polyhedral surface has no faces");
  if(!CGAL::is_closed(sm))
    throw Invalid_input("domain: the surface is not closed");
  if(!CGAL::is_triangle_mesh(sm))
    throw Invalid_input("domain: the surface has faces that are not triangles");
  const std::string problem = IO::check_triangle_surface(sm, false);
  if(!problem.empty())
    throw Invalid_input("domain: " + problem);
}

/// Where each vertex of the domain mesh lies in the domain (for the C3T3).
struct Domain_mesh {
  Indexed_tet_mesh_3 mesh;
  std::vector<C3t3_vertex_location> locations;
};

/// The C3T3 locations after the improvement: a kept vertex keeps its own
/// (`new_vertex_index`: empty if none was removed), a split vertex gets its
/// curve if on a feature edge, its patch if in a boundary triangle, else
/// its subdomain (`point_refs`: the index).
inline void relocate_after_improvement(const Indexed_tet_mesh_3& m, const std::vector<int>& new_vertex_index,
                                       std::vector<C3t3_vertex_location>& locations)
{
  std::vector<C3t3_vertex_location> moved(m.points.size(), C3t3_vertex_location{3, 0});
  std::vector<char> known(m.points.size(), 0);
  for(std::size_t v = 0; v < locations.size(); ++v) {
    const int w = new_vertex_index.empty() ? int(v) : new_vertex_index[v];
    if(w >= 0) {
      moved[std::size_t(w)] = locations[v];
      known[std::size_t(w)] = 1;
    }
  }
  if(std::find(known.begin(), known.end(), char(0)) != known.end()) {
    std::vector<int> dimension(m.points.size(), 3);
    for(const auto& f : m.triangles)
      for(int v : f)
        dimension[std::size_t(v)] = 2;
    for(const auto& e : m.edges)
      for(int v : e)
        dimension[std::size_t(v)] = 1;
    for(std::size_t v = 0; v < m.points.size(); ++v)
      if(!known[v])
        moved[v] = C3t3_vertex_location{dimension[v], m.point_refs[v]};
  }
  locations = std::move(moved);
}

/// The domain's curve id of each feature chain of the input surface: the
/// curve of a packed curve node on a front feature edge over that chain, or,
/// for a chain without one (between two corners, all its nodes added by the
/// boundary front), the domain curve with the same two ends whose length is
/// closest to the chain's. -1 for a chain the front does not use.
template <typename Kernel, typename MeshDomain>
std::vector<int> curves_of_feature_chains(const MeshDomain& domain, const front::Boundary_surface& surface,
                                          const front::Feature_chains& chains, const front::Boundary_front& bf,
                                          const std::vector<C3t3_vertex_location>& locations)
{
  std::vector<int> curve(chains.chains.size(), -1);
  std::vector<char> used(chains.chains.size(), 0);
  for(std::size_t i = 0; i < bf.feature_edges.size(); ++i) {
    const int chain = chains.chain_of_edge[std::size_t(bf.feature_edge_sources[i])];
    used[std::size_t(chain)] = 1;
    for(int v : bf.feature_edges[i])
      if(locations[std::size_t(v)].dimension == 1 && locations[std::size_t(v)].index >= 0)
        curve[std::size_t(chain)] = locations[std::size_t(v)].index;
  }
  typedef typename Kernel::Point_3 Point;
  std::vector<std::tuple<typename MeshDomain::Curve_index, std::pair<Point, typename MeshDomain::Index>,
                         std::pair<Point, typename MeshDomain::Index>>>
      curves;
  domain.get_curves(std::back_inserter(curves));
  for(std::size_t c = 0; c < curve.size(); ++c) {
    if(curve[c] >= 0 || !used[c])
      continue;
    const auto& a = surface.points[std::size_t(chains.chains[c].ends[0])];
    const auto& b = surface.points[std::size_t(chains.chains[c].ends[1])];
    auto same = [](const Point& p, const std::array<double, 3>& q) {
      return CGAL::to_double(p.x()) == q[0] && CGAL::to_double(p.y()) == q[1] && CGAL::to_double(p.z()) == q[2];
    };
    // a closed loop without corner: the domain's cycle through one of its vertices
    const bool loop = chains.chains[c].ends[0] == chains.chains[c].ends[1];
    std::set<std::array<double, 3>> loop_points;
    if(loop)
      for(int e : chains.chains[c].edges)
        for(int v : surface.feature_edges[std::size_t(e)])
          loop_points.insert(surface.points[std::size_t(v)]);
    auto on_loop = [&](const Point& p) {
      return loop_points.count({{CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())}}) != 0;
    };
    double best = std::numeric_limits<double>::max();
    for(const auto& dc : curves) {
      const Point &ca = std::get<1>(dc).first, &cb = std::get<2>(dc).first;
      const bool ends_match = loop ? ca == cb && on_loop(ca)
                                   : (same(ca, a) && same(cb, b)) || (same(ca, b) && same(cb, a));
      if(!ends_match)
        continue;
      const double d = std::abs(CGAL::to_double(domain.curve_length(std::get<0>(dc))) - chains.chains[c].length);
      if(d < best) {
        best = d;
        curve[c] = static_cast<int>(std::get<0>(dc));
      }
    }
    if(curve[c] < 0)
      throw Meshing_failure("boundary front: a feature curve of the surface is not a curve of the domain");
  }
  return curve;
}

template <typename F>
struct Is_surface_approximation_field : std::false_type {};
template <typename F>
struct Is_surface_approximation_field<CGAL::Surface_approximation_metric_field_3<F>> : std::true_type {};
template <typename F>
struct Is_feature_size_field : std::false_type {};
template <typename F>
struct Is_feature_size_field<CGAL::Feature_size_metric_field_3<F>> : std::true_type {};

template <typename MeshDomain, typename MetricField>
Domain_mesh mesh_checked_domain(const MeshDomain& domain, const MetricField& field, const Meshing_settings& s,
                                std::chrono::steady_clock::time_point t_start, Meshing_report& rep);

template <typename MetricField>
void report_feature_sizes(const CGAL::Feature_size_metric_field_3<MetricField>& field, const Meshing_settings& s,
                          Meshing_report& rep)
{
  const auto& st = field.statistics();
  rep.small_feature_samples = st.refined_samples;
  rep.smallest_feature_size = field.refines() ? st.smallest_size : 0;
  rep.feature_size_seconds = st.seconds;
  if(s.progress && field.refines()) {
    std::ostringstream m;
    m << "small features: " << st.refined_samples << " of " << st.samples
      << " corner and curve samples closer than the metric's size, sizes down to " << st.smallest_size << " ("
      << st.smallest_ratio << " of the metric's)";
    if(st.floored_samples > 0)
      m << ", " << st.floored_samples << " raised to " << field.smallest_relative_size() << " of it";
    m << ", " << rep.feature_size_seconds << " s";
    s.progress(m.str());
  }
}

/// The feature sizes over `field` (unless turned off), then the meshing.
template <typename MeshDomain, typename MetricField>
Domain_mesh mesh_with_feature_sizes(const MeshDomain& domain, const MetricField& field, const Meshing_settings& s,
                                    std::chrono::steady_clock::time_point t_start, Meshing_report& rep)
{
  const auto refined = s.small_feature_refinement ? make_feature_size_metric_field_3(domain, field)
                                                  : CGAL::Feature_size_metric_field_3<MetricField>(field);
  report_feature_sizes(refined, s, rep);
  Stop_check(s, t_start)("the feature sizes");
  return mesh_checked_domain(domain, refined, s, t_start, rep);
}

/// The whole pipeline up to the domain's tet mesh: input checks, the
/// surface-approximation metric, the small features' sizes, packing,
/// boundary front, advancing front, improvement, validity. The field meshed
/// is always a `Feature_size_metric_field_3` (one instantiation of the
/// stages): the user's field, intersected with the curvature sizes of the
/// surface-distance bound if any, refined at small features; a field the
/// caller built as either is used as it is.
template <typename MeshDomain, typename MetricField>
Domain_mesh mesh_domain(const MeshDomain& domain, const MetricField& field, const Meshing_settings& s)
{
  const auto t_start = std::chrono::steady_clock::now();
  Meshing_report local_report;
  Meshing_report& rep = s.report ? *s.report : local_report;
  rep = Meshing_report();

  // 0. the domain's surface (a bad one would fail only after the packing)
  check_domain_surface(domain);
  Stop_check(s, t_start)("the input checks");

  if constexpr(Is_feature_size_field<MetricField>::value) {
    if constexpr(Is_surface_approximation_field<typename MetricField::Base_field>::value)
      rep.surface_distance_bound = field.base_field().bounded() ? field.base_field().distance() : 0;
    report_feature_sizes(field, s, rep);
    return mesh_checked_domain(domain, field, s, t_start, rep);
  } else if constexpr(Is_surface_approximation_field<MetricField>::value) {
    rep.surface_distance_bound = field.bounded() ? field.distance() : 0;
    return mesh_with_feature_sizes(domain, field, s, t_start, rep);
  } else {
    // the user's metric near the surface intersected with the one that keeps
    // the boundary within the bound (without a bound the field passes the
    // user's metric through)
    const auto t0 = std::chrono::steady_clock::now();
    const auto approximating = make_surface_approximation_metric_field_3(domain, field, s.surface_distance);
    rep.surface_distance_bound = approximating.bounded() ? approximating.distance() : 0;
    rep.surface_metric_seconds = seconds_since(t0);
    if(s.progress && approximating.bounded())
      s.progress("surface metric: curvature sizes for a distance bound of " +
                 std::to_string(rep.surface_distance_bound) + ", " + std::to_string(rep.surface_metric_seconds) +
                 " s");
    return mesh_with_feature_sizes(domain, approximating, s, t_start, rep);
  }
}

template <typename MeshDomain, typename MetricField>
Domain_mesh mesh_checked_domain(const MeshDomain& domain, const MetricField& field, const Meshing_settings& s,
                                std::chrono::steady_clock::time_point t_start, Meshing_report& rep)
{
  namespace F = Bubble_mesh_3::internal::front;
  typedef typename MetricField::Kernel K;
  auto say = [&](const std::string& m) {
    if(s.progress)
      s.progress(m);
  };
  const Stop_check stop(s, t_start);

  // 1. packing
  typedef CGAL::Bubble_packer_3<MeshDomain, MetricField> Packer;
  typename Packer::Parameters pp;
  pp.seed = s.seed;
  pp.number_of_threads = s.threads;
  pp.maximum_iterations = s.iterations;
  pp.maximum_number_of_bubbles = s.maximum_bubbles;
  install_stop_check(pp, stop, "the packing");
  Packer packer(domain, field, pp);
  try {
    rep.estimated_nodes = packer.estimated_number_of_bubbles();
  } catch(const Invalid_input& e) {
    // the packer's refusal: add the limit and what to do
    const std::string what = e.what();
    if(what.find("exceeds maximum_number_of_bubbles") == std::string::npos)
      throw;
    throw Invalid_input(what + " = " + std::to_string(std::llround(s.maximum_bubbles)) +
                        " (a run needs about 2.6 kB of memory per node; raise maximum_number_of_bubbles or "
                        "--max-nodes, or coarsen the metric)");
  }
  say("estimated nodes: " + std::to_string(std::llround(rep.estimated_nodes)));
  stop("the packing");
  const char* stage_names[4] = {"corners", "curves", "surfaces", "volume"};
  for(int d = 0; d < 4; ++d) {
    switch(d) {
    case 0: packer.pack_corners(); break;
    case 1: packer.pack_curves(); break;
    case 2: packer.pack_surfaces(); break;
    default: packer.pack_volume(); break;
    }
    const auto& st = packer.statistics().stages[d];
    rep.nodes[d] = st.bubbles;
    rep.packing_seconds[d] = st.seconds;
    rep.packing_iterations[d] = st.iterations;
    rep.packing_converged[d] = st.converged;
    say(std::string("packed ") + stage_names[d] + ": " + std::to_string(st.bubbles) + " bubbles, " +
        std::to_string(st.iterations) + " iterations, " + std::to_string(st.seconds) + " s");
    stop(std::string("the packing (after the ") + stage_names[d] + ")");
  }
  const auto nodes = packer.nodes();

  // 2. boundary front on the surface nodes (they come first in the point list)
  auto t0 = std::chrono::steady_clock::now();
  const F::Boundary_surface surface = F::boundary_surface_from_polyhedral_domain(domain);
  std::vector<F::Boundary_node> bnodes;
  std::vector<int> point_of_node(nodes.size(), -1);
  Domain_mesh out;
  Indexed_tet_mesh_3& m = out.mesh;
  std::vector<typename Anisotropic_advancing_front_3<MetricField>::Point_3> points;
  auto add_point = [&](const typename K::Point_3& p, int dim, int index) {
    const double x = CGAL::to_double(p.x()), y = CGAL::to_double(p.y()), z = CGAL::to_double(p.z());
    points.emplace_back(x, y, z);
    m.points.push_back({{x, y, z}});
    m.point_refs.push_back(index);
    out.locations.push_back(C3t3_vertex_location{dim, index});
  };
  // Patch nodes on a feature curve bounding their patch, or within metric
  // distance 0.1 of it, are dropped (counted). The surface packer keeps a
  // bubble on its patch by a wall at the patch boundary, but a step that
  // overshoots the wall by less than its rounding allowance ends on the
  // curve itself (a 1:100 metric oblique to the faces of a cube did it): the
  // boundary front then refused the node ("of dimension 2 lies on a feature
  // curve", exit 2 for valid input). Closer than 0.1 the node would only make
  // a sliver triangle against the curve, whose own nodes stand.
  typedef CGAL::Exact_predicates_inexact_constructions_kernel EK;
  std::vector<EK::Segment_3> feature_segments;
  std::vector<std::array<int, 2>> segment_patches; // the patches on both sides
  typedef CGAL::AABB_segment_primitive<EK, typename std::vector<EK::Segment_3>::const_iterator> Segment_primitive;
  CGAL::AABB_tree<CGAL::AABB_traits<EK, Segment_primitive>> segment_tree;
  {
    std::map<std::pair<int, int>, std::array<int, 2>> sides;
    for(const auto& e : surface.feature_edges)
      sides.emplace(std::minmax(e[0], e[1]), std::array<int, 2>{{-1, -1}});
    for(std::size_t f = 0; f < surface.triangles.size(); ++f)
      for(int k = 0; k < 3; ++k) {
        auto it = sides.find(std::minmax(surface.triangles[f][k], surface.triangles[f][(k + 1) % 3]));
        if(it != sides.end())
          it->second[it->second[0] < 0 ? 0 : 1] = surface.patches[f];
      }
    for(const auto& e : sides) {
      const auto &a = surface.points[e.first.first], &b = surface.points[e.first.second];
      feature_segments.emplace_back(EK::Point_3(a[0], a[1], a[2]), EK::Point_3(b[0], b[1], b[2]));
      segment_patches.push_back(e.second);
    }
    if(!feature_segments.empty()) {
      segment_tree.insert(feature_segments.begin(), feature_segments.end());
      segment_tree.accelerate_distance_queries();
    }
  }
  auto too_close_to_a_curve = [&](const std::array<double, 3>& x, int patch) {
    if(feature_segments.empty())
      return false;
    const EK::Point_3 q(x[0], x[1], x[2]);
    const auto cp = segment_tree.closest_point_and_primitive(q);
    const std::size_t si = static_cast<std::size_t>(cp.second - feature_segments.begin());
    if(segment_patches[si][0] != patch && segment_patches[si][1] != patch)
      return false;
    // the distance in the node's metric to that segment (closest point in the metric)
    const Metric_3 mq = Metric_3(field(typename K::Point_3(x[0], x[1], x[2])));
    const EK::Segment_3& sg = feature_segments[si];
    const Eigen::Vector3d a(sg.source().x(), sg.source().y(), sg.source().z());
    const Eigen::Vector3d ab = Eigen::Vector3d(sg.target().x(), sg.target().y(), sg.target().z()) - a;
    const Eigen::Vector3d p(x[0], x[1], x[2]);
    const double l2 = mq.squared_length(ab);
    const double t = l2 > 0 ? std::clamp((p - a).dot(mq.matrix() * ab) / l2, 0.0, 1.0) : 0.0;
    return mq.length(a + t * ab - p) < 0.1;
  };
  for(std::size_t i = 0; i < nodes.size(); ++i) {
    const auto& n = nodes[i];
    if(n.dimension > 2)
      continue;
    int index = 0;
    if(n.dimension == 0)
      index = static_cast<int>(domain.corner_index(n.index));
    else if(n.dimension == 1)
      index = static_cast<int>(domain.curve_index(n.index));
    else
      index = static_cast<int>(domain.surface_patch_index(n.index));
    if(n.dimension == 2 &&
       too_close_to_a_curve({{CGAL::to_double(n.point.x()), CGAL::to_double(n.point.y()), CGAL::to_double(n.point.z())}},
                            index)) {
      ++rep.dropped_patch_nodes;
      continue;
    }
    F::Boundary_node b;
    b.point = {{CGAL::to_double(n.point.x()), CGAL::to_double(n.point.y()), CGAL::to_double(n.point.z())}};
    b.dimension = n.dimension;
    b.patch = n.dimension == 2 ? index : -1;
    bnodes.push_back(b);
    point_of_node[i] = static_cast<int>(points.size());
    add_point(n.point, n.dimension, index);
    if(n.dimension == 0)
      m.corners.push_back(point_of_node[i]);
  }
  if(rep.dropped_patch_nodes > 0)
    say("dropped surface nodes: " + std::to_string(rep.dropped_patch_nodes) +
        " on or within 0.1 of a feature curve bounding their patch");
  // The nodes come from the packer, not from the user: a node the front
  // cannot place is a meshing failure (exit 3), not invalid input.
  F::Boundary_front bf;
  try {
    bf = F::build_boundary_front(surface, bnodes, field);
  } catch(const Invalid_metric&) {
    throw;
  } catch(const Invalid_input& e) {
    throw Meshing_failure(e.what());
  }
  rep.boundary_triangles = bf.triangles.size();
  rep.boundary_seconds = seconds_since(t0);
  say("boundary front: " + std::to_string(bf.triangles.size()) + " triangles, " + std::to_string(rep.boundary_seconds) +
      " s");
  stop("the boundary front");
  // nodes the front added (it counts them); their curve ids follow
  for(const auto& a : bf.added_nodes) {
    add_point(typename K::Point_3(a.point[0], a.point[1], a.point[2]), a.dimension, a.dimension == 2 ? a.patch : -1);
    if(a.dimension == 0)
      m.corners.push_back(static_cast<int>(points.size()) - 1);
  }
  rep.added_boundary_nodes = bf.added_nodes.size();
  rep.boundary_repair_rounds = bf.repair_rounds;
  if(!bf.added_nodes.empty())
    say("boundary front: added " + std::to_string(bf.added_nodes.size()) +
        " nodes where the packed nodes could not represent the surface");
  m.triangles = bf.triangles;
  m.triangle_refs = bf.patches;
  // feature edges: the curve of the input chain each one runs along
  std::vector<char> is_corner(surface.points.size(), 0);
  {
    std::map<std::array<double, 3>, int> vertex_at;
    for(std::size_t v = 0; v < surface.points.size(); ++v)
      vertex_at.emplace(surface.points[v], int(v));
    for(int c : m.corners) {
      const auto& p = m.points[std::size_t(c)];
      const auto it = vertex_at.find(p);
      int v = it != vertex_at.end() ? it->second : -1;
      if(v < 0) { // off by a rounding: the closest input vertex
        double best = std::numeric_limits<double>::max();
        for(std::size_t u = 0; u < surface.points.size(); ++u) {
          const auto& q = surface.points[u];
          const double d = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
          if(d < best) {
            best = d;
            v = int(u);
          }
        }
      }
      if(v >= 0)
        is_corner[std::size_t(v)] = 1;
    }
  }
  const F::Feature_chains chains = F::feature_chains(surface, is_corner);
  const std::vector<int> chain_curves = curves_of_feature_chains<K>(domain, surface, chains, bf, out.locations);
  m.edges = bf.feature_edges;
  for(std::size_t i = 0; i < bf.feature_edges.size(); ++i) {
    const int curve = chain_curves[std::size_t(chains.chain_of_edge[std::size_t(bf.feature_edge_sources[i])])];
    m.edge_refs.push_back(curve);
    for(int v : bf.feature_edges[i])
      if(out.locations[std::size_t(v)].dimension == 1 && out.locations[std::size_t(v)].index < 0)
        out.locations[std::size_t(v)].index = m.point_refs[std::size_t(v)] = curve; // an added curve node
  }

  // 3. interior nodes, then the advancing front. The front's chords cut
  //    curved walls: an interior node packed between a chord and the true
  //    surface lies outside the front, and one very close to a front triangle
  //    would only make a flat tet; both are dropped (counted).
  int subdomain = 1;
  {
    typedef typename K::Point_3 P;
    typedef CGAL::Surface_mesh<P> Front_mesh;
    Front_mesh fm;
    std::vector<typename Front_mesh::Vertex_index> vi;
    for(const auto& p : points)
      vi.push_back(fm.add_vertex(P(p.x(), p.y(), p.z())));
    for(const auto& t : m.triangles)
      fm.add_face(vi[t[0]], vi[t[1]], vi[t[2]]);
    const CGAL::Side_of_triangle_mesh<Front_mesh, K> side(fm);
    typedef CGAL::AABB_face_graph_triangle_primitive<Front_mesh> Primitive;
    CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>> tree(faces(fm).first, faces(fm).second, fm);
    tree.accelerate_distance_queries();
    for(std::size_t i = 0; i < nodes.size(); ++i) {
      if(nodes[i].dimension != 3)
        continue;
      const P q(CGAL::to_double(nodes[i].point.x()), CGAL::to_double(nodes[i].point.y()),
                CGAL::to_double(nodes[i].point.z()));
      if(side(q) != CGAL::ON_BOUNDED_SIDE) {
        ++rep.dropped_outside;
        continue;
      }
      const P c = tree.closest_point(q);
      const Metric_3 mq = Metric_3(field(q));
      if(mq.length(Eigen::Vector3d(CGAL::to_double(c.x() - q.x()), CGAL::to_double(c.y() - q.y()),
                                   CGAL::to_double(c.z() - q.z()))) < 0.25) {
        ++rep.dropped_near_boundary;
        continue;
      }
      subdomain = static_cast<int>(domain.subdomain_index(nodes[i].index));
      point_of_node[i] = static_cast<int>(points.size());
      add_point(nodes[i].point, 3, subdomain);
    }
  }
  if(rep.dropped_outside + rep.dropped_near_boundary > 0)
    say("dropped interior nodes: " + std::to_string(rep.dropped_outside) + " outside the boundary front, " +
        std::to_string(rep.dropped_near_boundary) + " within 0.25 of it");
  t0 = std::chrono::steady_clock::now();
  typedef Anisotropic_advancing_front_3<MetricField> Front;
  typename Front::Parameters fp;
  fp.allow_steiner_points = s.allow_steiner;
  // The progress hook doubles as a check point: every 2,000 tets when a stop
  // is possible (about 50 ms of work), the messages every 100,000.
  const std::size_t message_interval = fp.progress_interval;
  if(stop.active())
    fp.progress_interval = 2000;
  if(s.progress || stop.active())
    fp.progress = [&, message_interval](std::size_t tets, std::size_t front) {
      stop("the advancing front");
      if(tets % message_interval == 0)
        say("advancing front: " + std::to_string(tets) + " tets, front " + std::to_string(front) + " triangles");
    };
  install_stop_check(fp, stop, "the advancing front");
  Front front(field, fp);
  const typename Front::Result r = front.run(points, m.triangles);
  rep.front_seconds = seconds_since(t0);
  const auto& fs = r.statistics;
  rep.tets = r.tets.size();
  rep.front = fs;
  say("advancing front: " + std::to_string(r.tets.size()) + " tets, " + std::to_string(rep.front_seconds) + " s");
  for(std::size_t i = points.size(); i < r.points.size(); ++i) {
    const auto& p = r.points[i];
    m.points.push_back({{p.x(), p.y(), p.z()}});
    m.point_refs.push_back(subdomain);
    out.locations.push_back(C3t3_vertex_location{3, subdomain});
  }
  m.tets = r.tets;
  m.tet_refs.assign(m.tets.size(), subdomain);
  if(fs.unused_nodes > 0) {
    // nodes outside the boundary front (should not happen with the packer's nodes)
    throw Meshing_failure("advancing front: " + std::to_string(fs.unused_nodes) +
                          " packed nodes lie outside the boundary front");
  }

  stop("the advancing front");

  // 4. quality: metric flips and smoothing (boundary and features unchanged).
  //    A run time limit cuts the improvement to the time left (the mesh
  //    stays valid) instead of throwing.
  if(s.improve) {
    Improvement_options io;
    io.time_limit_seconds = s.improve_time_limit;
    if(s.time_limit < std::numeric_limits<double>::infinity()) {
      const double own = s.improve_time_limit < 0 ? 2.0 + 1e-4 * double(m.tets.size()) : s.improve_time_limit;
      io.time_limit_seconds = std::max(0.0, std::min(own, stop.remaining()));
    }
    install_stop_check(io, stop, "the improvement", false);
    // boundary vertices inside curved patches and curved feature curves
    // slide on the input surface and on its feature polylines
    const improve::Input_projections projections(surface, chains, chain_curves);
    io.surface_projection = [&projections](int ref, const std::array<double, 3>& p, std::array<double, 3>& q) {
      return projections.surface(ref, p, q);
    };
    io.curve_projection = [&projections](int ref, const std::array<double, 3>& p, std::array<double, 3>& q) {
      return projections.curve(ref, p, q);
    };
    // where flips and moves are stuck, collapse short edges and split others
    // (vertices removed and added: the locations follow below)
    io.edge_splits = true;
    io.edge_collapses = true;
    // Boundary moves, curved flips, splits and collapses each keep the
    // triangles near the surface, but at a thin part (a tip thinner than the
    // sizes) they can push a triangle through the opposite side: then the
    // improvement is done again on the front's mesh with the boundary fixed.
    Indexed_tet_mesh_3 front_mesh = m;
    rep.improvement = improve_mesh(m, field, io);
    if(boundary_self_intersections(m) > 0) {
      say("improvement: the boundary it changed intersects itself at a thin part; improving again with the "
          "boundary fixed");
      m = std::move(front_mesh);
      io.boundary_smoothing = false; // no projections either: only interior moves, flips and splits
      if(s.time_limit < std::numeric_limits<double>::infinity())
        io.time_limit_seconds = std::max(0.0, std::min(io.time_limit_seconds, stop.remaining()));
      rep.improvement = improve_mesh(m, field, io);
      rep.improvement_boundary_fixed = true;
    }
    rep.improved = true;
    relocate_after_improvement(m, rep.improvement.new_vertex_index, out.locations);
    say("improvement: worst metric min dihedral " + std::to_string(rep.improvement.worst_before) + " -> " +
        std::to_string(rep.improvement.worst_after) + " deg, " + std::to_string(rep.improvement.seconds) + " s");
  }

  rep.final_tets = m.tets.size();

  // 5. validity: never hand out an invalid mesh
  stop("the improvement", false);
  t0 = std::chrono::steady_clock::now();
  Validity_options vo;
  vo.require_outward_triangles = true;
  vo.check_boundary_self_intersections = false; // checked after the improvement (above), or the front's
  const Validity_report vr = check_validity(m, vo);
  rep.validity_seconds = seconds_since(t0);
  if(!vr.is_valid()) {
    std::string first = vr.problems.empty() ? std::string() : vr.problems.front();
    throw Meshing_failure("the mesh failed the validity check (" + std::to_string(vr.number_of_problems) +
                          " problems; first: " + first + ")");
  }
  const Surface_fidelity fidelity = surface_fidelity(surface, m);
  rep.surface_distance = fidelity.mesh_to_surface;
  rep.surface_distance_relative = fidelity.diagonal > 0 ? fidelity.mesh_to_surface / fidelity.diagonal : 0;
  rep.input_to_boundary_distance = fidelity.surface_to_mesh;
  rep.volume_error = fidelity.volume_error;
  rep.total_seconds = seconds_since(t_start);
  return out;
}

} // namespace internal

/// \ingroup PkgBubbleMesh3Functions
/// The anisotropic mesh of `domain` as plain arrays (what MEDIT files hold):
/// boundary triangles with their patch ids, feature edges with their curve
/// ids, corners, tets with their subdomain id. Same parameters as
/// `CGAL::make_anisotropic_mesh_3()`; no padding, no C3T3.
template <typename MeshDomain, typename MetricField, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Indexed_tet_mesh_3 make_indexed_anisotropic_mesh_3(const MeshDomain& domain, const MetricField& field,
                                                   const NamedParameters& np = CGAL::parameters::default_values())
{
  return internal::mesh_domain(domain, field, internal::resolve_settings(np)).mesh;
}

} // namespace Bubble_mesh_3

/// \ingroup PkgBubbleMesh3Functions
/// Generates an anisotropic tetrahedral mesh of `domain` whose edges have
/// metric length about 1 in `field`: bubble packing (corners, curves,
/// patches, interior), boundary front on the surface nodes, anisotropic
/// advancing front. The complex holds the domain's cells (subdomain index),
/// boundary facets (surface patch index), feature edges (curve index) and
/// corners; the rest of the triangulation's convex hull is filled with cells
/// of subdomain 0 (exterior padding by TetGen's constrained tetrahedralization
/// of the box minus the domain; a build without TetGen handles convex domains
/// only and throws `Bubble_mesh_3::Meshing_failure` otherwise).
///
/// \tparam C3T3 `Mesh_complex_3_in_triangulation_3<Tr, MeshDomain::Corner_index,
///   MeshDomain::Curve_index>` with `Tr = Anisotropic_mesh_triangulation_3<MeshDomain>::type`
/// \tparam MeshDomain `Polyhedral_mesh_domain_with_features_3` (after `detect_features()`)
/// \tparam MetricField a model of `MetricField_3`
///
/// \cgalNamedParamsBegin
///   \cgalParamNBegin{random_seed} \cgalParamType{unsigned int} \cgalParamDefault{0} \cgalParamNEnd
///   \cgalParamNBegin{number_of_iterations} \cgalParamDescription{iteration cap of each packing stage}
///     \cgalParamType{int} \cgalParamDefault{400} \cgalParamNEnd
///   \cgalParamNBegin{number_of_threads} \cgalParamDescription{threads of the packing (0: all); the mesh does not
///     depend on it} \cgalParamType{int} \cgalParamDefault{0} \cgalParamNEnd
///   \cgalParamNBegin{maximum_number_of_bubbles} \cgalParamDescription{refuse (`Bubble_mesh_3::Invalid_input`, before
///     any packing) when the estimated node count exceeds this; the default keeps a run under about 16 GB}
///     \cgalParamType{double} \cgalParamDefault{`Bubble_mesh_3::default_maximum_number_of_nodes`} \cgalParamNEnd
///   \cgalParamNBegin{time_limit} \cgalParamDescription{seconds for the whole run: when a check point (between
///     stages, every 2,000 tets of the front) is passed after it, `Bubble_mesh_3::Time_limit_exceeded` is thrown; the
///     improvement is cut to the time left instead (the mesh is returned), later stages are not cut}
///     \cgalParamType{double} \cgalParamDefault{no limit} \cgalParamNEnd
///   \cgalParamNBegin{should_stop} \cgalParamDescription{polled at the same check points (from the calling
///     thread); when it returns true, `Bubble_mesh_3::Interrupted` is thrown. The command-line tool sets it from
///     SIGINT} \cgalParamType{std::function<bool()>} \cgalParamDefault{none} \cgalParamNEnd
///   \cgalParamNBegin{allow_steiner_points} \cgalParamDescription{cavities the front cannot close may get points
///     strictly inside} \cgalParamType{bool} \cgalParamDefault{true} \cgalParamNEnd
///   \cgalParamNBegin{mesh_improvement} \cgalParamDescription{metric flips and smoothing after the front
///     (`Bubble_mesh_3::improve_mesh()`)} \cgalParamType{bool} \cgalParamDefault{true} \cgalParamNEnd
///   \cgalParamNBegin{improvement_time_limit} \cgalParamDescription{seconds for it (negative: 2 s + 10 s per 100k
///     tets); without it the work is bounded by a number of passes and the result is reproducible, with it a run
///     cut by the limit is not} \cgalParamType{double} \cgalParamDefault{no limit} \cgalParamNEnd
///   \cgalParamNBegin{surface_distance} \cgalParamDescription{bound D on the distance of the boundary
///     triangles to the input surface: near the surface the metric is intersected with sizes sqrt(3 D / |k|)
///     along the principal curvature directions (`CGAL::Surface_approximation_metric_field_3`), so curved
///     parts get the nodes they need; negative: the bounding box diagonal times
///     `Bubble_mesh_3::default_relative_surface_distance` (1/200); 0 or infinity: the metric as given. Off by
///     default for now: on organic inputs at coarse sizes it multiplies the node count (armadillo at diag/10,
///     measured with a first version of the field: 306 to 9,616 vertices, volume error 35 % to 0.9 %) and the
///     field costs about 1 microsecond per evaluation (elephant at 0.03: 2.3 s to 20 s). A field that is already a `Surface_approximation_metric_field_3` is used as it is}
///     \cgalParamType{double} \cgalParamDefault{0 (off)} \cgalParamNEnd
///   \cgalParamNBegin{small_feature_refinement} \cgalParamDescription{refine the metric where the domain's corners
///     and feature curves are closer to each other than its sizes (`CGAL::Feature_size_metric_field_3`: sizes down
///     to the features' distance there, growing by half the distance away from them), so short curves and corner
///     clusters do not force flat tets. A field that is already a `Feature_size_metric_field_3` is used as it is}
///     \cgalParamType{bool} \cgalParamDefault{true} \cgalParamNEnd
///   \cgalParamNBegin{callback} \cgalParamDescription{progress messages}
///     \cgalParamType{std::function<void(const std::string&)>} \cgalParamDefault{none} \cgalParamNEnd
///   \cgalParamNBegin{meshing_report} \cgalParamDescription{filled with counts and times}
///     \cgalParamType{Bubble_mesh_3::Meshing_report*} \cgalParamDefault{nullptr} \cgalParamNEnd
/// \cgalNamedParamsEnd
///
/// Throws `Bubble_mesh_3::Invalid_input` (a domain surface refused by
/// `Bubble_mesh_3::IO::check_triangle_surface()`: zero-area faces, flat,
/// self-intersecting, components oriented against their nesting; a bad
/// metric; too many nodes), `Bubble_mesh_3::Meshing_failure` (no valid mesh)
/// or `Bubble_mesh_3::Interrupted` / `Bubble_mesh_3::Time_limit_exceeded`
/// (stopped on request); never returns a partial mesh. Several components,
/// disjoint or nested (a hollow shell), make one subdomain.
template <typename C3T3, typename MeshDomain, typename MetricField,
          typename NamedParameters = CGAL::parameters::Default_named_parameters>
void make_anisotropic_mesh_3(C3T3& c3t3, const MeshDomain& domain, const MetricField& field,
                             const NamedParameters& np = CGAL::parameters::default_values())
{
  namespace BM = Bubble_mesh_3;
  const BM::internal::Meshing_settings s = BM::internal::resolve_settings(np);
  const auto t_run = std::chrono::steady_clock::now();
  BM::internal::Domain_mesh dm = BM::internal::mesh_domain(domain, field, s);
  BM::internal::Stop_check(s, t_run)("the exterior padding", false);
  const auto t0 = std::chrono::steady_clock::now();
  c3t3.clear();
  std::size_t padding_tets = 0;
  if(BM::internal::has_exterior_padding) {
    BM::internal::Padded_tet_mesh_3 padded = BM::internal::pad_to_box(dm.mesh);
    std::vector<BM::internal::C3t3_vertex_location> locations = dm.locations;
    locations.resize(padded.mesh.points.size(), BM::internal::C3t3_vertex_location{3, 0});
    BM::internal::tet_mesh_to_c3t3(padded.mesh, locations, domain, c3t3);
    padding_tets = padded.mesh.tets.size() - dm.mesh.tets.size();
  } else {
    // without TetGen only a mesh of a convex domain fills its triangulation
    try {
      BM::internal::tet_mesh_to_c3t3(dm.mesh, dm.locations, domain, c3t3);
    } catch(const BM::Invalid_input& e) {
      c3t3.clear();
      throw BM::Meshing_failure(std::string("the domain is not convex (or has several components), and this build "
                                            "has no TetGen to pad it out to a box for the C3T3 (") +
                                e.what() + "); use make_indexed_anisotropic_mesh_3 or build with TetGen");
    }
  }
  if(s.report) {
    s.report->padding_tets = padding_tets;
    s.report->c3t3_seconds = BM::internal::seconds_since(t0);
    s.report->total_seconds += s.report->c3t3_seconds;
  }
}

/// \ingroup PkgBubbleMesh3Functions
/// Same as above, returning the complex.
template <typename C3T3, typename MeshDomain, typename MetricField,
          typename NamedParameters = CGAL::parameters::Default_named_parameters>
C3T3 make_anisotropic_mesh_3(const MeshDomain& domain, const MetricField& field,
                             const NamedParameters& np = CGAL::parameters::default_values())
{
  C3T3 c3t3;
  make_anisotropic_mesh_3(c3t3, domain, field, np);
  return c3t3;
}

} // namespace CGAL

#endif // CGAL_MAKE_ANISOTROPIC_MESH_3_H
