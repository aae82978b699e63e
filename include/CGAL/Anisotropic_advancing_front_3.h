// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_ANISOTROPIC_ADVANCING_FRONT_3_H
#define CGAL_ANISOTROPIC_ADVANCING_FRONT_3_H

#include <CGAL/Bubble_mesh_3/Anisotropic_advancing_front_traits_3.h>
#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/internal/front/cavity_filling.h>
#include <CGAL/Bubble_mesh_3/internal/front/front_geometry.h>
#include <CGAL/Bubble_mesh_3/internal/front/front_grid.h>
#include <CGAL/Bubble_mesh_3/metric_quality.h>

#include <CGAL/Default.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <deque>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <queue>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {

/// \ingroup PkgBubbleMesh3Classes
/// How `Anisotropic_advancing_front_3` made its tets.
struct Advancing_front_statistics {
  std::size_t delaunay_tets = 0;      ///< tets from the modified Delaunay choice
  std::size_t best_quality_tets = 0;  ///< tets from the best-quality fallback
  std::size_t undo_rounds = 0;
  std::size_t undone_tets = 0;
  std::size_t search_tets = 0;        ///< tets placed by the search in undone cavities (count may include retried ones)
  std::size_t cavities = 0;           ///< cavities left after the undo rounds
  std::size_t vertex_star_fills = 0;  ///< cavities closed from one of their vertices
  std::size_t steiner_star_fills = 0; ///< cavities closed from one Steiner point
  std::size_t tetgen_fills = 0;       ///< cavities closed by TetGen
  std::size_t steiner_points = 0;
  std::size_t cavity_tets = 0;        ///< tets created by the cavity fillers
  std::size_t cavity_enlargements = 0; ///< failed fills answered by undoing more tets, searching and advancing again
  std::size_t unused_nodes = 0;       ///< nodes no tet uses (outside the boundary)
  std::size_t removability_tests = 0; ///< the front's work (one or two per tet when it closes well)
  std::size_t fallback_tests = 0;     ///< of which by the best-quality fallback
  std::size_t recovery_tests = 0;     ///< of which by the searches in undone cavities
  std::size_t wakes = 0;              ///< waiting triangles woken by a tet added or removed in their region
  bool work_limit_reached = false;    ///< the front stopped at its work budget; the fillers closed the rest
  double seconds = 0;
};

} // namespace Bubble_mesh_3

/// \ingroup PkgBubbleMesh3Classes
///
/// Connects given nodes into a tetrahedral mesh by an advancing front that
/// creates no node of its own (Yamakawa and Shimada, section 5.2).
///
/// The front starts as the closed boundary surface (triangles on the nodes,
/// oriented outward). Repeatedly, a front triangle `f` is paired with a node
/// `p`: the tet `T(f, p)` is *removable* when it is positively oriented, its
/// three new triangles meet the front only in shared vertices and edges, and
/// no node lies in the closed tet (then `T` lies in the unmeshed volume).
///
/// <b>Choice of the node.</b> For each front triangle, the node among the
/// live nodes on its inner side whose M-circumsphere with the triangle
/// contains no other such node: the modified Delaunay criterion, decided by the
/// traits' exact `Side_of_oriented_metric_sphere_SOS_3` with node ids as the
/// symbolic perturbation (so there is always exactly one). `M` is the mean of
/// the metrics at the front triangle's three vertices, one matrix for all the
/// tests of that decision, which keeps them mutually consistent. Candidates come from a grid
/// over the nodes, searched first within `Parameters::search_radius` metric
/// units of the triangle and then over the bounding box of the winner's
/// M-circumsphere until that box is covered (so the choice is exactly the
/// Delaunay one among the live nodes on the inner side).
///
/// <b>When the Delaunay pair is not removable</b> the triangle waits. When no
/// waiting triangle has a removable Delaunay pair, the removable pair of best
/// quality over all waiting triangles is taken (quality: the minimum metric
/// dihedral angle, metric at the tet's centroid), and Delaunay choices resume
/// around it. When no pair at all is removable (twisted prisms), the tets
/// adjacent to the front are undone (one more layer each round) and each
/// cavity so enlarged is searched depth-first for a tetrahedrization of its
/// nodes (most constrained triangle first, best quality first, bounded
/// effort); then the front advances again. After
/// `Parameters::maximum_undo_rounds`, every remaining cavity is filled: from
/// one of its own vertices when all its triangles see it, else from one
/// Steiner point strictly inside that all its triangles see, else by TetGen's
/// constrained tetrahedralization with Steiner points strictly inside the
/// cavity only (when built with TetGen). Every recovery and every Steiner
/// point is counted in `Statistics`. If a cavity still remains,
/// `Bubble_mesh_3::Meshing_failure` is thrown: the result is a valid mesh of
/// the whole volume or an exception, never a partial mesh.
///
/// \tparam MetricField a model of `MetricField_3`
/// \tparam Traits_ a model of `AnisotropicAdvancingFrontTraits_3`, by
///   default `Bubble_mesh_3::Anisotropic_advancing_front_traits_3<>`.
template <class MetricField, class Traits_ = Default>
class Anisotropic_advancing_front_3 {
public:
  typedef MetricField Metric_field;
  typedef typename Default::Get<Traits_, Bubble_mesh_3::Anisotropic_advancing_front_traits_3<>>::type Traits;
  typedef typename Traits::Point_3 Point_3;
  typedef Bubble_mesh_3::Metric_3 Metric;
  typedef std::array<int, 3> Triangle;
  typedef std::array<int, 4> Tetrahedron;

  /// the front's state when `Parameters::work_progress` is called
  struct Work_progress {
    std::size_t tets = 0;               ///< tets in the mesh now
    std::size_t front_triangles = 0;    ///< triangles of the front
    std::size_t waiting_triangles = 0;  ///< front triangles whose Delaunay pair is not removable
    std::size_t removability_tests = 0; ///< the work so far
    double work_budget = 0;             ///< the tests after which the cavity fillers close the rest
    std::size_t best_quality_tets = 0;
    std::size_t undo_rounds = 0;
  };

  struct Parameters {
    /// candidate search radius around a front triangle, in metric units of its metric
    double search_radius = 1.0;
    /// the front's work budget: removability tests per node (a closing front
    /// uses one or two per tet, a stuck one thousands); past it the cavity
    /// fillers close what is left
    double removability_tests_per_node = 500;
    /// rounds of undoing the tets next to a stuck front before filling the cavities
    int maximum_undo_rounds = 4;
    /// times a cavity the fillers cannot close is enlarged (by 1, 2, ...
    /// layers of undone tets) and filled again before `Meshing_failure`
    int maximum_cavity_enlargements = 4;
    /// allow Steiner points strictly inside a cavity that no node can close
    bool allow_steiner_points = true;
    /// called every `progress_interval` tets with (tets, front triangles)
    std::function<void(std::size_t, std::size_t)> progress;
    std::size_t progress_interval = 100000;
    /// called every `work_report_interval` removability tests: a front that
    /// keeps failing makes few tets for its work, and `progress` alone would
    /// leave a long run silent
    std::function<void(const Work_progress&)> work_progress;
    std::size_t work_report_interval = 100000;
    /// asked every 1,000 decisions (also during recoveries, from the calling
    /// thread); when it returns true, `run()` throws
    /// `Bubble_mesh_3::Interrupted` (it may also throw itself)
    std::function<bool()> should_stop;
  };

