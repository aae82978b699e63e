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
// after the population is stable (converged), when the packing has settled
// (see window_settled), or at the iteration cap.
//
// Constraint (thread-safe, const):
//   void move(Bubble_record& b, const Vec3& delta) const;   // b.x += delta, kept on the entity
//   int  probe_directions(const Bubble_record& b, Vec3* out) const; // <= 32 vectors, metric length 1
//   bool place(Bubble_record& b, const Vec3& p) const;      // b on the entity near p, false if impossible
// Refresh (thread-safe, const): void operator()(Bubble_record& b) const; // metric at b.x
//
// Force: minus the gradient of the pair energies sum phi(w_ij) (phi' = -f)
// with respect to the bubble's position, the metrics' own variation included
// (estimated per bubble from its neighbours' metrics at each list rebuild),
// mapped to a displacement by the bubble's inverse metric.
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

#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/internal/packing/bubble.h>
#include <CGAL/Bubble_mesh_3/internal/packing/neighbour_search.h>
#include <CGAL/Bubble_mesh_3/internal/packing/parallel.h>
#include <CGAL/Bubble_mesh_3/internal/packing/population_control.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <type_traits>
#include <utility>
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
  std::function<bool()> should_stop; // polled every iteration; true: throw Interrupted
};

struct Relaxation_result {
  int iterations = 0;
  bool converged = false;
  // stopped because the packing settled: the bubbles' mean steps over a
  // window stopped decreasing, the bulk below the tolerance (window_settled)
  bool settled = false;
  std::size_t still_moving = 0; // when settled: bubbles whose mean step was above the tolerance
  double last_maximum_displacement = 0;
  std::size_t inserted = 0;
  std::size_t deleted = 0;
  int population_rounds = 0;
  std::size_t neighbour_rebuilds = 0;
};

// The part of a bubble the force loop reads, packed (one or two cache lines
// per neighbour instead of the whole record).
struct Hot_bubble {
  Vec3 x;
  Sym3 m;
  int entity;
  int fixed;
};

/// 63-bit Morton key of p in the box [lo, lo + 1/scale]^3
inline std::uint64_t morton_key(const Vec3& p, const Vec3& lo, double scale)
{
  std::uint64_t key = 0;
  std::uint64_t c[3];
  for(int d = 0; d < 3; ++d)
    c[d] = std::uint64_t(std::min(std::max((p[d] - lo[d]) * scale, 0.0), 2097151.0));
  for(int bit = 20; bit >= 0; --bit)
    for(int d = 0; d < 3; ++d)
      key = (key << 1) | ((c[d] >> bit) & 1);
  return key;
}

// Traits::metric_gradient_force() when the traits have it, else true.
template <typename Traits, typename = void>
struct Has_metric_gradient_force : std::false_type {};
template <typename Traits>
struct Has_metric_gradient_force<Traits, std::void_t<decltype(std::declval<const Traits&>().metric_gradient_force())>>
    : std::true_type {};
