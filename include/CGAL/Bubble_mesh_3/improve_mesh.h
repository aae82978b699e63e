// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_IMPROVE_MESH_H
#define CGAL_BUBBLE_MESH_3_IMPROVE_MESH_H

#include <CGAL/Bubble_mesh_3/Improvement_options.h>
#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/Quality_report.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/parameters.h>
#include <CGAL/Bubble_mesh_3/internal/improve/Mesh_improver.h>
#include <CGAL/Bubble_mesh_3/internal/improve/Mutable_tet_mesh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

/// \file improve_mesh.h
/// Quality improvement of a tetrahedral mesh in a metric field by flips and
/// by smoothing, boundary vertices included where the domain cannot change
/// (the paper's section 5.3, extended). `improve_c3t3.h` applies it to any
/// `Mesh_complex_3_in_triangulation_3`.
///
/// **Quality.** The quality of a tet is its minimum dihedral angle, in
/// degrees, after mapping its vertices by `Q` of the metric `M = Q^T Q`
/// evaluated at the tet's centroid (paper, section 6), exactly what
/// `compute_quality_report()` measures. For a candidate tet the metric is
/// evaluated at the candidate's own centroid. Only positively oriented tets
/// (exact `CGAL::orientation` on the double coordinates, Epick) are valid.
///
/// **Operations.** All of them are accepted only when the smallest quality
/// of the tets they create is strictly larger than the smallest quality of
/// the tets they destroy, and every created tet is positively oriented
/// (exact). Hence the worst quality of the mesh never decreases.
/// - *2-3 flip*: the two tets on an interior face `abc` are replaced by the
///   three tets around the new edge `de`.
/// - *edge removal*: the `n` tets around an interior edge `ab` (3 <= n <=
///   `maximum_ring_size`) are replaced by the `2n-4` tets joining `a` and `b`
///   to the triangles of the triangulation of the ring polygon that
///   maximises the smallest quality, found by the classic dynamic programme
///   over the sub-polygons of the ring (O(n^3)). `n = 3` is the 3-2 flip,
///   `n = 4` the 4-4 flip; both are counted apart.
/// - *boundary flip* (`boundary_flips`): the same for a boundary edge `ab`
///   whose two boundary triangles `abc`, `bad` lie exactly in one plane
///   (exact coplanarity), belong to one patch (same triangle ref), are faces
///   of one tet each (not interfaces) and which is no feature edge: the `k`
///   tets of its open fan `c = p_0 .. p_k = d` become the `2k-2` tets on the
///   best triangulation of the polygon `p_0 .. p_k`, and the two triangles
///   become `acd`, `bdc` (2-2 for `k = 2`, 4-4 on the boundary for `k = 3`).
///   The new tets are positive, so the quad `a c b d` is convex and the two
///   new triangles cover the same planar region: the surface is unchanged,
///   only its triangulation. Each new triangle takes the slot of an old one
///   in `triangles` with the same ref and the same orientation. Not done if
///   a triangle is listed twice.
/// - *curved boundary flip* (`curved_boundary_flips`, only with a
///   `surface_projection`): the same where `abc` and `bad` are not in one
///   plane, if neither new triangle turns by more than 20 degrees from
///   either old one (the bound of a surface vertex move). With `k = 1` the
///   fan is one tet `abcd` with two boundary triangles, a *cap* (flat on a
///   curved or noisy surface, it has no good shape): it is removed, and its
///   inner faces `acd`, `bdc` become boundary triangles (if `cd` is no
///   boundary edge yet and both have a tet of the same subdomain behind
///   them). The surface moves by the chords' change, at most the height of
///   the flipped tets; the vertices stay where they are.
/// - *smoothing*: a vertex moves to raise the smallest quality of its ball
///   (mean of the ideal positions over the ball's faces, then
///   steepest-ascent steps of the non-smooth max-min problem in the metric
///   of the vertex, with a halving line search).
/// - *boundary smoothing* (`boundary_smoothing`): the same for two kinds of
///   boundary or interface vertices, on a constraint found once, with exact
///   predicates on the input doubles: (1) *plane*: every protected face
///   around the vertex lies exactly in one plane, all of one patch, forming
///   one closed fan, and no feature edge or corner is at the vertex: it
///   moves in that plane; (2) *line*: the vertex is on exactly two feature
///   edges, exactly collinear with its two feature neighbours, and every
///   protected face around it lies in a plane through that line: it moves
///   along the line, strictly between the two neighbours. Candidates are
///   projected on the plane or line, gradients on its tangent space. Every
///   tet staying positive keeps every incident boundary triangle
///   non-degenerate and the same way round in its plane, so the boundary
///   surface as a point set, and the volume of every subdomain, do not
///   change. For an axis-parallel plane or line the constant coordinates are
///   copied, so this is exact; for another plane the projected point is the
///   closest double along the dominant normal axis, off the plane by a
///   rounding error (relative 1e-16), which the volume check of the tests
///   (1e-12 relative) sees as no change. (3) *surface* (only with a
///   `surface_projection`): the vertex is inside one curved patch (one closed
///   fan of listed triangles of one ref on the domain boundary, no feature
///   edge or corner at it): it moves in the tangent plane of its fan, every
///   candidate is projected onto the true surface of the patch by the
///   callback, stays within half its shortest metric edge of its start and
///   turns no triangle at it by more than 20 degrees. The triangles keep
///   their vertices and refs and the vertices stay on the surface, but the
///   chords move: the meshed volume changes by that (still exactly the
///   volume the triangles enclose). `make_anisotropic_mesh_3()` passes the
///   projection onto the input surface's patches. (4) *curve* (only with a
///   `curve_projection`): the vertex is inside a curved feature curve; it
///   moves along the chord of its two curve neighbours, every candidate
///   projected onto the true curve, with the bounds of (3).
///   `make_anisotropic_mesh_3()` passes the projection onto the input's
///   feature polylines.
/// - *sliver moves* (`sliver_moves`): a *sliver* here is a tet whose metric
///   edges are within a factor 2 of each other but whose smallest dihedral
///   angle is below 20 degrees and largest above 140 (four nearly coplanar
///   vertices: what the (metric) Delaunay criterion cannot remove; counted
///   in the report before and after). When smoothing cannot move a vertex
///   whose worst tet is a sliver, it is pushed off the sliver's opposite
///   face along its metric normal, then random trial moves (16 per try,
///   seeded by `random_seed`, the vertex and the operation count) are
///   accepted when the smallest quality of its ball increases.
///
/// **What never changes.** Protected faces are the listed `triangles`, the
/// faces of a single tet (the domain boundary, also for a mesh that lists no
/// triangles) and the faces between two subdomains; protected edges are
/// their edges and the feature `edges`. No flip removes a protected face or
/// edge except a boundary flip as above (an interior edge whose two end
/// points lie on the boundary may be removed), every flip only combines tets
/// of one subdomain, and the new tets get that subdomain. Corners never move;
/// other boundary, interface and feature vertices only as above. So
/// `edges`, `edge_refs`, `corners`, `point_refs`, the number of `triangles`
/// with their refs (their vertices only by boundary flips), the boundary
/// surface of every patch and every subdomain's region are unchanged (volume
/// unchanged up to rounding), and `check_validity()` still holds. With
/// `ref_0_is_exterior`, tets of ref 0 are passive padding (a C3T3's cells
/// outside the complex): kept positive by every move, never flipped (so no
/// boundary flip next to them) and left out of the report.
///
/// **Passes.** Each pass has two phases. (1) Flips: every tet below
/// `target_angle` goes into a priority queue, worst first (ties by slot
/// index); for a popped tet the best strictly improving flip among the
/// removals of its six edges (boundary flips for its boundary edges) and
/// the 2-3 flips of its four faces is applied (best: largest new smallest
/// quality), and the new tets still below the target are pushed. (2)
/// Smoothing: one sweep over the movable vertices of the tets below the
/// target, in the order of the worst tet they belong to. Passes repeat until
/// one changes nothing, `maximum_passes` is reached, or the time limit. An
/// operation that failed is retried in a later pass only if something
/// changed around it (a flip touching one of its vertices, or a move of one
/// of their neighbours). Slivers get the flips of any bad tet, worst first
/// (the removals of their six edges, the two crossing diagonals above all,
/// and the 2-3 flips of their four faces), then the smoothing of their four
/// vertices, then the sliver moves. Measured: flips and smoothing remove
/// nearly all slivers (0 left on the demo meshes, fandisk and the random
/// tests with a boundary), so the sliver moves rarely fire there (0 to 7
/// accepted moves per mesh, worst and 1st percentile unchanged within
/// 0.4 degrees); they matter when flips are off.
///
/// **Determinism.** No threads, no dependence on hash order (the hash sets
/// are only queried), and the random trial moves are seeded: the same input
/// and options give the same output, unless the time limit cuts the work
/// (where it cuts depends on the machine; pass an infinite limit for
/// reproducible results).
///
/// **Cost.** Per pass, O(number of bad tets) local operations: an edge
/// removal evaluates at most 2 C(n,3) candidate tets for a ring of n, a
/// smoothing a few dozen evaluations of the vertex's ball. Measured (one
/// core, release, shared machine): 0.1 s for the demo cylinder (12k tets),
/// about 1.5-2 s per 10,000 tets on the Delaunay tetrahedralisation of
/// random points (75% of its tets below 40 degrees), with a constant metric
/// field; a field that is expensive to evaluate costs proportionally more
/// (one evaluation per candidate tet; the boundary-layer field of the blob:
/// 6-8 s for 22k tets).
///
/// **Limitations of this version.** Vertices on curved feature curves move
/// only with a `curve_projection`, those on curved patches only with a
/// `surface_projection`, corners never, and
/// triangles of curved patches are never flipped, so a bad tet whose
/// vertices are all on curved features may stay. Vertex insertion only by
/// the optional edge splits (`Improvement_options::edge_splits`, off by
/// default: then the number of vertices is fixed), removal only by the
/// optional edge collapses (`Improvement_options::edge_collapses`); no
/// multi-face removal.
/// Smoothing maximises the worst tet of a ball, which can lower its other
/// tets (the mean quality may drop when smoothing alone is used).

