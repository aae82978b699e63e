// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_PACKER_TRAITS_3_H
#define CGAL_BUBBLE_PACKER_TRAITS_3_H

#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>

#include <cmath>
#include <string>

namespace CGAL {

/// \ingroup PkgBubbleMesh3Classes
/// The physics of `Bubble_packer_3`: the paper's inter-bubble force law, the
/// neutral length of a pair of anisotropic bubbles, the damped point-mass
/// integrator and the thresholds of adaptive population control.
///
/// <b>Conventions.</b> A bubble is the metric ball of radius 1/2 around its
/// centre, so two bubbles with the same metric are at rest when their centres
/// are at metric distance 1 (the target edge length of the mesh). For two
/// bubbles i, j at Euclidean distance `l` along `d = x_j - x_i`, the distance
/// from centre i to the boundary of its own bubble along the segment is
/// `l_i = (1/2) l / sqrt(d^T M_i d)`; the neutral length is `l0 = l_i + l_j`
/// and the normalized distance is `w = l / l0 = 2ab/(a+b)`, the harmonic mean
/// of the metric lengths `a = |d|_{M_i}` and `b = |d|_{M_j}`.
///
/// <b>Force.</b> `f(w) = k (1.25 w^3 - 2.375 w^2 + 1.125)` for `0 <= w <= 1.5`,
/// 0 beyond: repulsive below 1, attractive between 1 and 1.5.
///
/// <b>Force direction.</b> The pair force is minus the gradient of the pair
/// energy `phi(w)` (`phi' = -f`) with respect to the bubble's position. For a
/// constant metric it is along the segment between the centres. For a varying
/// metric the default (`metric_gradient_force() == true`) includes the
/// variation of the bubble's own metric as it moves, `d^T (dM_i/dx) d`, which
/// turns the direction from the chord to the (metric) geodesic between the two
/// centres: then a packing that is uniform in the metric is an equilibrium (to
/// first order in the metric's variation across a bubble).
/// With the metrics frozen (`false`, the previous behaviour) the direction is
/// the chord's, and in a graded metric the packing creeps toward the fine end
/// and does not converge (1:10 graded box: 400 iterations without converging
/// against 64 at 10k nodes, see benchmark/Bubble_mesh_3/RESULTS_packer.md).
/// The metric gradient is estimated at each bubble by least squares from its
/// neighbours' metrics, so the metric field is evaluated no more often.
///
/// <b>Dynamics.</b> `m x'' + c x' = f` is integrated by semi-implicit
/// (symplectic) Euler, `v' = (m v + dt f) / (m + c dt)`, `x' = x + dt v'`, with
/// the force of a pair expressed in the metric of the bubble it acts on: bubble
/// i receives `f(w) u` where `u` is the direction from j to i scaled to metric
/// length 1 in `M_i`. The time step is therefore measured in metric units and
/// the same `dt` is stable for bubbles of any size and stretching (this replaces
/// the paper's uniform mass and damping, which cannot handle sizes that vary by
/// orders of magnitude). The displacement per step is `beta * previous + gamma * f`
/// with `beta = m/(m + c dt)` (momentum) and `gamma = dt^2/(m + c dt)`.
/// Time-step rule: the linearised stiffness of one pair is `k |f'(1)| = k`, a
/// bubble has at most about 12 (3D), 6 (2D) or 2 (1D) neighbours, so the
/// highest mode of a packing has stiffness about `2 k n_d / d`; heavy-ball
/// iteration is stable for `gamma * 2 k n_d / d < 2 (1 + beta)`. The defaults
/// (`k = 1`, `m = 1`, `c = 2.5`, `dt = 0.4`: beta = 0.5, gamma = 0.08) keep a
/// safety factor of about 5 in 3D and converge in a few tens of iterations.
/// A step is also capped at `maximum_step()` metric units.
///
/// <b>Population control.</b> A bubble whose overlap `sum_j max(0, 1 - w_ij)`
/// exceeds `overlap_deletion_threshold(dim)` is deleted (the most overlapped
/// first, never two overlapping neighbours in one round, at most
/// `maximum_change_fraction()` of the moving bubbles per round). A point at
/// metric distance `gap_probe_distance()` from a bubble, in one of a fixed set of
/// directions, whose normalized distance to every other bubble is at least
/// `gap_insertion_threshold(dim)` is a gap and gets a new bubble.
///
/// \cgalModels `BubblePackerTraits_3`
/// \tparam K a CGAL kernel (only `K::FT` and `K::Point_3` are used)
template <typename K>
class Bubble_packer_traits_3 {
public:
  typedef K Kernel;
  typedef typename K::FT FT;
  typedef typename K::Point_3 Point_3;
  typedef Bubble_mesh_3::Metric_3 Metric;

