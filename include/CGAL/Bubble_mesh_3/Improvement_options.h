// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_IMPROVEMENT_OPTIONS_H
#define CGAL_BUBBLE_MESH_3_IMPROVEMENT_OPTIONS_H

#include <array>
#include <functional>

namespace CGAL {
namespace Bubble_mesh_3 {

/// \ingroup PkgBubbleMesh3Ref
/// Options of `improve_mesh()`.
struct Improvement_options {
  /// upper bound on the number of passes over the bad tets
  int maximum_passes = 10;
  /// wall-clock budget in seconds; a negative value means automatic:
  /// 2 s plus 10 s per 100,000 tets (`time_limit_reached` tells when it cut)
  double time_limit_seconds = -1;
  /// apply 2-3 flips and edge removals (3-2, 4-4, n-to-(2n-4))
  bool flips = true;
  /// move vertices (interior ones; boundary ones with `boundary_smoothing`)
  bool smoothing = true;
  /// tets whose quality (metric minimum dihedral angle, degrees) is below
  /// this are worked on
  double target_angle = 40;
  /// largest number of tets around an edge that edge removal considers
  int maximum_ring_size = 10;
  /// steepest-ascent steps per smoothing of one vertex
  int smoothing_iterations = 8;
  /// also move boundary and interface vertices where that cannot change the
  /// domain: in the plane of a planar region of one patch, along a straight
  /// feature line (see the file documentation); needs `smoothing`
  bool boundary_smoothing = true;
  /// flip boundary edges inside planar regions of one patch (2-2, 4-4, ...:
  /// see the file documentation); changes `triangles` but not the surface
  bool boundary_flips = true;
  /// with `boundary_flips` and a `surface_projection`: also flip boundary
  /// edges whose two triangles are not in one plane, and remove *caps* (a
  /// tet with two boundary triangles of one patch, flat on a curved or
  /// noisy surface), when no new boundary triangle turns by more than 20
  /// degrees from the old ones: the surface changes by the flipped chords
  /// (see the file documentation); false keeps every boundary triangle
  bool curved_boundary_flips = true;
  /// for a vertex of a sliver that smoothing could not move: push it off
  /// the sliver's opposite face, then random trial moves
  bool sliver_moves = true;
  /// when flips and moves are stuck: split an edge of each tet still below
  /// `split_below_angle` (an interior edge, a boundary edge of one patch
  /// with a `surface_projection`, a feature edge with a `curve_projection`;
  /// never an interface edge), at the point near
  /// its midpoint that maximises the worst of the new tets (on the patch's
  /// surface for a boundary edge), when that raises the worst tet around
  /// the edge by a degree or more; then flips and moves again (up to three
  /// rounds). Adds vertices (appended to `points`, and to `point_refs` if it
  /// is filled: the patch of a boundary vertex, the subdomain of an interior
  /// one, the curve of a feature-edge vertex), splits listed triangles (the
  /// second halves appended) and feature edges (likewise).
  /// Off by default: a caller holding data per vertex (a C3T3) must expect
  /// the new vertices.
  bool edge_splits = false;
  double split_below_angle = 15;
  /// in the same rounds, before the splits: collapse a short edge of each
  /// tet still below `split_below_angle` (the shortest in the metric first,
  /// each direction), removing a free vertex or a vertex inside one patch
  /// (the edge then a boundary edge of that patch) onto its neighbour, when
  /// the link condition holds (the mesh and its boundary stay manifold),
  /// every new tet is positive, no boundary triangle turns by more than 20
  /// degrees, and the worst tet of the removed vertex's star rises by a
  /// degree. Removes vertices and listed triangles, renumbering the rest
  /// (`Improvement_report::new_vertex_index`). Off by default, like the splits.
  bool edge_collapses = false;
  /// interior vertex moves keep every edge of the vertex that is in [1/sqrt(2),
  /// sqrt(2)] in the metric in that range (boundary moves always do), so the
  /// smoothing does not buy angles with edge lengths. Off by default (as
  /// before); on in the pipeline: on UGAWG polar-1 at sizes x2 the edges in
  /// range go from 71.7 % to 74.6 % instead of 62.3 %, the worst angle
  /// 9.8 degrees instead of 10.6
  bool keep_edges_in_range = false;
  /// the flips (2-3, edge removals, boundary flips) of tets not below
  /// `split_below_angle` create no edge outside [1/sqrt(2), sqrt(2)] in the
  /// metric; slivers are still flipped freely. Conformity for angles: on 12
  /// runs of the anisotropy family (every shock layer, the elephant's
  /// cylindrical and 1:4 layer metrics; benchmark/Bubble_mesh_3/RESULTS_anisotropy.md),
  /// paired against the same engine without it, the edges in range after
  /// the improvement rose on all 12 (by 0.3-1.5 points; knot1's 1:40 shock
  /// 79.6 -> 81.1 %) and the worst angle fell on 10 (elephant cylindrical
  /// 27.1 -> 21.6, fandisk 1:40 shock 9.0 -> 4.7 degrees). Off by default and
  /// in the pipeline.
  bool flips_keep_edges_in_range = false;
  /// after the first passes of flips and moves, up to 4 rounds over the edges outside
  /// [1/sqrt(2), sqrt(2)] in the metric, which flips and moves cannot fix
  /// where the metric grades fast: each edge longer than sqrt(2) (longest
  /// first) is removed by an edge removal when no new edge is as long (an
  /// edge cutting through a layer of nodes), else split near its midpoint
  /// when every new edge is shorter than it and not shorter than 1/sqrt(2)
  /// (a gap); each edge shorter than 1/sqrt(2) (shortest first) is
  /// collapsed when that lowers the summed log-scale excess outside the
  /// range of the removed vertex's edges (a cluster). Every change keeps
  /// the worst tet around at least at the lower of its old worst and the
  /// higher of 20 degrees and the mesh's worst (the worst never drops). Then
  /// passes again. Adds and removes vertices like the splits and collapses (with
  /// the same conditions on the boundary). Off by default; on in the
  /// pipeline (the elephant with a 1:10 layer: edges in range 81 -> 84 %)
  bool edge_lengths = false;
  /// with a `surface_projection` and `boundary_smoothing` (and a
  /// `curve_projection` for the feature edges) and a positive value D: at the end, up to 4 rounds over the
  /// boundary triangles farther than D from their patch's surface (sampled on
  /// a barycentric grid of 4 steps per edge and at the centroid: a chord
  /// strays most inside),
  /// farthest first, each triangle's edges tried longest first and split at a
  /// point on the input (placed like the splits above; its new boundary
  /// triangles turn by at most 80 degrees) when no new tet is below 15
  /// degrees (or the mesh's worst, if lower); then passes again. Throughout
  /// the improvement, boundary moves and curved boundary flips keep each
  /// boundary triangle within D or no farther than before. Adds vertices
  /// like `edge_splits`. `Improvement_report` gives the splits, the largest
  /// distance after and the triangles still beyond D (where no split was
  /// good enough). 0 (the default): off
  double surface_distance = 0;
  /// seed of those random trial moves (the result is a function of it)
  unsigned random_seed = 0;
  /// tets of ref 0 are padding outside the domain (as the cells outside the
  /// complex of a C3T3): every move keeps them positively oriented, but they
  /// are never flipped, never measured, and not counted in the report
  bool ref_0_is_exterior = false;
  /// the true surface of the curved patches: `surface_projection(ref, p, q)`
  /// writes into `q` the point of patch `ref` (a triangle ref) closest to
  /// `p` and returns true (false: no move). When set, with
  /// `boundary_smoothing`, a vertex inside one curved patch (one closed fan
  /// of listed triangles of that ref on the domain boundary, no feature edge
  /// or corner at it) slides along the surface: every candidate is
  /// projected by it, moves by at most half its shortest metric edge, and
  /// turns no boundary triangle at it by more than 20 degrees. The boundary
  /// triangles stay the same (same vertices, refs and orientation) and their
  /// vertices stay on the surface, but the triangles move with their
  /// vertices, so the meshed volume changes by the change of the chords.
  /// Unset (the default): vertices of curved patches never move.
  std::function<bool(int, const std::array<double, 3>&, std::array<double, 3>&)> surface_projection;
  /// the true curves of the curved feature curves: `curve_projection(ref, p,
  /// q)` writes into `q` the point of curve `ref` (an edge ref) closest to `p`
  /// and returns true (false: no move). When set, with `boundary_smoothing`,
  /// a vertex inside a curved feature curve (two feature edges of that ref,
  /// not on a straight line) slides along the curve, strictly between its
  /// two neighbours on it, under the same bounds as a surface move. Unset
  /// (the default): vertices of curved feature curves never move.
  std::function<bool(int, const std::array<double, 3>&, std::array<double, 3>&)> curve_projection;
  /// polled between operations (every 64 flips, every 16 vertex moves); a
  /// `true` ends the work as the time limit does (`time_limit_reached`).
  /// An exception thrown by it propagates and leaves `mesh` unchanged.
  std::function<bool()> should_stop;
};

} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_IMPROVEMENT_OPTIONS_H
