// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_IMPROVE_MESH_H
#define CGAL_BUBBLE_MESH_3_IMPROVE_MESH_H

#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/Quality_report.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/internal/improve/Mesh_improver.h>
#include <CGAL/Bubble_mesh_3/internal/improve/Mutable_tet_mesh.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>
#include <vector>

/// \file improve_mesh.h
/// Quality improvement of a tetrahedral mesh in a metric field by flips and
/// by smoothing of interior vertices (the paper's section 5.3, extended).
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
/// - *smoothing*: a free vertex moves to raise the smallest quality of its
///   ball (mean of the ideal positions over the ball's faces, then
///   steepest-ascent steps of the non-smooth max-min problem in the metric
///   of the vertex, with a halving line search).
///
/// **What never changes.** Protected faces are the listed `triangles`, the
/// faces of a single tet (the domain boundary, also for a mesh that lists no
/// triangles) and the faces between two subdomains; protected edges are
/// their edges and the feature `edges`. No flip removes a protected face or
/// edge (an interior edge whose two end points lie on the boundary may be
/// removed), every flip only combines tets of one subdomain, and the new tets
/// get that subdomain. Vertices on protected faces, on feature edges, and
/// corners never move (in this version boundary vertices are not smoothed
/// at all). So `triangles`, `triangle_refs`, `edges`, `edge_refs`,
/// `corners`, `point_refs` and the coordinates of every boundary point are
/// unchanged; the tets fill the same region (volume unchanged up to the
/// rounding of its sum) and `check_validity()` still holds.
///
/// **Passes.** Each pass has two phases. (1) Flips: every tet below
/// `target_angle` goes into a priority queue, worst first (ties by slot
/// index); for a popped tet the best strictly improving flip among the
/// removals of its six edges and the 2-3 flips of its four faces is applied
/// (best: largest new smallest quality), and the new tets still below the
/// target are pushed. (2) Smoothing: one sweep over the free vertices of the
/// tets below the target, in the order of the worst tet they belong to.
/// Passes repeat until one changes nothing, `maximum_passes` is reached, or
/// the time limit. An operation that failed is retried in a later pass only
/// if something changed around it (a flip touching one of its vertices, or
/// a move of one of their neighbours). Slivers (four nearly coplanar
/// vertices with good edges) get exactly this treatment, worst first: the
/// removals of their six edges (the two crossing diagonals above all), the
/// 2-3 flips of their four faces, then the smoothing of their four
/// vertices; there is no separate sliver classification in this version.
///
/// **Determinism.** No threads, no randomness, no dependence on hash order
/// (the hash sets are only queried): the same input and options give the
/// same output, unless the time limit cuts the work (where it cuts depends
/// on the machine; pass an infinite limit for reproducible results).
///
/// **Cost.** Per pass, O(number of bad tets) local operations: an edge
/// removal evaluates at most 2 C(n,3) candidate tets for a ring of n, a
/// smoothing a few dozen evaluations of the vertex's ball. Measured (one
/// core, release): 0.04 s per 10,000 tets on a mesh of the pipeline, about
/// 1 s per 10,000 tets on the Delaunay tetrahedralisation of random points
/// (75% of its tets below 40 degrees), with a constant metric field; a
/// field that is expensive to evaluate costs proportionally more (one
/// evaluation per candidate tet).
///
/// **Limitations of this version.** Boundary and interface vertices never
/// move and boundary faces are never flipped, so a bad tet whose vertices
/// are all on the boundary and whose edges are all boundary edges stays.
/// No vertex insertion or edge contraction: the number of vertices is fixed.
/// Smoothing maximises the worst tet of a ball, which can lower its other
/// tets (the mean quality may drop when smoothing alone is used).

namespace CGAL {
namespace Bubble_mesh_3 {

/// \ingroup PkgBubbleMesh3Ref
/// Options of `improve_mesh()`.
struct Improvement_options {
  /// upper bound on the number of passes over the bad tets
  int maximum_passes = 10;
  /// wall-clock budget in seconds; a negative value means automatic:
  /// 2 s plus 10 s per 100,000 tets
  double time_limit_seconds = -1;
  /// apply 2-3 flips and edge removals (3-2, 4-4, n-to-(2n-4))
  bool flips = true;
  /// move interior vertices
  bool smoothing = true;
  /// tets whose quality (metric minimum dihedral angle, degrees) is below
  /// this are worked on
  double target_angle = 40;
  /// largest number of tets around an edge that edge removal considers
  int maximum_ring_size = 10;
  /// steepest-ascent steps per smoothing of one vertex
  int smoothing_iterations = 8;
};

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
  std::size_t flips_2_3 = 0;
  std::size_t flips_3_2 = 0;
  std::size_t flips_4_4 = 0;
  /// removals of edges with 5 or more tets around them (n-to-(2n-4))
  std::size_t edge_removals = 0;
  /// accepted vertex moves
  std::size_t smoothing_moves = 0;
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

} // namespace internal

/// \ingroup PkgBubbleMesh3Functions
/// Improves the quality of `mesh` in the metric `field` (a model of
/// `MetricField_3`) by flips and interior-vertex smoothing, in place; see
/// the file documentation for the operations and the guarantees. `mesh`
/// must be valid (`check_validity()`), with positively oriented tets.
/// Tets keep their subdomain; their order changes. Throws `Invalid_input`
/// if an index is out of range; exceptions of `field` propagate.
template <typename MetricField_3>
Improvement_report improve_mesh(Indexed_tet_mesh_3& mesh, const MetricField_3& field,
                                const Improvement_options& options = {})
{
  Improvement_report report;
  report.tets_before = mesh.tets.size();
  if(mesh.tets.empty())
    return report;
  internal::improve::Mutable_tet_mesh work(mesh);
  internal::improve::Improver_settings settings;
  settings.maximum_passes = std::max(0, options.maximum_passes);
  settings.time_limit_seconds = options.time_limit_seconds >= 0
                                    ? options.time_limit_seconds
                                    : 2.0 + 1e-4 * double(mesh.tets.size());
  settings.flips = options.flips;
  settings.smoothing = options.smoothing;
  settings.target_angle = options.target_angle;
  settings.maximum_ring_size = std::size_t(std::max(3, options.maximum_ring_size));
  settings.smoothing_iterations = std::max(0, options.smoothing_iterations);

  internal::improve::Mesh_improver<MetricField_3> improver(work, field, settings);
  internal::improvement_statistics(improver.qualities(), options.target_angle, report.worst_before,
                                   report.p01_before, report.mean_before, report.below_target_before);
  improver.run();
  internal::improvement_statistics(improver.qualities(), options.target_angle, report.worst_after,
                                   report.p01_after, report.mean_after, report.below_target_after);
  work.write_back(mesh);

  const internal::improve::Improver_counters& c = improver.counters();
  report.tets_after = mesh.tets.size();
  report.flips_2_3 = c.flips_2_3;
  report.flips_3_2 = c.flips_3_2;
  report.flips_4_4 = c.flips_4_4;
  report.edge_removals = c.edge_removals;
  report.smoothing_moves = c.smoothing_moves;
  report.passes = c.passes;
  report.time_limit_reached = c.time_limit_reached;
  report.seconds = improver.elapsed_seconds();
  return report;
}

} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_IMPROVE_MESH_H
