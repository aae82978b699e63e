// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_PACKER_3_H
#define CGAL_BUBBLE_PACKER_3_H

#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/internal/packing/bubble.h>
#include <CGAL/Bubble_mesh_3/internal/packing/curve_packing.h>
#include <CGAL/Bubble_mesh_3/internal/packing/domain_oracle.h>
#include <CGAL/Bubble_mesh_3/internal/packing/dynamics.h>
#include <CGAL/Bubble_mesh_3/internal/packing/neighbour_search.h>
#include <CGAL/Bubble_mesh_3/internal/packing/parallel.h>
#include <CGAL/Bubble_mesh_3/internal/packing/surface_packing.h>
#include <CGAL/Bubble_mesh_3/internal/packing/volume_packing.h>
#include <CGAL/Bubble_mesh_3/parameters.h>
#include <CGAL/Bubble_packer_traits_3.h>

#include <CGAL/Default.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <vector>

namespace CGAL {

/// \ingroup PkgBubbleMesh3Classes
/// Ellipsoidal bubble packing (Yamakawa and Shimada, sections 3 and 4): node
/// positions for an anisotropic tetrahedral mesh of a domain, spaced by metric
/// length 1 in the metric field.
///
/// <b>Convention.</b> The mesh edge target is metric length 1, so a bubble is
/// the metric ball of radius 1/2 around its centre and two bubbles are at rest
/// when their centres are at metric distance 1 (see `Bubble_packer_traits_3`
/// for the neutral length of two different metrics). An ideal (face-centred
/// cubic) packing has sqrt(2) nodes per unit metric volume, a hexagonal surface
/// packing 2/sqrt(3) nodes per unit metric area, a curve one node per unit
/// metric length; the initial populations use these densities locally.
///
/// <b>Stages</b>, in the paper's order, each a method: `pack_corners()` fixes a
/// bubble on every corner; `pack_curves()` packs every feature curve (bubbles
/// move along their curve, ends fixed); `pack_surfaces()` packs every surface
/// patch (motion in the tangent plane, projection back onto the same patch,
/// curve bubbles fixed); `pack_volume()` packs the interior (boundary bubbles
/// fixed; a bubble never leaves its subdomain). Each stage runs the damped
/// dynamics with adaptive population control (deletion of over-lapped
/// bubbles, insertion in gaps) until a round changes nothing, then to
/// convergence: the largest displacement of one iteration, in metric units, is
/// below `Parameters::tolerance`; or until it has settled (a few bubbles
/// still creeping where the metric varies sharply, see
/// `Stage_statistics::settled`); or until `Parameters::maximum_iterations`.
/// `run()` calls the four stages.
///
/// <b>Threads and determinism.</b> With TBB (`CGAL_LINKED_WITH_TBB`), forces,
/// moves, metric evaluations and neighbour searches run in parallel on
/// `Parameters::number_of_threads` threads. Forces are summed over each bubble's
/// neighbours in a fixed order and population control is serial, so the result
/// is bit-identical for any number of threads.
///
/// <b>Neighbour search.</b> Verlet lists over a multi-level grid whose cells
/// follow the bubbles' reach ellipsoids axis by axis (metric reach 1.5 +
/// `Parameters::skin`), so sizes varying by orders of magnitude and stretched
/// bubbles cost about the same; the interaction itself is decided in the
/// metric (w = l / l0 < 1.5).
///
/// <b>End of a stage.</b> After the dynamics, one bubble of every pair closer
/// than the traits' minimum distance is deleted and the gaps are filled again,
/// without moving any bubble, until nothing changes.
///
/// \tparam MeshDomain a model of `MeshDomainWithFeatures_3`:
///   `CGAL::Polyhedral_mesh_domain_with_features_3` (call `detect_features()`
///   first; its faces are the patches), or any other model such as
///   `CGAL::Mesh_domain_with_polyline_features_3<CGAL::Labeled_mesh_domain_3<K>>`
///   (an implicit function with the feature curves given by the user through
///   `add_features()`), whose patches are triangulated on a grid from its inside
///   test (`Parameters::surface_grid_resolution`) to guide the surface stage;
///   the surface nodes are then moved onto the exact surface (bisection with
///   the inside test). On such a domain a patch that a feature curve crosses
///   (a labelled domain has one patch per pair of labels) is packed as one
///   patch: its bubbles may slide across the curve, which they only meet as
///   fixed curve bubbles.
/// \tparam MetricField a model of `MetricField_3` (evaluated concurrently).
/// \tparam Traits_ a model of `BubblePackerTraits_3`; default
///   `Bubble_packer_traits_3<MetricField::Kernel>`.
///
/// Errors: a metric field value that is not SPD throws
/// `Bubble_mesh_3::Invalid_metric` (from the field); an estimated number of
/// bubbles (`estimated_number_of_bubbles()`, computed by the first stage before
/// any packing) above `Parameters::maximum_number_of_bubbles` throws
/// `Bubble_mesh_3::Too_many_nodes` before any memory is used for them;
/// `Parameters::should_stop` returning true throws `Bubble_mesh_3::Interrupted`.
template <typename MeshDomain, typename MetricField, typename Traits_ = Default>
class Bubble_packer_3 {
public:
  typedef MeshDomain Mesh_domain;
  typedef MetricField Metric_field;
  typedef typename Metric_field::Kernel Kernel;
  typedef typename Default::Get<Traits_, Bubble_packer_traits_3<Kernel>>::type Traits;
  typedef typename Kernel::FT FT;
  typedef typename Kernel::Point_3 Point_3;
  typedef typename Mesh_domain::Index Index;

