// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Contract: adaptive population control (paper, section 4.3), serial and
// deterministic (candidates are ranked by score, ties by index).
//  - `delete_overlapping`: deletes moving bubbles whose overlap
//    sum_j max(0, 1 - w_ij) exceeds the traits' threshold.
//  - `fill_gaps`: probes around every moving bubble and inserts new bubbles
//    where the normalized distance to every bubble is at least the threshold.
//  - `thin_out`: removes seeds closer than `w_min` to a fixed bubble or to a
//    kept seed of smaller index (clean-up of an initial population).
// A round flags the deleted bubbles, inserts (ignoring the flagged ones),
// appends the new ones, then compacts the array (order kept); the caller
// rebuilds the neighbour lists once afterwards.
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_POPULATION_CONTROL_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_POPULATION_CONTROL_H

#include <CGAL/Bubble_mesh_3/internal/packing/bubble.h>
#include <CGAL/Bubble_mesh_3/internal/packing/neighbour_search.h>
#include <CGAL/Bubble_mesh_3/internal/packing/parallel.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {
namespace packing {

/// does bubble j act on moving bubble i in the current stage?
/// Does bubble j pull moving bubble i (full force law)? Fixed bubbles and
/// bubbles of the same entity do. Moving bubbles of other entities (a
/// neighbouring patch or curve) only repel (`w < 1`), so bubbles keep their
/// distance across the feature between two patches without being pulled onto it.
inline bool interacts(const Bubble_record& bi, const Bubble_record& bj)
{
  return bj.fixed || bj.entity == bi.entity;
}

/// normalized distance between a point p carrying metric mp and bubble j
inline double normalized_distance_to(const Vec3& p, const Sym3& mp, const Bubble_record& bj)
{
  const Vec3 d = bj.x - p;
  return normalized_distance(mp.length(d), bj.m.length(d));
}

/// removes the bubbles flagged in `dead` (keeps the order of the others)
inline std::size_t compact(std::vector<Bubble_record>& bubbles, const std::vector<char>& dead)
{
  std::size_t k = 0;
  for(std::size_t i = 0; i < bubbles.size(); ++i)
    if(!dead[i])
      bubbles[k++] = bubbles[i];
  const std::size_t removed = bubbles.size() - k;
  bubbles.resize(k);
  return removed;
}

/// flags in `dead` (resized to the number of bubbles) the moving bubbles to
/// delete; the caller compacts the array after `fill_gaps`
template <typename Traits>
std::size_t delete_overlapping(const std::vector<Bubble_record>& bubbles, const Neighbour_lists& lists,
                               const std::vector<double>& overlap, const std::vector<double>& nearest,
                               const Traits& traits, std::size_t moving, std::vector<char>& dead)
{
  dead.assign(bubbles.size(), 0);
  std::vector<int> candidates;
  for(std::size_t i = 0; i < bubbles.size(); ++i)
    if(!bubbles[i].fixed && (overlap[i] > traits.overlap_deletion_threshold(bubbles[i].dimension) ||
                             nearest[i] < traits.minimum_distance_deletion_threshold(bubbles[i].dimension)))
      candidates.push_back(static_cast<int>(i));
  if(candidates.empty())
    return 0;
  std::sort(candidates.begin(), candidates.end(), [&](int a, int b) {
    return overlap[a] > overlap[b] || (overlap[a] == overlap[b] && a < b);
  });
  const std::size_t limit = std::max<std::size_t>(1, std::size_t(traits.maximum_change_fraction() * moving));
  std::size_t count = 0;
  for(int i : candidates) {
    if(count >= limit)
      break;
    bool blocked = false;
    for(const int* j = lists.begin(i); j != lists.end(i) && !blocked; ++j)
      if(dead[*j] && normalized_distance_to(bubbles[i].x, bubbles[i].m, bubbles[*j]) < 1)
        blocked = true;
    if(blocked)
      continue;
    dead[i] = 1;
    ++count;
  }
  return count;
}

/// Clean-up deletion: flags the moving bubbles whose nearest neighbour is
/// closer than the traits' minimum distance, the closest first; a bubble whose too-close partner is
/// already flagged is kept (one of each pair goes). Returns the count.
template <typename Traits>
std::size_t delete_too_close(const std::vector<Bubble_record>& bubbles, const Neighbour_lists& lists,
                             const std::vector<double>& nearest, const Traits& traits, std::vector<char>& dead)
{
  dead.assign(bubbles.size(), 0);
  std::vector<int> candidates;
  for(std::size_t i = 0; i < bubbles.size(); ++i)
    if(!bubbles[i].fixed && nearest[i] < traits.minimum_distance_deletion_threshold(bubbles[i].dimension))
      candidates.push_back(static_cast<int>(i));
  std::sort(candidates.begin(), candidates.end(),
            [&](int a, int b) { return nearest[a] < nearest[b] || (nearest[a] == nearest[b] && a < b); });
  std::size_t count = 0;
  for(int i : candidates) {
    const double w_min = traits.minimum_distance_deletion_threshold(bubbles[i].dimension);
    bool still_close = false;
    for(const int* j = lists.begin(i); j != lists.end(i) && !still_close; ++j)
      if(!dead[*j] && normalized_distance_to(bubbles[i].x, bubbles[i].m, bubbles[*j]) < w_min)
        still_close = true;
    if(!still_close)
      continue;
    dead[i] = 1;
    ++count;
  }
  return count;
}

// Which bubbles fill_gaps() searches. Incremental search: a bubble is
// searched again only when it, or a listed neighbour, moved more than `drift`
// since its last search, was searched with a result, or lost a neighbour.
// (Gaps open by motion or deletion.)
inline std::vector<char> bubbles_to_search(const std::vector<Bubble_record>& bubbles, const Neighbour_lists& lists,
                                           const Parallel_executor& exec, const std::vector<char>& dead,
                                           bool incremental)
{
  const std::size_t n = bubbles.size();
  std::vector<char> search(n, 1);
  if(!incremental)
    return search;
  const double drift = 0.05;
  std::vector<char> changed(n, 0);
  exec.for_each(n, [&](std::size_t i) {
    const Bubble_record& b = bubbles[i];
    changed[i] = dead[i] || (!b.fixed && (!b.gap_free || b.m.squared_length(b.x - b.probed_at) > drift * drift));
  });
  exec.for_each(n, [&](std::size_t i) {
    if(bubbles[i].fixed || dead[i])
      return;
    char s = changed[i];
    for(const int* j = lists.begin(i); j != lists.end(i) && !s; ++j)
      s = changed[*j];
    search[i] = s;
  });
  return search;
}

// a neighbour of the searched bubble, in its metric frame: y = Q (x_j - x_i)
struct Gap_search_neighbour {
  Vec3 y;
  const Bubble_record* b;
  bool across; // on the other side of a thin part from the searched bubble: does not guide the search
};

// The best gap next to bubble i (a new bubble `record` at normalized distance
// `score` from its nearest one): probes around i, the three best refined
// towards the centre of their hole, placed on i's entity. False if none is
// wider than the insertion threshold. `near` is scratch space.
template <typename Traits, typename Constraint, typename Refresh>
bool best_gap(std::vector<Bubble_record>& bubbles, int i, const Neighbour_lists& lists, double list_reach,
              const Traits& traits, const Constraint& constraint, const Refresh& refresh,
              const std::vector<char>& dead, std::vector<Gap_search_neighbour>& near, double& score,
              Bubble_record& record)
{
  typedef Gap_search_neighbour Near;
  Bubble_record& bi = bubbles[std::size_t(i)];
  bi.gap_free = false;
  bi.probed_at = bi.x;
  const double threshold = traits.gap_insertion_threshold(bi.dimension);
  const double r = traits.gap_probe_distance(bi.dimension);
  const double refine_bound = 0.5 * threshold;
  // a candidate farther from bi than this could be near an unlisted bubble
  // (the lists hold every bubble within metric distance `list_reach`; 0.05
  // is left for the difference of neighbouring metrics)
  const double reach = std::min(1.1, list_reach - threshold - 0.05);
  const Eigen::Matrix3d q = bi.m.cholesky_upper();
  auto frame = [&](const Vec3& x) {
    const Vec3 d = x - bi.x;
    return Vec3(q(0, 0) * d[0] + q(0, 1) * d[1] + q(0, 2) * d[2], q(1, 1) * d[1] + q(1, 2) * d[2],
                q(2, 2) * d[2]);
  };
  // the bubbles that can be within the threshold of a candidate
  const double keep2 = (reach + threshold + 0.05) * (reach + threshold + 0.05);
  near.clear();
  near.push_back(Near{Vec3::Zero(), &bi, false});
  for(const int* j = lists.begin(i); j != lists.end(i); ++j)
    if(!dead[*j]) {
      const Vec3 y = frame(bubbles[*j].x);
      if(y.squaredNorm() <= keep2)
        near.push_back(Near{y, &bubbles[*j], on_opposite_sides(bi, bubbles[*j])});
    }
  // Search score of a point p: its metric distance, in bi's metric, to the
  // nearest bubble (exact for a constant metric; it only guides the
  // search). Any value below `bound` may be returned for a lower score.
  auto search_score = [&](const Vec3& p, double bound, const Bubble_record*& nearest) {
    const Vec3 y = frame(p);
    double best2 = std::numeric_limits<double>::infinity();
    const double bound2 = bound * bound;
    nearest = &bi;
    for(const Near& e : near) {
      if(e.across)
        continue;
      const double d2 = (e.y - y).squaredNorm();
      if(d2 < best2) {
        best2 = d2;
        nearest = e.b;
        if(best2 < bound2)
          break;
      }
    }
    return std::sqrt(best2);
  };
  // exact score of a placed candidate: the normalized distance w to the
  // nearest bubble it does not ignore (see on_opposite_sides)
  auto exact_score = [&](const Bubble_record& c) {
    double sc = std::numeric_limits<double>::infinity();
    for(const Near& e : near)
      if(!on_opposite_sides(c, *e.b))
        sc = std::min(sc, normalized_distance_to(c.x, c.m, *e.b));
    return sc;
  };
  std::array<Vec3, 32> directions;
  const int nd = constraint.probe_directions(bi, directions.data());
  // the probes, best first; the three best are refined towards the centre
  // of their hole (ascent of the distance to the nearest bubble)
  std::array<std::pair<double, int>, 32> order;
  std::array<const Bubble_record*, 32> nearest_of;
  for(int k = 0; k < nd; ++k)
    order[k] = std::make_pair(-search_score(bi.x + r * directions[k], refine_bound, nearest_of[k]), k);
  std::sort(order.begin(), order.begin() + nd);
  double best_score = -1;
  Bubble_record best_record;
  for(int kk = 0; kk < std::min(nd, 3); ++kk) {
    Vec3 p = bi.x + r * directions[order[kk].second];
    double s = -order[kk].first;
    if(s < refine_bound)
      break;
    const Bubble_record* nearest = nearest_of[order[kk].second];
    double step = 0.25 * r;
    // (a step below 0.04 r no longer changes which hole is filled)
    for(int it = 0; it < 12 && step > 0.04 * r; ++it) {
      Vec3 away = p - nearest->x;
      // stay on the entity's tangent space (the nearest bubble may lie on
      // another patch or curve)
      if(bi.dimension == 2)
        away -= away.dot(bi.n) * bi.n;
      else if(bi.dimension == 1)
        away = away.dot(directions[0]) / directions[0].squaredNorm() * directions[0];
      const double la = bi.m.length(away);
      if(!(la > 0))
        break;
      const Vec3 qp = p + (step / la) * away;
      // the score only sees bi's listed neighbours: stay near bi
      if(bi.m.length(qp - bi.x) > reach) {
        step *= 0.5;
        continue;
      }
      const Bubble_record* nq;
      const double sq = search_score(qp, s, nq); // only "better than s" matters
      if(sq > s) {
        p = qp;
        s = sq;
        nearest = nq;
      } else {
        step *= 0.5;
      }
    }
    if(s < threshold || s <= best_score)
      continue;
    Bubble_record c = bi;
    c.v = Vec3::Zero();
    c.gap_free = false;
    if(!constraint.place(c, p) || bi.m.length(c.x - bi.x) > reach)
      continue;
    refresh(c);
    s = exact_score(c);
    if(s < threshold || s <= best_score)
      continue;
    best_score = s;
    best_record = c;
  }
  bi.gap_free = best_score < 0;
  score = best_score;
  record = best_record;
  return best_score >= 0;
}

// Inserts the best candidates (widest gap first) that are not within the
// insertion threshold of an accepted one, at most the traits' change fraction
// of the moving bubbles; returns how many.
template <typename Traits, typename Candidate>
std::size_t insert_accepted_gaps(std::vector<Bubble_record>& bubbles, const Neighbour_lists& lists,
                                 const Traits& traits, std::size_t moving, std::vector<Candidate>& all)
{
  const std::size_t n = bubbles.size();
  std::sort(all.begin(), all.end(), [](const Candidate& a, const Candidate& b) {
    return a.score > b.score || (a.score == b.score && a.origin < b.origin);
  });
  const std::size_t limit = std::max<std::size_t>(1, std::size_t(traits.maximum_change_fraction() * moving));
  std::vector<int> accepted(n, -1); // origin -> slot in `all` of its accepted candidate
  std::size_t count = 0;
  for(std::size_t a = 0; a < all.size() && count < limit; ++a) {
    const Bubble_record& c = all[a].record;
    const double threshold = traits.gap_insertion_threshold(c.dimension);
    auto conflicts = [&](int j) {
      return accepted[j] >= 0 && !on_opposite_sides(c, all[accepted[j]].record) &&
             normalized_distance_to(c.x, c.m, all[accepted[j]].record) < threshold;
    };
    const int i = all[a].origin;
    bool blocked = false;
    for(const int* j = lists.begin(i); j != lists.end(i) && !blocked; ++j) {
      if(conflicts(*j))
        blocked = true;
      for(const int* k = lists.begin(*j); k != lists.end(*j) && !blocked; ++k)
        if(conflicts(*k))
          blocked = true;
    }
    if(blocked)
      continue;
    accepted[i] = static_cast<int>(a);
    ++count;
  }
  // appended in the order of their origins
  for(std::size_t i = 0; i < n; ++i)
    if(accepted[i] >= 0)
      bubbles.push_back(all[accepted[i]].record);
  return count;
}

/// The best gap next to each moving bubble. `Constraint` gives the probe
/// directions (metric length 1, tangent to the bubble's entity) and places a
/// new bubble on the entity (`place(record, point)`, false when impossible).
template <typename Traits, typename Constraint, typename Refresh>
std::size_t fill_gaps(std::vector<Bubble_record>& bubbles, const Neighbour_lists& lists, double list_reach,
                      const Traits& traits,
                      const Constraint& constraint, const Refresh& refresh, const Parallel_executor& exec,
                      std::size_t moving, const std::vector<char>& dead, bool incremental)
{
  const std::size_t n = bubbles.size();
  const std::vector<char> search = bubbles_to_search(bubbles, lists, exec, dead, incremental);
  // the best candidate of each bubble, collected per block (deterministic)
  struct Candidate {
    int origin;
    double score;
    Bubble_record record;
  };
  const std::size_t nb = Parallel_executor::number_of_blocks(n);
  std::vector<std::vector<Candidate>> found(nb);
  exec.for_each_block(n, [&](std::size_t blk, std::size_t begin, std::size_t end) {
    std::vector<Gap_search_neighbour> near;
    for(std::size_t ii = begin; ii < end; ++ii) {
      const int i = static_cast<int>(ii);
      if(bubbles[ii].fixed || dead[ii] || !search[ii])
        continue;
      double score;
      Bubble_record record;
      if(best_gap(bubbles, i, lists, list_reach, traits, constraint, refresh, dead, near, score, record))
        found[blk].push_back(Candidate{i, score, record});
    }
  });
  std::vector<Candidate> all;
  for(auto& f : found)
    all.insert(all.end(), f.begin(), f.end());
  if(all.empty())
    return 0;
  return insert_accepted_gaps(bubbles, lists, traits, moving, all);
}

/// removes moving bubbles closer than `w_min` to a fixed bubble or to a kept
/// moving bubble of smaller index
inline std::size_t thin_out(std::vector<Bubble_record>& bubbles, const Neighbour_lists& lists, double w_min)
{
  std::vector<char> dead(bubbles.size(), 0);
  for(std::size_t i = 0; i < bubbles.size(); ++i) {
    if(bubbles[i].fixed)
      continue;
    for(const int* j = lists.begin(i); j != lists.end(i); ++j) {
      const Bubble_record& bj = bubbles[*j];
      if(dead[*j] || (!bj.fixed && std::size_t(*j) > i))
        continue;
      if(normalized_distance_to(bubbles[i].x, bubbles[i].m, bj) < w_min) {
        dead[i] = 1;
        break;
      }
    }
  }
  return compact(bubbles, dead);
}

} // namespace packing
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_POPULATION_CONTROL_H