  /// how the tets were made (`Bubble_mesh_3::Advancing_front_statistics`)
  typedef Bubble_mesh_3::Advancing_front_statistics Statistics;

  /// The mesh: the input points followed by the Steiner points, and the
  /// positively oriented tets.
  struct Result {
    std::vector<Point_3> points;
    std::vector<Tetrahedron> tets;
    Statistics statistics;
  };

  explicit Anisotropic_advancing_front_3(const Metric_field& field, const Parameters& parameters = Parameters(),
                                         const Traits& traits = Traits())
      : field_(field), param_(parameters), traits_(traits)
  {
    if(!(param_.removability_tests_per_node >= 0))
      throw Bubble_mesh_3::Invalid_input("advancing front: removability_tests_per_node must be a number >= 0");
  }

  /// Meshes the volume enclosed by `boundary` (triangles on `points`, closed,
  /// oriented outward) using every point inside it. Throws
  /// `Bubble_mesh_3::Invalid_input` if the boundary is not closed or refers
  /// to missing points, `Bubble_mesh_3::Meshing_failure` if the volume cannot
  /// be completed.
  Result run(const std::vector<Point_3>& points, const std::vector<Triangle>& boundary)
  {
    const auto t0 = std::chrono::steady_clock::now();
    init(points, boundary);
    advance();
    Result r;
    fill_cavities();
    collect(r);
    r.statistics.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
  }

private:
  typedef Bubble_mesh_3::internal::front::Box Box;
  typedef std::array<double, 3> P3;

  /// Why a pair is not removable, and for how long: a wrong orientation
  /// forever (nodes do not move), a front triangle in the way while it is on
  /// the front, a node in the tet while it is alive. (Recoveries, which can
  /// bring triangles and nodes back, drop every recorded reason.)
  struct Blocker {
    enum Kind : char { none, always, face, node } kind = none;
    int id = -1;
  };

  struct Candidate {
    double quality;
    int node;
    bool rejected;
    Blocker why; // while rejected
  };

  // Every face the front ever had is kept (ids stay valid), so a face holds
  // only what every face needs; what a face needs only once it has waited
  // is in a Waiting_state of its own, given back when the face dies (a
  // 1M-tet front has about 2M faces, most of which never wait).
  struct Face {
    Triangle v;                    // (its box is recomputed: `box_of(f)`)
    bool alive = true;
    bool waiting = false;      // its Delaunay pair was not removable
    // its Delaunay node when the search covered the node's sphere (it stays
    // the Delaunay node until it dies: nodes only die while the front
    // advances), and why that pair was not removable
    int delaunay = -1;
    Blocker delaunay_why;
    unsigned stamp = 0;            // heap entries with another stamp are stale
    int state = -1;                // its Waiting_state, -1 before it first waits
  };

  struct Waiting_state {
    // while waiting: the box its decisions depend on (its triangle, the tets
    // they tested; the scanned boxes when a Delaunay search ended before
    // covering its winner's sphere); only a tet added in it can change them
    // (tets are removed only by recoveries, which re-decide every face)
    Box region;
    // the best-quality fallback (see best_quality_step): the candidate nodes
    // ranked by the quality of their tet, and those found not removable
    std::vector<Candidate> ranked;
    bool ranked_valid = false;
    std::size_t cursor = 0;        // the next candidate to offer
    Box rejected_box;              // of the rejected candidates' tets
    bool has_rejected = false;
  };

  // a waiting face's best candidate not yet found not removable; the
  // fallback takes the highest (quality, then the oldest face)
  struct Heap_entry {
    double quality;
    int face;
    unsigned stamp;
    bool operator<(const Heap_entry& o) const { return quality < o.quality || (quality == o.quality && face > o.face); }
  };