  /// A packed node.
  struct Node {
    Point_3 point;
    int dimension;  ///< 0 corner, 1 curve, 2 surface patch, 3 interior
    Index index;    ///< the domain's index of the corner, curve, patch or subdomain
  };

  /// Settings of the packing (the physics is in the traits).
  struct Parameters {
    int maximum_iterations = 400;   ///< iteration cap per stage
    double tolerance = 0.02;        ///< convergence: largest step of an iteration, metric units
    unsigned int seed = 0;          ///< seeds the lattice offsets of the initial populations
    int number_of_threads = 0;      ///< 0: all available (TBB); 1: serial
    /// refuse larger estimates (`Bubble_mesh_3::Too_many_nodes`)
    double maximum_number_of_bubbles = Bubble_mesh_3::default_maximum_number_of_nodes;
    double skin = 0.2;              ///< Verlet list margin, in bubble sizes
    bool population_control = true; ///< adaptive insertion and deletion
    std::size_t curve_samples = 2048; ///< arc-length table size per feature curve
    /// domains without a polyhedral surface (e.g. `Labeled_mesh_domain_3`): cells
    /// along the longest side of the bounding box of the grid on which their
    /// surface patches are triangulated (a guide for the surface stage; the
    /// surface nodes end on the domain's exact surface)
    int surface_grid_resolution = 64;
    /// polled once per iteration of every stage (from the calling thread):
    /// when it returns true the packing throws `Bubble_mesh_3::Interrupted`
    std::function<bool()> should_stop;
  };

  /// What happened in one stage.
  struct Stage_statistics {
    std::size_t bubbles = 0;        ///< bubbles of that dimension at the end
    double expected_bubbles = 0;    ///< the initial estimate (density times metric measure)
    std::size_t seeded = 0;         ///< the initial population after clean-up
    int iterations = 0;
    bool converged = false;         ///< the largest step of an iteration fell below `Parameters::tolerance`
    /// stopped because the packing had settled: over windows of 10 iterations
    /// the 99th percentile of the bubbles' mean steps was below the tolerance
    /// and no longer decreasing (a sharply varying metric can leave a slow
    /// creep that more iterations do not improve)
    bool settled = false;
    std::size_t still_moving = 0;   ///< when settled: bubbles whose mean step was above the tolerance
    double last_maximum_displacement = 0;
    std::size_t inserted = 0;
    std::size_t deleted = 0;
    int population_rounds = 0;
    std::size_t neighbour_rebuilds = 0; ///< neighbour list constructions
    double seconds = 0;
  };

  /// Packing statistics: per stage (index = dimension) and the distribution of
  /// the nearest-neighbour normalized distance w over all nodes.
  struct Statistics {
    std::array<Stage_statistics, 4> stages;
    double nearest_min = 0, nearest_mean = 0, nearest_max = 0;
    double nearest_p05 = 0, nearest_p50 = 0, nearest_p95 = 0;
  };

