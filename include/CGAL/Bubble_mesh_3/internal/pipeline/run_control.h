// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_RUN_CONTROL_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_RUN_CONTROL_H

// The settings of a run of `make_anisotropic_mesh_3()` (resolved once from
// the named parameters) and the one mechanism through which every stage
// reports progress and honours stop requests: `Run_control`.

#include <CGAL/Bubble_mesh_3/Meshing_report.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/parameters.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <utility>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

inline double seconds_since(std::chrono::steady_clock::time_point t0)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The settings resolved from the named parameters.
struct Meshing_settings {
  unsigned int seed = 0;
  int threads = 0;
  int iterations = 400;
  double maximum_bubbles = default_maximum_number_of_nodes;
  double time_limit = std::numeric_limits<double>::infinity();
  std::function<bool()> should_stop;
  /// CGAL's `callback`: the advancement in [0, 1]; false stops the run
  std::function<bool(double)> callback;
  bool allow_steiner = true;
  /// the stage messages and the final summary to `std::cerr` (unless
  /// `progress` takes the messages)
  bool verbose = false;
  bool improve = true;
  double improve_time_limit = std::numeric_limits<double>::infinity();
  std::function<void(const std::string&)> progress;
  Meshing_report* report = nullptr;
  /// the surface-approximation bound: 0 or infinite for none (the default),
  /// negative for a fraction of the bounding box diagonal
  double surface_distance = 0;
  /// refine the metric where corners and curves are closer than its sizes
  bool small_feature_refinement = true;
  /// reduce the large sizes where the metric's frame turns too fast for them
  bool realizable_metric = true;
};

template <typename NP>
Meshing_settings resolve_settings(const NP& np)
{
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  namespace BNP = Bubble_mesh_3::internal_np;
  const double infinity = std::numeric_limits<double>::infinity();
  Meshing_settings s;
  s.seed = choose_parameter(get_parameter(np, CGAL::internal_np::random_seed), 0u);
  s.threads = choose_parameter(get_parameter(np, BNP::number_of_threads), 0);
  s.iterations = choose_parameter(get_parameter(np, CGAL::internal_np::number_of_iterations), 400);
  s.maximum_bubbles = choose_parameter(get_parameter(np, BNP::maximum_number_of_bubbles),
                                       default_maximum_number_of_nodes);
  s.time_limit = choose_parameter(get_parameter(np, BNP::time_limit), infinity);
  s.should_stop = choose_parameter(get_parameter(np, BNP::should_stop), std::function<bool()>());
  s.callback = choose_parameter(get_parameter(np, CGAL::internal_np::callback), std::function<bool(double)>());
  s.allow_steiner = choose_parameter(get_parameter(np, BNP::allow_steiner_points), true);
  s.verbose = choose_parameter(get_parameter(np, CGAL::internal_np::verbose), false);
  s.improve = choose_parameter(get_parameter(np, BNP::mesh_improvement), true);
  s.improve_time_limit = choose_parameter(get_parameter(np, BNP::improvement_time_limit), infinity);
  s.progress = choose_parameter(get_parameter(np, BNP::progress_messages),
                                std::function<void(const std::string&)>());
  s.report = choose_parameter(get_parameter(np, BNP::meshing_report), static_cast<Meshing_report*>(nullptr));
  s.surface_distance = choose_parameter(get_parameter(np, BNP::surface_distance), 0.0);
  // a NaN would pass every comparison as false: no limit at all, or an
  // automatic one, instead of the number the caller meant
  if(std::isnan(s.surface_distance))
    throw Invalid_input("surface_distance: not a number");
  if(std::isnan(s.time_limit))
    throw Invalid_input("time_limit: not a number");
  if(std::isnan(s.improve_time_limit))
    throw Invalid_input("improvement_time_limit: not a number");
  s.small_feature_refinement = choose_parameter(get_parameter(np, BNP::small_feature_refinement), true);
  s.realizable_metric = choose_parameter(get_parameter(np, BNP::realizable_metric), true);
  return s;
}

