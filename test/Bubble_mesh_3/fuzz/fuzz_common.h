// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Shared by the libFuzzer harnesses: how a harness reports a bug. Expected
// input errors (Invalid_input and subclasses) are not bugs; anything else
// (another exception type, a broken invariant) aborts so that libFuzzer
// saves the input as a crash reproducer.
#ifndef BUBBLE_MESH_3_FUZZ_COMMON_H
#define BUBBLE_MESH_3_FUZZ_COMMON_H

#include <CGAL/Bubble_mesh_3/exceptions.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

namespace bubble_mesh_3_fuzz {

[[noreturn]] inline void fail(const std::string& what)
{
  std::fprintf(stderr, "\n*** fuzz invariant violated: %s\n", what.c_str());
  std::abort();
}

// `what` is a literal: building messages only on failure keeps checks cheap
inline void check(bool condition, const char* what)
{
  if(!condition)
    fail(what);
}

// Runs `f` and returns true if it returned normally, false if it threw
// Invalid_input (the expected outcome of bad input). Any other exception is a
// bug: abort with its message (clearer than libFuzzer's "uncaught exception").
template <class F>
bool run_expecting_only_invalid_input(F&& f)
{
  try {
    f();
    return true;
  } catch(const CGAL::Bubble_mesh_3::Invalid_input&) {
    return false;
  } catch(const std::exception& e) {
    fail(std::string("unexpected exception type: ") + e.what());
  } catch(...) {
    fail("unexpected non-std exception");
  }
}

// Runs `f`, a check on data the library accepted: any exception is a bug.
template <class F>
void run_expecting_no_exception(const char* what, F&& f)
{
  try {
    f();
  } catch(const std::exception& e) {
    fail(std::string(what) + ": " + e.what());
  } catch(...) {
    fail(std::string(what) + ": non-std exception");
  }
}

} // namespace bubble_mesh_3_fuzz

#endif // BUBBLE_MESH_3_FUZZ_COMMON_H