namespace CGAL {
namespace Bubble_mesh_3 {


/// \ingroup PkgBubbleMesh3Ref
/// What `improve_mesh()` did. Qualities are metric minimum dihedral angles
/// in degrees as in `compute_quality_report()`; `p01` is the nearest-rank
/// 1st percentile.
struct Improvement_report {
  double worst_before = 0;
  double worst_after = 0;
  double p01_before = 0;
  double p01_after = 0;
  double mean_before = 0;
  double mean_after = 0;
  /// tets below `target_angle`
  std::size_t below_target_before = 0;
  std::size_t below_target_after = 0;
  std::size_t tets_before = 0;
  std::size_t tets_after = 0;
  /// fraction of the unique edges whose metric length lies in [1/sqrt(2),
  /// sqrt(2)] (as in `compute_quality_report()`), and the longest: the
  /// improvement raises angles and may trade edge conformity for them
  double edges_in_range_before = 0;
  double edges_in_range_after = 0;
  double longest_edge_before = 0;
  double longest_edge_after = 0;
  std::size_t flips_2_3 = 0;
  std::size_t flips_3_2 = 0;
  std::size_t flips_4_4 = 0;
  /// removals of edges with 5 or more tets around them (n-to-(2n-4))
  std::size_t edge_removals = 0;
  /// accepted vertex moves
  std::size_t smoothing_moves = 0;
  /// those of vertices in a boundary plane or on a feature line
  std::size_t boundary_moves = 0;
  /// flips of boundary edges in planar regions (they replace two listed
  /// triangles by two others covering the same quad)
  std::size_t boundary_flips = 0;
  /// those of sliver vertices by the push off the opposite face or by a
  /// random trial move
  std::size_t sliver_moves = 0;
  /// edge splits (`Improvement_options::edge_splits`: one new vertex each),
  /// and those of boundary edges (two listed triangles become four)
  std::size_t edge_splits = 0;
  std::size_t boundary_edge_splits = 0;
  /// those of feature edges (counted in `boundary_edge_splits` too)
  std::size_t feature_edge_splits = 0;
  /// edge collapses (`Improvement_options::edge_collapses`: one vertex
  /// removed each), and those of boundary edges (two listed triangles go)
  std::size_t edge_collapses = 0;
  std::size_t boundary_edge_collapses = 0;
  /// those of feature edges (a node removed from a feature curve; counted in
  /// `boundary_edge_collapses` too)
  std::size_t feature_edge_collapses = 0;
  /// the splits and collapses for edge lengths
  /// (`Improvement_options::edge_lengths`; counted in the above too)
  std::size_t length_splits = 0;
  std::size_t length_collapses = 0;
  /// the edge removals of long edges that cut through a layer of nodes
  /// (`Improvement_options::edge_lengths`; counted in the flips too)
  std::size_t length_flips = 0;
  /// with `Improvement_options::surface_distance` (and a `surface_projection`
  /// with `boundary_smoothing`; else nothing is measured and these stay 0):
  /// the splits of boundary edges for it (counted in the splits too), the
  /// largest sampled distance of a boundary triangle to its patch's surface
  /// after the improvement, and the triangles still farther than the bound
  std::size_t distance_splits = 0;
  double largest_surface_distance = 0;
  std::size_t triangles_beyond_distance = 0;
  /// if a collapse removed vertices: the index in the improved mesh of each
  /// vertex of the input mesh followed by the split ones (-1: removed); empty
  /// if no vertex was removed (indices unchanged, split vertices appended)
  std::vector<int> new_vertex_index;
  /// slivers (metric edges within a factor 2, smallest dihedral angle below
  /// 20 degrees, largest above 140)
  std::size_t slivers_before = 0;
  std::size_t slivers_after = 0;
  int passes = 0;
  double seconds = 0;
  bool time_limit_reached = false;
};

namespace internal {

inline void improvement_statistics(std::vector<double> values, double target, double& worst, double& p01,
                                   double& mean, std::size_t& below)
{
  if(values.empty())
    return;
  worst = *std::min_element(values.begin(), values.end());
  mean = compensated_sum(values) / double(values.size());
  below = std::size_t(std::count_if(values.begin(), values.end(), [target](double q) { return q < target; }));
  p01 = nearest_rank_percentile(std::move(values), 1.0);
}

/// Throws `Invalid_input` naming the first option that has no meaning (a
/// NaN would otherwise silently turn a part of the improvement off: no tet
/// is below a NaN target, no triangle beyond a NaN distance).
inline void check_improvement_options(const Improvement_options& o)
{
  auto refuse = [](const std::string& what) {
    throw Invalid_input("improve_mesh: " + what);
  };
  if(std::isnan(o.time_limit_seconds))
    refuse("time_limit_seconds is NaN (negative means automatic)");
  if(!(o.target_angle >= 0 && o.target_angle <= 90))
    refuse("target_angle must be between 0 and 90 degrees, not " + std::to_string(o.target_angle));
  if(!(o.split_below_angle >= 0 && o.split_below_angle <= 90))
    refuse("split_below_angle must be between 0 and 90 degrees, not " + std::to_string(o.split_below_angle));
  if(std::isnan(o.surface_distance) || o.surface_distance < 0)
    refuse("surface_distance must be a distance >= 0 (0 or infinity: off), not " +
           std::to_string(o.surface_distance));
}

} // namespace internal

/// \ingroup PkgBubbleMesh3Functions
/// Improves the quality of `mesh` in the metric `field` (a model of
/// `MetricField_3`) by flips and smoothing, in place; see the file
/// documentation for the operations and the guarantees. `mesh` must be
/// valid (`check_validity()`), with positively oriented tets. Tets keep
/// their subdomain; their order changes; boundary flips replace listed
/// triangles in place (same count, refs and orientation). Throws `Invalid_input`
/// if an index is out of range or an option has no meaning (a NaN, an angle
/// outside [0, 90], a negative distance); exceptions of `field` propagate.
template <typename MetricField_3>
Improvement_report improve_mesh(Indexed_tet_mesh_3& mesh, const MetricField_3& field,
                                const Improvement_options& options = {})
{
  internal::check_improvement_options(options);
  Improvement_report report;
  if(mesh.tets.empty())
    return report;
  auto edge_lengths = [&field](const Indexed_tet_mesh_3& m) {
    std::vector<char> used;
    internal::check_mesh_for_quality(m, used);
    return internal::metric_edge_lengths(m, field, used);
  };
  const Quality_report::Edge_length before = edge_lengths(mesh);
  report.edges_in_range_before = before.in_range_fraction;
  report.longest_edge_before = before.max;
  internal::improve::Mutable_tet_mesh work(mesh, options.ref_0_is_exterior,
                                          options.boundary_smoothing ? options.surface_projection : nullptr,
                                          options.boundary_smoothing ? options.curve_projection : nullptr);
  const internal::improve::Improver_settings settings(options, mesh.tets.size());

  internal::improve::Mesh_improver<MetricField_3> improver(work, field, settings);
  internal::improvement_statistics(improver.qualities(), options.target_angle, report.worst_before,
                                   report.p01_before, report.mean_before, report.below_target_before);
  report.tets_before = improver.number_of_active_tets();
  report.slivers_before = improver.number_of_slivers();
  improver.run();
  report.slivers_after = improver.number_of_slivers();
  report.tets_after = improver.number_of_active_tets();
  internal::improvement_statistics(improver.qualities(), options.target_angle, report.worst_after,
                                   report.p01_after, report.mean_after, report.below_target_after);
  report.new_vertex_index = work.write_back(mesh);
  const Quality_report::Edge_length after = edge_lengths(mesh);
  report.edges_in_range_after = after.in_range_fraction;
  report.longest_edge_after = after.max;

  const internal::improve::Improver_counters& c = improver.counters();
  report.flips_2_3 = c.flips_2_3;
  report.flips_3_2 = c.flips_3_2;
  report.flips_4_4 = c.flips_4_4;
  report.edge_removals = c.edge_removals;
  report.smoothing_moves = c.smoothing_moves;
  report.boundary_moves = c.boundary_moves;
  report.boundary_flips = c.boundary_flips;
  report.sliver_moves = c.sliver_moves;
  report.edge_splits = c.edge_splits;
  report.boundary_edge_splits = c.boundary_edge_splits;
  report.feature_edge_splits = c.feature_edge_splits;
  report.edge_collapses = c.edge_collapses;
  report.boundary_edge_collapses = c.boundary_edge_collapses;
  report.feature_edge_collapses = c.feature_edge_collapses;
  report.length_splits = c.length_splits;
  report.length_collapses = c.length_collapses;
  report.length_flips = c.length_flips;
  report.distance_splits = c.distance_splits;
  report.largest_surface_distance = c.largest_surface_distance;
  report.triangles_beyond_distance = c.triangles_beyond_distance;
  report.passes = c.passes;
  report.time_limit_reached = c.time_limit_reached;
  report.seconds = improver.elapsed_seconds();
  return report;
}

/// \ingroup PkgBubbleMesh3Ref
/// The `Improvement_options` set by named parameters (the ones not given keep
/// their defaults): `number_of_iterations` (`maximum_passes`),
/// `improvement_time_limit` (`time_limit_seconds`), `should_stop`,
/// `random_seed`, and the options of the same name: `target_angle`, `flips`,
/// `smoothing`, `boundary_smoothing`, `boundary_flips`,
/// `curved_boundary_flips`, `sliver_moves`, `edge_splits`,
/// `split_below_angle`, `edge_collapses`, `keep_edges_in_range`,
/// `flips_keep_edges_in_range`, `edge_lengths`, `surface_distance`, `maximum_ring_size`,
/// `smoothing_iterations`, `surface_projection`, `curve_projection`.
template <typename NamedParameters>
Improvement_options improvement_options(const NamedParameters& np)
{
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  namespace BNP = Bubble_mesh_3::internal_np;
  Improvement_options o;
  o.maximum_passes = choose_parameter(get_parameter(np, CGAL::internal_np::number_of_iterations), o.maximum_passes);
  o.time_limit_seconds = choose_parameter(get_parameter(np, BNP::improvement_time_limit), o.time_limit_seconds);
  o.should_stop = choose_parameter(get_parameter(np, BNP::should_stop), o.should_stop);
  o.random_seed = choose_parameter(get_parameter(np, CGAL::internal_np::random_seed), o.random_seed);
  o.target_angle = choose_parameter(get_parameter(np, BNP::target_angle), o.target_angle);
  o.flips = choose_parameter(get_parameter(np, BNP::flips), o.flips);
  o.smoothing = choose_parameter(get_parameter(np, BNP::smoothing), o.smoothing);
  o.boundary_smoothing = choose_parameter(get_parameter(np, BNP::boundary_smoothing), o.boundary_smoothing);
  o.boundary_flips = choose_parameter(get_parameter(np, BNP::boundary_flips), o.boundary_flips);
  o.curved_boundary_flips = choose_parameter(get_parameter(np, BNP::curved_boundary_flips), o.curved_boundary_flips);
  o.sliver_moves = choose_parameter(get_parameter(np, BNP::sliver_moves), o.sliver_moves);
  o.edge_splits = choose_parameter(get_parameter(np, BNP::edge_splits), o.edge_splits);
  o.split_below_angle = choose_parameter(get_parameter(np, BNP::split_below_angle), o.split_below_angle);
  o.edge_collapses = choose_parameter(get_parameter(np, BNP::edge_collapses), o.edge_collapses);
  o.keep_edges_in_range = choose_parameter(get_parameter(np, BNP::keep_edges_in_range), o.keep_edges_in_range);
  o.flips_keep_edges_in_range =
    choose_parameter(get_parameter(np, BNP::flips_keep_edges_in_range), o.flips_keep_edges_in_range);
  o.edge_lengths = choose_parameter(get_parameter(np, BNP::edge_lengths), o.edge_lengths);
  o.surface_distance = choose_parameter(get_parameter(np, BNP::surface_distance), o.surface_distance);
  o.maximum_ring_size = choose_parameter(get_parameter(np, BNP::maximum_ring_size), o.maximum_ring_size);
  o.smoothing_iterations = choose_parameter(get_parameter(np, BNP::smoothing_iterations), o.smoothing_iterations);
  o.surface_projection = choose_parameter(get_parameter(np, BNP::surface_projection), o.surface_projection);
  o.curve_projection = choose_parameter(get_parameter(np, BNP::curve_projection), o.curve_projection);
  return o;
}

/// \ingroup PkgBubbleMesh3Functions
/// `improve_mesh()` with named parameters (`improvement_options()` lists
/// them), CGAL's way:
/// `improve_mesh(mesh, field, CGAL::Bubble_mesh_3::parameters::edge_splits(true).random_seed(3))`.
template <typename MetricField_3, typename NamedParameters>
Improvement_report improve_mesh(Indexed_tet_mesh_3& mesh, const MetricField_3& field, const NamedParameters& np)
{
  return improve_mesh(mesh, field, improvement_options(np));
}

} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_IMPROVE_MESH_H
