// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_IMPROVE_MESH_IMPROVER_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_IMPROVE_MESH_IMPROVER_H

#include <CGAL/Bubble_mesh_3/Improvement_options.h>
#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/Quality_report.h>
#include <CGAL/Bubble_mesh_3/internal/improve/Boundary_grid.h>
#include <CGAL/Bubble_mesh_3/internal/improve/Mutable_tet_mesh.h>
#include <CGAL/Bubble_mesh_3/metric_quality.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <functional>
#include <iterator>
#include <memory>
#include <limits>
#include <queue>
#include <random>
#include <utility>
#include <vector>

// The driver of improve_mesh(): passes of (1) a flip phase, a worklist of
// the tets below the target angle, worst first, each removed by the best
// strictly improving flip among the removals of its six edges (3-2, 4-4,
// n-to-(2n-4); boundary flips for boundary edges in a plane, and with a
// surface projection off it, caps included) and the 2-3
// flips of its four faces; (2) a smoothing sweep over the movable vertices
// (free, or sliding in a boundary plane or along a feature line) of the
// remaining bad tets, with pushes and seeded random trial moves for sliver
// vertices that smoothing could not move. The flip phase ends:
// every flip raises the sorted vector of all qualities lexicographically
// (it removes a tet of quality m and adds only tets above m), so no
// configuration repeats. See improve_mesh.h for the documentation.

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {
namespace improve {

/// The improver's settings: the user's options (`Improvement_options`) with
/// their ranges enforced and the automatic time limit resolved.
struct Improver_settings : Improvement_options {
  /// `maximum_ring_size`, at least 3
  std::size_t ring_limit;
  /// random trial moves per sliver vertex that a push could not free
  int perturbation_trials = 16;

  Improver_settings(const Improvement_options& o, std::size_t number_of_tets)
    : Improvement_options(o), ring_limit(std::size_t(std::max(3, o.maximum_ring_size)))
  {
    maximum_passes = std::max(0, o.maximum_passes);
    time_limit_seconds = o.time_limit_seconds >= 0 ? o.time_limit_seconds : 2.0 + 1e-4 * double(number_of_tets);
    smoothing_iterations = std::max(0, o.smoothing_iterations);
  }
};

struct Improver_counters {
  std::size_t flips_2_3 = 0;
  std::size_t flips_3_2 = 0;
  std::size_t flips_4_4 = 0;
  std::size_t edge_removals = 0;
  std::size_t smoothing_moves = 0;
  /// accepted moves of vertices on a boundary plane or a feature line
  /// (counted in `smoothing_moves` too)
  std::size_t boundary_moves = 0;
  /// boundary flips (2-2, 4-4, ... in a planar region of one patch)
  std::size_t boundary_flips = 0;
  /// accepted moves of sliver vertices by the push or by perturbation
  std::size_t sliver_moves = 0;
  /// edge splits (each adds a vertex), and those of boundary edges
  std::size_t edge_splits = 0;
  std::size_t boundary_edge_splits = 0;
  /// those of feature edges (counted in both above too)
  std::size_t feature_edge_splits = 0;
  /// edge collapses (each removes a vertex), and those of boundary edges
  std::size_t edge_collapses = 0;
  std::size_t boundary_edge_collapses = 0;
  /// those of feature edges (counted in both above too)
  std::size_t feature_edge_collapses = 0;
  /// the splits and collapses of `length_phase()` (counted in the above too)
  std::size_t length_splits = 0;
  std::size_t length_collapses = 0;
  /// edge removals of long edges by `length_phase()` (counted in the flips too)
  std::size_t length_flips = 0;
  /// the splits of `distance_phase()` (counted in the splits too), and the
  /// boundary triangles still farther than the bound from the input after it
  std::size_t distance_splits = 0;
  std::size_t triangles_beyond_distance = 0;
  /// the largest sampled distance of a boundary triangle to its patch after
  /// the improvement (measured only with a bound)
  double largest_surface_distance = 0;
  int passes = 0;
  bool time_limit_reached = false;
};

/// The smallest dihedral angle (degrees) of the tet spanned by the edge
/// vectors a, b, c: the same value as
/// `minimum_dihedral_angle_of_edge_vectors()` (the same `atan2` of the same
/// normals), with one `atan2` instead of six: the smallest angle is the one
/// of largest cosine.
inline double fast_minimum_dihedral_angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c)
{
  Eigen::Vector3d n[4];
  face_normals(a, b, c, n);
  double inverse_length[4];
  for(int k = 0; k < 4; ++k) {
    const double l = n[k].norm();
    if(!(l > 0))
      return minimum_dihedral_angle_of_edge_vectors(a, b, c); // degenerate face
    inverse_length[k] = 1 / l;
  }
  int best = 0;
  double best_cosine = -std::numeric_limits<double>::infinity();
  for(int e = 0; e < 6; ++e) {
    const int k = edge_opposite_faces[e][0], l = edge_opposite_faces[e][1];
    const double cosine = -n[k].dot(n[l]) * inverse_length[k] * inverse_length[l];
    if(cosine > best_cosine) {
      best_cosine = cosine;
      best = e;
    }
  }
  return radians_to_degrees() *
         dihedral_angle_from_normals(n[edge_opposite_faces[best][0]], n[edge_opposite_faces[best][1]]);
}

/// Whether the tet spanned by the metric edge vectors a, b, c (from its
/// first vertex) is a sliver: its edges are all of about the same length
/// (longest / shortest <= 2), yet it is nearly flat (smallest dihedral angle
/// below 20 degrees and largest above 140): four nearly coplanar vertices,
/// the shape the (metric) Delaunay criterion does not remove.
inline bool is_sliver_of_edge_vectors(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c)
{
  const double lengths[6] = {a.norm(), b.norm(), c.norm(), (b - a).norm(), (c - a).norm(), (c - b).norm()};
  const double shortest = *std::min_element(lengths, lengths + 6);
  const double longest = *std::max_element(lengths, lengths + 6);
  if(!(longest <= 2 * shortest))
    return false;
  const std::array<double, 6> angles = dihedral_angles_of_edge_vectors(a, b, c);
  return *std::min_element(angles.begin(), angles.end()) < 20 && *std::max_element(angles.begin(), angles.end()) > 140;
}

/// The quality of a tet: its minimum dihedral angle (degrees) after mapping
/// by `Q` of the metric at its centroid (`M = Q^T Q`), as in
/// `compute_quality_report()`; -1 for a tet that is not positively oriented
/// (exact test), so that it loses against every valid configuration.
template <typename MetricField_3>
class Tet_quality {
public:
  typedef typename MetricField_3::Point_3 Field_point;

  explicit Tet_quality(const MetricField_3& field) : field_(field) {}

  double operator()(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                    const Eigen::Vector3d& p3) const
  {
    if(exact_orientation(p0, p1, p2, p3) != CGAL::POSITIVE)
      return -1;
    return unchecked(p0, p1, p2, p3);
  }

  /// the quality of a tet known to be positively oriented
  double unchecked(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                   const Eigen::Vector3d& p3) const
  {
    const Eigen::Matrix3d& q = q_at(0.25 * (p0 + p1 + p2 + p3));
    return fast_minimum_dihedral_angle(map_by_upper(q, p1 - p0), map_by_upper(q, p2 - p0),
                                       map_by_upper(q, p3 - p0));
  }

  /// the value `compute_quality_report()` gives: 0 for a flat tet, the
  /// six-`atan2` minimum otherwise (whatever the orientation)
  double reference(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                   const Eigen::Vector3d& p3) const
  {
    if(exact_orientation(p0, p1, p2, p3) == CGAL::COPLANAR)
      return 0;
    const Eigen::Matrix3d& q = q_at(0.25 * (p0 + p1 + p2 + p3));
    return minimum_dihedral_angle_of_edge_vectors(map_by_upper(q, p1 - p0), map_by_upper(q, p2 - p0),
                                                  map_by_upper(q, p3 - p0));
  }

  /// `is_sliver_of_edge_vectors()` in the metric at the centroid
  bool is_sliver(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                 const Eigen::Vector3d& p3) const
  {
    const Eigen::Matrix3d& q = q_at(0.25 * (p0 + p1 + p2 + p3));
    return is_sliver_of_edge_vectors(map_by_upper(q, p1 - p0), map_by_upper(q, p2 - p0), map_by_upper(q, p3 - p0));
  }

  Metric_3 metric_at(const Eigen::Vector3d& p) const
  {
    const auto& m = field_(Field_point(p[0], p[1], p[2]));
    const Metric_3& metric = m;
    return metric;
  }

private:
  const Eigen::Matrix3d& q_at(const Eigen::Vector3d& c) const
  {
    q_ = Metric_3(field_(Field_point(c[0], c[1], c[2]))).Q();
    return q_;
  }

  const MetricField_3& field_;
  mutable Eigen::Matrix3d q_;
};

template <typename MetricField_3>
class Mesh_improver {
public:
  typedef Mutable_tet_mesh::Tet Tet;

  Mesh_improver(Mutable_tet_mesh& mesh, const MetricField_3& field, const Improver_settings& settings)
    : m_(mesh), quality_(field), s_(settings), target_(settings.target_angle),
      start_(std::chrono::steady_clock::now())
  {
    q_.resize(m_.tets.size());
    for(std::size_t t = 0; t < m_.tets.size(); ++t)
      q_[t] = tet_quality(int(t));
    tet_tried_.assign(m_.tets.size(), -1);
    vertex_tried_.assign(m_.points.size(), -1);
    vertex_changed_.assign(m_.points.size(), 0);
    // Only the operations that leave a plane (with a projection on the
    // input's curved patches and curves) can fold the boundary
    if(s_.boundary_smoothing && (m_.surface_projection || m_.curve_projection))
      build_boundary_grid();
  }

  /// the qualities of the current tets (slot order), computed exactly as
  /// `compute_quality_report()` does (same bits, also for a flat tet)
  std::vector<double> qualities() const
  {
    std::vector<double> values;
    for(std::size_t t = 0; t < m_.tets.size(); ++t)
      if(m_.alive[t] && !m_.is_passive(int(t))) {
        const Tet& T = m_.tets[t];
        values.push_back(quality_.reference(P(T[0]), P(T[1]), P(T[2]), P(T[3])));
      }
    return values;
  }

  /// the number of slivers (`is_sliver_of_edge_vectors()`) among the
  /// current tets
  std::size_t number_of_slivers() const
  {
    std::size_t n = 0;
    for(std::size_t t = 0; t < m_.tets.size(); ++t)
      if(m_.alive[t] && !m_.is_passive(int(t))) {
        const Tet& T = m_.tets[t];
        n += quality_.is_sliver(P(T[0]), P(T[1]), P(T[2]), P(T[3])) ? 1 : 0;
      }
    return n;
  }

  /// tets that are not passive
  std::size_t number_of_active_tets() const
  {
    std::size_t n = 0;
    for(std::size_t t = 0; t < m_.tets.size(); ++t)
      n += m_.alive[t] && !m_.is_passive(int(t)) ? 1 : 0;
    return n;
  }

  double elapsed_seconds() const
  {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

  const Improver_counters& counters() const { return c_; }

  /// Passes of (1) flips driven by a worklist of the bad tets, worst
  /// first, until no flip improves, then (2) one smoothing sweep over the
  /// free vertices of the bad tets, worst ball first. Stops when a pass
  /// changes nothing, after `maximum_passes`, or at the time limit.
  /// With `edge_lengths`, then `length_phase()` and passes again. With
  /// `edge_splits`, then rounds of edge splits of the tets still below
  /// `split_below_angle`, each followed by passes again.
  void run()
  {
    const int split_rounds = s_.edge_splits || s_.edge_collapses ? 3 : 0;
    for(int round = 0;; ++round) {
      for(int pass = 0; pass < s_.maximum_passes; ++pass) {
        if(!has_bad_tet())
          break;
        ++c_.passes;
        std::size_t changes = 0;
        if(s_.flips)
          changes += flip_phase();
        if(s_.smoothing && !c_.time_limit_reached)
          changes += smoothing_phase();
        if(c_.time_limit_reached || changes == 0)
          break;
      }
      // after the first passes, so that the length changes start from (and
      // keep) the worst angle they reached
      if(s_.edge_lengths && round == 0 && !c_.time_limit_reached && length_phase() > 0)
        continue;
      if(round >= split_rounds || c_.time_limit_reached)
        break;
      std::size_t changes = s_.edge_collapses ? collapse_phase() : 0;
      if(s_.edge_splits && !c_.time_limit_reached)
        changes += split_phase();
      if(changes == 0)
        break;
      target_ = std::min(s_.target_angle, s_.split_below_angle);
    }
    if(s_.surface_distance > 0 && m_.surface_projection)
      keep_surface_distance();
  }

private:
  struct Entry {
    double quality;
    int tet;
    unsigned stamp;
    // std::priority_queue pops the largest: make the worst tet the largest
    bool operator<(const Entry& o) const
    {
      if(quality != o.quality)
        return quality > o.quality;
      if(tet != o.tet)
        return tet > o.tet;
      return stamp > o.stamp;
    }
  };
  typedef std::priority_queue<Entry> Queue;

  /// a proposed flip: remove `old_tets`, insert `new_tets`
  struct Flip {
    double new_worst = -std::numeric_limits<double>::infinity();
    double old_worst = 0;
    bool is_edge_removal = false;
    std::size_t ring_size = 0;
    std::vector<int> old_tets;
    std::vector<Tet> new_tets;
    int ref = 0;
    /// a boundary flip: the boundary faces it replaces and creates, and the
    /// old edge (a, b) and the new one (c, d) as {a, b, c, d}
    bool boundary = false;
    std::array<std::array<int, 3>, 2> old_faces{}, new_faces{};
    std::array<int, 4> edge_vertices{};
    /// a boundary flip off a plane (its embedding is checked when chosen)
    bool leaves_plane = false;
  };

  const Eigen::Vector3d& P(int v) const { return m_.points[std::size_t(v)]; }

  /// the quality of slot `t`; +infinity for a passive (exterior) tet, so
  /// that it is never bad and never the worst of anything
  double tet_quality(int t) const
  {
    if(m_.is_passive(t))
      return std::numeric_limits<double>::infinity();
    const Tet& T = m_.tets[std::size_t(t)];
    return quality_(P(T[0]), P(T[1]), P(T[2]), P(T[3]));
  }

  double quality_of(const Tet& T) const { return quality_(P(T[0]), P(T[1]), P(T[2]), P(T[3])); }

  void push_if_bad(int t)
  {
    if(q_[std::size_t(t)] < target_)
      queue_.push({q_[std::size_t(t)], t, m_.stamp[std::size_t(t)]});
  }

  // ---- the boundary's embedding ---------------------------------------------

  void build_boundary_grid()
  {
    double length = 0;
    std::size_t count = 0;
    for(const Face_key& f : m_.protected_faces)
      for(int k = 0; k < 3; ++k) {
        length += (P(f.v[std::size_t(k)]) - P(f.v[std::size_t((k + 1) % 3)])).norm();
        ++count;
      }
    grid_ = std::make_unique<Boundary_grid>(count > 0 ? 2 * length / double(count) : 1.0);
    for(const Face_key& f : m_.protected_faces)
      index_face(f.v[0], f.v[1], f.v[2]);
  }

  void index_face(int a, int b, int c)
  {
    if(grid_)
      grid_->insert(Face_key(a, b, c).v, {{P(a), P(b), P(c)}});
  }

  /// Whether the boundary stays embedded when the protected faces `old_faces`
  /// are replaced by `new_faces` (vertex ids; -1 and `moved` stand for the
  /// point `x`): no new face meets a protected face other than the old ones
  /// and the new ones except in shared vertices and edges. True without a
  /// grid (no operation that could fold the boundary).
  bool boundary_stays_embedded(const std::vector<std::array<int, 3>>& new_faces,
                               const std::vector<std::array<int, 3>>& old_faces, int moved, const Eigen::Vector3d& x) const
  {
    if(!grid_)
      return true;
    auto point = [&](int v) -> const Eigen::Vector3d& { return v < 0 || v == moved ? x : P(v); };
    std::vector<Face_key> skip;
    for(const auto& f : old_faces)
      skip.push_back(Face_key(f[0], f[1], f[2]));
    for(const auto& f : new_faces)
      if(f[0] >= 0 && f[1] >= 0 && f[2] >= 0)
        skip.push_back(Face_key(f[0], f[1], f[2]));
    for(const auto& f : new_faces) {
      const std::array<Eigen::Vector3d, 3> xf{{point(f[0]), point(f[1]), point(f[2])}};
      const bool met = grid_->any_near(xf, [&](const Boundary_grid::Face& g) {
        const Face_key key(g[0], g[1], g[2]);
        if(!m_.protected_faces.count(key) || std::find(skip.begin(), skip.end(), key) != skip.end())
          return false;
        return triangles_meet_improperly(xf, f, {{point(g[0]), point(g[1]), point(g[2])}}, g);
      });
      if(met)
        return false;
    }
    return true;
  }

  // ---- flips --------------------------------------------------------------

  /// The 2-3 flip of the face of `t` opposite its vertex `T[f]`: the tets
  /// (a,b,c,d) and (a,b,c,e) become (a,b,e,d), (b,c,e,d), (c,a,e,d).
  void consider_face_flip(int t, int f, Flip& best) const
  {
    const Tet& T = m_.tets[std::size_t(t)];
    const int d = T[std::size_t(f)];
    int a = T[std::size_t((f + 1) % 4)], b = T[std::size_t((f + 2) % 4)], c = T[std::size_t((f + 3) % 4)];
    if(permutation_parity(T, a, b, c, d) != 0)
      std::swap(a, b); // now orientation(a, b, c, d) > 0
    if(m_.is_protected_face(a, b, c))
      return;
    const int s = m_.opposite_tet(t, a, b, c);
    if(s < 0 || m_.refs[std::size_t(s)] != m_.refs[std::size_t(t)])
      return;
    const int e = m_.fourth_vertex(s, a, b, c);
    const double old_worst = std::min(q_[std::size_t(t)], q_[std::size_t(s)]);
    const double bar = std::max(old_worst, best.new_worst);
    const Tet n0{{a, b, e, d}}, n1{{b, c, e, d}}, n2{{c, a, e, d}};
    double w = quality_of(n0);
    if(w <= bar)
      return;
    w = std::min(w, quality_of(n1));
    if(w <= bar)
      return;
    w = std::min(w, quality_of(n2));
    if(w <= bar)
      return;
    // In a valid mesh d and e cannot already be joined (the segment de
    // crosses the face abc); checked anyway, it is cheap.
    if(m_.are_connected(d, e))
      return;
    // the flip's one new edge: the angles are not bought with conformity
    if(flips_keep_lengths(old_worst) && !in_metric_range(cached_edge_length(d, e)))
      return;
    best.new_worst = w;
    best.old_worst = old_worst;
    best.is_edge_removal = false;
    best.boundary = false;
    best.ring_size = 0;
    best.old_tets = {t, s};
    best.new_tets = {n0, n1, n2};
    best.ref = m_.refs[std::size_t(t)];
  }

  /// Edge removal: the n tets around the interior edge (a, b) are replaced
  /// by the 2n-4 tets joining a and b to the triangles of the best
  /// triangulation of the ring polygon p_0 .. p_{n-1} (`best_ring_triangulation()`).
  void consider_edge_removal(int t, int a, int b, Flip& best)
  {
    if(m_.is_protected_edge(a, b)) {
      consider_boundary_flip(t, a, b, best);
      return;
    }
    if(!m_.edge_ring(a, b, s_.ring_limit, ring_, ring_tets_))
      return;
    const int ref = m_.refs[std::size_t(t)];
    double old_worst = std::numeric_limits<double>::infinity();
    for(int s : ring_tets_) {
      if(m_.refs[std::size_t(s)] != ref)
        return;
      old_worst = std::min(old_worst, q_[std::size_t(s)]);
    }
    const double bar = std::max(old_worst, best.new_worst);
    double result = 0;
    int top = -1;
    // as the 2-3 flip: no new edge out of the metric's range
    if(!best_ring_triangulation(a, b, bar, result, scratch_tets_, top, flips_keep_lengths(old_worst)))
      return;
    take_edge_removal(best, result, old_worst, ref);
  }

  /// `f` as the edge removal that `best_ring_triangulation()` left in
  /// `scratch_tets_` for the ring in `ring_` / `ring_tets_`
  void take_edge_removal(Flip& f, double new_worst, double old_worst, int ref) const
  {
    f.new_worst = new_worst;
    f.old_worst = old_worst;
    f.is_edge_removal = true;
    f.boundary = false;
    f.ring_size = ring_.size();
    f.old_tets = ring_tets_;
    f.new_tets = scratch_tets_;
    f.ref = ref;
  }

  /// Boundary flip (2-2, 4-4, ...: the boundary analogue of edge removal):
  /// the boundary edge (a, b) whose two boundary faces (a, b, p_0) and
  /// (a, b, p_k) lie exactly in one plane, in one patch, and which is no
  /// feature edge, is replaced by the edge (p_0, p_k): the k tets of its open
  /// fan p_0 .. p_k become the 2k-2 tets joining a and b to the best
  /// triangulation of the polygon p_0 .. p_k, whose chord (p_0, p_k) gives
  /// the new boundary faces (a, p_0, p_k) and (b, p_k, p_0). The quad
  /// a, p_0, b, p_k is then convex (the new tets are positive), so the
  /// boundary covers the same planar region. Only for faces of one tet (not
  /// interfaces, not next to passive padding) and without duplicate listed
  /// triangles.
  void consider_boundary_flip(int t, int a, int b, Flip& best)
  {
    if(!s_.boundary_flips || m_.has_duplicate_triangles || m_.is_feature_edge(a, b))
      return;
    if(!m_.edge_fan(a, b, s_.ring_limit - 1, ring_, ring_tets_))
      return;
    const int n = int(ring_.size());
    const int p0 = ring_.front(), pk = ring_.back();
    if(!m_.is_protected_face(a, b, p0) || !m_.is_protected_face(a, b, pk))
      return;
    for(int i = 1; i + 1 < n; ++i)
      if(m_.is_protected_face(a, b, ring_[std::size_t(i)]))
        return;
    const int ref = m_.refs[std::size_t(t)];
    double old_worst = std::numeric_limits<double>::infinity();
    for(int s : ring_tets_) {
      if(m_.refs[std::size_t(s)] != ref)
        return;
      old_worst = std::min(old_worst, q_[std::size_t(s)]);
    }
    const double bar = std::max(old_worst, best.new_worst);
    if(m_.opposite_tet(ring_tets_.front(), a, b, p0) >= 0 || m_.opposite_tet(ring_tets_.back(), a, b, pk) >= 0)
      return; // an interface
    if(m_.face_patch(a, b, p0) != m_.face_patch(a, b, pk))
      return;
    const bool coplanar = exact_orientation(P(a), P(b), P(p0), P(pk)) == CGAL::COPLANAR;
    if(!coplanar && !(s_.curved_boundary_flips && m_.surface_projection))
      return; // the caller accepts no change of the surface
    // n == 2: the one tet (a, b, p0, pk) is a cap on the surface (never flat
    // when coplanar); removing it makes its two inner faces boundary faces
    const bool cap = n == 2;
    int inside_a = -1, inside_b = -1; // the inner apices of the new faces (a, p0, pk), (b, p0, pk)
    if(cap) {
      if(m_.is_protected_edge(p0, pk) || m_.is_protected_face(a, p0, pk) || m_.is_protected_face(b, p0, pk))
        return; // the new boundary would not be a 2-manifold
      const int ta = m_.opposite_tet(t, a, p0, pk), tb = m_.opposite_tet(t, b, p0, pk);
      if(ta < 0 || tb < 0 || m_.refs[std::size_t(ta)] != ref || m_.refs[std::size_t(tb)] != ref)
        return;
      inside_a = m_.fourth_vertex(ta, a, p0, pk);
      inside_b = m_.fourth_vertex(tb, b, p0, pk);
    } else if(m_.are_connected(p0, pk))
      return;
    // as the interior flips: no new edge out of the metric's range (a cap's
    // removal creates none)
    const bool keep_range = flips_keep_lengths(old_worst) && !cap;
    if(keep_range && !in_metric_range(cached_edge_length(p0, pk)))
      return;
    double result = 0;
    int top = -1;
    if(!best_ring_triangulation(a, b, bar, result, scratch_tets_, top, keep_range))
      return;
    if(!cap)
      inside_a = inside_b = ring_[std::size_t(top)];
    if(!coplanar && !surface_change_is_small(a, b, p0, pk, ring_[1], ring_[std::size_t(n - 2)], inside_a, inside_b))
      return;
    // Off a plane the new boundary edge is a chord of the curved surface:
    // one longer than the metric allows strays by its sagitta (on a cylinder
    // wall a flip to the circumferential diagonal turned the faces by a few
    // degrees only, and left a chord of metric length 2, 1.5 times the
    // surface-distance bound away from the wall)
    if(!coplanar && metric_edge_length(p0, pk) > std::max(std::sqrt(2.0), metric_edge_length(a, b)))
      return;
    if(!coplanar && !keeps_surface_distance({{{P(a), P(b), P(p0)}}, {{P(a), P(b), P(pk)}}},
                                            {{{P(a), P(p0), P(pk)}}, {{P(b), P(p0), P(pk)}}},
                                            m_.face_patch(a, b, p0)))
      return;

    // the old faces as stored (listed orientation), the new ones oriented
    // like them with respect to the inside
    auto stored = [&](int x, int y, int z) {
      const int i = m_.listed_triangle(x, y, z);
      return i < 0 ? std::array<int, 3>{{x, y, z}} : m_.listed[std::size_t(i)];
    };
    const std::array<int, 3> old0 = stored(a, b, p0), old1 = stored(a, b, pk);
    const int apex_old0 = ring_[1], apex_old1 = ring_[std::size_t(n - 2)];
    auto oriented_like = [&](std::array<int, 3> f, int apex_f, const std::array<int, 3>& old, int apex_old) {
      if(exact_orientation(P(f[0]), P(f[1]), P(f[2]), P(apex_f)) !=
         exact_orientation(P(old[0]), P(old[1]), P(old[2]), P(apex_old)))
        std::swap(f[0], f[1]);
      return f;
    };
    best.new_worst = result;
    best.old_worst = old_worst;
    best.is_edge_removal = true;
    best.boundary = true;
    best.ring_size = std::size_t(n);
    best.old_tets = ring_tets_;
    best.new_tets = scratch_tets_;
    best.ref = ref;
    best.old_faces = {{old0, old1}};
    best.new_faces = {{oriented_like({{a, p0, pk}}, inside_a, old0, apex_old0),
                       oriented_like({{b, p0, pk}}, inside_b, old1, apex_old1)}};
    best.edge_vertices = {{a, b, p0, pk}};
    best.leaves_plane = !coplanar;
  }

  /// whether a metric edge length is in [1/sqrt2, sqrt2], the range of the
  /// quality report's conformity
  static bool in_metric_range(double l) { return l >= std::sqrt(0.5) && l <= std::sqrt(2.0); }

  /// whether a flip of tets whose worst quality is `old_worst` may create
  /// only edges in the metric's range (`flips_keep_edges_in_range`). Tets
  /// below `split_below_angle` are flipped freely: on the anisotropy family's
  /// shock layers the guard on every flip left slivers (elephant 1:10 shock
  /// worst 12.3 -> 7.9 degrees, 1:40 3.3 -> 1.1, against no guard).
  bool flips_keep_lengths(double old_worst) const
  {
    return s_.flips_keep_edges_in_range && old_worst >= s_.split_below_angle;
  }

  /// metric length of the segment (i, j): the mean of its lengths in the
  /// metrics at its ends (as `keeps_edges_in_range()` measures)
  double metric_edge_length(int i, int j) const
  {
    const Eigen::Vector3d d = P(j) - P(i);
    return 0.5 * (quality_.metric_at(P(i)).length(d) + quality_.metric_at(P(j)).length(d));
  }

  /// the largest turn of a boundary triangle (20 degrees) by a surface
  /// vertex move or a curved boundary flip: the triangles stay close to the
  /// surface they approximate
  static double cos_of_largest_boundary_turn() { return std::cos(20.0 * std::acos(-1.0) / 180.0); }

  /// A boundary flip off a plane changes the surface: as for the moves of
  /// surface vertices, no new boundary face may turn by more than 20
  /// degrees from either old one (outward normals: away from each face's
  /// inner apex). A flat cap, the tet this is mostly for, has nearly
  /// coplanar faces, so removing it moves the surface by its small height.
  bool surface_change_is_small(int a, int b, int p0, int pk, int inside_old0, int inside_old1, int inside_a,
                               int inside_b) const
  {
    auto outward = [&](int x, int y, int z, int inside) -> Eigen::Vector3d {
      const Eigen::Vector3d n = (P(y) - P(x)).cross(P(z) - P(x));
      return n.dot(P(inside) - P(x)) > 0 ? Eigen::Vector3d(-n) : n;
    };
    const Eigen::Vector3d old_normals[2] = {outward(a, b, p0, inside_old0), outward(a, b, pk, inside_old1)};
    const Eigen::Vector3d new_normals[2] = {outward(a, p0, pk, inside_a), outward(b, p0, pk, inside_b)};
    const double cos_turn = cos_of_largest_boundary_turn();
    for(const Eigen::Vector3d& o : old_normals)
      for(const Eigen::Vector3d& n : new_normals)
        if(!(o.dot(n) > cos_turn * o.norm() * n.norm()))
          return false;
    return true;
  }

  /// The triangulation of the polygon `ring_` = p_0 .. p_{n-1} that
  /// maximises the smallest quality of the tets joining a and b to its
  /// triangles, by the classic O(n^3) dynamic programme over the
  /// sub-polygons p_i .. p_j: the triangle (p_i, p_k, p_j), i < k < j, gives
  /// the tets (a, p_i, p_k, p_j) and (b, p_i, p_j, p_k). True if its smallest
  /// quality `result` is above `bar`; then `tets` holds the 2n-4 tets and
  /// `top` the k of the triangle on the chord (p_0, p_{n-1}). With
  /// `diagonals_in_range`, only triangulations whose diagonals (the new
  /// edges) have metric lengths in [1/sqrt2, sqrt2].
  bool best_ring_triangulation(int a, int b, double bar, double& result, std::vector<Tet>& tets, int& top,
                               bool diagonals_in_range = false)
  {
    const int n = int(ring_.size());
    const double unknown = std::numeric_limits<double>::quiet_NaN();
    // a chord (p_i, p_j), i < j, is a new edge unless it is a side of the
    // ring ((p_0, p_{n-1}) is one for an edge removal, and the new boundary
    // edge of a boundary flip, which checks it itself)
    auto chord_allowed = [&](int i, int j) {
      return !diagonals_in_range || j - i < 2 || (i == 0 && j == n - 1) ||
             in_metric_range(cached_edge_length(ring_[std::size_t(i)], ring_[std::size_t(j)]));
    };
    // triangle qualities, computed on demand; -1: invalid or not above `bar`
    triangle_.assign(std::size_t(n * n * n), unknown);
    auto triangle = [&](int i, int k, int j) {
      double& value = triangle_[std::size_t((i * n + k) * n + j)];
      if(value == value)
        return value;
      if(!chord_allowed(i, k) || !chord_allowed(k, j) || !chord_allowed(i, j)) {
        value = -1.0;
        return value;
      }
      const int pi = ring_[std::size_t(i)], pk = ring_[std::size_t(k)], pj = ring_[std::size_t(j)];
      double w = quality_of(Tet{{a, pi, pk, pj}});
      if(w > bar)
        w = std::min(w, quality_of(Tet{{b, pi, pj, pk}}));
      value = w > bar ? w : -1.0;
      return value;
    };
    const double infinity = std::numeric_limits<double>::infinity();
    table_.assign(std::size_t(n * n), -1.0);
    choice_.assign(std::size_t(n * n), -1);
    for(int i = 0; i + 1 < n; ++i)
      table_[std::size_t(i * n + i + 1)] = infinity;
    for(int length = 2; length < n; ++length)
      for(int i = 0; i + length < n; ++i) {
        const int j = i + length;
        double best_value = -1;
        int best_k = -1;
        for(int k = i + 1; k < j; ++k) {
          const double left = table_[std::size_t(i * n + k)];
          const double right = table_[std::size_t(k * n + j)];
          if(std::min(left, right) <= std::max(best_value, bar))
            continue;
          const double w = std::min(std::min(left, right), triangle(i, k, j));
          if(w > best_value) {
            best_value = w;
            best_k = k;
          }
        }
        table_[std::size_t(i * n + j)] = best_value;
        choice_[std::size_t(i * n + j)] = best_k;
      }
    result = table_[std::size_t(n - 1)];
    if(!(result > bar))
      return false;
    top = choice_[std::size_t(n - 1)];
    tets.clear();
    std::vector<std::pair<int, int>> stack{{0, n - 1}};
    while(!stack.empty()) {
      const auto [i, j] = stack.back();
      stack.pop_back();
      if(j - i < 2)
        continue;
      const int k = choice_[std::size_t(i * n + j)];
      const int pi = ring_[std::size_t(i)], pk = ring_[std::size_t(k)], pj = ring_[std::size_t(j)];
      tets.push_back(Tet{{a, pi, pk, pj}});
      tets.push_back(Tet{{b, pi, pj, pk}});
      stack.push_back({i, k});
      stack.push_back({k, j});
    }
    return true;
  }

  void apply(const Flip& flip)
  {
    ++clock_;
    for(int s : flip.old_tets)
      for(int v : m_.tets[std::size_t(s)])
        vertex_changed_[std::size_t(v)] = clock_;
    const std::vector<int> created = m_.replace(flip.old_tets, flip.new_tets, flip.ref);
    if(flip.boundary) {
      const auto& e = flip.edge_vertices;
      m_.replace_boundary_faces(flip.old_faces[0], flip.old_faces[1], flip.new_faces[0], flip.new_faces[1], e[0], e[1],
                                e[2], e[3]);
      for(const auto& f : flip.new_faces)
        index_face(f[0], f[1], f[2]);
      ++c_.boundary_flips;
    }
    q_.resize(m_.tets.size());
    tet_tried_.resize(m_.tets.size(), -1);
    for(int s : created)
      tet_tried_[std::size_t(s)] = -1;
    for(int s : created)
      q_[std::size_t(s)] = tet_quality(s);
    for(int s : created)
      push_if_bad(s);
    if(flip.boundary) {
      // counted above
    } else if(!flip.is_edge_removal)
      ++c_.flips_2_3;
    else if(flip.ring_size == 3)
      ++c_.flips_3_2;
    else if(flip.ring_size == 4)
      ++c_.flips_4_4;
    else
      ++c_.edge_removals;
  }

  // ---- smoothing ------------------------------------------------------------

  /// Moves the vertex `v` to raise the smallest quality of its ball:
  /// candidates are the (relaxed) mean of the ideal positions over the
  /// ball's opposite faces, then steepest-ascent steps of the max-min
  /// problem (direction: the smallest vector of the convex hull of the
  /// gradients of the nearly worst tets), in the coordinates `y = Q x` of the
  /// metric at `v`, with a halving line search. If nothing improved and the
  /// worst tet of the ball is a sliver, the push of `v` off the sliver's
  /// opposite face (along its metric normal), then random trial moves.
  /// A vertex with a plane or line constraint moves only in it: every
  /// candidate is projected, the gradients are projected on the tangent
  /// space. A move is accepted only if every ball tet (passive ones
  /// included) stays positively oriented (exact) and the smallest quality
  /// of the ball increases.
  bool smooth_vertex(int v)
  {
    Smoothing_ball b;
    if(!prepare_smoothing(v, b))
      return false;
    if(!move_to_ideal_position(b)) // a degenerate face in the ball
      return false;
    ascend(b);
    const std::size_t sliver_move = push_off_sliver(b);
    if(!(b.current > b.start + Smoothing_ball::minimum_gain) || b.x == b.x_start)
      return false;
    if(!apply_move(b))
      return false;
    c_.sliver_moves += sliver_move;
    return true;
  }

  /// An opposite face of a ball, with (v, f0, f1, f2) positively oriented.
  struct Ball_face {
    double quality;
    std::array<int, 3> f;
    bool passive;
  };

  /// One smoothing attempt of a vertex: its ball, the metric at its start,
  /// the constraint's tangent space, the bounds of a boundary move, and the
  /// best position so far.
  struct Smoothing_ball {
    static constexpr double minimum_gain = 1e-3; // degrees: no churn of negligible moves
    int v = -1;
    std::vector<int> ball;
    std::vector<Ball_face> faces; // worst first; passive tets (quality +infinity) last
    const Vertex_constraint* constraint = nullptr;
    bool constrained = false, on_curve = false, on_surface = false;
    double start = 0; // the ball's smallest quality before the move
    Eigen::Vector3d x_start;
    Metric_3 metric;
    Eigen::Matrix3d Q, Q_inverse;
    double scale = 0; // shortest metric edge at v
    // the tangent space of a constrained vertex, orthonormal in y = Q x
    int tangent_dimension = 3;
    Eigen::Vector3d tangent[2];
    // surface vertices: the protected faces at v (outward from their tet)
    // and their normals now, to bound how far each one turns
    std::vector<std::pair<std::array<int, 2>, Eigen::Vector3d>> surface_faces;
    std::vector<std::pair<int, Metric_3>> conforming; // neighbours joined by an edge in range
    double cos_turn = 1;
    Eigen::Vector3d x; // the best position so far, of quality `current`
    double current = 0;
    // the qualities of the faces' tets with the vertex at x, once a candidate
    // was taken (ball_quality() computed all of them then): the ascent reads
    // them instead of evaluating the metric again
    std::vector<double> face_quality;
    bool face_quality_at_x = false;
  };

  /// the ball of `v`, its faces, metric, tangent space and boundary bounds;
  /// false if `v` cannot move (no ball, a passive worst tet, degenerate)
  bool prepare_smoothing(int v, Smoothing_ball& b) const
  {
    b.v = v;
    b.ball = m_.vertex_tets[std::size_t(v)];
    if(b.ball.empty())
      return false;
    b.constraint = &m_.constraint[std::size_t(v)];
    b.constrained = b.constraint->kind != Vertex_constraint::free;
    b.faces.reserve(b.ball.size());
    for(int s : b.ball) {
      const Tet& T = m_.tets[std::size_t(s)];
      std::array<int, 3> f;
      int k = 0;
      for(int u : T)
        if(u != v)
          f[std::size_t(k++)] = u;
      if(permutation_parity(T, v, f[0], f[1], f[2]) != 0)
        std::swap(f[1], f[2]);
      b.faces.push_back({q_[std::size_t(s)], f, m_.is_passive(s)});
    }
    std::stable_sort(b.faces.begin(), b.faces.end(),
                     [](const Ball_face& x, const Ball_face& y) { return x.quality < y.quality; });
    if(b.faces.front().passive)
      return false;
    b.start = b.faces.front().quality;
    b.x_start = P(v);
    b.metric = vertex_metric(v);
    b.Q = b.metric.Q();
    b.Q_inverse = b.metric.Q_inverse();
    b.scale = std::numeric_limits<double>::infinity();
    for(const Ball_face& f : b.faces)
      for(int u : f.f)
        b.scale = std::min(b.scale, b.metric.length(P(u) - b.x_start));
    if(!(b.scale > 0 && std::isfinite(b.scale)))
      return false;
    // curved patches and curved feature curves change the boundary: the same bounds on the move
    b.on_curve = b.constraint->kind == Vertex_constraint::curve;
    b.on_surface = b.constraint->kind == Vertex_constraint::surface || b.on_curve;
    Eigen::Vector3d surface_tangent[2];
    if(b.on_surface && !collect_surface_faces(b, surface_tangent))
      return false;
    if(b.constrained) {
      b.tangent_dimension =
          (b.constraint->kind == Vertex_constraint::plane || (b.on_surface && !b.on_curve)) ? 2 : 1;
      for(int i = 0; i < b.tangent_dimension; ++i) {
        Eigen::Vector3d e = b.Q * (b.on_surface ? surface_tangent[i] : b.constraint->tangent[i]);
        for(int j = 0; j < i; ++j)
          e -= e.dot(b.tangent[j]) * b.tangent[j];
        b.tangent[i] = e.normalized();
      }
    }
    b.x = b.x_start;
    b.current = b.start;
    // A surface vertex changes the boundary: it stays within half its
    // shortest metric edge of where it started, no boundary face at it turns
    // by more than 20 degrees (the faces stay close to the surface), and no
    // edge at it leaves [1/sqrt 2, sqrt 2] in the metric (edge length: the
    // mean of its lengths in the two end metrics). Without the last rule the
    // elephant's boundary layer lost 1 % of its edges in range.
    b.cos_turn = cos_of_largest_boundary_turn();
    if(b.on_surface || s_.keep_edges_in_range)
      collect_conforming_edges(b);
    return true;
  }

  /// the boundary faces at a surface or curve vertex and its tangent plane
  /// or line; false if it has none
  bool collect_surface_faces(Smoothing_ball& b, Eigen::Vector3d (&surface_tangent)[2]) const
  {
    const int v = b.v;
    const Eigen::Vector3d normal = m_.boundary_normal(v);
    if(!b.on_curve && !(normal.norm() > 0))
      return false;
    const Eigen::Vector3d axis = b.on_curve ? b.constraint->axis : normal.normalized();
    surface_tangent[0] = b.on_curve ? b.constraint->axis : axis.unitOrthogonal();
    surface_tangent[1] = axis.cross(surface_tangent[0]);
    for(const Ball_face& f : b.faces) {
      if(f.passive)
        continue;
      // the faces of the tet at v: (v, f_k+1, f_k+2) opposite f_k
      for(int k = 0; k < 3; ++k) {
        const int a = f.f[std::size_t((k + 1) % 3)], c = f.f[std::size_t((k + 2) % 3)];
        if(!m_.protected_faces.count(Face_key(v, a, c)))
          continue;
        Eigen::Vector3d n = (P(a) - b.x_start).cross(P(c) - b.x_start);
        if(n.dot(P(f.f[std::size_t(k)]) - b.x_start) > 0) // point away from the tet's fourth vertex
          b.surface_faces.push_back({{{c, a}}, -n});
        else
          b.surface_faces.push_back({{{a, c}}, n});
      }
    }
    return !b.surface_faces.empty();
  }

  /// the neighbours of a vertex joined by an edge in range, whose edges a
  /// move must keep in range (surface vertices always; interior ones with
  /// `keep_edges_in_range`)
  void collect_conforming_edges(Smoothing_ball& b) const
  {
    std::vector<int> neighbours;
    for(const Ball_face& f : b.faces)
      neighbours.insert(neighbours.end(), f.f.begin(), f.f.end());
    std::sort(neighbours.begin(), neighbours.end());
    neighbours.erase(std::unique(neighbours.begin(), neighbours.end()), neighbours.end());
    for(int u : neighbours) {
      const Metric_3& mu = vertex_metric(u);
      const double l = 0.5 * (b.metric.length(P(u) - b.x_start) + mu.length(P(u) - b.x_start));
      if(l >= std::sqrt(0.5) && l <= std::sqrt(2.0))
        b.conforming.push_back({u, mu});
    }
  }

  /// smallest quality of the ball with its vertex at x (+infinity from a
  /// passive tet if positive); stops early at <= threshold
  double ball_quality(const Smoothing_ball& b, const Eigen::Vector3d& x, double threshold,
                      std::vector<double>* each = nullptr) const
  {
    double w = std::numeric_limits<double>::infinity();
    if(each)
      each->clear();
    for(const Ball_face& f : b.faces) {
      double q;
      if(f.passive)
        q = exact_orientation(x, P(f.f[0]), P(f.f[1]), P(f.f[2])) == CGAL::POSITIVE
                ? std::numeric_limits<double>::infinity()
                : -1.0;
      else
        q = quality_(x, P(f.f[0]), P(f.f[1]), P(f.f[2]));
      if(each)
        each->push_back(q);
      w = std::min(w, q);
      if(w <= threshold)
        return w;
    }
    return w;
  }

  /// g (in y = Q x) projected on the tangent space of the vertex's constraint
  static Eigen::Vector3d tangential(const Smoothing_ball& b, const Eigen::Vector3d& g)
  {
    if(!b.constrained)
      return g;
    Eigen::Vector3d r = Eigen::Vector3d::Zero();
    for(int i = 0; i < b.tangent_dimension; ++i)
      r += g.dot(b.tangent[i]) * b.tangent[i];
    return r;
  }

  /// whether a surface vertex may move to `candidate` (see prepare_smoothing())
  bool surface_move_ok(const Smoothing_ball& b, const Eigen::Vector3d& candidate) const
  {
    if(!(b.metric.length(candidate - b.x_start) <= 0.5 * b.scale))
      return false;
    for(const auto& sf : b.surface_faces) {
      const Eigen::Vector3d n = (P(sf.first[0]) - candidate).cross(P(sf.first[1]) - candidate);
      if(!(n.dot(sf.second) > b.cos_turn * n.norm() * sf.second.norm()))
        return false;
    }
    return keeps_edges_in_range(b, candidate);
  }

  /// with a distance bound, whether each boundary face at a surface vertex
  /// keeps it (`keeps_surface_distance()`) with the vertex at `candidate`
  bool surface_distance_kept(const Smoothing_ball& b, const Eigen::Vector3d& candidate) const
  {
    if(!(s_.surface_distance > 0))
      return true;
    for(const auto& sf : b.surface_faces) {
      const int a = sf.first[0], c = sf.first[1];
      if(!keeps_surface_distance({{{b.x_start, P(a), P(c)}}}, {{{candidate, P(a), P(c)}}}, m_.face_patch(b.v, a, c)))
        return false;
    }
    return true;
  }

  /// whether the edges of `b.conforming` stay in range with the vertex at `candidate`
  bool keeps_edges_in_range(const Smoothing_ball& b, const Eigen::Vector3d& candidate) const
  {
    if(b.conforming.empty())
      return true;
    const Metric_3 mc = quality_.metric_at(candidate);
    for(const auto& c : b.conforming) {
      const Eigen::Vector3d d = P(c.first) - candidate;
      if(!in_metric_range(0.5 * (mc.length(d) + c.second.length(d))))
        return false;
    }
    return true;
  }

  /// takes `raw` (projected on the constraint) as the best position if it
  /// raises the ball's smallest quality by the minimum gain
  bool try_candidate(Smoothing_ball& b, const Eigen::Vector3d& raw) const
  {
    const Eigen::Vector3d candidate = b.constrained ? m_.project(b.v, raw) : raw;
    if(candidate == b.x || !candidate.allFinite())
      return false;
    if(b.on_surface ? !surface_move_ok(b, candidate) : !keeps_edges_in_range(b, candidate))
      return false;
    const double w = ball_quality(b, candidate, b.current + Smoothing_ball::minimum_gain, &candidate_quality_);
    if(w > b.current + Smoothing_ball::minimum_gain && (!b.on_surface || surface_distance_kept(b, candidate))) {
      b.current = w;
      b.x = candidate;
      b.face_quality.swap(candidate_quality_); // every face was evaluated (no early stop above the bar)
      b.face_quality_at_x = true;
      return true;
    }
    return false;
  }

  /// 1. the mean of the ideal apex positions (regular tet on each face),
  /// relaxed; false if a face of the ball is degenerate
  bool move_to_ideal_position(Smoothing_ball& b) const
  {
    const Eigen::Vector3d y_v = b.Q * b.x_start;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    std::size_t count = 0;
    for(const Ball_face& f : b.faces) {
      if(f.passive)
        continue;
      const Eigen::Vector3d y0 = b.Q * P(f.f[0]), y1 = b.Q * P(f.f[1]), y2 = b.Q * P(f.f[2]);
      const Eigen::Vector3d c = (y0 + y1 + y2) / 3;
      Eigen::Vector3d normal = (y1 - y0).cross(y2 - y0);
      const double norm = normal.norm();
      if(!(norm > 0))
        return false;
      normal /= norm;
      if(normal.dot(y_v - c) < 0)
        normal = -normal;
      const double side = ((y1 - y0).norm() + (y2 - y1).norm() + (y0 - y2).norm()) / 3;
      sum += c + std::sqrt(2.0 / 3.0) * side * normal;
      ++count;
    }
    const Eigen::Vector3d ideal = b.Q_inverse * (sum / double(std::max<std::size_t>(count, 1)));
    for(double omega : {1.0, 0.5, 0.25})
      try_candidate(b, b.x_start + omega * (ideal - b.x_start));
    return true;
  }

  /// 2. steepest ascent of the smallest quality
  void ascend(Smoothing_ball& b) const
  {
    std::vector<Eigen::Vector3d> gradients;
    for(int iteration = 0; iteration < s_.smoothing_iterations; ++iteration) {
      // qualities at x, and the nearly active tets
      std::vector<std::pair<double, std::size_t>> values;
      for(std::size_t i = 0; i < b.faces.size(); ++i) {
        if(b.faces[i].passive)
          continue;
        const auto& f = b.faces[i].f;
        values.push_back({b.face_quality_at_x ? b.face_quality[i] : quality_(b.x, P(f[0]), P(f[1]), P(f[2])), i});
      }
      std::sort(values.begin(), values.end());
      gradients.clear();
      const double h = 1e-5 * b.scale;
      for(const auto& value : values) {
        if(value.first > values.front().first + 1.0 || gradients.size() >= 8)
          break;
        const auto& f = b.faces[value.second].f;
        Eigen::Vector3d g;
        for(int axis = 0; axis < 3; ++axis) {
          const Eigen::Vector3d step = b.Q_inverse.col(axis) * h;
          const double plus = quality_.unchecked(b.x + step, P(f[0]), P(f[1]), P(f[2]));
          const double minus = quality_.unchecked(b.x - step, P(f[0]), P(f[1]), P(f[2]));
          g[axis] = (plus - minus) / (2 * h);
        }
        gradients.push_back(tangential(b, g));
      }
      if(gradients.empty())
        break;
      const Eigen::Vector3d d = minimum_norm_point(gradients);
      const double d_norm = d.norm();
      if(!(d_norm > 1e-12) || !std::isfinite(d_norm))
        break;
      const Eigen::Vector3d direction = b.Q_inverse * (d / d_norm);
      bool moved = false;
      for(double step = 0.25 * b.scale; step > 1e-4 * b.scale && !moved; step *= 0.5)
        moved = try_candidate(b, b.x + step * direction);
      if(!moved)
        break;
    }
  }

  /// 3. a sliver that smoothing could not fix: push the vertex off its
  /// opposite face, then random trial moves (seeded by the vertex and the
  /// clock); 1 if one of them was taken
  std::size_t push_off_sliver(Smoothing_ball& b) const
  {
    std::size_t sliver_move = 0;
    if(!(s_.sliver_moves && !(b.current > b.start + Smoothing_ball::minimum_gain)))
      return 0;
    const auto& f = b.faces.front().f;
    if(!quality_.is_sliver(b.x_start, P(f[0]), P(f[1]), P(f[2])))
      return 0;
    const Eigen::Vector3d y0 = b.Q * P(f[0]), y1 = b.Q * P(f[1]), y2 = b.Q * P(f[2]);
    Eigen::Vector3d normal = tangential(b, (y1 - y0).cross(y2 - y0));
    if(normal.norm() > 0) {
      normal.normalize();
      if(normal.dot(b.Q * b.x_start - y0) < 0)
        normal = -normal;
      const Eigen::Vector3d direction = b.Q_inverse * normal;
      for(double step = 0.3 * b.scale; step > 0.01 * b.scale; step *= 0.5)
        if(try_candidate(b, b.x_start + step * direction)) {
          sliver_move = 1;
          break;
        }
    }
    std::mt19937 random(s_.random_seed * 2654435761u ^ unsigned(b.v) * 40503u ^ unsigned(clock_));
    std::normal_distribution<double> gauss;
    std::uniform_real_distribution<double> radius(0.02, 0.2);
    for(int trial = 0; trial < s_.perturbation_trials; ++trial) {
      Eigen::Vector3d r(gauss(random), gauss(random), gauss(random));
      r = tangential(b, r);
      if(!(r.norm() > 0))
        continue;
      if(try_candidate(b, b.x + radius(random) * b.scale * (b.Q_inverse * r.normalized())))
        sliver_move = 1;
    }
    return sliver_move;
  }

  /// moves the vertex to the best position (a boundary one only if the
  /// boundary stays embedded) and updates the ball's qualities and counters
  bool apply_move(const Smoothing_ball& b)
  {
    const int v = b.v;
    if(b.on_surface && grid_) {
      std::vector<std::array<int, 3>> fan;
      for(const auto& sf : b.surface_faces)
        fan.push_back({{v, sf.first[0], sf.first[1]}});
      if(!boundary_stays_embedded(fan, fan, v, b.x))
        return false;
      m_.points[std::size_t(v)] = b.x;
      for(const auto& f : fan)
        index_face(f[0], f[1], f[2]);
    }
    m_.points[std::size_t(v)] = b.x;
    forget_vertex_metric(v);
    ++clock_;
    for(int s : b.ball)
      for(int u : m_.tets[std::size_t(s)])
        vertex_changed_[std::size_t(u)] = clock_;
    for(int s : b.ball) {
      q_[std::size_t(s)] = tet_quality(s);
      ++m_.stamp[std::size_t(s)];
    }
    ++c_.smoothing_moves;
    if(b.constrained)
      ++c_.boundary_moves;
    return true;
  }

  /// the point of smallest norm in the convex hull of `points` (Gilbert's
  /// algorithm; a few dozen iterations suffice in 3D)
  static Eigen::Vector3d minimum_norm_point(const std::vector<Eigen::Vector3d>& points)
  {
    Eigen::Vector3d d = points.front();
    for(int iteration = 0; iteration < 64; ++iteration) {
      std::size_t best = 0;
      double best_dot = points[0].dot(d);
      for(std::size_t i = 1; i < points.size(); ++i) {
        const double dot = points[i].dot(d);
        if(dot < best_dot) {
          best_dot = dot;
          best = i;
        }
      }
      const double dd = d.squaredNorm();
      if(dd - best_dot <= 1e-12 * dd)
        break;
      const Eigen::Vector3d e = d - points[best];
      const double lambda = std::min(1.0, std::max(0.0, d.dot(e) / e.squaredNorm()));
      d -= lambda * e;
    }
    return d;
  }

  /// What an edge collapse must achieve to be applied: where flips and
  /// moves are stuck (the default), raise the worst tet around by a degree;
  /// in `length_phase()`, lower the summed `length_excess()` of the edges at
  /// the removed vertex and keep the worst tet around at least at the lower
  /// of its old worst and `floor`.
  struct Change_rule {
    bool lengths = false;
    double floor = 0;
    bool accepts(double new_worst, double old_worst) const
    {
      return lengths ? new_worst >= std::min(old_worst, floor) : new_worst > old_worst + 1.0;
    }
  };

  // ---- edge splits ------------------------------------------------------------

  /// Local refinement where flips and moves are stuck (a cap in a thin part,
  /// a flat tet whose four vertices are all on the boundary): for each tet
  /// below `split_below_angle`, worst first, its edges are tried longest
  /// (in the metric) first, and the first split that raises the worst tet
  /// around the edge is applied. Interfaces are not split; feature edges only
  /// with a curve projection.
  /// Returns the number of splits.
  std::size_t split_phase()
  {
    return for_stuck_tets(true, [this](int t, int a, int b) { return split_edge(t, a, b); });
  }

  /// Where a bad tet is bad because of a short edge (a vertex too close to
  /// another: a cluster left by packing, a surface vertex next to a curve),
  /// splitting cannot help: for each tet below `split_below_angle`, worst
  /// first, its edges are tried shortest (in the metric) first, each in both
  /// directions, and the first collapse that raises the worst tet of the
  /// removed vertex's star by a degree is applied. Returns the number of
  /// collapses (each removes a vertex).
  std::size_t collapse_phase()
  {
    return for_stuck_tets(false, [this](int, int a, int b) {
      return collapse_edge(a, b, Change_rule()) || collapse_edge(b, a, Change_rule());
    });
  }

  /// The driver of both: the tets below `split_below_angle`, worst first,
  /// each with its edges by metric length (longest first or shortest
  /// first) until `change(t, a, b)` applies to one; at most 1 % of the
  /// vertices (at least 16) changes per round: where far more tets are stuck
  /// (features far closer than the sizes) they would mostly add short edges.
  template <typename Change>
  std::size_t for_stuck_tets(bool longest_first, const Change& change)
  {
    std::vector<std::pair<double, int>> bad;
    for(std::size_t t = 0; t < m_.tets.size(); ++t)
      if(m_.alive[t] && !m_.is_passive(int(t)) && q_[t] < s_.split_below_angle)
        bad.push_back({q_[t], int(t)});
    std::sort(bad.begin(), bad.end());
    const std::size_t budget = std::max<std::size_t>(16, m_.points.size() / 100);
    std::size_t changes = 0;
    for(const auto& entry : bad) {
      if(changes >= budget)
        break;
      const int t = entry.second;
      if(!m_.alive[std::size_t(t)] || q_[std::size_t(t)] != entry.first)
        continue; // changed by an earlier one
      const Tet T = m_.tets[std::size_t(t)];
      static constexpr int edges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
      std::vector<std::pair<double, int>> order;
      for(int e = 0; e < 6; ++e) {
        const Eigen::Vector3d& a = P(T[std::size_t(edges[e][0])]);
        const Eigen::Vector3d& b = P(T[std::size_t(edges[e][1])]);
        const double length = quality_.metric_at(0.5 * (a + b)).length(b - a);
        order.push_back({longest_first ? -length : length, e});
      }
      std::sort(order.begin(), order.end());
      for(const auto& o : order)
        if(change(t, T[std::size_t(edges[o.second][0])], T[std::size_t(edges[o.second][1])])) {
          ++changes;
          break;
        }
      if(out_of_time())
        break;
    }
    return changes;
  }

  /// Collapses the edge (v, w) by removing `v`: its tets through w go, the
  /// others get w for v. Only for `v` free, inside one patch (plane or
  /// surface constraint; then (v, w) is a boundary edge of that patch), or
  /// inside a feature curve (line or curve constraint; then w is one of its
  /// two neighbours on the curve, and the curve loses v); its star in one
  /// active subdomain; only if the link condition holds (the result is a
  /// manifold mesh with the same boundary topology: the boundary closed by a
  /// virtual vertex joined to each boundary face; no two curves between the
  /// same vertices, a closed curve keeps 3 edges), every new tet is
  /// positively oriented (exact), no boundary face turns by more than 20
  /// degrees, and the worst new tet is a degree above the worst of v's star.
  bool collapse_edge(int v, int w, const Change_rule& rule)
  {
    const Vertex_constraint& constraint = m_.constraint[std::size_t(v)];
    const Vertex_constraint::Kind kind = constraint.kind;
    const bool boundary = m_.fixed[std::size_t(v)] != 0;
    const bool on_curve = kind == Vertex_constraint::line || kind == Vertex_constraint::curve;
    if(boundary && kind != Vertex_constraint::plane && kind != Vertex_constraint::surface && !on_curve)
      return false;
    if(boundary && (!s_.boundary_smoothing || !m_.is_protected_edge(v, w) || m_.has_duplicate_triangles))
      return false;
    int u = -1; // v's other neighbour on its curve
    if(on_curve && !curve_collapse_keeps_curves(v, w, u))
      return false;
    const std::vector<int>& star = m_.vertex_tets[std::size_t(v)];
    if(star.empty())
      return false;
    const int ref = m_.refs[std::size_t(star.front())];
    double old_worst = std::numeric_limits<double>::infinity();
    for(int s : star) {
      if(m_.refs[std::size_t(s)] != ref || m_.is_passive(s))
        return false;
      old_worst = std::min(old_worst, q_[std::size_t(s)]);
    }
    // the boundary faces at v, each the face of one tet, all of one patch
    std::vector<std::array<int, 3>> faces;
    std::vector<Eigen::Vector3d> face_normals; // in the order of `faces`' vertices
    int patch = 0;
    for(int s : star) {
      const Tet& T = m_.tets[std::size_t(s)];
      for(int k = 0; k < 4; ++k) {
        if(T[std::size_t(k)] == v)
          continue;
        std::array<int, 3> f;
        int n = 0;
        for(int j = 0; j < 4; ++j)
          if(j != k)
            f[std::size_t(n++)] = T[std::size_t(j)];
        if(!m_.is_protected_face(f[0], f[1], f[2]))
          continue;
        if(m_.opposite_tet(s, f[0], f[1], f[2]) >= 0)
          return false; // an interface
        const int p = m_.face_patch(f[0], f[1], f[2]);
        if(faces.empty())
          patch = p;
        else if(p != patch && !on_curve)
          return false;
        faces.push_back(f);
        face_normals.push_back((P(f[1]) - P(f[0])).cross(P(f[2]) - P(f[0])));
      }
    }
    if(boundary == faces.empty())
      return false; // a fixed vertex without faces, or a free one with faces: not ours
    if(!link_condition(v, w))
      return false;
    // the new tets and their worst quality
    std::vector<Tet> new_tets;
    std::vector<int> old_tets;
    double new_worst = std::numeric_limits<double>::infinity();
    for(int s : star) {
      old_tets.push_back(s);
      Tet T = m_.tets[std::size_t(s)];
      if(Mutable_tet_mesh::has_vertex(T, w))
        continue;
      for(int& x : T)
        if(x == v)
          x = w;
      if(exact_orientation(P(T[0]), P(T[1]), P(T[2]), P(T[3])) != CGAL::POSITIVE)
        return false;
      new_worst = std::min(new_worst, quality_of(T));
      if(!rule.accepts(new_worst, old_worst))
        return false;
      new_tets.push_back(T);
    }
    if(rule.lengths && !(collapse_excess(v, w) < 0))
      return false;
    const double cos_turn = cos_of_largest_boundary_turn();
    for(std::size_t i = 0; i < faces.size(); ++i) {
      const auto& f = faces[i];
      if(f[0] == w || f[1] == w || f[2] == w)
        continue;
      Eigen::Vector3d x[3];
      for(int k = 0; k < 3; ++k)
        x[k] = f[std::size_t(k)] == v ? P(w) : P(f[std::size_t(k)]);
      const Eigen::Vector3d normal = (x[1] - x[0]).cross(x[2] - x[0]);
      const Eigen::Vector3d& o = face_normals[i];
      // both in the same vertex order (w replaces v in place). (The old
      // normal was turned outward and the new one not: every face listed
      // inward-first refused the collapse, and so did most curve collapses.)
      if(!(normal.dot(o) > cos_turn * normal.norm() * o.norm()))
        return false;
    }

    std::vector<std::array<int, 3>> renamed;
    for(const auto& f : faces)
      if(f[0] != w && f[1] != w && f[2] != w)
        renamed.push_back({{f[0] == v ? w : f[0], f[1] == v ? w : f[1], f[2] == v ? w : f[2]}});
    if(boundary && !boundary_stays_embedded(renamed, faces, -2, Eigen::Vector3d::Zero()))
      return false;

    // apply
    ++clock_;
    for(int s : star)
      for(int x : m_.tets[std::size_t(s)])
        vertex_changed_[std::size_t(x)] = clock_;
    const std::vector<int> created = m_.replace(old_tets, new_tets, ref);
    if(boundary) {
      m_.collapse_boundary_faces(v, w, faces);
      if(on_curve)
        m_.collapse_feature_edge(v, w, u);
      for(const auto& f : renamed)
        index_face(f[0], f[1], f[2]);
    }
    else
      m_.removed[std::size_t(v)] = 1;
    q_.resize(m_.tets.size());
    tet_tried_.resize(m_.tets.size(), -1);
    for(int s : created) {
      tet_tried_[std::size_t(s)] = -1;
      q_[std::size_t(s)] = tet_quality(s);
    }
    ++c_.edge_collapses;
    if(rule.lengths)
      ++c_.length_collapses;
    if(boundary)
      ++c_.boundary_edge_collapses;
    if(on_curve)
      ++c_.feature_edge_collapses;
    return true;
  }

  /// Whether removing the curve vertex `v` (line or curve constraint) by
  /// its curve edge to `w` keeps the feature curves a proper graph: `w` is
  /// one of v's two curve neighbours, both of v's edges are of one curve,
  /// the other neighbour `u` (returned) is not already joined to `w` by a
  /// feature edge (two curves between the same vertices: a thin patch
  /// between them would vanish; a closed curve would have 2 edges).
  bool curve_collapse_keeps_curves(int v, int w, int& u) const
  {
    const Vertex_constraint& c = m_.constraint[std::size_t(v)];
    if(c.ends[0] != w && c.ends[1] != w)
      return false;
    u = c.ends[0] == w ? c.ends[1] : c.ends[0];
    const int curve = m_.feature_edge_curve(v, w);
    // (a closed curve of 3 edges has its third edge between u and w)
    return u != w && curve >= 0 && m_.feature_edge_curve(u, v) == curve && !m_.is_feature_edge(u, w);
  }

  /// The link condition for the collapse of (v, w), with the boundary
  /// closed by a virtual vertex (-2) joined to every protected face: the
  /// vertices and edges common to the links of v and w are those of the link
  /// of the edge (v, w).
  bool link_condition(int v, int w) const
  {
    const int virtual_vertex = -2;
    typedef std::pair<int, int> Edge;
    auto sorted = [](int x, int y) { return x < y ? Edge(x, y) : Edge(y, x); };
    auto link = [&](int u, std::vector<int>& vertices, std::vector<Edge>& edges) {
      for(int s : m_.vertex_tets[std::size_t(u)]) {
        const Tet& T = m_.tets[std::size_t(s)];
        int o[3];
        int n = 0;
        for(int x : T)
          if(x != u)
            o[n++] = x;
        for(int k = 0; k < 3; ++k) {
          vertices.push_back(o[k]);
          const int x = o[k], y = o[(k + 1) % 3];
          edges.push_back(sorted(x, y));
          if(m_.is_protected_face(u, x, y)) {
            vertices.push_back(virtual_vertex);
            edges.push_back(sorted(x, virtual_vertex));
            edges.push_back(sorted(y, virtual_vertex));
          }
        }
      }
      std::sort(vertices.begin(), vertices.end());
      vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
      std::sort(edges.begin(), edges.end());
      edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    };
    std::vector<int> vertices_v, vertices_w, vertices_vw;
    std::vector<Edge> edges_v, edges_w, edges_vw;
    link(v, vertices_v, edges_v);
    link(w, vertices_w, edges_w);
    // the link of (v, w): the far edge of each tet through it, and the
    // virtual vertex for each boundary face through it
    for(int s : m_.vertex_tets[std::size_t(v)]) {
      const Tet& T = m_.tets[std::size_t(s)];
      if(!Mutable_tet_mesh::has_vertex(T, w))
        continue;
      int o[2];
      int n = 0;
      for(int x : T)
        if(x != v && x != w)
          o[n++] = x;
      vertices_vw.push_back(o[0]);
      vertices_vw.push_back(o[1]);
      edges_vw.push_back(sorted(o[0], o[1]));
      for(int k = 0; k < 2; ++k)
        if(m_.is_protected_face(v, w, o[k])) {
          vertices_vw.push_back(virtual_vertex);
          edges_vw.push_back(sorted(o[k], virtual_vertex));
        }
    }
    std::sort(vertices_vw.begin(), vertices_vw.end());
    vertices_vw.erase(std::unique(vertices_vw.begin(), vertices_vw.end()), vertices_vw.end());
    std::sort(edges_vw.begin(), edges_vw.end());
    edges_vw.erase(std::unique(edges_vw.begin(), edges_vw.end()), edges_vw.end());
    std::vector<int> common_vertices;
    std::set_intersection(vertices_v.begin(), vertices_v.end(), vertices_w.begin(), vertices_w.end(),
                          std::back_inserter(common_vertices));
    std::vector<Edge> common_edges;
    std::set_intersection(edges_v.begin(), edges_v.end(), edges_w.begin(), edges_w.end(),
                          std::back_inserter(common_edges));
    return common_vertices == vertices_vw && common_edges == edges_vw;
  }

  /// Splits the edge (a, b) of tet `t` if a new vertex near its midpoint
  /// gives the 2n tets replacing the n around it a worst quality at least
  /// 1 degree above theirs. The vertex is placed by a compass search from
  /// the midpoint (in the metric's frame there): free for an interior edge;
  /// for a boundary edge of one patch (with a surface projection), on that
  /// patch's surface, each new boundary triangle turning by at most 20
  /// degrees from the one it replaces, and it then slides on the patch; for
  /// a feature edge (with a curve projection), on its curve, strictly
  /// between a and b, and it then slides along the curve.
  bool split_edge(int t, int a, int b)
  {
    Edge_split e;
    if(!prepare_split(t, a, b, e) || !place_split_vertex(e))
      return false;
    if(!(e.best > e.old_worst + 1.0))
      return false;
    if(!split_keeps_boundary_embedded(e))
      return false;
    apply_split(e);
    return true;
  }

  /// A candidate split of the edge (a, b): the tets around it, what kind of
  /// edge it is, and the new vertex's best position so far.
  struct Edge_split {
    int a = -1, b = -1;
    bool feature = false, boundary = false;
    int curve = -1, patch = 0, ref = 0;
    std::vector<int> ring, ring_tets; // a boundary edge's ring is open (a fan)
    double old_worst = std::numeric_limits<double>::infinity();
    Eigen::Vector3d old_normals[2]; // of the two boundary faces at the edge, outward
    std::vector<Tet> templates;     // the new tets, -1 standing for the new vertex
    Eigen::Vector3d x;              // the new vertex, of worst quality `best`
    double best = -std::numeric_limits<double>::infinity();
    /// a length split (`length_phase()`): the split edge's metric length;
    /// positions where a new edge is at least as long or shorter than
    /// 1/sqrt2 are refused
    double length_limit = std::numeric_limits<double>::infinity();
    /// the cosine of the largest turn of a new boundary triangle from the
    /// old one it halves: 20 degrees, 80 for a distance split (the old
    /// triangle is the chord that strays, the new ones follow the surface;
    /// the embedding is checked: at 45 degrees, the long chords of a coarse
    /// sphere mesh next to thin triangles could not be split)
    double cos_turn = cos_of_largest_boundary_turn();
  };

  /// whether the boundary stays embedded with the split's new boundary
  /// triangles (a -1 standing for the new vertex at `e.x`) for the two it
  /// halves (always, for an interior edge)
  bool split_keeps_boundary_embedded(const Edge_split& e) const
  {
    const int a = e.a, b = e.b;
    return !e.boundary || boundary_stays_embedded({{{a, -1, e.ring.front()}}, {{-1, b, e.ring.front()}},
                                                   {{a, -1, e.ring.back()}}, {{-1, b, e.ring.back()}}},
                                                  {{{a, b, e.ring.front()}}, {{a, b, e.ring.back()}}}, -1, e.x);
  }

  /// the ring of (a, b) and the new tets; false if the edge cannot be split
  /// (a feature edge without a curve projection, a boundary edge between two
  /// patches or at an interface, passive tets or several subdomains, ...)
  bool prepare_split(int t, int a, int b, Edge_split& e) const
  {
    e.a = a;
    e.b = b;
    e.feature = m_.is_feature_edge(a, b);
    e.curve = e.feature ? m_.feature_edge_curve(a, b) : -1;
    if(e.feature && (!m_.curve_projection || e.curve < 0))
      return false;
    e.boundary = m_.is_protected_edge(a, b);
    if(e.feature && !e.boundary)
      return false;
    std::vector<int>& ring = e.ring;
    if(e.boundary) {
      if((!e.feature && !m_.surface_projection) || m_.has_duplicate_triangles ||
         !m_.edge_fan(a, b, s_.ring_limit - 1, ring, e.ring_tets))
        return false;
    } else if(!m_.edge_ring(a, b, s_.ring_limit, ring, e.ring_tets))
      return false;
    e.ref = m_.refs[std::size_t(t)];
    for(int s : e.ring_tets) {
      if(m_.refs[std::size_t(s)] != e.ref || m_.is_passive(s))
        return false;
      e.old_worst = std::min(e.old_worst, q_[std::size_t(s)]);
    }
    const int n = int(ring.size());
    if(e.boundary) {
      const int p0 = ring.front(), pk = ring.back();
      if(!m_.is_protected_face(a, b, p0) || !m_.is_protected_face(a, b, pk) ||
         m_.listed_triangle(a, b, p0) < 0 || m_.listed_triangle(a, b, pk) < 0 ||
         (!e.feature && m_.face_patch(a, b, p0) != m_.face_patch(a, b, pk)))
        return false;
      for(int i = 1; i + 1 < n; ++i)
        if(m_.is_protected_face(a, b, ring[std::size_t(i)]))
          return false;
      if(m_.opposite_tet(e.ring_tets.front(), a, b, p0) >= 0 || m_.opposite_tet(e.ring_tets.back(), a, b, pk) >= 0)
        return false; // an interface
      e.patch = m_.face_patch(a, b, p0);
      // outward: away from the apex of the tet on each face
      const int apex[2] = {ring[1], ring[std::size_t(n - 2)]};
      const int ends[2] = {p0, pk};
      for(int k = 0; k < 2; ++k) {
        Eigen::Vector3d normal = (P(b) - P(a)).cross(P(ends[k]) - P(a));
        if(normal.dot(P(apex[k]) - P(a)) > 0)
          normal = -normal;
        e.old_normals[k] = normal;
      }
    }
    const int tets_around = e.boundary ? n - 1 : n;
    for(int i = 0; i < tets_around; ++i) {
      const int p = ring[std::size_t(i)], q = ring[std::size_t((i + 1) % n)];
      e.templates.push_back(Tet{{-1, b, p, q}});
      e.templates.push_back(Tet{{a, -1, p, q}});
    }
    return true;
  }

  /// the worst quality of the new tets with the new vertex at x (-1 if a new
  /// boundary triangle turns too far); stops early at <= threshold
  double split_quality(const Edge_split& e, const Eigen::Vector3d& x, double threshold) const
  {
    if(e.length_limit < std::numeric_limits<double>::infinity() && !split_lengths_ok(e, x))
      return -1.0;
    if(e.boundary) {
      const double cos_turn = e.cos_turn;
      const int ends[2] = {e.ring.front(), e.ring.back()};
      for(int k = 0; k < 2; ++k)
        for(int u : {e.a, e.b}) {
          Eigen::Vector3d normal = (P(u) - x).cross(P(ends[k]) - x);
          if(normal.dot(e.old_normals[k]) < 0)
            normal = -normal; // orientation is checked by the tets
          if(!(normal.dot(e.old_normals[k]) > cos_turn * normal.norm() * e.old_normals[k].norm()))
            return -1.0;
        }
    }
    auto point = [&](int v) -> const Eigen::Vector3d& { return v < 0 ? x : P(v); };
    double w = std::numeric_limits<double>::infinity();
    for(const Tet& T : e.templates) {
      w = std::min(w, quality_(point(T[0]), point(T[1]), point(T[2]), point(T[3])));
      if(w <= threshold)
        return w;
    }
    return w;
  }

  /// y: x on the input (its curve, strictly between a and b, or its patch's
  /// surface) for a boundary edge, x itself for an interior one
  bool split_point_on_input(const Edge_split& e, const Eigen::Vector3d& x, Eigen::Vector3d& y) const
  {
    if(!e.boundary) {
      y = x;
      return true;
    }
    std::array<double, 3> closest;
    if(e.feature) {
      if(!m_.curve_projection(e.curve, {{x[0], x[1], x[2]}}, closest))
        return false;
      y = Eigen::Vector3d(closest[0], closest[1], closest[2]);
      // strictly between a and b along their chord
      const double s = (y - P(e.a)).dot(P(e.b) - P(e.a)) / (P(e.b) - P(e.a)).squaredNorm();
      return s > 0.05 && s < 0.95;
    }
    if(!m_.surface_projection(e.patch, {{x[0], x[1], x[2]}}, closest))
      return false;
    y = Eigen::Vector3d(closest[0], closest[1], closest[2]);
    return true;
  }

  /// the new vertex by a compass search from the midpoint, in the metric's
  /// frame there (tangent directions only on the surface); false if the
  /// midpoint has no place on the input
  bool place_split_vertex(Edge_split& e) const
  {
    const Eigen::Vector3d middle = 0.5 * (P(e.a) + P(e.b));
    if(!split_point_on_input(e, middle, e.x))
      return false;
    e.best = split_quality(e, e.x, -std::numeric_limits<double>::infinity());
    const Metric_3 metric = quality_.metric_at(middle);
    std::vector<Eigen::Vector3d> directions;
    if(e.feature) {
      directions.push_back(P(e.b) - P(e.a));
      directions.push_back(P(e.a) - P(e.b));
    } else if(e.boundary) {
      const Eigen::Vector3d normal = (e.old_normals[0].normalized() + e.old_normals[1].normalized()).normalized();
      const Eigen::Vector3d u = normal.unitOrthogonal(), v = normal.cross(u);
      for(int k = 0; k < 8; ++k) {
        const double angle = k * std::acos(-1.0) / 4;
        directions.push_back(std::cos(angle) * u + std::sin(angle) * v);
      }
    } else
      for(int k = 0; k < 3; ++k)
        for(double sign : {-1.0, 1.0})
          directions.push_back(sign * (metric.Q_inverse() * Eigen::Vector3d::Unit(k)));
    const double half = 0.5 * (P(e.b) - P(e.a)).norm();
    for(Eigen::Vector3d& d : directions)
      d *= half / d.norm();
    for(double step = 0.5; step > 0.01;) {
      bool moved = false;
      for(const Eigen::Vector3d& d : directions) {
        Eigen::Vector3d y;
        if(!split_point_on_input(e, e.x + step * d, y))
          continue;
        const double w = split_quality(e, y, e.best);
        if(w > e.best) {
          e.best = w;
          e.x = y;
          moved = true;
        }
      }
      if(!moved)
        step *= 0.5;
    }
    return true;
  }

  /// adds the new vertex (with its constraint) and its tets, splits the
  /// boundary faces and the feature edge, updates qualities and counters
  void apply_split(const Edge_split& e)
  {
    const int a = e.a, b = e.b;
    Vertex_constraint constraint;
    if(e.feature) {
      constraint.kind = Vertex_constraint::curve;
      constraint.patch = e.curve;
      constraint.origin = e.x;
      constraint.axis = (P(b) - P(a)).normalized();
      constraint.tangent[0] = constraint.axis;
      constraint.ends[0] = a;
      constraint.ends[1] = b;
    } else if(e.boundary) {
      constraint.kind = Vertex_constraint::surface;
      constraint.patch = e.patch;
    }
    const int m = m_.add_vertex(e.x, constraint, e.boundary, e.feature ? e.curve : e.boundary ? e.patch : e.ref);
    vertex_tried_.push_back(-1);
    vertex_changed_.push_back(0);
    std::vector<Tet> new_tets;
    for(Tet T : e.templates) {
      for(int& v : T)
        if(v < 0)
          v = m;
      new_tets.push_back(T);
    }
    ++clock_;
    for(int s : e.ring_tets)
      for(int v : m_.tets[std::size_t(s)])
        vertex_changed_[std::size_t(v)] = clock_;
    vertex_changed_[std::size_t(m)] = clock_;
    const std::vector<int> created = m_.replace(e.ring_tets, new_tets, e.ref);
    if(e.boundary) {
      m_.split_boundary_faces(a, b, m, e.ring.front(), e.ring.back());
      for(int p : {e.ring.front(), e.ring.back()}) {
        index_face(a, m, p);
        index_face(m, b, p);
      }
    }
    if(e.feature)
      m_.split_feature_edge(a, b, m);
    q_.resize(m_.tets.size());
    tet_tried_.resize(m_.tets.size(), -1);
    for(int s : created) {
      tet_tried_[std::size_t(s)] = -1;
      q_[std::size_t(s)] = tet_quality(s);
    }
    ++c_.edge_splits;
    if(e.length_limit < std::numeric_limits<double>::infinity())
      ++c_.length_splits;
    if(e.boundary)
      ++c_.boundary_edge_splits;
    if(e.feature)
      ++c_.feature_edge_splits;
  }

  // ---- edge lengths -----------------------------------------------------------

  /// how far the metric length `l` lies outside [1/sqrt2, sqrt2], on a log
  /// scale (0 inside): a gap of twice the size weighs like a cluster at half
  static double length_excess(double l)
  {
    const double out = std::abs(std::log(l)) - 0.5 * std::log(2.0);
    return out > 0 ? out : 0;
  }

  /// the metric at vertex v, cached until the vertex moves (new vertices
  /// extend the cache)
  const Metric_3& vertex_metric(int v) const
  {
    if(vertex_metric_.size() < m_.points.size()) {
      vertex_metric_.resize(m_.points.size());
      vertex_metric_known_.resize(m_.points.size(), 0);
    }
    if(!vertex_metric_known_[std::size_t(v)]) {
      vertex_metric_[std::size_t(v)] = quality_.metric_at(P(v));
      vertex_metric_known_[std::size_t(v)] = 1;
    }
    return vertex_metric_[std::size_t(v)];
  }

  void forget_vertex_metric(int v)
  {
    if(std::size_t(v) < vertex_metric_known_.size())
      vertex_metric_known_[std::size_t(v)] = 0;
  }

  /// metric length of the edge (u, v) with the cached vertex metrics (the
  /// measure of `metric_edge_length()` and of the quality report)
  double cached_edge_length(int u, int v) const
  {
    const Eigen::Vector3d d = P(v) - P(u);
    return 0.5 * (vertex_metric(u).length(d) + vertex_metric(v).length(d));
  }

  /// whether every edge a split of `e` at x creates is shorter than the
  /// split edge and not shorter than 1/sqrt2 (no cluster made for a gap)
  bool split_lengths_ok(const Edge_split& e, const Eigen::Vector3d& x) const
  {
    const Metric_3 mx = quality_.metric_at(x);
    auto ok = [&](int u) {
      const Eigen::Vector3d d = P(u) - x;
      const double l = 0.5 * (mx.length(d) + vertex_metric(u).length(d));
      return l >= std::sqrt(0.5) && l < e.length_limit;
    };
    if(!ok(e.a) || !ok(e.b))
      return false;
    for(int u : e.ring)
      if(!ok(u))
        return false;
    return true;
  }

  /// the neighbours of v (through its tets), sorted
  std::vector<int> neighbours(int v) const
  {
    std::vector<int> n;
    for(int s : m_.vertex_tets[std::size_t(v)])
      for(int x : m_.tets[std::size_t(s)])
        if(x != v)
          n.push_back(x);
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
    return n;
  }

  /// the summed excess of the edges at v that a collapse of v onto w
  /// removes, minus that of the edges it creates: positive if it helps
  double collapse_excess(int v, int w) const
  {
    const std::vector<int> nv = neighbours(v), nw = neighbours(w);
    double old_sum = 0, new_sum = 0;
    for(int u : nv) {
      old_sum += length_excess(cached_edge_length(v, u));
      if(u != w && !std::binary_search(nw.begin(), nw.end(), u))
        new_sum += length_excess(cached_edge_length(w, u));
    }
    return new_sum - old_sum;
  }

  /// an active tet of the edge (a, b), -1 if the edge is gone
  int tet_of_edge(int a, int b) const
  {
    for(int s : m_.vertex_tets[std::size_t(a)])
      if(m_.alive[std::size_t(s)] && !m_.is_passive(s) && Mutable_tet_mesh::has_vertex(m_.tets[std::size_t(s)], b))
        return s;
    return -1;
  }

  /// whether a length change whose new tets' worst is `new_worst` where the
  /// old worst was `old_worst` may be applied
  bool length_change_ok(double new_worst, double old_worst) const
  {
    return new_worst >= std::min(old_worst, length_floor_);
  }

  /// Removes the interior edge (a, b) of metric length `length` by an edge
  /// removal (its n tets become the 2n-4 joining a and b to the best
  /// triangulation of its ring) when no new edge (a chord of the ring) is as
  /// long and the new tets' worst is at least the lower of the old worst and
  /// `floor`: a long edge that cuts through a layer of nodes (one lies near
  /// its middle, so a split would make a cluster) is a wrong connection,
  /// not a gap. Counted as a length flip.
  bool remove_long_edge(int t, int a, int b, double length)
  {
    if(m_.is_protected_edge(a, b) || !m_.edge_ring(a, b, s_.ring_limit, ring_, ring_tets_))
      return false;
    const int ref = m_.refs[std::size_t(t)];
    double old_worst = std::numeric_limits<double>::infinity();
    for(int s : ring_tets_) {
      if(m_.refs[std::size_t(s)] != ref || m_.is_passive(s))
        return false;
      old_worst = std::min(old_worst, q_[std::size_t(s)]);
    }
    double result = 0;
    int top = -1;
    if(!best_ring_triangulation(a, b, std::min(old_worst, length_floor_) - 1e-12, result, scratch_tets_, top) ||
       !length_change_ok(result, old_worst))
      return false;
    for(const Tet& T : scratch_tets_)
      for(int i = 0; i < 4; ++i)
        for(int j = i + 1; j < 4; ++j) {
          const int x = T[std::size_t(i)], y = T[std::size_t(j)];
          if(x == a || x == b || y == a || y == b)
            continue; // an edge of the old tets
          if(!(cached_edge_length(x, y) < length))
            return false;
        }
    Flip f;
    take_edge_removal(f, result, old_worst, ref);
    apply(f);
    ++c_.length_flips;
    return true;
  }

  /// the worst tet a length change may leave around it, if the worst there
  /// was better and the mesh's worst is lower (else that worst is the
  /// floor): low enough that most long edges can go (at 15 degrees the
  /// splits stopped at a fifth of them on the elephant with a 1:10 layer;
  /// 25 degrees gave fewer edges in range and no better angles)
  static constexpr double length_quality_floor = 20;

  /// The packing's errors that flips and moves cannot fix: where the metric
  /// changes fast (a 1:10 boundary layer on a curved wall) its edges are far
  /// outside [1/sqrt2, sqrt2], mostly too long (elephant, 1:10 layer: 18.5 %
  /// of the edges longer, 0.4 % shorter). Run after the first passes of
  /// flips and moves. Up to 4 rounds over the edges, each change keeping the
  /// worst tet around at least at the lower of its old worst and the higher
  /// of `length_quality_floor` and the mesh's worst (so the phase never
  /// lowers the mesh's worst):
  /// (1) the edges longer than sqrt2, longest first: removed by an edge
  /// removal if no chord it creates is as long (an edge cutting through a
  /// layer of nodes: a wrong connection, `remove_long_edge()`), else split
  /// near the midpoint where every new edge is shorter than it and not
  /// shorter than 1/sqrt2 (a gap; the split places its vertex like the
  /// other splits, boundary and feature edges on the input);
  /// (2) the edges shorter than 1/sqrt2, shortest first: collapsed onto
  /// either end where that lowers the summed `length_excess()` of the
  /// edges at the removed vertex (a cluster).
  /// Returns the number of changes.
  std::size_t length_phase()
  {
    // never below the worst the passes reached: the phase cannot lower the mesh's worst
    double worst = std::numeric_limits<double>::infinity();
    for(std::size_t t = 0; t < m_.tets.size(); ++t)
      if(m_.alive[t] && !m_.is_passive(int(t)))
        worst = std::min(worst, q_[t]);
    length_floor_ = std::max(length_quality_floor, worst);
    std::size_t changes = 0;
    for(int round = 0; round < 4 && !out_of_time(); ++round) {
      std::vector<std::pair<double, std::pair<int, int>>> long_edges, short_edges;
      std::vector<std::pair<int, int>> edges;
      for(std::size_t t = 0; t < m_.tets.size(); ++t) {
        if(!m_.alive[t] || m_.is_passive(int(t)))
          continue;
        const Tet& T = m_.tets[t];
        for(int i = 0; i < 4; ++i)
          for(int j = i + 1; j < 4; ++j)
            edges.push_back(std::minmax(T[std::size_t(i)], T[std::size_t(j)]));
      }
      std::sort(edges.begin(), edges.end());
      edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
      for(const auto& e : edges) {
        const double l = cached_edge_length(e.first, e.second);
        if(l > std::sqrt(2.0))
          long_edges.push_back({-l, e});
        else if(l < std::sqrt(0.5))
          short_edges.push_back({l, e});
      }
      std::sort(long_edges.begin(), long_edges.end());
      std::sort(short_edges.begin(), short_edges.end());
      std::size_t round_changes = 0;
      for(const auto& entry : long_edges) {
        const int a = entry.second.first, b = entry.second.second;
        const int t = tet_of_edge(a, b);
        if(t < 0)
          continue;
        Edge_split e;
        e.length_limit = -entry.first;
        if(remove_long_edge(t, a, b, e.length_limit)) {
          ++round_changes;
          continue;
        }
        if(!prepare_split(t, a, b, e) || !place_split_vertex(e))
          continue;
        if(!split_lengths_ok(e, e.x) || !length_change_ok(e.best, e.old_worst))
          continue;
        if(!split_keeps_boundary_embedded(e))
          continue;
        apply_split(e);
        ++round_changes;
        if(out_of_time())
          break;
      }
      Change_rule rule;
      rule.lengths = true;
      rule.floor = length_floor_;
      for(const auto& entry : short_edges) {
        if(out_of_time())
          break;
        const int a = entry.second.first, b = entry.second.second;
        if(m_.removed[std::size_t(a)] || m_.removed[std::size_t(b)] || tet_of_edge(a, b) < 0)
          continue;
        if(collapse_edge(a, b, rule) || collapse_edge(b, a, rule))
          ++round_changes;
      }
      changes += round_changes;
      if(round_changes == 0)
        break;
    }
    return changes;
  }

  // ---- surface distance -------------------------------------------------------

  /// the worst tet a distance split may leave (or the mesh's worst, if
  /// lower): the bound is the user's, so it may cost angles down to this,
  /// then flips and moves raise them again (requiring the mesh's worst
  /// instead refused most splits on the eight: its chords stayed 1.6 times
  /// the bound away)
  static constexpr double distance_quality_floor = 15;

  /// Rounds of `distance_phase()`, each followed by passes of flips and moves
  /// (which move boundary vertices on the surface and flip curved boundary
  /// edges, so the next round measures again), then the count of the
  /// triangles still beyond the bound.
  void keep_surface_distance()
  {
    for(int round = 0; round < 16 && !out_of_time(); ++round) {
      if(distance_phase() == 0)
        break;
      for(int pass = 0; pass < s_.maximum_passes && has_bad_tet() && !c_.time_limit_reached; ++pass) {
        ++c_.passes;
        std::size_t changes = s_.flips ? flip_phase() : 0;
        if(s_.smoothing && !c_.time_limit_reached)
          changes += smoothing_phase();
        if(changes == 0)
          break;
      }
    }
    c_.triangles_beyond_distance = 0;
    c_.largest_surface_distance = 0;
    for(std::size_t f = 0; f < m_.listed.size(); ++f) {
      const double d = triangle_distance(f);
      c_.largest_surface_distance = std::max(c_.largest_surface_distance, d);
      c_.triangles_beyond_distance += d > s_.surface_distance ? 1 : 0;
    }
  }

  /// the largest distance to its patch's surface of the points of a
  /// barycentric grid of 4 steps per edge and the centroid of the listed
  /// triangle in slot `f` (about the measure of the meshing report's surface
  /// distance, against the patch instead of the whole input); 0 if the patch
  /// has no projection
  double triangle_distance(std::size_t f) const
  {
    const std::array<int, 3>& t = m_.listed[f];
    return triangle_distance(P(t[0]), P(t[1]), P(t[2]), m_.listed_refs[f]);
  }

  /// the same for the triangle (x0, x1, x2) of patch `patch`
  double triangle_distance(const Eigen::Vector3d& x0, const Eigen::Vector3d& x1, const Eigen::Vector3d& x2,
                           int patch) const
  {
    double d2 = 0;
    auto sample = [&](double a, double b) {
      const Eigen::Vector3d x = a * x0 + b * x1 + (1 - a - b) * x2;
      std::array<double, 3> q;
      if(!m_.surface_projection(patch, {{x[0], x[1], x[2]}}, q))
        return false;
      d2 = std::max(d2, (x - Eigen::Vector3d(q[0], q[1], q[2])).squaredNorm());
      return true;
    };
    constexpr int n = 4;
    for(int i = 0; i <= n; ++i)
      for(int j = 0; i + j <= n; ++j)
        if(!((i == 0 && j == 0) || i == n || j == n) && !sample(double(i) / n, double(j) / n)) // vertices are on the input
          return 0;
    // the centroid too: a chord triangle of a smooth surface strays most near its circumcentre
    return sample(1.0 / 3, 1.0 / 3) ? std::sqrt(d2) : 0;
  }

  /// With a distance bound: whether the boundary triangles `after` (of
  /// `patch`) are each within the bound or no farther than the farthest of
  /// `before` (so moves and flips never make the bound worse)
  bool keeps_surface_distance(const std::vector<std::array<Eigen::Vector3d, 3>>& before,
                              const std::vector<std::array<Eigen::Vector3d, 3>>& after, int patch) const
  {
    if(!(s_.surface_distance > 0) || !m_.surface_projection || patch == Mutable_tet_mesh::unlisted_patch)
      return true;
    double allowed = -1;
    for(const auto& t : after) {
      const double d = triangle_distance(t[0], t[1], t[2], patch);
      if(d <= s_.surface_distance)
        continue;
      if(allowed < 0) {
        allowed = s_.surface_distance;
        for(const auto& o : before)
          allowed = std::max(allowed, triangle_distance(o[0], o[1], o[2], patch));
      }
      if(d > allowed)
        return false;
    }
    return true;
  }

  /// Where a boundary triangle strays farther than `surface_distance` from
  /// its patch's surface (a chord across a curved patch or along a curved
  /// feature curve), its edges, longest first, are split at a point on the
  /// input (on the patch, or on the curve for a feature edge; placed like
  /// the other splits, its new boundary triangles turning by at most 80
  /// degrees) until one split leaves no tet below `distance_quality_floor`
  /// (or the mesh's worst, if lower). Farthest triangles first. Returns the
  /// number of splits.
  std::size_t distance_phase()
  {
    double worst = std::numeric_limits<double>::infinity();
    for(std::size_t t = 0; t < m_.tets.size(); ++t)
      if(m_.alive[t] && !m_.is_passive(int(t)))
        worst = std::min(worst, q_[t]);
    const double floor = std::min(distance_quality_floor, worst);
    std::vector<std::pair<double, std::size_t>> far;
    for(std::size_t f = 0; f < m_.listed.size(); ++f) {
      const double d = triangle_distance(f);
      if(d > s_.surface_distance)
        far.push_back({-d, f});
    }
    std::sort(far.begin(), far.end());
    std::size_t splits = 0;
    for(const auto& entry : far) {
      if(out_of_time())
        break;
      const std::array<int, 3> t = m_.listed[entry.second];
      if(triangle_distance(entry.second) <= s_.surface_distance)
        continue; // an earlier split nearby changed it
      std::array<std::pair<double, int>, 3> order;
      for(int k = 0; k < 3; ++k)
        order[std::size_t(k)] = {-(P(t[std::size_t((k + 1) % 3)]) - P(t[std::size_t(k)])).squaredNorm(), k};
      std::sort(order.begin(), order.end());
      for(const auto& o : order) {
        const int a = t[std::size_t(o.second)], b = t[std::size_t((o.second + 1) % 3)];
        const int tet = tet_of_edge(a, b);
        Edge_split e;
        e.cos_turn = std::cos(80.0 * std::acos(-1.0) / 180.0);
        if(tet < 0 || !prepare_split(tet, a, b, e) || !place_split_vertex(e) || !(e.best >= floor))
          continue;
        if(!split_keeps_boundary_embedded(e))
          continue;
        apply_split(e);
        ++c_.distance_splits;
        ++splits;
        break;
      }
    }
    return splits;
  }

  // ---- phases ----------------------------------------------------------------

  /// false if `t` was tried and nothing around it changed since
  bool needs_try(std::size_t t) const
  {
    if(tet_tried_[t] < 0)
      return true;
    for(int v : m_.tets[t])
      if(vertex_changed_[std::size_t(v)] > tet_tried_[t])
        return true;
    return false;
  }

  /// free, or (with boundary smoothing) constrained to a plane or a line
  bool movable(int v) const
  {
    if(!m_.fixed[std::size_t(v)])
      return true;
    const Vertex_constraint::Kind k = m_.constraint[std::size_t(v)].kind;
    return s_.boundary_smoothing &&
           (k == Vertex_constraint::plane || k == Vertex_constraint::line || k == Vertex_constraint::surface ||
            k == Vertex_constraint::curve);
  }

  bool has_bad_tet() const
  {
    for(std::size_t t = 0; t < m_.tets.size(); ++t)
      if(m_.alive[t] && q_[t] < target_)
        return true;
    return false;
  }

  bool out_of_time()
  {
    if(!c_.time_limit_reached &&
       (elapsed_seconds() > s_.time_limit_seconds || (s_.should_stop && s_.should_stop())))
      c_.time_limit_reached = true;
    return c_.time_limit_reached;
  }

  /// flips until none improves; returns the number of flips
  std::size_t flip_phase()
  {
    queue_ = Queue();
    for(std::size_t t = 0; t < m_.tets.size(); ++t)
      if(m_.alive[t] && needs_try(t))
        push_if_bad(int(t));
    std::size_t flips = 0;
    while(!queue_.empty()) {
      const Entry e = queue_.top();
      queue_.pop();
      const std::size_t t = std::size_t(e.tet);
      if(!m_.alive[t] || m_.stamp[t] != e.stamp)
        continue;
      if(flip_tet(e.tet))
        ++flips;
      else
        tet_tried_[t] = clock_;
      if((flips & 63) == 0 && out_of_time())
        break;
    }
    queue_ = Queue();
    return flips;
  }

  /// one smoothing sweep; returns the number of moves
  std::size_t smoothing_phase()
  {
    // free vertices of bad tets, ordered by the worst tet they are in
    std::vector<std::pair<double, int>> order;
    std::vector<char> seen(m_.points.size(), 0);
    std::vector<std::pair<double, int>> bad;
    for(std::size_t t = 0; t < m_.tets.size(); ++t)
      if(m_.alive[t] && q_[t] < target_)
        bad.push_back({q_[t], int(t)});
    std::sort(bad.begin(), bad.end());
    for(const auto& b : bad)
      for(int v : m_.tets[std::size_t(b.second)])
        if(movable(v) && !seen[std::size_t(v)] &&
           vertex_tried_[std::size_t(v)] < vertex_changed_[std::size_t(v)]) {
          seen[std::size_t(v)] = 1;
          order.push_back(b);
          order.back().second = v;
        }
    std::size_t moves = 0;
    for(std::size_t i = 0; i < order.size(); ++i) {
      if(smooth_vertex(order[i].second))
        ++moves;
      else
        vertex_tried_[std::size_t(order[i].second)] = clock_;
      if((i & 15) == 0 && out_of_time())
        break;
    }
    return moves;
  }

  /// the best strictly improving flip that removes `t`, applied
  bool flip_tet(int t)
  {
    Flip best;
    const Tet T = m_.tets[std::size_t(t)];
    static constexpr int edges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    for(const auto& e : edges)
      consider_edge_removal(t, T[std::size_t(e[0])], T[std::size_t(e[1])], best);
    for(int f = 0; f < 4; ++f)
      consider_face_flip(t, f, best);
    if(best.old_tets.empty()) // nothing proposed (a cap removal proposes no new tets)
      return false;
    if(best.boundary && best.leaves_plane) {
      const auto& e = best.edge_vertices;
      if(!boundary_stays_embedded({{{e[0], e[2], e[3]}}, {{e[1], e[2], e[3]}}}, {{{e[0], e[1], e[2]}}, {{e[0], e[1], e[3]}}},
                                  -2, Eigen::Vector3d::Zero()))
        return false;
    }
    apply(best);
    return true;
  }

  Mutable_tet_mesh& m_;
  Tet_quality<MetricField_3> quality_;
  Improver_settings s_;
  /// the tets worked on are those below it: `target_angle`, then, after
  /// edge splits, `split_below_angle` (the passes after a split round work
  /// on the tets that splits are for, not again on all below the target)
  double target_ = 0;
  std::unique_ptr<Boundary_grid> grid_;
  std::chrono::steady_clock::time_point start_;
  std::vector<double> q_;
  Queue queue_;
  Improver_counters c_;
  // change tracking: an operation that failed is retried only after a
  // change nearby (vertex_changed_ of one of its vertices is later)
  long clock_ = 1;
  std::vector<long> tet_tried_, vertex_tried_, vertex_changed_;
  // the vertex metrics (`vertex_metric()`)
  mutable std::vector<Metric_3> vertex_metric_;
  mutable std::vector<char> vertex_metric_known_;
  // scratch of try_candidate(): the face qualities of a candidate position
  mutable std::vector<double> candidate_quality_;
  /// a length change keeps the worst tet around at least at the lower of
  /// its old worst and this (`length_phase()`)
  double length_floor_ = 0;
  // scratch of the edge removal
  std::vector<int> ring_, ring_tets_, choice_;
  std::vector<Tet> scratch_tets_;
  std::vector<double> triangle_, table_;
};

} // namespace improve
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_IMPROVE_MESH_IMPROVER_H
