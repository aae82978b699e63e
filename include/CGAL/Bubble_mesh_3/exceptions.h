// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_EXCEPTIONS_H
#define CGAL_BUBBLE_MESH_3_EXCEPTIONS_H

#include <stdexcept>
#include <string>

namespace CGAL {
namespace Bubble_mesh_3 {

/// \ingroup PkgBubbleMesh3Ref
/// Base of every error the package reports about its *input* (files, metrics,
/// domains). Library code never asserts on user input: it throws one of these,
/// and the command-line tool turns them into exit code 2.
class Invalid_input : public std::runtime_error {
public:
  explicit Invalid_input(const std::string& what) : std::runtime_error(what) {}
};

/// \ingroup PkgBubbleMesh3Ref
/// A metric value that is not finite, not symmetric or not positive definite.
/// The message names where the value came from (file and vertex, or point).
class Invalid_metric : public Invalid_input {
public:
  explicit Invalid_metric(const std::string& what) : Invalid_input(what) {}
};

/// \ingroup PkgBubbleMesh3Ref
/// A file that cannot be opened, is truncated, or does not follow its format.
/// The message names the file and, where known, the line.
class Invalid_file : public Invalid_input {
public:
  explicit Invalid_file(const std::string& what) : Invalid_input(what) {}
};

/// \ingroup PkgBubbleMesh3Ref
/// The metric asks for more nodes than the cap allows
/// (`maximum_number_of_bubbles`, the tool's `--max-nodes`): refused before
/// any memory is spent on them. An `Invalid_input` (exit code 2); the message
/// gives the estimate, the cap and what to do.
class Too_many_nodes : public Invalid_input {
public:
  Too_many_nodes(double estimated, double limit)
      : Invalid_input("the metric asks for about " + whole(estimated) + " nodes, more than the cap of " +
                      whole(limit) + " (maximum_number_of_bubbles, --max-nodes; a run needs about 2 kB of "
                      "memory per node): coarsen the metric or raise the cap"),
        estimated_(estimated), limit_(limit)
  {}
  /// the estimated number of nodes (a lower bound when refused early)
  double estimated() const { return estimated_; }
  /// the cap it exceeds
  double limit() const { return limit_; }

private:
  static std::string whole(double x)
  {
    return x < 9.2e18 ? std::to_string(static_cast<long long>(x + 0.5)) : std::to_string(x);
  }
  double estimated_, limit_;
};

/// \ingroup PkgBubbleMesh3Ref
/// Meshing could not produce a valid mesh from valid input (for example the
/// advancing front could not close and no cavity filler was available). Not
/// an `Invalid_input`: the command-line tool turns it into exit code 3. The
/// message says which stage failed and why.
class Meshing_failure : public std::runtime_error {
public:
  explicit Meshing_failure(const std::string& what) : std::runtime_error(what) {}
};

/// \ingroup PkgBubbleMesh3Ref
/// Meshing was stopped on request: the `should_stop` callback returned true
/// (the command-line tool sets it on SIGINT and exits with code 130). Neither
/// an `Invalid_input` nor a `Meshing_failure`; no mesh is returned. The
/// message says in which stage the run stopped.
class Interrupted : public std::runtime_error {
public:
  explicit Interrupted(const std::string& what) : std::runtime_error(what) {}
};

/// \ingroup PkgBubbleMesh3Ref
/// The `time_limit` of the whole run was reached before the mesh was complete
/// (the command-line tool's `--time-limit`, exit code 4). An `Interrupted`;
/// no mesh is returned. The message gives the limit and the stage.
class Time_limit_exceeded : public Interrupted {
public:
  explicit Time_limit_exceeded(const std::string& what) : Interrupted(what) {}
};

} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_EXCEPTIONS_H
