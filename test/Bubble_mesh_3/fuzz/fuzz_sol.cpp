// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// libFuzzer harness: the MEDIT .sol metric reader (IO/sol.h): the parser both
// read_sol() overloads run on the file's bytes, called on the fuzz buffer
// (see fuzz_medit.cpp for why not the stream). The first byte picks the expected vertex count (0 = any, else
// 1..15), the rest is the file. Oracle: Invalid_input, or as many metrics as
// expected, each one valid, writing and reading back bitwise identical.
#include <CGAL/Bubble_mesh_3/IO/sol.h>

#include "fuzz_common.h"

#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

namespace BIO = CGAL::Bubble_mesh_3::IO;
using CGAL::Bubble_mesh_3::Metric_3;
using bubble_mesh_3_fuzz::check;

namespace {

void check_metrics(const std::vector<Metric_3>& metrics, std::size_t expected)
{
  if(expected != 0)
    check(metrics.size() == expected, "wrong number of metrics for the expected vertex count");
  for(const Metric_3& m : metrics) {
    check(m.matrix().allFinite(), "non-finite metric accepted");
    check(m.matrix() == m.matrix().transpose(), "non-symmetric metric stored");
    Metric_3::validate(m.matrix(), "stored metric");
  }
  std::ostringstream out;
  BIO::write_sol(out, metrics);
  std::istringstream in(out.str());
  const std::vector<Metric_3> again = BIO::read_sol(in, "round trip", expected);
  check(again.size() == metrics.size(), "write_sol/read_sol round trip changed the count");
  for(std::size_t i = 0; i < metrics.size(); ++i)
    check(again[i].matrix() == metrics[i].matrix(), "write_sol/read_sol round trip changed a metric");
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  if(size == 0)
    return 0;
  const std::size_t expected = data[0] % 16;
  const char* begin = reinterpret_cast<const char*>(data) + 1;
  std::vector<Metric_3> metrics;
  if(bubble_mesh_3_fuzz::run_expecting_only_invalid_input(
         [&] { metrics = BIO::internal::parse_sol(begin, begin + (size - 1), "fuzz.sol", expected); }))
    // A metric the reader accepted that re-validation or the round trip
    // rejects is a bug, not bad input.
    bubble_mesh_3_fuzz::run_expecting_no_exception("accepted .sol", [&] { check_metrics(metrics, expected); });
  return 0;
}
