// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// TetGen in a child process. TetGen 1.5 (Debian's libtet1.5) is built with
// its assertions on, and some near-degenerate inputs trip one of them
// (seen: `recoverfacebyflips` on a cavity of the advancing front): abort()
// would end the caller's program. On POSIX systems the call runs in a
// fork()ed child, which sends the output points and tets back through a
// pipe; a child that dies is reported as an error, not a crash. The parent
// only reads the pipe and waits, so threads it may run (TBB) do not matter:
// the child runs TetGen alone, on its copy of the input, and leaves by
// _exit(). Elsewhere TetGen runs in process, and an assertion inside it ends
// the program (the documented limit of builds without fork()).
//
// Fault injection (a test mode): when the environment variable
// BUBBLE_MESH_3_INJECT_FAULT is set at the time of a call, the call fails
// the way it names, so tests can check that every caller ends in a valid
// mesh or its documented exception:
//   abort  the child aborts (what TetGen's assertions do)
//   crash  the child dies of SIGSEGV
//   error  TetGen's own error return
//   wrong  TetGen "succeeds" with a corrupted result: its last tet dropped
//          and a vertex of its first tet replaced by another point
//   hang   the child never answers (what TetGen's flips did on a hard
//          cavity: minutes without end)
// Without fork(), abort, crash and hang are injected as errors.
//
// A child that does not answer within its time budget
// (`tetgen_time_budget()`, far above what TetGen needs on inputs of that
// size) is killed and reported as an error, so a TetGen that loops cannot
// hang the caller; the caller's stop request (`should_stop`) is asked every
// 100 ms as well.
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_TETGEN_ISOLATED_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_TETGEN_ISOLATED_H

#ifndef TETLIBRARY
#  define TETLIBRARY
#endif
#include <tetgen.h>

#include <CGAL/Bubble_mesh_3/exceptions.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <chrono>
#include <functional>
#include <string>
#include <vector>

#if defined(__unix__) || defined(__APPLE__)
#  include <fcntl.h>
#  include <poll.h>
#  include <sys/types.h>
#  include <sys/wait.h>
#  include <unistd.h>
#  define CGAL_BUBBLE_MESH_3_TETGEN_FORK 1
#endif

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

/// What a TetGen run gives back: points (the input ones first), tets (4
/// corners each) and, for `-d`, the number of intersecting faces.
struct Tetgen_output {
  std::vector<double> points;
  std::vector<int> tets;
  int intersecting_faces = 0;
};

enum class Injected_fault { none, abort, crash, error, wrong, hang };

/// The fault the environment asks for (`BUBBLE_MESH_3_INJECT_FAULT`, see the
/// file comment); an unknown value is treated as `error`, so a typo cannot
/// silently disable a fault test.
inline Injected_fault injected_fault()
{
  const char* v = std::getenv("BUBBLE_MESH_3_INJECT_FAULT");
  if(v == nullptr || *v == '\0')
    return Injected_fault::none;
  const std::string s(v);
  if(s == "abort")
    return Injected_fault::abort;
  if(s == "crash")
    return Injected_fault::crash;
  if(s == "wrong")
    return Injected_fault::wrong;
  if(s == "hang")
    return Injected_fault::hang;
  return Injected_fault::error;
}

