// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_IO_SOL_H
#define CGAL_BUBBLE_MESH_3_IO_SOL_H

#include <CGAL/Bubble_mesh_3/IO/medit.h>
#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <istream>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace IO {
namespace internal {

// Number of values per entry of a MEDIT solution field type in 3D.
inline int sol_type_size(long long type)
{
  switch(type) {
  case 1: return 1; // scalar
  case 2: return 3; // vector
  case 3: return 6; // symmetric matrix
  case 4: return 9; // full matrix
  default: return 0;
  }
}

// Reads the header and the sections of a MEDIT .sol file; `read_values(in, n,
// type)` reads the n entries of the single SolAtVertices field (of type
// `type`, already checked by `accept_type(type)`, which returns an error
// message or an empty string).
template <typename AcceptType, typename ReadValues>
void parse_sol_file(const char* begin, const char* end, const std::string& name,
                    std::size_t expected_number_of_vertices, const AcceptType& accept_type,
                    const ReadValues& read_values)
{
  Token_reader in(begin, end, name);
  bool has_version = false, has_dimension = false, has_solution = false;

  std::string_view token;
  bool have_token = in.next(token);
  if(!have_token)
    in.fail("empty file (expected MeshVersionFormatted)");
  while(have_token) {
    if(token == "End")
      break;
    if(!has_version && token != "MeshVersionFormatted")
      in.fail("expected MeshVersionFormatted, got '" + Token_reader::shown(token) + "' (not a MEDIT .sol file?)");

    if(token == "MeshVersionFormatted") {
      if(has_version)
        in.fail("second MeshVersionFormatted");
      has_version = true;
      const long long v = in.read_integer("MeshVersionFormatted");
      if(v != 1 && v != 2)
        in.fail("unsupported MeshVersionFormatted " + std::to_string(v) + " (expected 1 or 2)");
    } else if(token == "Dimension") {
      if(has_dimension)
        in.fail("second Dimension");
      has_dimension = true;
      const long long d = in.read_integer("Dimension");
      if(d != 3)
        in.fail("Dimension " + std::to_string(d) + " is not supported (expected 3)");
    } else if(token == "SolAtVertices") {
      if(!has_dimension)
        in.fail("SolAtVertices before Dimension");
      if(has_solution)
        in.fail("second SolAtVertices section");
      has_solution = true;
      const std::size_t n = in.read_count("SolAtVertices", 2);
      if(expected_number_of_vertices != 0 && n != expected_number_of_vertices)
        in.fail("SolAtVertices has " + std::to_string(n) + " entries but the mesh has " +
                std::to_string(expected_number_of_vertices) + " vertices");
      const long long fields = in.read_integer("SolAtVertices number of fields");
      if(fields < 1 || fields > 64)
        in.fail("invalid number of fields " + std::to_string(fields) + " in SolAtVertices");
      std::vector<long long> types;
      for(long long f = 0; f < fields; ++f)
        types.push_back(in.read_integer("SolAtVertices field type"));
      const std::string problem = accept_type(fields, types);
      if(!problem.empty())
        in.fail(problem);
      read_values(in, n, types.front());
    } else if(token.size() > 5 && token.substr(0, 5) == "SolAt") {
      // another solution section (at triangles, tetrahedra...): read past it
      const std::string keyword(token);
      const std::size_t n = in.read_count(keyword.c_str(), 2);
      const long long fields = in.read_integer(keyword.c_str());
      if(fields < 0 || fields > 64)
        in.fail("invalid number of fields " + std::to_string(fields) + " in " + keyword);
      std::size_t per_entry = 0;
      for(long long f = 0; f < fields; ++f) {
        const long long type = in.read_integer(keyword.c_str());
        const int size = sol_type_size(type);
        if(size == 0)
          in.fail("unknown field type " + std::to_string(type) + " in " + keyword);
        per_entry += static_cast<std::size_t>(size);
      }
      for(std::size_t i = 0; i < n * per_entry; ++i)
        in.read_double(keyword.c_str());
    } else if(Token_reader::is_keyword(token)) {
      have_token = in.skip_to_next_keyword(token);
      continue;
    } else {
      in.fail_stray_token(token);
    }
    have_token = in.next(token);
  }
  if(!has_solution)
    in.fail("no SolAtVertices section");
}

inline std::vector<Metric_3> parse_sol(const char* begin, const char* end, const std::string& name,
                                       std::size_t expected_number_of_vertices)
{
  std::vector<Metric_3> metrics;
  auto accept = [](long long fields, const std::vector<long long>& types) -> std::string {
    if(fields != 1)
      return "SolAtVertices has " + std::to_string(fields) +
             " fields; exactly one metric field (type 3, or type 1 for a scalar size) is supported";
    if(types[0] != 1 && types[0] != 3)
      return "SolAtVertices field of type " + std::to_string(types[0]) +
             " is not a metric; expected 3 (symmetric matrix) or 1 (scalar size)";
    return std::string();
  };
  auto read = [&](Token_reader& in, std::size_t n, long long type) {
    metrics.reserve(n);
    for(std::size_t i = 0; i < n; ++i) {
      if(type == 3) {
        double v[6];
        v[0] = in.read_double("SolAtVertices");
        const std::size_t line = in.line();
        for(int k = 1; k < 6; ++k)
          v[k] = in.read_double("SolAtVertices");
        // file order: m11 m21 m22 m31 m32 m33
        Metric_3::Matrix m;
        m << v[0], v[1], v[3], v[1], v[2], v[4], v[3], v[4], v[5];
        try {
          metrics.emplace_back(m);
        } catch(const Invalid_metric&) {
          // Build the location string only on failure (this loop is hot);
          // constructing again reproduces the error with it.
          metrics.emplace_back(m, name + ":" + std::to_string(line) + ": vertex " + std::to_string(i + 1));
        }
      } else {
        const double h = in.read_double("SolAtVertices");
        try {
          metrics.push_back(Metric_3::isotropic(h));
        } catch(const Invalid_metric&) {
          metrics.push_back(
            Metric_3::isotropic(h, name + ":" + std::to_string(in.line()) + ": vertex " + std::to_string(i + 1)));
        }
      }
    }
  };
  parse_sol_file(begin, end, name, expected_number_of_vertices, accept, read);
  return metrics;
}

inline std::vector<double> parse_scalar_sol(const char* begin, const char* end, const std::string& name,
                                            std::size_t expected_number_of_vertices)
{
  std::vector<double> values;
  auto accept = [](long long fields, const std::vector<long long>& types) -> std::string {
    if(fields != 1 || types[0] != 1)
      return "SolAtVertices must hold exactly one scalar field (1 1), got " + std::to_string(fields) +
             " field(s) of type(s)" + [&] {
               std::string t;
               for(long long x : types)
                 t += " " + std::to_string(x);
               return t;
             }();
    return std::string();
  };
  auto read = [&](Token_reader& in, std::size_t n, long long) {
    values.reserve(n);
    for(std::size_t i = 0; i < n; ++i) {
      const double v = in.read_double("SolAtVertices");
      if(!std::isfinite(v))
        in.fail("vertex " + std::to_string(i + 1) + ": the value is not a finite number");
      values.push_back(v);
    }
  };
  parse_sol_file(begin, end, name, expected_number_of_vertices, accept, read);
  return values;
}

} // namespace internal