template <typename Traits>
bool uses_metric_gradient(const Traits& traits)
{
  if constexpr(Has_metric_gradient_force<Traits>::value)
    return bool(traits.metric_gradient_force());
  else
    return true;
}

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
    spatial_sort();
    rebuild(true);
    if(moving_count() == 0) {
      result.converged = true;
      return result;
    }
    bool stable = !settings_.population_control;
    int since_control = 0;
    while(result.iterations < settings_.maximum_iterations) {
      if(settings_.should_stop && settings_.should_stop())
        throw Interrupted("interrupted during the packing");
      const double max_disp = step();
      ++result.iterations;
      ++since_control;
      result.last_maximum_displacement = max_disp;
      const bool still = max_disp < settings_.tolerance;
      if(still && stable) {
        result.converged = true;
        break;
      }
      if(stable && window_settled(result))
        break;
      if(!stable && (still || since_control >= traits_.population_control_period())) {
        since_control = 0;
        ++result.population_rounds;
        std::size_t moving = moving_count();
        build_wide_lists();
        const std::size_t deleted = delete_overlapping(b_, wide_, overlap_, nearest_, traits_, moving, dead_);
        moving -= deleted;
        const std::size_t inserted =
            fill_gaps(b_, wide_, wide_reach, traits_, constraint_, refresh_, exec_, moving, dead_, true);
        if(deleted > 0) {
          dead_.resize(b_.size(), 0);
          compact(b_, dead_);
        }
        result.deleted += deleted;
        result.inserted += inserted;
        // stable: a round on a relaxed packing that changes nothing
        const double churn = traits_.population_stability_fraction() * double(moving);
        if(double(deleted + inserted) <= churn ||
           result.population_rounds >= traits_.maximum_population_rounds())
          stable = true;
        if(inserted > 0 || deleted > 0) {
          if(inserted > 0)
            spatial_sort();
          rebuild(true);
        }
      } else if(needs_rebuild_) {
        rebuild(true);
      }
    }
    if(settings_.population_control)
      clean_up(result);
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
  // The dynamics can leave pairs closer than the deletion threshold where the
  // packing is under pressure (e.g. bubbles of two patches meeting at a small
  // metric angle, which only repel). Without moving anything: delete one
  // bubble of every such pair, then fill the gaps (a new bubble is at least the
  // insertion threshold from all others), until nothing changes.
  void clean_up(Relaxation_result& result)
  {
    for(int round = 0; round < 8; ++round) {
      rebuild(true);
      measure_nearest();
      std::size_t moving = moving_count();
      const std::size_t deleted = delete_too_close(b_, lists_, nearest_, traits_, dead_);
      moving -= deleted;
      build_wide_lists();
      // the first search is complete: the main loop's searches were incremental
      const std::size_t inserted =
          fill_gaps(b_, wide_, wide_reach, traits_, constraint_, refresh_, exec_, moving, dead_, round > 0);
      if(deleted > 0) {
        dead_.resize(b_.size(), 0);
        compact(b_, dead_);
      }
      result.deleted += deleted;
      result.inserted += inserted;
      if(deleted == 0 && inserted == 0)
        break;
    }
  }

  // nearest_[i]: the smallest w from moving bubble i to a listed bubble
  void measure_nearest()
  {
    const double cut = force_.cutoff();
    exec_.for_each(b_.size(), [&](std::size_t i) {
      const Bubble_record& bi = b_[i];
      if(bi.fixed)
        return;
      double nearest = cut;
      for(const int* jp = lists_.begin(i); jp != lists_.end(i); ++jp) {
        const Vec3 d = b_[*jp].x - bi.x;
        nearest = std::min(nearest, distance_(bi.m.length(d), b_[*jp].m.length(d)));
      }
      nearest_[i] = nearest;
    });
  }

  // Moving bubbles in Morton order (new ones are appended at the end): the
  // neighbours of a bubble are then mostly near it in memory. Only the moving
  // bubbles move in the array, and only when they form its tail.
  void spatial_sort()
  {
    const std::size_t n = b_.size();
    std::size_t first = n;
    while(first > 0 && !b_[first - 1].fixed)
      --first;
    for(std::size_t i = 0; i < first; ++i)
      if(!b_[i].fixed)
        return;
    const std::size_t m = n - first;
    if(m < 2)
      return;
    Vec3 lo = b_[first].x, hi = lo;
    for(std::size_t i = first; i < n; ++i) {
      lo = lo.cwiseMin(b_[i].x);
      hi = hi.cwiseMax(b_[i].x);
    }
    const double span = (hi - lo).maxCoeff();
    const double scale = span > 0 ? 2097151.0 / span : 0.0;
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keys(m);
    exec_.for_each(m, [&](std::size_t k) {
      keys[k] = std::make_pair(morton_key(b_[first + k].x, lo, scale), static_cast<std::uint32_t>(k));
    });
    std::sort(keys.begin(), keys.end());
    std::vector<Bubble_record> sorted(m);
    exec_.for_each(m, [&](std::size_t k) { sorted[k] = b_[first + keys[k].second]; });
    std::copy(sorted.begin(), sorted.end(), b_.begin() + first);
  }

  // Population control needs every bubble near a probe, whatever the skin:
  // its own lists, of metric reach `wide_reach`, from the current positions.
  static constexpr double wide_reach = 2.1;
  void build_wide_lists()
  {
    const std::size_t n = b_.size();
    exec_.for_each(n, [&](std::size_t i) { hot_[i].x = b_[i].x; });
    // (unfiltered: a new bubble must not land on one of the other side)
    wide_.build(hot_, has_row_, wide_reach, exec_);
  }

  // pairs that ignore each other (see on_opposite_sides)
  auto separated() const
  {
    return [this](int i, int j) { return on_opposite_sides(b_[std::size_t(i)], b_[std::size_t(j)]); };
  }

  void rebuild(bool refresh_metrics)
  {
    const std::size_t n = b_.size();
    if(refresh_metrics)
      exec_.for_each(n, [&](std::size_t i) {
        if(!b_[i].fixed)
          refresh_(b_[i]);
      });
    const double reach_factor = force_.cutoff() + settings_.skin;
    has_row_.resize(n);
    anchor_.resize(n);
    hot_.resize(n);
    minv_.resize(n);
    exec_.for_each(n, [&](std::size_t i) {
      minv_[i] = b_[i].m.inverse();
      has_row_[i] = b_[i].fixed ? 0 : 1;
      anchor_[i] = b_[i].x;
      hot_[i] = Hot_bubble{b_[i].x, b_[i].m, b_[i].entity, b_[i].fixed ? 1 : 0};
    });
    lists_.build(hot_, has_row_, reach_factor, exec_, separated());
    if(use_gradient_)
      estimate_metric_gradients();
    overlap_.assign(n, 0.0);
    nearest_.assign(n, force_.cutoff());
    displacement_.resize(n);
    needs_rebuild_ = false;
    ++rebuilds_;
  }

  // grad_[i][k] ~ dM/dx_k at moving bubble i: least-squares fit of
  // M_j - M_i = sum_k (x_j - x_i)_k G_k over its listed neighbours (no field
  // evaluations; a secant slope over the neighbourhood, which is the scale at
  // which w is measured). Directions without neighbours (normal to a curve or
  // a patch) get 0 through a small Tikhonov term: the constraint removes them.
  void estimate_metric_gradients()
  {
    const std::size_t n = b_.size();
    grad_.resize(n);
    flat_.assign(n, 1);
    typedef Eigen::Matrix<double, 6, 1> Vec6;
    const auto entries = [](const Sym3& m) {
      Vec6 v;
      v << m.a00, m.a01, m.a02, m.a11, m.a12, m.a22;
      return v;
    };
    exec_.for_each(n, [&](std::size_t i) {
      const Hot_bubble& bi = hot_[i];
      if(bi.fixed)
        return;
      // the common case of a locally constant metric costs comparisons only
      // (the fit below costs identity packings about 15 % of their time)
      bool flat = true;
      for(const int* jp = lists_.begin(i); jp != lists_.end(i) && flat; ++jp) {
        const Sym3& mj = hot_[*jp].m;
        flat = mj.a00 == bi.m.a00 && mj.a01 == bi.m.a01 && mj.a02 == bi.m.a02 && mj.a11 == bi.m.a11 &&
               mj.a12 == bi.m.a12 && mj.a22 == bi.m.a22;
      }
      if(flat)
        return;
      Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
      Eigen::Matrix<double, 3, 6> B = Eigen::Matrix<double, 3, 6>::Zero();
      const Vec6 mi = entries(bi.m);
      for(const int* jp = lists_.begin(i); jp != lists_.end(i); ++jp) {
        const Hot_bubble& bj = hot_[*jp];
        const Vec3 d = bj.x - bi.x;
        A += d * d.transpose();
        B += d * (entries(bj.m) - mi).transpose();
      }
      flat_[i] = B.isZero(0) ? 1 : 0;
      const double trace = A.trace();
      if(!(trace > 0) || flat_[i])
        return;
      // Fit only along the entity's own directions: the `dimension` largest
      // spreads of the neighbours (the tangent of a curve, the plane of a
      // patch). Across a curve or patch the neighbours spread by its
      // curvature only, and a regularised solve there returns slopes amplified
      // by up to 1/(1e-3 trace): garbage that M_i^-1 carries into the
      // tangential motion (it cost the elephant's closed feature curves a
      // bubble). The constraint removes the normal part of the motion anyway.
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
      eig.computeDirect(A);
      const int rank = std::min(3, std::max(1, b_[i].dimension));
      Eigen::Matrix<double, 3, 6> X = Eigen::Matrix<double, 3, 6>::Zero();
      for(int e = 3 - rank; e < 3; ++e) { // eigenvalues in increasing order
        const Eigen::Vector3d v = eig.eigenvectors().col(e);
        X += (v / (eig.eigenvalues()(e) + 1e-3 * trace)) * (v.transpose() * B);
      }
      for(int k = 0; k < 3; ++k) {
        Sym3& g = grad_[i][k];
        g.a00 = X(k, 0);
        g.a01 = X(k, 1);
        g.a02 = X(k, 2);
        g.a11 = X(k, 3);
        g.a12 = X(k, 4);
        g.a22 = X(k, 5);
      }
    });
  }

  // One iteration: forces (Jacobi, every bubble from the same positions),
  // then the constrained moves. Returns the largest step.
  double step()
  {
    exec_.for_each(b_.size(), [&](std::size_t i) {
      if(!hot_[i].fixed)
        displacement_[i] = displacement_of(i);
    });
    return move_bubbles();
  }

  // The step bubble i takes this iteration (also records its overlap and its
  // nearest neighbour for the population control).
  Vec3 displacement_of(std::size_t i)
  {
    const double cut = force_.cutoff();
    const double cut2 = cut * cut;
    const Hot_bubble& bi = hot_[i];
    // The force is minus the gradient of the pair potentials (phi' = -f) of
    // w(a, b) with respect to x_i, turned into a displacement by M_i^-1:
    //   F_i = -f(w) (dw/da (d - M_i^-1 q / 2) / a + dw/db M_i^-1 M_j d / b),
    // q_k = d^T (dM_i/dx_k) d: the metric's own variation as bubble i moves.
    // For a constant metric this is -f(w) d / a (the paper's force along the
    // segment, in metric units). Without q (metrics frozen), the pair force
    // points along the chord, whereas in a graded metric the shortest path
    // (the geodesic) bends toward the coarse side: the neighbours of a
    // metric-uniform packing then do not balance (repulsion pushes toward
    // the coarse side, attraction toward the fine side, by about
    // f * |grad log h| / 2 per pair), a body force that the second shell's
    // attraction turns into a steady creep toward the fine end. q restores
    // the geodesic direction to first order (see doc/design.md).
    // f: the d / a terms, g: the covector terms (mapped by M_i^-1 at the end).
    Vec3 f = Vec3::Zero(), g = Vec3::Zero();
    const std::array<Sym3, 3>* G = (use_gradient_ && !flat_[i]) ? &grad_[i] : nullptr;
    const bool volume = b_[i].dimension == 3;
    double overlap = 0;
    double nearest = cut;
    // stiffness of i's pairs: sum |f'(w)| |grad_i w|^2 (gradient in M_i),
    // and what it would be in a constant metric (|grad_i w| = 1); equal
    // where every neighbour has i's metric (flat), so only measured elsewhere
    const bool measure_stiffness = !flat_[i];
    double stiffness = 0, constant_metric_stiffness = 0;
    for(const int* jp = lists_.begin(i); jp != lists_.end(i); ++jp) {
      const Hot_bubble& bj = hot_[*jp];
      // full force law with fixed bubbles and its own entity; repulsion only otherwise
      const bool pulls = bj.fixed || bj.entity == bi.entity;
      const Vec3 d = bj.x - bi.x;
      const double a2 = bi.m.squared_length(d);
      const Vec3 mjd = bj.m * d;
      const double b2 = d.dot(mjd);
      if(a2 >= cut2 && b2 >= cut2)
        continue;
      const double a = std::sqrt(a2), b = std::sqrt(b2);
      const double w = distance_(a, b);
      if(w >= cut)
        continue;
      overlap += std::max(0.0, 1 - w);
      nearest = std::min(nearest, w);
      if(!pulls && w >= 1)
        continue;
      const double fw = force_(w);
      if(a > 0 && b > 0) {
        // w = 2ab / (a + b): dw/da = 2 b^2 / (a + b)^2, dw/db = 2 a^2 / (a + b)^2
        const double k = 2 * fw / ((a + b) * (a + b));
        f -= (k * b * b / a) * d;
        g -= (k * a * a / b) * mjd;
        if(measure_stiffness) {
          const double slope = std::abs(force_(w + 1e-4) - force_(std::max(0.0, w - 1e-4))) / 2e-4;
          const Vec3 grad_w = (2 * b * b / ((a + b) * (a + b) * a)) * d +
                              (2 * a * a / ((a + b) * (a + b) * b)) * (minv_[i] * mjd);
          stiffness += slope * bi.m.squared_length(grad_w);
          constant_metric_stiffness += slope;
        }
        if(G) {
          // The first-order correction holds while the metric changes
          // little across the pair. Where it changes by a large factor (a
          // fine surface metric next to a coarse interior) the secant slope
          // times |d|^2 outgrows the pair force itself and the bubble
          // swings at the step cap without end (the armadillo's volume
          // with a surface distance bound: half its bubbles at the cap for
          // 300 iterations). So the correction is at most half the pair's
          // own push (both in the metric of i: q M_i^-1 q / 4 a^2 against 1).
          // On patches the bound is twice as loose: for an isotropic size h
          // the ratio is about a |grad h|, so a surface field graded by 0.5
          // already reaches 0.5 there, and that cut left a gap in a
          // cylinder's wall that the boundary front bridged 0.27 off the
          // surface. Unbounded, a patch crossing a boundary layer (a side
          // wall where the normal size grows by 1-4 per unit length) swings
          // at the step cap for the whole stage.
          const Vec3 q((*G)[0].squared_length(d), (*G)[1].squared_length(d), (*G)[2].squared_length(d));
          const double relative = 0.5 * std::sqrt(std::max(0.0, q.dot(minv_[i] * q))) / a;
          const double bound = volume ? maximum_relative_correction : maximum_relative_correction_on_patches;
          const double damp = relative > bound ? bound / relative : 1.0;
          g += (0.5 * damp * k * b * b / a) * q;
        }
      } else {
        // coincident centres: a deterministic push, opposite for the pair
        Vec3 e(1, 0.5, 0.25);
        e /= bi.m.length(e);
        f += (std::size_t(*jp) > i ? -fw : fw) * e;
      }
    }
    f += minv_[i] * g;
    // The integrator's step is stable for the stiffness of a constant
    // metric. Where the metrics of i and its neighbours differ by a large
    // factor (a boundary layer), w = 2ab / (a + b) follows the smaller of
    // the two lengths with up to twice the slope, and M_i^-1 M_j amplifies
    // the neighbour's term: the stiffness grows several times and the
    // packing swings with a growing amplitude instead of settling (the
    // elephant with a 1:10 layer: median step 0.01 -> 0.05 over 300
    // iterations). Scaling i's force to the constant-metric stiffness keeps
    // every equilibrium and restores the stable step.
    if(stiffness > constant_metric_stiffness * (1 + 1e-9))
      f *= constant_metric_stiffness / stiffness;
    overlap_[i] = overlap;
    nearest_[i] = nearest;
    if(!flat_[i]) // a constant metric keeps the step the integrator was chosen for
      f *= b_[i].step_scale;
    Vec3 delta = integrate_(b_[i].v, f);
    const double len = bi.m.length(delta);
    const double max_step = traits_.maximum_step();
    if(len > max_step)
      delta *= max_step / len;
    return delta;
  }

  // Moves every free bubble by its displacement under its constraint, adapts
  // the step scales and flags a rebuild of the neighbour lists. Returns the
  // largest step (in the bubbles' metrics, unscaled).
  double move_bubbles()
  {
    const std::size_t n = b_.size();
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
        const Vec3 previous = bi.v;
        bi.v = bi.x - old;
        hot_[i].x = bi.x;
        // convergence is judged on the step the unscaled force would make: a
        // bubble held back by its step scale has not settled
        mx = std::max(mx, bi.m.length(bi.v) / (flat_[i] ? 1.0 : bi.step_scale));
        if(window_steps_ > 0)
          window_sum_[i] += bi.v;
        // where the metric varies, a bubble whose step reverses swings about
        // its equilibrium faster than the damping removes it: its force is
        // scaled down until it does not, and recovers by 5 % a step (the
        // equilibria do not change)
        if(!flat_[i]) {
          if(bi.v.dot(bi.m * previous) < 0)
            bi.step_scale = std::max(minimum_step_scale, 0.7 * bi.step_scale);
          else
            bi.step_scale = std::min(1.0, 1.05 * bi.step_scale);
        }
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

  /// Where the metric changes sharply (a 1:100 layer on a curved wall), the
  /// packing can settle into a slow steady creep instead of converging: on
  /// the UGAWG polar-1 volume, from its 100th iteration to its cap of 400,
  /// the bubbles' mean step per iteration kept a median of 0.003 and a 99th
  /// percentile of 0.012 - 0.019 metric units while the largest step stayed
  /// above the tolerance. Those 300 iterations took 70 % of the stage's time
  /// and did not give a better mesh (stopped at 120: mean-ratio p01 0.21
  /// against 0.18, edges in range 91.3 % against 90.8 %). Settled: over
  /// windows of 10 iterations, the 99th percentile of the bubbles' mean step
  /// is below the tolerance and no lower than 0.9 times the lower of the
  /// two windows before it (no longer decreasing). A packing that still
  /// converges lowers it by more than that and goes on.
  bool window_settled(Relaxation_result& result)
  {
    constexpr int window = 10;
    const std::size_t n = b_.size();
    if(window_steps_ == 0) { // a window starts with the next step
      window_sum_.assign(n, Vec3::Zero());
      window_steps_ = 1;
      return false;
    }
    if(++window_steps_ <= window)
      return false;
    window_steps_ = 0;
    mean_steps_.clear();
    for(std::size_t i = 0; i < n; ++i)
      if(!b_[i].fixed)
        mean_steps_.push_back(b_[i].m.length(window_sum_[i]) / window);
    if(mean_steps_.empty())
      return false;
    const std::size_t k = std::min(mean_steps_.size() - 1, std::size_t(0.99 * double(mean_steps_.size())));
    std::nth_element(mean_steps_.begin(), mean_steps_.begin() + std::ptrdiff_t(k), mean_steps_.end());
    const double p99 = mean_steps_[k];
    const double previous = std::min(window_p99_[0], window_p99_[1]);
    window_p99_[1] = window_p99_[0];
    window_p99_[0] = p99;
    if(!(p99 < settings_.tolerance && p99 >= 0.9 * previous))
      return false;
    result.settled = true;
    result.still_moving = std::size_t(
        std::count_if(mean_steps_.begin(), mean_steps_.end(), [&](double v) { return v >= settings_.tolerance; }));
    return true;
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

  Neighbour_lists lists_, wide_;
  std::vector<double> overlap_, nearest_, block_max_;
  std::vector<char> has_row_, block_flag_, dead_;
  std::vector<Vec3> anchor_, displacement_;
  std::vector<Hot_bubble> hot_;
  std::vector<Sym3> minv_; // M_i^-1
  std::vector<std::array<Sym3, 3>> grad_; // dM/dx_k at moving bubbles
  std::vector<char> flat_;                 // 1: the metric is the same at all listed neighbours (grad_ = 0)
  bool use_gradient_ = uses_metric_gradient(traits_);
  // 0.5: the armadillo case above still swings at 0.7 and 1; the UGAWG
  // linear cube is unchanged
  static constexpr double maximum_relative_correction = 0.5;
  // 1: the 1:10 boundary-layer box of the packer tests converges on its side
  // walls in 39-45 iterations instead of 400 (bound 2: 95; 0.5: 39); the
  // UGAWG linear cube keeps its quality (worst mean ratio 0.574 -> 0.588)
  static constexpr double maximum_relative_correction_on_patches = 1.0;
  static constexpr double minimum_step_scale = 1.0 / 16;
  bool needs_rebuild_ = false;
  std::size_t rebuilds_ = 0;
  int window_steps_ = 0;          // 1 + the steps summed in window_sum_; 0: no window open
  std::vector<Vec3> window_sum_;  // per bubble, the sum of its steps in the window
  std::vector<double> mean_steps_;
  std::array<double, 2> window_p99_{{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()}};
};

} // namespace packing
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_DYNAMICS_H