namespace tetgen_detail {

// the corruption of `wrong`: a hole (the last tet dropped) and an overlap or
// a dangling face (a vertex of the first tet moved to another point that
// leaves it a proper tet, so that only a tiling check can tell)
inline void corrupt(Tetgen_output& r)
{
  if(r.tets.size() >= 4)
    r.tets.resize(r.tets.size() - 4);
  const int points = int(r.points.size() / 3);
  if(r.tets.size() < 4)
    return;
  auto p = [&](int v, int k) { return r.points[3 * std::size_t(v) + std::size_t(k)]; };
  auto volume = [&](int a, int b, int c, int d) {
    double u[3], v[3], w[3];
    for(int k = 0; k < 3; ++k) {
      u[k] = p(b, k) - p(a, k);
      v[k] = p(c, k) - p(a, k);
      w[k] = p(d, k) - p(a, k);
    }
    return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
  };
  const double own = std::abs(volume(r.tets[0], r.tets[1], r.tets[2], r.tets[3]));
  for(int w = 0; w < points; ++w)
    if(w != r.tets[0] && w != r.tets[1] && w != r.tets[2] && w != r.tets[3] &&
       std::abs(volume(w, r.tets[1], r.tets[2], r.tets[3])) > 1e-3 * own) {
      r.tets[0] = w;
      return;
    }
}

inline bool write_all(int fd, const void* data, std::size_t n)
{
  const char* p = static_cast<const char*>(data);
  while(n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if(w < 0 && errno == EINTR)
      continue;
    if(w <= 0)
      return false;
    p += w;
    n -= std::size_t(w);
  }
  return true;
}

/// Why a read from the child stopped short.
enum class Read_end { complete, closed, stopped, timed_out };

/// Reads n bytes from the child. It waits for data in slices of 100 ms;
/// after each empty slice it asks `should_stop` (if any; it may throw) and
/// checks `deadline`: TetGen can spend many minutes in its flips on a hard
/// cavity, and neither the caller's time limit nor a loop in TetGen may
/// hang the caller.
inline Read_end read_all(int fd, void* data, std::size_t n, const std::function<bool()>& should_stop,
                         std::chrono::steady_clock::time_point deadline)
{
  char* p = static_cast<char*>(data);
  while(n > 0) {
    pollfd pfd{fd, POLLIN, 0};
    const int ready = ::poll(&pfd, 1, 100);
    if(ready < 0 && errno != EINTR)
      return Read_end::closed;
    if(ready <= 0) {
      if(should_stop && should_stop())
        return Read_end::stopped;
      if(std::chrono::steady_clock::now() > deadline)
        return Read_end::timed_out;
      continue;
    }
    const ssize_t r = ::read(fd, p, n);
    if(r < 0 && errno == EINTR)
      continue;
    if(r <= 0)
      return Read_end::closed;
    p += r;
    n -= std::size_t(r);
  }
  return Read_end::complete;
}

// runs TetGen; false on its own error (it throws an int)
inline bool run(const std::string& switches, tetgenio& in, Tetgen_output& result, Injected_fault fault)
{
  if(fault == Injected_fault::error)
    return false;
  tetgenio out;
  std::vector<char> s(switches.begin(), switches.end());
  s.push_back('\0');
  try {
    tetrahedralize(s.data(), &in, &out);
  } catch(...) {
    return false;
  }
  if(out.numberofcorners != 4 && out.numberoftetrahedra > 0)
    return false;
  result.points.assign(out.pointlist, out.pointlist + 3 * std::size_t(std::max(0, out.numberofpoints)));
  result.tets.assign(out.tetrahedronlist,
                     out.tetrahedronlist + 4 * std::size_t(std::max(0, out.numberoftetrahedra)));
  result.intersecting_faces = out.numberoftrifaces;
  if(fault == Injected_fault::wrong)
    corrupt(result);
  return true;
}

} // namespace tetgen_detail

/// Seconds TetGen may take on `in` before it is taken for looping: 20 s
/// plus 1 ms per input point and facet, two orders of magnitude above its
/// usual speed on inputs of that size (a 20,000-tet cavity fill takes well
/// under a second).
inline double tetgen_time_budget(const tetgenio& in)
{
  return 20.0 + 1e-3 * (double(std::max(0, in.numberofpoints)) + double(std::max(0, in.numberoffacets)));
}