/// \ingroup PkgBubbleMesh3IO
/// Reads the metric of a MEDIT ASCII `.sol` file from `is` (`name_for_messages`
/// starts every error message).
///
/// The file must hold one `SolAtVertices` section with exactly one field,
/// either
/// - of type 3 (symmetric matrix): six values per vertex in the MEDIT order
///   `m11 m21 m22 m31 m32 m33` (lower triangle, row by row), or
/// - of type 1 (scalar): an isotropic size `h` per vertex, converted to the
///   metric `M = I / h^2`.
///
/// Other `SolAt...` sections are read past. If `expected_number_of_vertices`
/// is not 0, the number of entries must equal it.
///
/// Throws `Invalid_file` (`name:line: ...`) on a format error, a count or a
/// field type mismatch, and `Invalid_metric` (`name:line: vertex i: ...`, `i`
/// 1-based as in the file) when a value is not a valid metric (NaN, not
/// positive definite, too anisotropic) or a size is not positive.
inline std::vector<Metric_3> read_sol(std::istream& is, const std::string& name_for_messages,
                                      std::size_t expected_number_of_vertices = 0)
{
  const std::string buffer = internal::read_stream_to_string(is, name_for_messages);
  return internal::parse_sol(buffer.data(), buffer.data() + buffer.size(), name_for_messages,
                             expected_number_of_vertices);
}

