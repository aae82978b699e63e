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
// Without fork(), abort and crash are injected as errors.
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_TETGEN_ISOLATED_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_TETGEN_ISOLATED_H

#ifndef TETLIBRARY
#  define TETLIBRARY
#endif
#include <tetgen.h>

#include <CGAL/Bubble_mesh_3/exceptions.h>

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <cstring>
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

enum class Injected_fault { none, abort, crash, error, wrong };

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

/// Reads n bytes; false at the end of the pipe or on an error. Between
/// reads it waits for data in slices of 100 ms and asks `should_stop` (if
/// any) after each: true sets `stopped` and returns false (TetGen can spend
/// many minutes in its flips on a hard cavity; the caller's time limit and
/// Ctrl-C must still end the run).
inline bool read_all(int fd, void* data, std::size_t n, const std::function<bool()>& should_stop, bool& stopped)
{
  char* p = static_cast<char*>(data);
  while(n > 0) {
    if(should_stop) {
      pollfd pfd{fd, POLLIN, 0};
      const int ready = ::poll(&pfd, 1, 100);
      if(ready < 0 && errno != EINTR)
        return false;
      if(ready <= 0) {
        if(should_stop()) {
          stopped = true;
          return false;
        }
        continue;
      }
    }
    const ssize_t r = ::read(fd, p, n);
    if(r < 0 && errno == EINTR)
      continue;
    if(r <= 0)
      return false;
    p += r;
    n -= std::size_t(r);
  }
  return true;
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

/// Runs `tetrahedralize(switches, in)`; returns false (with the reason in
/// `error`) if TetGen reported an error or died. With `should_stop`, it is
/// asked every 100 ms while TetGen runs (in a child process only): true
/// kills the child and throws `Interrupted`.
inline bool tetrahedralize_isolated(const std::string& switches, tetgenio& in, Tetgen_output& result,
                                    std::string& error, const std::function<bool()>& should_stop = {})
{
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
  bool stopped = false;
  bool received = false;
  try {
    received = read_all(fds[0], header, sizeof header, should_stop, stopped);
    if(received && header[0] == 1) {
      result.points.resize(std::size_t(header[1]));
      result.tets.resize(std::size_t(header[2]));
      result.intersecting_faces = int(header[3]);
      received = read_all(fds[0], result.points.data(), result.points.size() * sizeof(double), should_stop, stopped) &&
                 read_all(fds[0], result.tets.data(), result.tets.size() * sizeof(int), should_stop, stopped);
    }
  } catch(...) {
    end_child();
    throw;
  }
  if(stopped) {
    end_child();
    throw Interrupted("TetGen stopped on request");
  }
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
  if(!tetgen_detail::run(switches, in, result,
                         fault == Injected_fault::abort || fault == Injected_fault::crash ? Injected_fault::error
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