  /// the paper's cubic force of normalized distance `w` (positive: repulsive)
  class Compute_interbubble_force {
  public:
    explicit Compute_interbubble_force(double k = 1) : k_(k) {}
    double operator()(double w) const
    {
      if(!(w >= 0) || w > 1.5)
        return 0;
      return k_ * ((1.25 * w - 2.375) * w * w + 1.125);
    }
    /// the largest `w` with a non-zero force
    double cutoff() const { return 1.5; }

  private:
    double k_;
  };

  /// `w = l / l0` from the metric lengths `a = |d|_{M_i}`, `b = |d|_{M_j}` of
  /// the segment between the two centres (see the class documentation)
  class Compute_normalized_distance {
  public:
    double operator()(double a, double b) const { return (a + b > 0) ? 2 * a * b / (a + b) : 0.0; }
  };

  /// one step of the damped dynamics: new displacement from the previous
  /// displacement and the force (any vector type with `+` and scalar `*`)
  class Integrate_step {
  public:
    Integrate_step(double beta, double gamma) : beta_(beta), gamma_(gamma) {}
    template <typename V>
    V operator()(const V& previous_displacement, const V& force) const
    {
      return beta_ * previous_displacement + gamma_ * force;
    }
    double momentum() const { return beta_; }
    double gain() const { return gamma_; }

  private:
    double beta_, gamma_;
  };

  /// `k`, `m`, `c`, `dt`, `metric_gradient_force`: see the class documentation
  explicit Bubble_packer_traits_3(double spring_constant = 1, double mass = 1, double damping = 2.5,
                                  double time_step = 0.4, bool metric_gradient_force = true)
      : k_(spring_constant), m_(mass), c_(damping), dt_(time_step), gradient_(metric_gradient_force)
  {
    if(!(k_ > 0 && m_ >= 0 && c_ >= 0 && dt_ > 0 && m_ + c_ * dt_ > 0))
      throw Bubble_mesh_3::Invalid_input("Bubble_packer_traits_3: need k > 0, m >= 0, c >= 0, dt > 0, m + c dt > 0");
  }

  Compute_interbubble_force compute_interbubble_force_object() const { return Compute_interbubble_force(k_); }
  Compute_normalized_distance compute_normalized_distance_object() const { return Compute_normalized_distance(); }
  Integrate_step integrate_step_object() const
  {
    return Integrate_step(m_ / (m_ + c_ * dt_), dt_ * dt_ / (m_ + c_ * dt_));
  }

  double spring_constant() const { return k_; }
  double mass() const { return m_; }
  double damping() const { return c_; }
  double time_step() const { return dt_; }
  /// whether the force includes the variation of the bubble's own metric with
  /// its position (true: the exact gradient of the pair energies; false: the
  /// metrics frozen, the force along the chord between the centres)
  bool metric_gradient_force() const { return gradient_; }

  /// the largest displacement of one step, in metric units of the bubble
  double maximum_step() const { return 0.25; }

  /// overlap (sum over neighbours of max(0, 1 - w)) above which a bubble on an
  /// entity of dimension `dim` is deleted
  double overlap_deletion_threshold(int dim) const
  {
    return dim == 1 ? 0.7 : (dim == 2 ? 1.0 : 1.4);
  }
  /// a bubble closer than this normalized distance to another one is also deleted
  double minimum_distance_deletion_threshold(int) const { return 0.65; }
  /// the normalized distance to every bubble from which a probe point is a gap
  double gap_insertion_threshold(int dim) const { return dim == 1 ? 0.95 : (dim == 2 ? 0.72 : 0.74); }
  /// metric distance of gap probes from the bubble that probes
  double gap_probe_distance(int dim) const { return dim == 1 ? 1.0 : 0.85; }
  /// population control runs every that many iterations
  int population_control_period() const { return 8; }
  /// at most that many population control rounds per stage
  int maximum_population_rounds() const { return 12; }
  /// the population is stable when a round on a relaxed packing inserts and
  /// deletes together at most that fraction of the moving bubbles
  double population_stability_fraction() const { return 0.005; }
  /// at most that fraction of the moving bubbles is inserted, or deleted, per round
  double maximum_change_fraction() const { return 0.1; }

private:
  double k_, m_, c_, dt_;
  bool gradient_;
};

} // namespace CGAL

#endif // CGAL_BUBBLE_PACKER_TRAITS_3_H