/// Progress and stop requests of one run, shared by every stage (copies share
/// the state). A check point (`check()`) throws `Interrupted` once
/// `should_stop` returns true or `callback` returns false, and
/// `Time_limit_exceeded` once the time limit has passed; stages set the
/// advancement that `callback` receives (`advance()`).
class Run_control {
public:
  explicit Run_control(const Meshing_settings& s) : state_(std::make_shared<State>())
  {
    state_->limit = s.time_limit;
    state_->should_stop = s.should_stop;
    state_->callback = s.callback;
    state_->progress = s.progress;
    if(!state_->progress && s.verbose)
      state_->progress = [](const std::string& m) { std::cerr << m << std::endl; };
    state_->start = std::chrono::steady_clock::now();
  }

  /// whether a check point can throw (worth polling often)
  bool active() const
  {
    return bool(state_->should_stop) || bool(state_->callback) ||
           state_->limit < std::numeric_limits<double>::infinity();
  }
  bool has_time_limit() const { return state_->limit < std::numeric_limits<double>::infinity(); }
  /// seconds left before the time limit (infinite without one)
  double remaining() const { return state_->limit - elapsed(); }
  double elapsed() const { return seconds_since(state_->start); }
  std::chrono::steady_clock::time_point start() const { return state_->start; }

  /// a progress message (to `progress_messages`, or `std::cerr` when verbose)
  void say(const std::string& message) const
  {
    if(state_->progress)
      state_->progress(message);
  }
  bool says() const { return bool(state_->progress); }

  /// the fraction of the run done, for `callback` (stages set it as they start)
  void advance(double fraction) const { state_->advancement = fraction; }

  void check(const std::string& stage, bool check_time = true) const
  {
    if(state_->should_stop && state_->should_stop())
      throw Interrupted("interrupted during " + stage);
    if(state_->callback && !state_->callback(state_->advancement))
      throw Interrupted("interrupted during " + stage + " (the callback returned false)");
    if(check_time && has_time_limit() && remaining() < 0) {
      std::ostringstream o;
      o << "time limit of " << state_->limit << " s reached during " << stage;
      throw Time_limit_exceeded(o.str());
    }
  }

  /// the run is complete: `callback` sees 1 (what it returns no longer matters)
  void finish() const
  {
    state_->advancement = 1;
    if(state_->callback)
      state_->callback(1.0);
  }

  /// the check as a stage's `should_stop` (it throws instead of returning true)
  std::function<bool()> poll(const std::string& stage, bool check_time = true) const
  {
    const Run_control self = *this;
    return [self, stage, check_time]() {
      self.check(stage, check_time);
      return false;
    };
  }

private:
  struct State {
    double limit = std::numeric_limits<double>::infinity();
    std::function<bool()> should_stop;
    std::function<bool(double)> callback;
    std::function<void(const std::string&)> progress;
    std::chrono::steady_clock::time_point start;
    double advancement = 0;
  };
  std::shared_ptr<State> state_;
};

/// One run of the pipeline: its settings, its control, and the report it
/// fills (the caller's `meshing_report`, else its own).
struct Pipeline_run {
  template <typename NP>
  explicit Pipeline_run(const NP& np)
      : settings(resolve_settings(np)), control(settings), report(settings.report ? *settings.report : own_report)
  {
    report = Meshing_report();
  }
  Pipeline_run(const Pipeline_run&) = delete;
  Pipeline_run& operator=(const Pipeline_run&) = delete;

  /// the total time, `callback(1)`, and with `verbose` the summary to `std::cerr`
  void finish()
  {
    report.total_seconds = control.elapsed();
    control.finish();
    if(settings.verbose)
      print_meshing_summary(std::cerr, report);
  }

  const Meshing_settings settings;
  const Run_control control;

private:
  Meshing_report own_report;

public:
  Meshing_report& report;
};

// A stage's parameters (the packer's, the front's, the improver's) get the
// check as their `should_stop`; the check throws.
template <typename P>
void install_stop_check(P& parameters, const Run_control& control, const std::string& stage,
                        bool check_time = true)
{
  if(control.active())
    parameters.should_stop = control.poll(stage, check_time);
}

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_RUN_CONTROL_H
