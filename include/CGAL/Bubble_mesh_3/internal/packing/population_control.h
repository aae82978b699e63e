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

/// The best gap next to each moving bubble. `Constraint` gives the probe
/// directions (metric length 1, tangent to the bubble's entity) and places a
/// new bubble on the entity (`place(record, point)`, false when impossible).
template <typename Traits, typename Constraint, typename Refresh>
std::size_t fill_gaps(std::vector<Bubble_record>& bubbles, const Neighbour_lists& lists, const Traits& traits,
                      const Constraint& constraint, const Refresh& refresh, const Parallel_executor& exec,
                      std::size_t moving, const std::vector<char>& dead)
{
  const std::size_t n = bubbles.size();
  struct Candidate {
    double score = -1;
    Bubble_record record;
  };
  std::vector<Candidate> best(n);
  exec.for_each(n, [&](std::size_t ii) {
    const int i = static_cast<int>(ii);
    const Bubble_record& bi = bubbles[i];
    if(bi.fixed || dead[i])
      return;
    // The score of a point p is its normalized distance to the nearest of bi
    // and its neighbours (computed in bi's metric at p). The neighbours are
    // visited nearest to bi first, and a scan stops as soon as the score is
    // below `bound` (the caller only needs to know that it is): a probe at 0.85
    // from bi is usually near one of bi's first neighbours.
    thread_local std::vector<std::pair<double, const Bubble_record*>> near;
    near.clear();
    near.emplace_back(0.0, &bi);
    for(const int* j = lists.begin(i); j != lists.end(i); ++j)
      if(!dead[*j])
        near.emplace_back(bi.m.squared_length(bubbles[*j].x - bi.x), &bubbles[*j]);
    std::sort(near.begin() + 1, near.end(), [](const auto& a, const auto& b) {
      return a.first < b.first || (a.first == b.first && a.second < b.second);
    });
    // returns the score (or any value below `bound`) and the nearest bubble
    auto score = [&](const Vec3& p, double bound, const Bubble_record*& nearest) {
      double sc = std::numeric_limits<double>::infinity();
      nearest = &bi;
      for(const auto& e : near) {
        const double d = normalized_distance_to(p, bi.m, *e.second);
        if(d < sc) {
          sc = d;
          nearest = e.second;
          if(sc < bound)
            break;
        }
      }
      return sc;
    };
    const double threshold = traits.gap_insertion_threshold(bi.dimension);
    const double r = traits.gap_probe_distance(bi.dimension);
    const double refine_bound = 0.5 * threshold;
    std::array<Vec3, 32> directions;
    const int nd = constraint.probe_directions(bi, directions.data());
    // the probes, best first; the three best are refined towards the centre
    // of their hole (ascent of the distance to the nearest bubble)
    std::array<std::pair<double, int>, 32> order;
    std::array<const Bubble_record*, 32> nearest_of;
    for(int k = 0; k < nd; ++k)
      order[k] = std::make_pair(-score(bi.x + r * directions[k], refine_bound, nearest_of[k]), k);
    std::sort(order.begin(), order.begin() + nd);
    for(int kk = 0; kk < std::min(nd, 3); ++kk) {
      Vec3 p = bi.x + r * directions[order[kk].second];
      double s = -order[kk].first;
      if(s < refine_bound)
        break;
      const Bubble_record* nearest = nearest_of[order[kk].second];
      double step = 0.25 * r;
      // (a step below 0.04 r no longer changes which hole is filled)
      for(int it = 0; it < 12 && step > 0.04 * r; ++it) {
        const Vec3 away = p - nearest->x;
        const double la = bi.m.length(away);
        if(!(la > 0))
          break;
        const Vec3 q = p + (step / la) * away;
        const Bubble_record* nq;
        const double sq = score(q, s, nq); // only "better than s" matters
        if(sq > s) {
          p = q;
          s = sq;
          nearest = nq;
        } else {
          step *= 0.5;
        }
      }
      if(s < threshold || s <= best[i].score)
        continue;
      Bubble_record nb = bi;
      nb.v = Vec3::Zero();
      if(!constraint.place(nb, p))
        continue;
      const Bubble_record* unused;
      s = score(nb.x, std::max(threshold, best[i].score), unused);
      if(s < threshold || s <= best[i].score)
        continue;
      best[i].score = s;
      best[i].record = nb;
    }
  });
  std::vector<int> candidates;
  for(std::size_t i = 0; i < n; ++i)
    if(best[i].score >= 0)
      candidates.push_back(static_cast<int>(i));
  if(candidates.empty())
    return 0;
  std::sort(candidates.begin(), candidates.end(), [&](int a, int b) {
    return best[a].score > best[b].score || (best[a].score == best[b].score && a < b);
  });
  const std::size_t limit = std::max<std::size_t>(1, std::size_t(traits.maximum_change_fraction() * moving));
  std::vector<char> accepted(n, 0);
  std::size_t count = 0;
  for(int i : candidates) {
    if(count >= limit)
      break;
    const Bubble_record& c = best[i].record;
    const double threshold = traits.gap_insertion_threshold(c.dimension);
    auto conflicts = [&](int j) {
      return accepted[j] &&
             normalized_distance_to(c.x, c.m, best[j].record) < threshold;
    };
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
    accepted[i] = 1;
    ++count;
  }
  const std::size_t first_new = bubbles.size();
  for(int i : candidates)
    if(accepted[i])
      bubbles.push_back(best[i].record);
  exec.for_each(bubbles.size() - first_new, [&](std::size_t k) { refresh(bubbles[first_new + k]); });
  return count;
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