  Bubble_packer_3(const Mesh_domain& domain, const Metric_field& field, const Parameters& parameters = Parameters(),
                  const Traits& traits = Traits())
      : domain_(domain), field_(field), param_(parameters), traits_(traits), refresh_(field),
        exec_(parameters.number_of_threads)
  {
    auto patches = Bubble_mesh_3::internal::packing::patches_of_domain(domain, parameters.surface_grid_resolution);
    oracle_ = std::make_unique<Oracle>(domain, parameters.curve_samples, std::move(patches.first), patches.second);
    const CGAL::Bbox_3 bb = domain.bbox();
    lo_ = Vec3(bb.xmin(), bb.ymin(), bb.zmin());
    hi_ = Vec3(bb.xmax(), bb.ymax(), bb.zmax());
    std::mt19937 gen(parameters.seed);
    for(int d = 0; d < 3; ++d)
      offset_[d] = Bubble_mesh_3::internal::packing::uniform_01(gen);
  }

  /// The expected total number of nodes, computed once before any packing
  /// (every stage starts with it): the corners, the metric length of the
  /// curves (one node per unit), the metric area of the patches times 2/sqrt(3)
  /// (hexagonal packing) and sqrt(2) times the metric volume of the domain
  /// (face-centred cubic packing; the volume is integrated over an octree,
  /// cells crossing the boundary by sampling). Throws
  /// `Bubble_mesh_3::Too_many_nodes` when it exceeds
  /// `Parameters::maximum_number_of_bubbles` (the integration stops early then).
  double estimated_number_of_bubbles()
  {
    if(estimate_ < 0) {
      namespace P = Bubble_mesh_3::internal::packing;
      const double limit = param_.maximum_number_of_bubbles;
      double total = double(oracle_->corners().size()) + P::curve_metric_length(*oracle_, refresh_);
      check_estimate(total);
      std::vector<Record> none;
      P::Patch_seeder<Oracle, Refresh> surfaces(*oracle_, refresh_, lo_, offset_, limit - total, none, true);
      total += counted_from(total, [&] { return surfaces.run(); });
      check_estimate(total);
      P::Volume_estimator<Oracle, Refresh> volume(*oracle_, refresh_, metric_samples(), limit - total);
      volume_estimate_ = volume.run(lo_, hi_);
      total += volume_estimate_;
      check_estimate(total);
      estimate_ = total;
    }
    return estimate_;
  }

  /// runs the four stages
  void run()
  {
    pack_corners();
    pack_curves();
    pack_surfaces();
    pack_volume();
  }

  /// one fixed bubble on every corner
  void pack_corners()
  {
    estimated_number_of_bubbles();
    const auto t0 = std::chrono::steady_clock::now();
    for(std::size_t k = 0; k < oracle_->corners().size(); ++k) {
      Record r;
      r.dimension = 0;
      r.entity = static_cast<int>(k);
      r.x = Bubble_mesh_3::internal::packing::to_vec<Kernel>(oracle_->corners()[k].point);
      r.fixed = true;
      refresh_(r);
      bubbles_.push_back(r);
    }
    Stage_statistics& s = stats_.stages[0];
    s.bubbles = s.seeded = oracle_->corners().size();
    s.expected_bubbles = double(s.bubbles);
    s.converged = true;
    s.seconds = seconds_since(t0);
  }

  /// 1D packing of every feature curve
  void pack_curves()
  {
    estimated_number_of_bubbles();
    const auto t0 = std::chrono::steady_clock::now();
    Stage_statistics& s = stats_.stages[1];
    const std::size_t first = bubbles_.size();
    s.expected_bubbles = Bubble_mesh_3::internal::packing::seed_curves(*oracle_, refresh_, bubbles_);
    check_limit(s.expected_bubbles);
    s.seeded = bubbles_.size() - first;
    Bubble_mesh_3::internal::packing::Curve_constraint<Oracle> constraint(*oracle_);
    relax(constraint, s, 0.0);
    // exact positions on the domain's curves
    exec_.for_each(bubbles_.size(), [&](std::size_t i) {
      Record& b = bubbles_[i];
      if(b.fixed)
        return;
      b.x = Bubble_mesh_3::internal::packing::to_vec<Kernel>(oracle_->exact_curve_point(b.entity, b.s));
      refresh_(b);
    });
    finish_stage(1, s, t0);
  }

