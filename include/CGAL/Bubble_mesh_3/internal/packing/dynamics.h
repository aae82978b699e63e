// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Contract: one packing stage run to convergence (paper, sections 4.2-4.3).
// `relax(...)` moves the non-fixed bubbles of `bubbles` under the traits'
// inter-bubble forces, with the stage's `Constraint` keeping each bubble on its
// entity, and runs population control every few iterations until a round
// changes nothing (or the round cap). It stops when the largest displacement of
// an iteration, in metric units of the moving bubble, is below the tolerance
// after the population is stable, or at the iteration cap.
//
// Constraint (thread-safe, const):
//   void move(Bubble_record& b, const Vec3& delta) const;   // b.x += delta, kept on the entity
//   int  probe_directions(const Bubble_record& b, Vec3* out) const; // <= 32 vectors, metric length 1
//   bool place(Bubble_record& b, const Vec3& p) const;      // b on the entity near p, false if impossible
// Refresh (thread-safe, const): void operator()(Bubble_record& b) const; // metric at b.x
//
// Bubbles of another entity of the same dimension only repel (w < 1): this
// keeps apart two curves, or two patches, that meet at a small angle in the
// metric (a bubble is deleted below the traits' minimum distance).
//
// Determinism: forces are summed over each bubble's neighbours in a fixed order
// (that of the neighbour lists, independent of the number of threads);
// threads only split the loops over bubbles into fixed blocks; population
// control is serial. Results are bit-identical for any number of threads.
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_DYNAMICS_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_DYNAMICS_H

#include <CGAL/Bubble_mesh_3/internal/packing/bubble.h>
#include <CGAL/Bubble_mesh_3/internal/packing/neighbour_search.h>
#include <CGAL/Bubble_mesh_3/internal/packing/parallel.h>
#include <CGAL/Bubble_mesh_3/internal/packing/population_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {
namespace packing {

struct Relaxation_settings {
  int maximum_iterations = 300;
  double tolerance = 0.02;          // metric units per iteration
  double skin = 0.3;                // Verlet margin, in units of the bubble's largest size
  bool population_control = true;
};

struct Relaxation_result {
  int iterations = 0;
  bool converged = false;
  double last_maximum_displacement = 0;
  std::size_t inserted = 0;
  std::size_t deleted = 0;
  int population_rounds = 0;
  std::size_t neighbour_rebuilds = 0;
};

template <typename Traits, typename Constraint, typename Refresh>
class Relaxation {
public:
  Relaxation(std::vector<Bubble_record>& bubbles, const Traits& traits, const Constraint& constraint,
             const Refresh& refresh, const Parallel_executor& exec, const Relaxation_settings& settings)
      : b_(bubbles), traits_(traits), constraint_(constraint), refresh_(refresh), exec_(exec), settings_(settings),
        force_(traits.compute_interbubble_force_object()), distance_(traits.compute_normalized_distance_object()),
        integrate_(traits.integrate_step_object())
  {}

  /// removes seeds closer than `w_min` to a fixed bubble or an earlier seed
  std::size_t thin_out(double w_min)
  {
    rebuild(true);
    return packing::thin_out(b_, lists_, w_min);
  }

  Relaxation_result run()
  {
    Relaxation_result result;
    rebuild(true);
    if(moving_count() == 0) {
      result.converged = true;
      return result;
    }
    bool stable = !settings_.population_control;
    int since_control = 0;
    while(result.iterations < settings_.maximum_iterations) {
      const double max_disp = step();
      ++result.iterations;
      ++since_control;
      result.last_maximum_displacement = max_disp;
      const bool still = max_disp < settings_.tolerance;
      if(still && stable) {
        result.converged = true;
        break;
      }
      if(!stable && (still || since_control >= traits_.population_control_period())) {
        since_control = 0;
        ++result.population_rounds;
        std::size_t moving = moving_count();
        const std::size_t deleted = delete_overlapping(b_, lists_, overlap_, nearest_, traits_, moving, dead_);
        moving -= deleted;
        const std::size_t inserted = fill_gaps(b_, lists_, traits_, constraint_, refresh_, exec_, moving, dead_);
        if(deleted > 0) {
          dead_.resize(b_.size(), 0);
          compact(b_, dead_);
        }
        result.deleted += deleted;
        result.inserted += inserted;
        // stable: a round on a relaxed packing that changes nothing
        const double churn = traits_.population_stability_fraction() * double(moving);
        if((double(deleted + inserted) <= churn && still) ||
           result.population_rounds >= traits_.maximum_population_rounds())
          stable = true;
        if(inserted > 0 || deleted > 0)
          rebuild(true);
      } else if(needs_rebuild_) {
        rebuild(true);
      }
    }
    result.neighbour_rebuilds = rebuilds_;
    return result;
  }