/// \ingroup PkgBubbleMesh3IO
/// Reads the `.sol` file `path` (see the stream overload).
inline std::vector<Metric_3> read_sol(const std::string& path, std::size_t expected_number_of_vertices = 0)
{
  const std::string buffer = internal::read_file_to_string(path);
  return internal::parse_sol(buffer.data(), buffer.data() + buffer.size(), path, expected_number_of_vertices);
}

/// \ingroup PkgBubbleMesh3IO
/// Reads a scalar solution (one value per mesh vertex) from the MEDIT ASCII
/// `.sol` file `path`: one `SolAtVertices` section with exactly one field of
/// type 1 (`SolAtVertices N 1 1`); other `SolAt...` sections are read past.
/// Throws `Invalid_file` (`path:line: ...`) on a format error, another field
/// layout, a non-finite value, or (if `expected_number_of_vertices` is not 0)
/// a count that differs from it.
inline std::vector<double> read_scalar_sol(const std::string& path, std::size_t expected_number_of_vertices = 0)
{
  const std::string buffer = internal::read_file_to_string(path);
  return internal::parse_scalar_sol(buffer.data(), buffer.data() + buffer.size(), path, expected_number_of_vertices);
}

/// \ingroup PkgBubbleMesh3IO
/// Writes `values` (one per mesh vertex) as a MEDIT `.sol` scalar solution
/// (`SolAtVertices N 1 1`), each value in the shortest decimal form that reads
/// back to the same double, through a temporary file renamed at the end.
inline void write_scalar_sol(const std::string& path, const std::vector<double>& values)
{
  write_file_atomically(path, [&values](std::ostream& os) {
    internal::Number_writer w(os);
    w.text("MeshVersionFormatted 2\n\nDimension 3\n\nSolAtVertices\n").number(values.size()).text("\n1 1\n\n");
    for(double v : values)
      w.number(v).put('\n');
    w.text("\nEnd\n");
    w.flush();
  });
}

/// \ingroup PkgBubbleMesh3IO
/// Writes `metrics` as a MEDIT `.sol` file: one `SolAtVertices` field of type
/// 3, values in the order `m11 m21 m22 m31 m32 m33`, each in the shortest
/// decimal form that reads back to the same double, so that
/// `read_sol` returns bitwise identical metrics.
inline void write_sol(std::ostream& os, const std::vector<Metric_3>& metrics)
{
  internal::Number_writer w(os);
  w.text("MeshVersionFormatted 2\n\nDimension 3\n\nSolAtVertices\n").number(metrics.size()).text("\n1 3\n\n");
  for(const Metric_3& metric : metrics) {
    const Metric_3::Matrix& m = metric.matrix();
    w.number(m(0, 0)).put(' ').number(m(1, 0)).put(' ').number(m(1, 1)).put(' ').number(m(2, 0)).put(' ')
     .number(m(2, 1)).put(' ').number(m(2, 2)).put('\n');
  }
  w.text("\nEnd\n");
  w.flush();
}

/// \ingroup PkgBubbleMesh3IO
/// Writes `metrics` to the `.sol` file `path` (see the stream overload),
/// through a temporary file renamed at the end (never a partial `path`).
/// Throws `Invalid_file` if the file cannot be written.
inline void write_sol(const std::string& path, const std::vector<Metric_3>& metrics)
{
  write_file_atomically(path, [&metrics](std::ostream& os) { write_sol(os, metrics); });
}

} // namespace IO
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_IO_SOL_H