  /// 2D packing of every surface patch
  void pack_surfaces()
  {
    estimated_number_of_bubbles();
    const auto t0 = std::chrono::steady_clock::now();
    Stage_statistics& s = stats_.stages[2];
    const std::size_t first = bubbles_.size();
    Bubble_mesh_3::internal::packing::Patch_seeder<Oracle, Refresh> seeder(*oracle_, refresh_, lo_, offset_,
                                                                           remaining_limit(), bubbles_);
    Bubble_mesh_3::internal::packing::Surface_constraint<Oracle> constraint(*oracle_);
    s.expected_bubbles = counted_from(double(first), [&] { return seeder.run(); });
    s.seeded = bubbles_.size() - first;
    relax(constraint, s, 0.5);
    if(oracle_->surface_tolerance() > 0) {
      // the patches were a triangulated guide: onto the exact surface, along the guide's normal
      exec_.for_each(bubbles_.size(), [&](std::size_t i) {
        Record& b = bubbles_[i];
        if(b.fixed)
          return;
        b.x = oracle_->exact_surface_point(b.x, b.n);
        refresh_(b);
      });
    }
    finish_stage(2, s, t0);
  }

  /// 3D packing of the interior
  void pack_volume()
  {
    estimated_number_of_bubbles();
    const auto t0 = std::chrono::steady_clock::now();
    Stage_statistics& s = stats_.stages[3];
    const std::size_t first = bubbles_.size();
    Bubble_mesh_3::internal::packing::Volume_seeder<Oracle, Refresh> seeder(*oracle_, refresh_, metric_samples(), lo_,
                                                                            offset_, remaining_limit(), bubbles_);
    counted_from(double(first), [&] { return seeder.run(lo_, hi_); });
    s.expected_bubbles = volume_estimate_;
    s.seeded = bubbles_.size() - first;
    Bubble_mesh_3::internal::packing::Volume_constraint<Oracle> constraint(*oracle_);
    relax(constraint, s, 0.6);
    finish_stage(3, s, t0);
  }

  /// the nodes packed so far, in a deterministic order (stage by stage)
  std::vector<Node> nodes() const
  {
    std::vector<Node> out;
    out.reserve(bubbles_.size());
    for(const Record& b : bubbles_)
      out.push_back(Node{Point_3(b.x[0], b.x[1], b.x[2]), b.dimension, index_of(b)});
    return out;
  }

  std::size_t number_of_nodes() const { return bubbles_.size(); }

  /// statistics of the stages run so far; the nearest-neighbour distribution
  /// is computed by `compute_nearest_neighbour_statistics()` (called by `run()`'s last stage)
  const Statistics& statistics() const { return stats_; }

  /// fills the nearest-neighbour distribution of the statistics: for every node,
  /// the smallest normalized distance w to another node (capped at 1.5)
  void compute_nearest_neighbour_statistics()
  {
    const std::size_t n = bubbles_.size();
    if(n < 2)
      return;
    std::vector<char> row(n, 1);
    Bubble_mesh_3::internal::packing::Neighbour_lists lists;
    // (the two sides of a thin part do not count as neighbours: see on_opposite_sides)
    lists.build(bubbles_, row, 1.5, exec_, [this](int i, int j) {
      return Bubble_mesh_3::internal::packing::on_opposite_sides(bubbles_[std::size_t(i)], bubbles_[std::size_t(j)]);
    });
    std::vector<double> nearest(n, 1.5);
    exec_.for_each(n, [&](std::size_t i) {
      for(const int* j = lists.begin(i); j != lists.end(i); ++j)
        nearest[i] = std::min(nearest[i], Bubble_mesh_3::internal::packing::normalized_distance_to(
                                              bubbles_[i].x, bubbles_[i].m, bubbles_[*j]));
    });
    std::sort(nearest.begin(), nearest.end());
    double sum = 0;
    for(double d : nearest)
      sum += d;
    stats_.nearest_min = nearest.front();
    stats_.nearest_max = nearest.back();
    stats_.nearest_mean = sum / double(n);
    stats_.nearest_p05 = nearest[std::size_t(0.05 * double(n - 1))];
    stats_.nearest_p50 = nearest[std::size_t(0.50 * double(n - 1))];
    stats_.nearest_p95 = nearest[std::size_t(0.95 * double(n - 1))];
  }

  const Parameters& parameters() const { return param_; }
  const Traits& traits() const { return traits_; }

private:
  typedef Bubble_mesh_3::internal::packing::Vec3 Vec3;
  typedef Bubble_mesh_3::internal::packing::Bubble_record Record;
  typedef Bubble_mesh_3::internal::packing::Domain_oracle<Mesh_domain> Oracle;
  typedef Bubble_mesh_3::internal::packing::Metric_refresh<Metric_field> Refresh;