/// Runs `tetrahedralize(switches, in)`; returns false (with the reason in
/// `error`) if TetGen reported an error, died or ran longer than
/// `max_seconds` (negative: `tetgen_time_budget(in)`). With `should_stop`,
/// it is asked every 100 ms while TetGen runs (in a child process only):
/// true kills the child and throws `Interrupted`.
inline bool tetrahedralize_isolated(const std::string& switches, tetgenio& in, Tetgen_output& result,
                                    std::string& error, const std::function<bool()>& should_stop = {},
                                    double max_seconds = -1)
{
  if(max_seconds < 0)
    max_seconds = tetgen_time_budget(in);
  const Injected_fault fault = injected_fault();
#ifdef CGAL_BUBBLE_MESH_3_TETGEN_FORK
  using namespace tetgen_detail;
  int fds[2];
  if(::pipe(fds) != 0) {
    error = std::string("cannot create a pipe for TetGen: ") + std::strerror(errno);
    return false;
  }
  const pid_t pid = ::fork();
  if(pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    error = std::string("cannot start TetGen's process: ") + std::strerror(errno);
    return false;
  }
  if(pid == 0) { // the child: TetGen, then the result, then _exit
    ::close(fds[0]);
    // TetGen's assertion message would look like the caller's crash: the
    // parent reports the failure itself
    const int null = ::open("/dev/null", O_WRONLY);
    if(null >= 0) {
      ::dup2(null, 1);
      ::dup2(null, 2);
    }
    if(fault == Injected_fault::abort)
      std::abort();
    if(fault == Injected_fault::crash)
      std::raise(SIGSEGV);
    if(fault == Injected_fault::hang)
      for(;;)
        ::pause();
    Tetgen_output r;
    const std::uint64_t ok = run(switches, in, r, fault) ? 1 : 0;
    const std::uint64_t header[4] = {ok, r.points.size(), r.tets.size(), std::uint64_t(r.intersecting_faces)};
    bool sent = write_all(fds[1], header, sizeof header);
    sent = sent && write_all(fds[1], r.points.data(), r.points.size() * sizeof(double));
    sent = sent && write_all(fds[1], r.tets.data(), r.tets.size() * sizeof(int));
    ::close(fds[1]);
    ::_exit(sent ? 0 : 1);
  }
  ::close(fds[1]);
  std::uint64_t header[4] = {0, 0, 0, 0};
  int status = 0;
  // the child must not outlive a stop: `should_stop` may also throw (the
  // pipeline's time limit does)
  auto end_child = [&] {
    ::close(fds[0]);
    ::kill(pid, SIGKILL);
    while(::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
  };
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                            std::chrono::duration<double>(std::max(0.0, max_seconds)));
  Read_end end = Read_end::closed;
  try {
    end = read_all(fds[0], header, sizeof header, should_stop, deadline);
    if(end == Read_end::complete && header[0] == 1) {
      result.points.resize(std::size_t(header[1]));
      result.tets.resize(std::size_t(header[2]));
      result.intersecting_faces = int(header[3]);
      end = read_all(fds[0], result.points.data(), result.points.size() * sizeof(double), should_stop, deadline);
      if(end == Read_end::complete)
        end = read_all(fds[0], result.tets.data(), result.tets.size() * sizeof(int), should_stop, deadline);
    }
  } catch(...) {
    end_child();
    throw;
  }
  if(end == Read_end::stopped) {
    end_child();
    throw Interrupted("TetGen stopped on request");
  }
  if(end == Read_end::timed_out) {
    end_child();
    char budget[32];
    std::snprintf(budget, sizeof budget, "%.3g", max_seconds);
    error = std::string("TetGen did not finish within its budget of ") + budget + " s and was stopped";
    return false;
  }
  const bool received = end == Read_end::complete;
  ::close(fds[0]);
  while(::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if(WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    error = "TetGen died (signal " + std::to_string(sig) +
            (sig == SIGABRT ? ": an internal assertion failed on this input)" : ": it crashed on this input)");
    return false;
  }
  if(!received || header[0] != 1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    error = "TetGen reported an error on this input";
    return false;
  }
  return true;
#else
  (void)should_stop; // TetGen in process cannot be stopped
  if(!tetgen_detail::run(switches, in, result,
                         fault == Injected_fault::abort || fault == Injected_fault::crash || fault == Injected_fault::hang
                             ? Injected_fault::error
                                                                                          : fault)) {
    error = "TetGen reported an error on this input";
    return false;
  }
  return true;
#endif
}

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_TETGEN_ISOLATED_H