  struct Key_hash {
    std::size_t operator()(const Triangle& t) const
    {
      std::uint64_t h = std::uint64_t(t[0]) * 0x9E3779B97F4A7C15ull;
      h ^= std::uint64_t(t[1]) + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2);
      h ^= std::uint64_t(t[2]) + 0x94D049BB133111EBull + (h << 6) + (h >> 2);
      return std::size_t(h);
    }
  };

  // ---------------------------------------------------------------- set-up
  void init(const std::vector<Point_3>& points, const std::vector<Triangle>& boundary)
  {
    const int n = static_cast<int>(points.size());
    xyz_.clear();
    for(const Point_3& p : points)
      xyz_.push_back({{CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())}});
    // the boundary: valid ids, non-degenerate, every edge once in each direction
    std::map<std::pair<int, int>, int> directed;
    double edge_sum = 0;
    for(const Triangle& t : boundary) {
      for(int k = 0; k < 3; ++k)
        if(t[k] < 0 || t[k] >= n)
          throw Bubble_mesh_3::Invalid_input("advancing front: a boundary triangle refers to a missing point");
      if(t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
        throw Bubble_mesh_3::Invalid_input("advancing front: a boundary triangle repeats a vertex");
      for(int k = 0; k < 3; ++k) {
        if(++directed[std::make_pair(t[k], t[(k + 1) % 3])] > 1)
          throw Bubble_mesh_3::Invalid_input("advancing front: the boundary is not consistently oriented or not manifold");
        edge_sum += distance(t[k], t[(k + 1) % 3]);
      }
    }
    for(const auto& e : directed)
      if(!directed.count(std::make_pair(e.first.second, e.first.first)))
        throw Bubble_mesh_3::Invalid_input("advancing front: the boundary surface is not closed");
    if(boundary.empty())
      throw Bubble_mesh_3::Invalid_input("advancing front: empty boundary");

    cell_ = edge_sum / double(3 * boundary.size());
    if(!(cell_ > 0))
      throw Bubble_mesh_3::Invalid_input("advancing front: degenerate boundary");
    renumber_nodes(points);
    nodes_.build(xyz_, cell_);
    {
      P3 lo = xyz_.front(), hi = xyz_.front();
      for(const P3& p : xyz_)
        for(int k = 0; k < 3; ++k) {
          lo[k] = std::min(lo[k], p[k]);
          hi[k] = std::max(hi[k], p[k]);
        }
      faces_grid_.reset(lo, hi, cell_, 2 * xyz_.size() + 8);
      waiting_grid_.reset(lo, hi, cell_, 2 * xyz_.size() + 8);
    }
    faces_.clear();
    // Every face ever made is kept: about two per tet (one per face of the
    // mesh), and a mesh has about 6 tets per node. Reserving room for 14 per
    // node spares the copies of a growing vector, whose old and new buffers
    // together were the front's peak memory; pages not reached are never
    // touched, so a generous reserve costs address space, not memory.
    faces_.reserve(std::size_t(14) * std::size_t(n) + boundary.size());
    states_.clear();
    free_states_.clear();
    face_of_.clear();
    tets_.clear();
    tet_alive_.clear();
    alive_tets_ = 0;
    tets_of_face_.clear();
    tets_of_face_built_ = false;
    waiting_count_ = 0;
    front_count_.assign(n, 0);
    tet_count_.assign(n, 0);
    queue_.clear();
    fallback_heap_ = decltype(fallback_heap_)();
    stats_ = Statistics();
    alive_faces_ = 0;
    // the front: boundary triangles reversed (the unmeshed side is positive)
    for(const Triangle& t : boundary)
      toggle_face(Triangle{{new_id_[t[0]], new_id_[t[2]], new_id_[t[1]]}});
  }

  /// Numbers the nodes internally in the order of the cells of a grid, so
  /// that nodes near each other in space are near each other in memory (the
  /// grid scans and the per-node arrays then stay in cache: 7% less CPU time
  /// at 100k nodes). Every decision that depends on ids (the symbolic
  /// perturbation, ties) uses the caller's ids, so the mesh does not depend
  /// on this numbering; `collect()` maps back.
  void renumber_nodes(const std::vector<Point_3>& points)
  {
    const int n = static_cast<int>(points.size());
    nodes_.build(xyz_, cell_);
    old_id_ = nodes_.ids_in_cell_order();
    new_id_.assign(n, 0);
    for(int i = 0; i < n; ++i)
      new_id_[old_id_[i]] = i;
    pts_.resize(n);
    std::vector<P3> xyz(n);
    for(int i = 0; i < n; ++i) {
      pts_[i] = points[old_id_[i]];
      xyz[i] = xyz_[old_id_[i]];
    }
    xyz_.swap(xyz);
    node_metric_.clear();
    node_metric_.reserve(n);
    for(int i = 0; i < n; ++i)
      node_metric_.push_back(metric_at(xyz_[i]));
  }

  /// the caller's id of node v (Steiner points keep theirs)
  std::size_t caller_id(int v) const { return v < static_cast<int>(old_id_.size()) ? std::size_t(old_id_[v]) : std::size_t(v); }

  double distance(int a, int b) const
  {
    double s = 0;
    for(int k = 0; k < 3; ++k)
      s += (xyz_[a][k] - xyz_[b][k]) * (xyz_[a][k] - xyz_[b][k]);
    return std::sqrt(s);
  }

  Box box_of(std::initializer_list<int> ids) const
  {
    Box b;
    b.lo = b.hi = xyz_[*ids.begin()];
    for(int i : ids)
      for(int k = 0; k < 3; ++k) {
        b.lo[k] = std::min(b.lo[k], xyz_[i][k]);
        b.hi[k] = std::max(b.hi[k], xyz_[i][k]);
      }
    return b;
  }

  Box box_of(const Face& f) const { return box_of({f.v[0], f.v[1], f.v[2]}); }

  bool is_alive_node(int v) const { return front_count_[v] > 0 || tet_count_[v] == 0; }

  // ------------------------------------------------------- front bookkeeping
  /// Adds `t` to the front, or removes its reverse if present.
  void toggle_face(const Triangle& t)
  {
    namespace F = Bubble_mesh_3::internal::front;
    const Triangle key = F::sorted(t);
    auto it = face_of_.find(key);
    if(it != face_of_.end()) {
      Face& g = faces_[it->second];
      CGAL_assertion(!F::same_orientation(g.v, t));
      g.alive = false;
      if(g.waiting)
        stop_waiting(it->second);
      release_state(g);
      --alive_faces_;
      for(int v : g.v)
        --front_count_[v];
      faces_grid_.remove(it->second, box_of(g));
      face_of_.erase(it);
      return;
    }
    const int id = static_cast<int>(faces_.size());
    Face f;
    f.v = t;
    faces_.push_back(f);
    face_of_.emplace(key, id);
    ++alive_faces_;
    for(int v : t)
      ++front_count_[v];
    faces_grid_.insert(id, box_of(f));
    queue_.push_back(id);
  }

  void add_tet(const Tetrahedron& t)
  {
    namespace F = Bubble_mesh_3::internal::front;
    const int id = static_cast<int>(tets_.size());
    tets_.push_back(t);
    tet_alive_.push_back(1);
    ++alive_tets_;
    for(int v : t)
      ++tet_count_[v];
    for(const Triangle& o : F::outward_faces(t)) {
      if(tets_of_face_built_)
        tets_of_face_[F::sorted(o)].push_back(id);
      // the outward face's reverse is the front face it consumes, or a new front face
      toggle_face(o);
    }
    wake_neighbours(t, false);
    if(param_.progress && tets_.size() % param_.progress_interval == 0)
      param_.progress(tets_.size(), std::size_t(alive_faces_));
  }

  void remove_tet(int id)
  {
    namespace F = Bubble_mesh_3::internal::front;
    const Tetrahedron t = tets_[id];
    tet_alive_[id] = 0;
    --alive_tets_;
    for(int v : t)
      --tet_count_[v];
    for(const Triangle& o : F::outward_faces(t)) {
      auto& list = tets_of_face_[F::sorted(o)];
      list.erase(std::remove(list.begin(), list.end(), id), list.end());
      // the space of the tet becomes unmeshed: its faces point into it
      toggle_face(Triangle{{o[0], o[2], o[1]}});
    }
    wake_neighbours(t, true);
  }

  /// Waiting triangles whose decisions looked where `t` is get another
  /// chance. Their Delaunay node, its removability and their best removable
  /// pair depend only on the live nodes and front triangles in their region,
  /// and a tet changes those only inside its own box, so the others keep
  /// their decisions: on a 1:100 layer a Euclidean neighbourhood of the
  /// tet's size woke a third of the front for every tet.
  /// A woken triangle keeps what it knows while it still holds (its
  /// Delaunay node, its ranked candidates and why they were not removable),
  /// unless the tet was removed.
  void wake_neighbours(const Tetrahedron& t, bool removed)
  {
    if(waiting_count_ == 0)
      return;
    woken_.clear();
    const Box b = box_of({t[0], t[1], t[2], t[3]});
    waiting_grid_.query(b, [&](int id) {
      const Face& f = faces_[id];
      if(f.alive && f.waiting && states_[std::size_t(f.state)].region.meets(b))
        woken_.push_back(id);
    });
    stats_.wakes += woken_.size();
    for(int id : woken_) {
      stop_waiting(id);
      if(removed) { // triangles and nodes can come back: the recorded reasons are void
        state_of(faces_[id]).ranked_valid = false;
        faces_[id].delaunay = -1;
      }
      queue_.push_back(id);
    }
  }

  /// the face's waiting state, made on first use
  Waiting_state& state_of(Face& f)
  {
    if(f.state < 0) {
      if(free_states_.empty()) {
        f.state = static_cast<int>(states_.size());
        states_.emplace_back();
      } else {
        f.state = free_states_.back();
        free_states_.pop_back();
      }
    }
    return states_[std::size_t(f.state)];
  }

  /// a dead face's waiting state goes back to the pool
  void release_state(Face& f)
  {
    if(f.state < 0)
      return;
    states_[std::size_t(f.state)] = Waiting_state();
    free_states_.push_back(f.state);
    f.state = -1;
  }

  void start_waiting(int id, const Box& region)
  {
    Face& f = faces_[id];
    Waiting_state& w = state_of(f);
    reconsider_rejected(f, w);
    f.waiting = true;
    w.region = region;
    w.region.extend(box_of(f));
    if(w.ranked_valid && w.has_rejected)
      w.region.extend(w.rejected_box);
    waiting_grid_.insert(id, w.region);
    ++waiting_count_;
    w.cursor = 0;
    push_next_candidate(id);
  }

  void stop_waiting(int id)
  {
    Face& f = faces_[id];
    f.waiting = false;
    ++f.stamp;
    waiting_grid_.remove(id, states_[std::size_t(f.state)].region);
    --waiting_count_;
  }

  /// A rejected candidate stays rejected while what blocked it is there
  void reconsider_rejected(const Face& f, Waiting_state& w)
  {
    if(!w.ranked_valid || !w.has_rejected)
      return;
    w.has_rejected = false;
    for(Candidate& c : w.ranked) {
      if(!c.rejected)
        continue;
      if(!still_blocks(c.why)) {
        c.rejected = false;
        continue;
      }
      const Box b = box_of({f.v[0], f.v[1], f.v[2], c.node});
      if(w.has_rejected)
        w.rejected_box.extend(b);
      else
        w.rejected_box = b;
      w.has_rejected = true;
    }
  }

  /// offers the waiting face's next candidate not known to be rejected (an
  /// unranked face is offered first, ranked when it comes out)
  void push_next_candidate(int id)
  {
    Face& f = faces_[id];
    Waiting_state& w = state_of(f);
    ++f.stamp;
    if(!w.ranked_valid) {
      fallback_heap_.push(Heap_entry{std::numeric_limits<double>::infinity(), id, f.stamp});
      return;
    }
    while(w.cursor < w.ranked.size() && w.ranked[w.cursor].rejected)
      ++w.cursor;
    if(w.cursor < w.ranked.size())
      fallback_heap_.push(Heap_entry{w.ranked[w.cursor].quality, id, f.stamp});
  }

  /// a waiting face's decisions looked into `b` too
  void extend_region(int id, const Box& b)
  {
    Face& f = faces_[id];
    if(!f.waiting)
      return;
    Waiting_state& w = states_[std::size_t(f.state)];
    if(w.region.contains(b))
      return;
    waiting_grid_.remove(id, w.region);
    w.region.extend(b);
    waiting_grid_.insert(id, w.region);
  }

  // ------------------------------------------------------------- metrics
  Metric metric_at(const P3& x) const
  {
    typedef typename Metric_field::Point_3 Field_point;
    return Metric(field_(Field_point(x[0], x[1], x[2])));
  }

  /// The metric of the decisions on front triangle f: the mean of its
  /// vertices' metrics. On a layer whose metric changes within one element
  /// the metric at the centroid is that of neither side, and neighbouring
  /// triangles' choices disagreed. The mean of positive definite
  /// matrices is positive definite; should it be more anisotropic than
  /// Metric_3 accepts, the centroid's metric is used.
  Metric decision_metric(const Triangle& f) const
  {
    auto at = [&](int v) { return v < int(node_metric_.size()) ? node_metric_[v] : metric_at(xyz_[v]); };
    const Metric::Matrix mean = (at(f[0]).matrix() + at(f[1]).matrix() + at(f[2]).matrix()) / 3.0;
    try {
      return Metric(mean);
    } catch(const Bubble_mesh_3::Invalid_metric&) {
      return metric_at(centroid({f[0], f[1], f[2]}));
    }
  }

  P3 centroid(std::initializer_list<int> ids) const
  {
    P3 c{{0, 0, 0}};
    for(int i : ids)
      for(int k = 0; k < 3; ++k)
        c[k] += xyz_[i][k];
    for(int k = 0; k < 3; ++k)
      c[k] /= double(ids.size());
    return c;
  }

  /// the Euclidean box of the points within metric distance r of x
  Box metric_ball_box(const P3& x, double r, const Metric& m) const
  {
    // the same metric is asked for several boxes of one decision
    if(!(qi_metric_ && *qi_metric_ == m)) {
      qi_ = m.Q_inverse();
      qi_metric_ = m;
    }
    const Eigen::Matrix3d& qi = qi_;
    Box b;
    for(int k = 0; k < 3; ++k) {
      const double e = r * qi.row(k).norm();
      b.lo[k] = x[k] - e;
      b.hi[k] = x[k] + e;
    }
    return b;
  }

  /// the box of the M-circumsphere of a, b, c, d (false if flat)
  bool circumsphere_box(const Triangle& f, int d, const Metric& m, Box& out) const
  {
    const Eigen::Matrix3d& q = m.Q();
    auto mapped = [&](int i) {
      return Eigen::Vector3d(q.template triangularView<Eigen::Upper>() *
                             Eigen::Vector3d(xyz_[i][0], xyz_[i][1], xyz_[i][2]));
    };
    const Eigen::Vector3d a = mapped(f[0]), b = mapped(f[1]), c = mapped(f[2]), e = mapped(d);
    Eigen::Matrix3d A;
    A.row(0) = b - a;
    A.row(1) = c - a;
    A.row(2) = e - a;
    const Eigen::Vector3d rhs(0.5 * (b - a).squaredNorm(), 0.5 * (c - a).squaredNorm(), 0.5 * (e - a).squaredNorm());
    Eigen::FullPivLU<Eigen::Matrix3d> lu(A);
    if(!lu.isInvertible())
      return false;
    const Eigen::Vector3d off = lu.solve(rhs);
    const double r = off.norm();
    const Eigen::Vector3d center_mapped = a + off;
    const Eigen::Vector3d center = q.template triangularView<Eigen::Upper>().solve(center_mapped);
    if(!std::isfinite(r) || !center.allFinite())
      return false;
    out = metric_ball_box(P3{{center[0], center[1], center[2]}}, r * (1 + 1e-9), m);
    return true;
  }

  double tet_quality(const Triangle& f, int p) const
  {
    namespace BM = Bubble_mesh_3;
    auto v = [&](int i) { return Eigen::Vector3d(xyz_[i][0], xyz_[i][1], xyz_[i][2]); };
    const Metric m = metric_at(centroid({f[0], f[1], f[2], p}));
    return BM::metric_minimum_dihedral_angle(v(f[0]), v(f[1]), v(f[2]), v(p), m);
  }

  // ---------------------------------------------------------- candidates
  /// live nodes strictly on the inner side of f within the box
  void candidates(const Triangle& f, const Box& b, std::vector<int>& out, const Box* skip = nullptr) const
  {
    auto orientation = traits_.orientation_3_object();
    const Bubble_mesh_3::internal::front::Plane_side_filter plane(pts_[f[0]], pts_[f[1]], pts_[f[2]]);
    out.clear();
    nodes_.query(b, [&](int q) {
      if(q == f[0] || q == f[1] || q == f[2] || !is_alive_node(q))
        return;
      if(skip != nullptr) {
        const P3& x = xyz_[q];
        if(x[0] >= skip->lo[0] && x[0] <= skip->hi[0] && x[1] >= skip->lo[1] && x[1] <= skip->hi[1] &&
           x[2] >= skip->lo[2] && x[2] <= skip->hi[2])
          return;
      }
      const CGAL::Orientation quick = plane(pts_[q]);
      if(quick == CGAL::POSITIVE ||
         (quick == CGAL::COPLANAR && orientation(pts_[f[0]], pts_[f[1]], pts_[f[2]], pts_[q]) == CGAL::POSITIVE))
        out.push_back(q);
    });
  }

  Box search_box(const Triangle& f, const Metric& m, double factor) const
  {
    const P3 c = centroid({f[0], f[1], f[2]});
    double longest = 0;
    for(int k = 0; k < 3; ++k)
      longest = std::max(longest, m.length(Eigen::Vector3d(xyz_[f[k]][0] - xyz_[f[(k + 1) % 3]][0],
                                                            xyz_[f[k]][1] - xyz_[f[(k + 1) % 3]][1],
                                                            xyz_[f[k]][2] - xyz_[f[(k + 1) % 3]][2])));
    return metric_ball_box(c, factor * param_.search_radius * std::max(0.75, 0.6 * longest), m);
  }

  /// Where the Delaunay node of f usually is: near the apex of the ideal
  /// tet on f (0.8 metric units on the inner side). The first box is a ball
  /// shifted inward by 0.2 units, of radius 0.9 (or 0.75 times f's longest
  /// edge): a box that is too small costs a second scan more often than a
  /// larger one costs (0.2 / 0.9 measured best among shifts 0 - 0.6 and
  /// radii 0.6 - 1.0: 1.10G instructions on a 10k node set against 1.43G
  /// for an unshifted ball of 0.75). Only a starting guess: the search
  /// grows until the winner's circumsphere is covered.
  Box first_search_box(const Triangle& f, const Metric& m) const
  {
    P3 c = centroid({f[0], f[1], f[2]});
    double longest = 0;
    for(int k = 0; k < 3; ++k)
      longest = std::max(longest, m.length(Eigen::Vector3d(xyz_[f[k]][0] - xyz_[f[(k + 1) % 3]][0],
                                                            xyz_[f[k]][1] - xyz_[f[(k + 1) % 3]][1],
                                                            xyz_[f[k]][2] - xyz_[f[(k + 1) % 3]][2])));
    const Eigen::Vector3d a(xyz_[f[0]][0], xyz_[f[0]][1], xyz_[f[0]][2]);
    const Eigen::Vector3d n = (Eigen::Vector3d(xyz_[f[1]][0], xyz_[f[1]][1], xyz_[f[1]][2]) - a)
                                  .cross(Eigen::Vector3d(xyz_[f[2]][0], xyz_[f[2]][1], xyz_[f[2]][2]) - a);
    const double len = m.length(n);
    if(len > 0 && std::isfinite(len))
      for(int k = 0; k < 3; ++k)
        c[k] += n[k] * (0.2 / len);
    return metric_ball_box(c, param_.search_radius * std::max(0.9, 0.75 * longest), m);
  }

  /// the node of the modified Delaunay pair of f, or -1
  int delaunay_node(const Triangle& f, Box& region, bool& exact)
  {
    exact = false;
    const Metric m = decision_metric(f);
    auto side = traits_.side_of_oriented_metric_sphere_SOS_3_object();
    // The Delaunay node minimises a strict total order along the pencil of
    // spheres through f ("q inside the sphere of (f, best)" means q comes
    // first), so one scan finds it and a scan can continue over nodes added
    // by a larger box: nodes of an already scanned box are skipped.
    Box box = first_search_box(f, m);
    Box scanned;
    bool has_scanned = false;
    int best = -1;
    for(int attempt = 0; attempt < 6; ++attempt) {
      candidates(f, box, cand_, has_scanned ? &scanned : nullptr);
      for(int q : cand_) {
        if(best < 0) {
          best = q;
          continue;
        }
        if(side(pts_[f[0]], pts_[f[1]], pts_[f[2]], pts_[best], pts_[q], m, caller_id(f[0]), caller_id(f[1]),
                caller_id(f[2]), caller_id(best), caller_id(q)) == CGAL::ON_POSITIVE_SIDE)
          best = q;
      }
      scanned = box;
      has_scanned = true;
      region = box;
      if(best < 0) {
        box = search_box(f, m, double(2 << attempt));
        box.extend(scanned);
        continue;
      }
      Box sphere;
      const bool has_sphere = circumsphere_box(f, best, m, sphere);
      if(has_sphere && box.contains(sphere)) {
        // every live node before `best` would be in its sphere, hence in the
        // box: `best` is the Delaunay node among all live nodes. Nodes only
        // die while the front advances, so it stays the answer until it dies
        // itself, and whether its tet is removable changes only with the
        // front inside the tet's box: that box is all the decision depends on
        region = box_of({f[0], f[1], f[2], best});
        exact = true;
        return best;
      }
      if(has_sphere)
        region.extend(sphere);
      if(!has_sphere || attempt == 5)
        return best;
      box.extend(sphere);
    }
    return best;
  }

  // ---------------------------------------------------------- removability
  bool still_blocks(const Blocker& b) const
  {
    switch(b.kind) {
    case Blocker::always: return true;
    case Blocker::face: return faces_[b.id].alive;
    case Blocker::node: return is_alive_node(b.id);
    default: return false;
    }
  }

  bool removable(int fid, int p, Blocker* why = nullptr)
  {
    Blocker local;
    Blocker& blocker = why ? *why : local;
    blocker = Blocker();
    if(++stats_.removability_tests % std::max<std::size_t>(param_.work_report_interval, 1) == 0 &&
       param_.work_progress)
      report_work();
    namespace F = Bubble_mesh_3::internal::front;
    const Triangle f = faces_[fid].v;
    if(traits_.orientation_3_object()(pts_[f[0]], pts_[f[1]], pts_[f[2]], pts_[p]) != CGAL::POSITIVE) {
      blocker.kind = Blocker::always;
      return false;
    }
    const std::array<Triangle, 3> nf = F::new_faces(f, p);
    std::array<int, 3> partner{{-1, -1, -1}};
    for(int i = 0; i < 3; ++i) {
      auto it = face_of_.find(F::sorted(nf[i]));
      if(it != face_of_.end()) {
        if(F::same_orientation(faces_[it->second].v, nf[i])) {
          blocker.kind = Blocker::face;
          blocker.id = it->second;
          return false; // would double the front over itself
        }
        partner[i] = it->second;
      }
    }
    const Box b = box_of({f[0], f[1], f[2], p});
    bool ok = true;
    std::array<Box, 3> nb;
    for(int i = 0; i < 3; ++i)
      nb[i] = box_of({nf[i][0], nf[i][1], nf[i][2]});
    const std::array<F::Plane_side_filter, 3> planes{{F::Plane_side_filter(pts_[nf[0][0]], pts_[nf[0][1]], pts_[nf[0][2]]),
                                                      F::Plane_side_filter(pts_[nf[1][0]], pts_[nf[1][1]], pts_[nf[1][2]]),
                                                      F::Plane_side_filter(pts_[nf[2][0]], pts_[nf[2][1]], pts_[nf[2][2]])}};
    const F::Plane_side_filter f_plane(pts_[f[0]], pts_[f[1]], pts_[f[2]]); // p's side positive
    // g meets T at most in vertices of T, all on one face plane of T, with
    // its other vertices strictly outside that plane (decided in double when
    // the filter is sure): then g meets T in a vertex or an edge of T, which
    // every new face containing it shares. Most front faces near T end here.
    auto separated = [&](const Triangle& g) {
      for(int k = 0; k < 4; ++k) {
        const Triangle& on = k < 3 ? nf[k] : f;
        const F::Plane_side_filter& plane = k < 3 ? planes[k] : f_plane;
        const CGAL::Orientation outside = k < 3 ? CGAL::POSITIVE : CGAL::NEGATIVE;
        int on_plane = 0;
        bool all_out = true;
        for(int j = 0; j < 3 && all_out; ++j) {
          if(g[j] == on[0] || g[j] == on[1] || g[j] == on[2])
            ++on_plane;
          else if(plane(pts_[g[j]]) != outside)
            all_out = false;
        }
        if(all_out && on_plane <= 2)
          return true;
      }
      return false;
    };
    faces_grid_.query(b, [&](int gid) {
      if(!ok || gid == fid || !faces_[gid].alive)
        return;
      const Triangle& g = faces_[gid].v;
      const Box gb = box_of(faces_[gid]);
      if(!b.meets(gb) || separated(g))
        return;
      for(int i = 0; i < 3 && ok; ++i)
        if(gid != partner[i] && nb[i].meets(gb) &&
           F::triangles_meet_beyond_shared(nf[i], g, pts_, traits_, &planes[i])) {
          ok = false;
          blocker.kind = Blocker::face;
          blocker.id = gid;
        }
    });
    if(!ok)
      return false;
    // dead nodes (inside the meshed volume) cannot be in T: the front would
    // have to cross T's faces or have a vertex in T, both excluded
    nodes_.query(b, [&](int q) {
      if(!ok || q == f[0] || q == f[1] || q == f[2] || q == p || !is_alive_node(q))
        return;
      // in the closed tet unless strictly outside one of its faces: the three
      // new faces and f (whose outside is where the meshed volume is)
      auto outside = [&](const F::Plane_side_filter& plane, const Triangle& face) {
        const CGAL::Orientation o = plane(pts_[q]);
        if(o != CGAL::COPLANAR)
          return o == CGAL::POSITIVE;
        return traits_.orientation_3_object()(pts_[face[0]], pts_[face[1]], pts_[face[2]], pts_[q]) == CGAL::POSITIVE;
      };
      if(outside(planes[0], nf[0]) || outside(planes[1], nf[1]) || outside(planes[2], nf[2]) ||
         traits_.orientation_3_object()(pts_[f[0]], pts_[f[1]], pts_[f[2]], pts_[q]) == CGAL::NEGATIVE)
        return;
      ok = false;
      blocker.kind = Blocker::node;
      blocker.id = q;
    });
    return ok;
  }

  void report_work() const
  {
    Work_progress w;
    w.tets = alive_tets_;
    w.front_triangles = std::size_t(alive_faces_);
    w.waiting_triangles = std::size_t(waiting_count_);
    w.removability_tests = stats_.removability_tests;
    w.work_budget = work_budget();
    w.best_quality_tets = stats_.best_quality_tets;
    w.undo_rounds = stats_.undo_rounds;
    param_.work_progress(w);
  }

  /// counts decisions and asks `Parameters::should_stop` every 1,000
  void check_stop()
  {
    if(param_.should_stop && ++decisions_ % 1000 == 0 && param_.should_stop())
      throw Bubble_mesh_3::Interrupted("advancing front: stopped on request");
  }

  // ------------------------------------------------------------ the loop
  bool run_queue()
  {
    bool progress = false;
    while(!queue_.empty() && !over_budget()) {
      check_stop();
      const int fid = queue_.front();
      queue_.pop_front();
      Face& f = faces_[fid];
      if(!f.alive || f.waiting)
        continue;
      if(f.delaunay >= 0 && is_alive_node(f.delaunay) && still_blocks(f.delaunay_why)) {
        start_waiting(fid, box_of({f.v[0], f.v[1], f.v[2], f.delaunay}));
        continue;
      }
      Box region;
      bool exact = false;
      const int p = delaunay_node(f.v, region, exact);
      Blocker why;
      if(p >= 0 && removable(fid, p, &why)) {
        const Triangle v = f.v;
        add_tet(Tetrahedron{{v[0], v[1], v[2], p}});
        ++stats_.delaunay_tets;
        progress = true;
      } else {
        faces_[fid].delaunay = exact ? p : -1;
        faces_[fid].delaunay_why = why;
        start_waiting(fid, region);
      }
    }
    return progress;
  }

  /// ranks the candidate nodes of waiting face `id` by the quality of their tet
  void rank_candidates(int id)
  {
    const Triangle f = faces_[id].v;
    const Metric m = decision_metric(f);
    std::vector<Candidate> ranked;
    for(int attempt = 0; attempt < 3 && ranked.empty(); ++attempt) {
      candidates(f, search_box(f, m, double(1 << attempt)), cand_);
      for(int q : cand_)
        ranked.push_back(Candidate{tet_quality(f, q), q, false, Blocker{}});
    }
    std::sort(ranked.begin(), ranked.end(), [this](const Candidate& a, const Candidate& b) {
      return a.quality > b.quality || (a.quality == b.quality && caller_id(a.node) < caller_id(b.node));
    });
    Waiting_state& w = state_of(faces_[id]);
    w.ranked.swap(ranked);
    w.ranked_valid = true;
    w.has_rejected = false;
    w.cursor = 0;
  }

  /// Adds the removable pair of best quality over all waiting triangles.
  /// The candidates of each waiting triangle are ranked once (they can only
  /// die) and offered to a max-heap one at a time, best first: the heap's top
  /// is the best pair not yet found not removable, so only pairs that could
  /// win are tested. A pair found not removable stays so until a tet is added
  /// in its box, which wakes its triangle (the triangle's region covers it).
  /// Heap entries of triangles woken or consumed since are stale (stamps).
  bool best_quality_step()
  {
    while(!fallback_heap_.empty()) {
      check_stop();
      const Heap_entry e = fallback_heap_.top();
      fallback_heap_.pop();
      if(!faces_[e.face].alive || !faces_[e.face].waiting || faces_[e.face].stamp != e.stamp)
        continue;
      if(!state_of(faces_[e.face]).ranked_valid) {
        rank_candidates(e.face);
        push_next_candidate(e.face);
        continue;
      }
      const Triangle v = faces_[e.face].v;
      const Waiting_state& w = state_of(faces_[e.face]);
      const int p = w.ranked[w.cursor].node;
      Blocker why;
      if(!is_alive_node(p))
        why.kind = Blocker::always; // dead nodes stay dead until a recovery
      else if((++stats_.fallback_tests, removable(e.face, p, &why))) {
        add_tet(Tetrahedron{{v[0], v[1], v[2], p}});
        ++stats_.best_quality_tets;
        return true;
      }
      Waiting_state& g = state_of(faces_[e.face]); // removable() adds no faces, but be safe
      g.ranked[g.cursor].rejected = true;
      g.ranked[g.cursor].why = why;
      const Box b = box_of({v[0], v[1], v[2], p});
      if(g.has_rejected)
        g.rejected_box.extend(b);
      else
        g.rejected_box = b;
      g.has_rejected = true;
      extend_region(e.face, b);
      ++g.cursor;
      push_next_candidate(e.face);
    }
    return false;
  }

  /// undoes `layers` layers of tets next to the front
  void undo_layers(int layers)
  {
    if(!tets_of_face_built_) { // only recoveries need it: built on the first one
      for(std::size_t t = 0; t < tets_.size(); ++t)
        if(tet_alive_[t])
          for(const Triangle& o : Bubble_mesh_3::internal::front::outward_faces(tets_[t]))
            tets_of_face_[Bubble_mesh_3::internal::front::sorted(o)].push_back(static_cast<int>(t));
      tets_of_face_built_ = true;
    }
    for(int layer = 0; layer < layers; ++layer) {
      std::vector<int> next;
      for(const auto& kv : face_of_) {
        auto it = tets_of_face_.find(kv.first);
        if(it == tets_of_face_.end())
          continue;
        for(int t : it->second)
          if(tet_alive_[t])
            next.push_back(t);
      }
      std::sort(next.begin(), next.end());
      next.erase(std::unique(next.begin(), next.end()), next.end());
      for(int t : next)
        if(tet_alive_[t]) {
          remove_tet(t);
          ++stats_.undone_tets;
        }
    }
  }

  /// removable nodes of the alive face with key k, best metric quality first
  std::vector<int> options(const Triangle& key)
  {
    std::vector<int> out;
    auto it = face_of_.find(key);
    if(it == face_of_.end())
      return out;
    const int fid = it->second;
    const Triangle f = faces_[fid].v;
    const Metric m = decision_metric(f);
    candidates(f, search_box(f, m, 2.0), cand_);
    std::vector<std::pair<double, int>> ranked;
    const std::vector<int> cand = cand_;
    for(int q : cand) {
      --budget_;
      check_stop();
      ++stats_.recovery_tests;
      if(removable(fid, q))
        ranked.emplace_back(tet_quality(f, q), q);
    }
    std::sort(ranked.begin(), ranked.end(), [this](const std::pair<double, int>& a, const std::pair<double, int>& b) {
      return a.first > b.first || (a.first == b.first && caller_id(a.second) < caller_id(b.second));
    });
    for(const auto& r : ranked)
      out.push_back(r.second);
    return out;
  }

  /// Depth-first search for a tetrahedrization of the cavity whose faces have
  /// their keys in `keys` (most constrained face first, best quality first).
  /// On failure everything it did is undone.
  bool search(std::set<Triangle>& keys)
  {
    Triangle chosen{{-1, -1, -1}};
    std::vector<int> chosen_options;
    bool any = false;
    for(const Triangle& k : keys) {
      if(!face_of_.count(k))
        continue;
      any = true;
      std::vector<int> opts = options(k);
      if(opts.empty() || budget_ < 0)
        return false;
      if(chosen[0] < 0 || opts.size() < chosen_options.size()) {
        chosen = k;
        chosen_options = std::move(opts);
        if(chosen_options.size() == 1)
          break;
      }
    }
    if(!any)
      return true;
    for(int p : chosen_options) {
      auto it = face_of_.find(chosen);
      if(it == face_of_.end())
        return false;
      const Triangle v = faces_[it->second].v;
      const int tid = static_cast<int>(tets_.size());
      const Tetrahedron t{{v[0], v[1], v[2], p}};
      add_tet(t);
      std::vector<Triangle> added;
      for(const Triangle& o : Bubble_mesh_3::internal::front::outward_faces(t)) {
        const Triangle k = Bubble_mesh_3::internal::front::sorted(o);
        if(keys.insert(k).second)
          added.push_back(k);
      }
      if(search(keys))
        return true;
      remove_tet(tid);
      for(const Triangle& k : added)
        keys.erase(k);
      if(budget_ < 0)
        return false;
    }
    return false;
  }

  /// undoes `layers` layers around the stuck front, then searches every
  /// cavity for a tetrahedrization of its enlarged volume
  void recover(int layers)
  {
    ++stats_.undo_rounds;
    undo_layers(layers);
    std::vector<Triangle> front;
    for(const auto& kv : face_of_)
      front.push_back(faces_[kv.second].v);
    std::sort(front.begin(), front.end());
    for(const auto& cavity : Bubble_mesh_3::internal::front::edge_connected_components(front)) {
      std::set<Triangle> keys;
      for(const Triangle& f : cavity)
        keys.insert(Bubble_mesh_3::internal::front::sorted(f));
      budget_ = 20000;
      const std::size_t before = tets_.size();
      if(search(keys))
        stats_.search_tets += tets_.size() - before;
    }
    for(Face& f : faces_)
      if(f.alive) {
        f.waiting = false;
        if(f.state >= 0)
          states_[std::size_t(f.state)].ranked_valid = false;
        f.delaunay = -1;
        ++f.stamp;
      }
    waiting_count_ = 0;
    waiting_grid_.clear();
    fallback_heap_ = decltype(fallback_heap_)();
    queue_.clear();
    for(const auto& kv : face_of_)
      queue_.push_back(kv.second);
    std::sort(queue_.begin(), queue_.end());
  }

  /// whether the front's work passed `Parameters::removability_tests_per_node`
  /// tests per node (at least 200 nodes' worth: small fronts may take a few
  /// hundred tests per tet); once it has, it stays so for the run
  double work_budget() const
  {
    return param_.removability_tests_per_node * double(std::max<std::size_t>(xyz_.size(), 200));
  }

  bool over_budget()
  {
    if(double(stats_.removability_tests) >= work_budget())
      stats_.work_limit_reached = true;
    return stats_.work_limit_reached;
  }

  /// Advances until the front is closed, the recoveries are spent, or the
  /// work budget is spent (a front that keeps failing, as on a 1:100 layer
  /// thinner than the sagitta of its curved wall's chords, would otherwise
  /// run for hours); the cavity fillers close what is left.
  void advance()
  {
    int rounds = 0;
    while(alive_faces_ > 0) {
      if(over_budget())
        break;
      run_queue();
      if(alive_faces_ == 0)
        break;
      if(best_quality_step())
        continue;
      if(rounds >= param_.maximum_undo_rounds)
        break;
      ++rounds;
      recover(rounds);
    }
  }

  // ------------------------------------------------------------ cavities
  void fill_cavities()
  {
    namespace F = Bubble_mesh_3::internal::front;
    if(alive_faces_ == 0)
      return;
    // A cavity TetGen cannot fill without splitting its triangles (a thin
    // gap, an edge shared by two cavities) is enlarged by undoing layers of
    // tets around it, which gives the filler room, and tried again.
    F::Cavity_fill_statistics cs;
    std::vector<Tetrahedron> filled;
    for(int attempt = 0;; ++attempt) {
      std::vector<Triangle> remaining;
      for(const auto& kv : face_of_)
        remaining.push_back(faces_[kv.second].v);
      std::sort(remaining.begin(), remaining.end());
      std::vector<int> free_nodes;
      for(int v = 0; v < static_cast<int>(pts_.size()); ++v)
        if(tet_count_[v] == 0 && front_count_[v] == 0)
          free_nodes.push_back(v);
      const std::size_t points_before = pts_.size();
      cs = F::Cavity_fill_statistics();
      try {
        filled = F::fill_cavities(remaining, free_nodes, pts_, param_.allow_steiner_points, traits_, cs, param_.should_stop);
        break;
      } catch(const Bubble_mesh_3::Meshing_failure&) {
        pts_.resize(points_before); // Steiner points of fills that were not kept
        if(attempt >= param_.maximum_cavity_enlargements)
          throw;
        ++stats_.cavity_enlargements;
        // the front's own recovery before the fillers again: undo more
        // layers, search the enlarged cavities, advance; the fillers get
        // what is left (a TetGen that failed on one cavity may not fail on
        // the larger one, and the fans may close it)
        recover(attempt + 1);
        // best-quality steps are costly (each rescans the waiting
        // triangles): a bounded number, then the fillers
        for(std::size_t steps = 0; alive_faces_ > 0 && !over_budget(); ++steps) {
          run_queue();
          if(alive_faces_ == 0 || steps > 2 * remaining.size() + 50 || !best_quality_step())
            break;
        }
        if(alive_faces_ == 0) {
          filled.clear();
          cs = F::Cavity_fill_statistics();
          break;
        }
        // what the front could not close goes back to the fillers larger:
        // TetGen, which may not split a cavity's triangles (-Y), leaves a
        // triangle out when it cannot recover it without a Steiner point on
        // it; a larger cavity gives it other triangles
        undo_layers(attempt + 1);
      }
    }
    stats_.cavities += cs.cavities;
    stats_.vertex_star_fills += cs.vertex_star_fills;
    stats_.steiner_star_fills += cs.steiner_star_fills;
    stats_.tetgen_fills += cs.tetgen_fills;
    stats_.steiner_points += pts_.size() - xyz_.size();
    // the fillers append Steiner points to pts_
    while(xyz_.size() < pts_.size()) {
      const Point_3& p = pts_[xyz_.size()];
      xyz_.push_back({{CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())}});
      front_count_.push_back(0);
      tet_count_.push_back(0);
    }
    for(const Tetrahedron& t : filled) {
      tets_.push_back(t);
      tet_alive_.push_back(1);
      ++alive_tets_;
      for(int v : t)
        ++tet_count_[v];
    }
    stats_.cavity_tets += filled.size();
    alive_faces_ = 0;
  }

  void collect(Result& r)
  {
    r.points = pts_;
    for(std::size_t i = 0; i < old_id_.size(); ++i)
      r.points[old_id_[i]] = pts_[i];
    for(std::size_t t = 0; t < tets_.size(); ++t)
      if(tet_alive_[t]) {
        Tetrahedron c;
        for(int k = 0; k < 4; ++k)
          c[k] = static_cast<int>(caller_id(tets_[t][k]));
        r.tets.push_back(c);
      }
    for(int v = 0; v < static_cast<int>(pts_.size()); ++v)
      if(tet_count_[v] == 0)
        ++stats_.unused_nodes;
    r.statistics = stats_;
  }

  const Metric_field& field_;
  Parameters param_;
  Traits traits_;

  std::vector<Point_3> pts_; // in the internal numbering
  std::vector<P3> xyz_;
  std::vector<int> old_id_, new_id_; // internal id -> caller's id and back
  double cell_ = 1;
  Bubble_mesh_3::internal::front::Point_grid nodes_;
  Bubble_mesh_3::internal::front::Box_grid faces_grid_;
  Bubble_mesh_3::internal::front::Box_grid waiting_grid_; // waiting faces by region
  std::vector<int> woken_;
  std::vector<Face> faces_;
  std::vector<Waiting_state> states_; // of the faces that waited
  std::vector<int> free_states_;      // of dead faces, to reuse
  std::unordered_map<Triangle, int, Key_hash> face_of_;
  std::vector<Tetrahedron> tets_;
  std::vector<char> tet_alive_;
  std::unordered_map<Triangle, std::vector<int>, Key_hash> tets_of_face_;
  bool tets_of_face_built_ = false;
  long waiting_count_ = 0; // alive faces waiting: nothing to wake while 0
  std::vector<int> front_count_, tet_count_;
  std::deque<int> queue_;
  std::priority_queue<Heap_entry> fallback_heap_;
  std::vector<Metric> node_metric_; // at each node (internal ids), for decision_metric
  std::vector<int> cand_;
  long alive_faces_ = 0;
  std::size_t alive_tets_ = 0;
  long budget_ = 0;
  std::size_t decisions_ = 0;
  mutable std::optional<Metric> qi_metric_;
  mutable Eigen::Matrix3d qi_;
  Statistics stats_;
};

} // namespace CGAL

#endif // CGAL_ANISOTROPIC_ADVANCING_FRONT_3_H