  /// where the field was given (see metric_samples.h), computed once
  const Bubble_mesh_3::internal::packing::Metric_samples& metric_samples()
  {
    namespace P = Bubble_mesh_3::internal::packing;
    if(!samples_) {
      std::vector<Vec3> points;
      P::append_metric_sample_points(field_, points);
      samples_ = std::make_unique<P::Metric_samples>(std::move(points), refresh_);
    }
    return *samples_;
  }

  static double seconds_since(std::chrono::steady_clock::time_point t0)
  {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  double remaining_limit() const { return param_.maximum_number_of_bubbles - double(bubbles_.size()); }

  void check_estimate(double total) const
  {
    if(total > param_.maximum_number_of_bubbles)
      throw Bubble_mesh_3::Too_many_nodes(total, param_.maximum_number_of_bubbles);
  }

  // runs a seeder that was given the cap left after `before` bubbles; its
  // refusal counts only its own, the caller's names the whole estimate
  template <typename Run>
  auto counted_from(double before, const Run& run) const
  {
    try {
      return run();
    } catch(const Bubble_mesh_3::Too_many_nodes& e) {
      throw Bubble_mesh_3::Too_many_nodes(before + e.estimated(), param_.maximum_number_of_bubbles);
    }
  }

  void check_limit(double expected) const
  {
    if(expected > remaining_limit())
      throw Bubble_mesh_3::Too_many_nodes(double(bubbles_.size()) + expected, param_.maximum_number_of_bubbles);
  }

  template <typename Constraint>
  void relax(const Constraint& constraint, Stage_statistics& s, double thin)
  {
    Bubble_mesh_3::internal::packing::Relaxation_settings rs;
    rs.maximum_iterations = param_.maximum_iterations;
    rs.tolerance = param_.tolerance;
    rs.skin = param_.skin;
    rs.population_control = param_.population_control;
    rs.should_stop = param_.should_stop;
    Bubble_mesh_3::internal::packing::Relaxation<Traits, Constraint, Refresh> relaxation(bubbles_, traits_, constraint,
                                                                                       refresh_, exec_, rs);
    if(thin > 0)
      s.seeded -= relaxation.thin_out(thin);
    const auto r = relaxation.run();
    s.iterations = r.iterations;
    s.converged = r.converged;
    s.settled = r.settled;
    s.still_moving = r.still_moving;
    s.last_maximum_displacement = r.last_maximum_displacement;
    s.inserted = r.inserted;
    s.deleted = r.deleted;
    s.population_rounds = r.population_rounds;
    s.neighbour_rebuilds = r.neighbour_rebuilds;
  }

  void finish_stage(int dimension, Stage_statistics& s, std::chrono::steady_clock::time_point t0)
  {
    std::size_t count = 0;
    for(Record& b : bubbles_) {
      b.fixed = true;
      b.v = Vec3::Zero();
      if(b.dimension == dimension)
        ++count;
    }
    s.bubbles = count;
    if(dimension == 3)
      compute_nearest_neighbour_statistics();
    s.seconds = seconds_since(t0);
  }

  Index index_of(const Record& b) const
  {
    switch(b.dimension) {
    case 0:
      return domain_.index_from_corner_index(oracle_->corners()[b.entity].index);
    case 1:
      return domain_.index_from_curve_index(oracle_->curves()[b.entity].index);
    case 2:
      return domain_.index_from_surface_patch_index(oracle_->patches()[b.entity].index);
    default:
      return domain_.index_from_subdomain_index(typename Mesh_domain::Subdomain_index(b.entity));
    }
  }

  const Mesh_domain& domain_;
  const Metric_field& field_;
  Parameters param_;
  Traits traits_;
  Refresh refresh_;
  Bubble_mesh_3::internal::packing::Parallel_executor exec_;
  std::unique_ptr<Oracle> oracle_;
  std::unique_ptr<Bubble_mesh_3::internal::packing::Metric_samples> samples_;
  std::vector<Record> bubbles_;
  Statistics stats_;
  Vec3 lo_, hi_, offset_;
  double estimate_ = -1, volume_estimate_ = 0;
};

} // namespace CGAL

#endif // CGAL_BUBBLE_PACKER_3_H
