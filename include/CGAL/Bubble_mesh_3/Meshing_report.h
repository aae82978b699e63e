// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_MESHING_REPORT_H
#define CGAL_BUBBLE_MESH_3_MESHING_REPORT_H

// What `make_anisotropic_mesh_3()` reports: counts, iterations and seconds of
// every stage, as a struct, as JSON and as a few lines of text.

#include <CGAL/Anisotropic_advancing_front_3.h>
#include <CGAL/Bubble_mesh_3/improve_mesh.h>
#include <CGAL/Bubble_mesh_3/internal/json.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <ostream>
#include <sstream>
#include <string>

namespace CGAL {
namespace Bubble_mesh_3 {

/// \ingroup PkgBubbleMesh3Classes
/// What `make_anisotropic_mesh_3()` did: counts and seconds per stage.
struct Meshing_report {
  std::array<std::size_t, 4> nodes{{0, 0, 0, 0}}; ///< packed nodes per dimension (corner, curve, patch, interior)
  std::array<double, 4> packing_seconds{{0, 0, 0, 0}};
  std::array<int, 4> packing_iterations{{0, 0, 0, 0}};
  std::array<bool, 4> packing_converged{{true, true, true, true}}; ///< the largest step fell below the tolerance
  /// the stage stopped because it had settled: its bubbles' mean steps stopped
  /// decreasing with the bulk below the tolerance, a few still creeping
  std::array<bool, 4> packing_settled{{false, false, false, false}};
  std::array<std::size_t, 4> packing_still_moving{{0, 0, 0, 0}}; ///< when settled: bubbles whose mean step was above the tolerance
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
  /// an implicit or labelled domain: the triangles of the polyhedral copy of
  /// its boundary the stages meshed (CGAL Mesh_3's surface mesh), its chord
  /// error and seconds; the boundary vertices then moved onto the domain's
  /// surface and curves, those left where they were (a move would have turned
  /// a tet over; they stay within about the chord error), the longest move
  std::size_t implicit_surface_triangles = 0;
  double implicit_surface_chord_error = 0, implicit_surface_seconds = 0;
  std::size_t snapped_boundary_vertices = 0, unsnapped_boundary_vertices = 0;
  double largest_snap = 0;
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
  std::string settled = "[";
  for(std::size_t i = 0; i < 4; ++i)
    settled += std::string(i ? ", " : "") + (r.packing_settled[i] ? "true" : "false");
  settled += "]";
  std::ostringstream o;
  o << "{\n    \"estimated_nodes\": " << num(r.estimated_nodes) << ",\n    \"nodes_per_dimension\": " << arr(r.nodes)
    << ",\n    \"packing_seconds\": " << arr(r.packing_seconds) << ",\n    \"packing_iterations\": "
    << arr(r.packing_iterations) << ",\n    \"packing_converged\": " << conv << ",\n    \"packing_settled\": " << settled
    << ",\n    \"packing_still_moving\": " << arr(r.packing_still_moving)
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
    << ", \"edges_in_range_before\": " << num(r.improvement.edges_in_range_before)
    << ", \"edges_in_range_after\": " << num(r.improvement.edges_in_range_after)
    << ", \"longest_edge_before\": " << num(r.improvement.longest_edge_before)
    << ", \"longest_edge_after\": " << num(r.improvement.longest_edge_after)
    << ", \"flips_2_3\": " << r.improvement.flips_2_3 << ", \"flips_3_2\": " << r.improvement.flips_3_2
    << ", \"flips_4_4\": " << r.improvement.flips_4_4 << ", \"edge_removals\": " << r.improvement.edge_removals
    << ", \"smoothing_moves\": " << r.improvement.smoothing_moves << ", \"edge_splits\": " << r.improvement.edge_splits
    << ", \"boundary_edge_splits\": " << r.improvement.boundary_edge_splits
    << ", \"feature_edge_splits\": " << r.improvement.feature_edge_splits
    << ", \"edge_collapses\": " << r.improvement.edge_collapses
    << ", \"boundary_edge_collapses\": " << r.improvement.boundary_edge_collapses
    << ", \"feature_edge_collapses\": " << r.improvement.feature_edge_collapses
    << ", \"length_splits\": " << r.improvement.length_splits
    << ", \"length_collapses\": " << r.improvement.length_collapses
    << ", \"length_flips\": " << r.improvement.length_flips
    << ", \"distance_splits\": " << r.improvement.distance_splits
    << ", \"triangles_beyond_distance\": " << r.improvement.triangles_beyond_distance
    << ", \"seconds\": " << num(r.improvement.seconds)
    << ", \"time_limit_reached\": " << (r.improvement.time_limit_reached ? "true" : "false") << "}"
    << ",\n    \"validity_seconds\": " << num(r.validity_seconds) << ",\n    \"surface_distance\": "
    << num(r.surface_distance) << ",\n    \"surface_distance_relative\": " << num(r.surface_distance_relative)
    << ",\n    \"input_to_boundary_distance\": " << num(r.input_to_boundary_distance)
    << ",\n    \"volume_error\": " << num(r.volume_error) << ",\n    \"surface_distance_bound\": "
    << num(r.surface_distance_bound) << ",\n    \"small_feature_samples\": " << r.small_feature_samples
    << ",\n    \"smallest_feature_size\": " << num(r.smallest_feature_size)
    << ",\n    \"feature_size_seconds\": " << num(r.feature_size_seconds)
    << ",\n    \"implicit_surface_triangles\": " << r.implicit_surface_triangles
    << ",\n    \"implicit_surface_chord_error\": " << num(r.implicit_surface_chord_error)
    << ",\n    \"implicit_surface_seconds\": " << num(r.implicit_surface_seconds)
    << ",\n    \"snapped_boundary_vertices\": " << r.snapped_boundary_vertices
    << ",\n    \"unsnapped_boundary_vertices\": " << r.unsnapped_boundary_vertices
    << ",\n    \"largest_snap\": " << num(r.largest_snap) << ",\n    \"total_seconds\": "
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
    << "/" << r.packing_iterations[3];
  {
    const char* names[4] = {"corners", "curves", "surfaces", "interior"};
    bool capped = false;
    std::string how;
    for(int d = 1; d < 4; ++d) {
      capped = capped || !(r.packing_converged[d] || r.packing_settled[d]);
      if(r.packing_settled[d])
        how += std::string(how.empty() ? "" : ", ") + names[d] + " (" + std::to_string(r.packing_still_moving[d]) +
               " still creeping)";
    }
    o << (capped ? ", iteration cap reached" : how.empty() ? ", converged" : ", settled: " + how) << ")\n";
  }
  if(r.implicit_surface_triangles > 0) {
    std::ostringstream small; // lengths far below the fixed two decimals
    small.precision(3);
    small << " (chord error " << r.implicit_surface_chord_error << ", ";
    std::ostringstream move;
    move.precision(3);
    move << " (longest move " << r.largest_snap << "), ";
    o << "surface:  " << r.implicit_surface_triangles << " triangles of the implicit domain's boundary" << small.str()
      << r.implicit_surface_seconds << " s); " << r.snapped_boundary_vertices << " boundary vertices moved onto it"
      << move.str() << r.unsnapped_boundary_vertices << " left\n";
  }
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
                                     std::to_string(i.boundary_edge_collapses) + " on the boundary (" +
                                     std::to_string(i.feature_edge_collapses) + " on feature curves)"
                               : std::string())
      << (i.time_limit_reached ? ", time limit reached" : "") << ")\n";
    o << "improve:  metric edges in [0.707, 1.414] " << 100 * i.edges_in_range_before << " -> "
      << 100 * i.edges_in_range_after << " %, longest " << i.longest_edge_before << " -> " << i.longest_edge_after
      << (i.length_splits + i.length_collapses + i.length_flips > 0
              ? " (for lengths: " + std::to_string(i.length_splits) + " splits, " +
                    std::to_string(i.length_collapses) + " collapses, " + std::to_string(i.length_flips) +
                    " edge removals)"
              : std::string())
      << "\n";
    if(r.improvement_boundary_fixed)
      o << "improve:  its first run made the boundary intersect itself at a thin part: redone with the boundary "
           "fixed\n";
  }
  o.precision(3);
  o << "surface:  boundary within " << r.surface_distance;
  if(r.surface_distance_bound > 0) {
    o << " (bound " << r.surface_distance_bound;
    if(r.improved && !r.improvement_boundary_fixed) // (with the boundary fixed nothing is split)
      o << "; " << r.improvement.distance_splits << " boundary edges split for it, "
        << r.improvement.triangles_beyond_distance << " triangles still beyond it";
    o << ")";
  }
  o << " of the input (" << 100 * r.surface_distance_relative
    << " % of the diagonal), input within " << r.input_to_boundary_distance << " of the boundary, volume error "
    << 100 * r.volume_error << " %\n";
  o.precision(2);
  o << "total:    " << r.total_seconds << " s\n";
  out << o.str();
}

} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_MESHING_REPORT_H