  std::size_t moving_count() const
  {
    std::size_t c = 0;
    for(const Bubble_record& b : b_)
      c += b.fixed ? 0 : 1;
    return c;
  }

private:
  void rebuild(bool refresh_metrics)
  {
    const std::size_t n = b_.size();
    if(refresh_metrics)
      exec_.for_each(n, [&](std::size_t i) {
        if(!b_[i].fixed)
          refresh_(b_[i]);
      });
    const double reach_factor = force_.cutoff() + settings_.skin;
    reach_.resize(n);
    has_row_.resize(n);
    anchor_.resize(n);
    for(std::size_t i = 0; i < n; ++i) {
      reach_[i] = reach_factor * b_[i].h_max;
      has_row_[i] = b_[i].fixed ? 0 : 1;
      anchor_[i] = b_[i].x;
    }
    lists_.build(b_, reach_, has_row_, reach_factor, exec_);
    overlap_.assign(n, 0.0);
    nearest_.assign(n, force_.cutoff());
    displacement_.resize(n);
    needs_rebuild_ = false;
    ++rebuilds_;
  }

  // One iteration: forces (Jacobi), integration, constrained moves.
  double step()
  {
    const std::size_t n = b_.size();
    const double cut = force_.cutoff();
    const double cut2 = cut * cut;
    const double max_step = traits_.maximum_step();
    exec_.for_each(n, [&](std::size_t i) {
      const Bubble_record& bi = b_[i];
      if(bi.fixed)
        return;
      Vec3 f = Vec3::Zero();
      double overlap = 0;
      double nearest = cut;
      for(const int* jp = lists_.begin(i); jp != lists_.end(i); ++jp) {
        const Bubble_record& bj = b_[*jp];
        const bool pulls = interacts(bi, bj);
        const Vec3 d = bj.x - bi.x;
        const double a2 = bi.m.squared_length(d);
        const double b2 = bj.m.squared_length(d);
        if(a2 >= cut2 && b2 >= cut2)
          continue;
        const double a = std::sqrt(a2);
        const double w = distance_(a, std::sqrt(b2));
        if(w >= cut)
          continue;
        overlap += std::max(0.0, 1 - w);
        nearest = std::min(nearest, w);
        if(!pulls && w >= 1)
          continue;
        const double fw = force_(w);
        if(a > 0) {
          f -= (fw / a) * d;
        } else {
          // coincident centres: a deterministic push, opposite for the pair
          Vec3 e(1, 0.5, 0.25);
          e /= bi.m.length(e);
          f += (std::size_t(*jp) > i ? -fw : fw) * e;
        }
      }
      overlap_[i] = overlap;
      nearest_[i] = nearest;
      Vec3 delta = integrate_(bi.v, f);
      const double len = bi.m.length(delta);
      if(len > max_step)
        delta *= max_step / len;
      displacement_[i] = delta;
    });
    const std::size_t nb = Parallel_executor::number_of_blocks(n);
    block_max_.assign(nb, 0.0);
    block_flag_.assign(nb, 0);
    // a bubble may drift a third of the skin (in its metric) before the
    // lists are rebuilt: half the skin for each bubble of a pair, less a
    // margin for the difference of the two metrics
    const double drift2 = (settings_.skin / 3) * (settings_.skin / 3);
    exec_.for_each_block(n, [&](std::size_t blk, std::size_t begin, std::size_t end) {
      double mx = 0;
      char flag = 0;
      for(std::size_t i = begin; i < end; ++i) {
        Bubble_record& bi = b_[i];
        if(bi.fixed)
          continue;
        const Vec3 old = bi.x;
        constraint_.move(bi, displacement_[i]);
        bi.v = bi.x - old;
        mx = std::max(mx, bi.m.length(bi.v));
        if(bi.m.squared_length(bi.x - anchor_[i]) > drift2)
          flag = 1;
      }
      block_max_[blk] = mx;
      block_flag_[blk] = flag;
    });
    double mx = 0;
    for(std::size_t k = 0; k < nb; ++k) {
      mx = std::max(mx, block_max_[k]);
      if(block_flag_[k])
        needs_rebuild_ = true;
    }
    return mx;
  }

  std::vector<Bubble_record>& b_;
  const Traits& traits_;
  const Constraint& constraint_;
  const Refresh& refresh_;
  const Parallel_executor& exec_;
  Relaxation_settings settings_;
  typename Traits::Compute_interbubble_force force_;
  typename Traits::Compute_normalized_distance distance_;
  typename Traits::Integrate_step integrate_;

  Neighbour_lists lists_;
  std::vector<double> reach_, overlap_, nearest_, block_max_;
  std::vector<char> has_row_, block_flag_, dead_;
  std::vector<Vec3> anchor_, displacement_;
  bool needs_rebuild_ = false;
  std::size_t rebuilds_ = 0;
};

} // namespace packing
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_DYNAMICS_H
