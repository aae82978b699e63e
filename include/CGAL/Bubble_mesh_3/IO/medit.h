// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_IO_MEDIT_H
#define CGAL_BUBBLE_MESH_3_IO_MEDIT_H

#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/IO/write_file_atomically.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <istream>
#include <limits>
#include <ostream>
#include <random>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace IO {
namespace internal {

// Shared by the MEDIT `.mesh`, `.sol` and VTU code of this directory:
// a whitespace/comment tolerant tokenizer over a file held in memory, fast
// number formatting, and the "write to a temporary file, then rename" rule.


// Whole stream into memory (the readers parse from a buffer: no per-token
// allocation). `name` is only used in messages.
inline std::string read_stream_to_string(std::istream& is, const std::string& name)
{
  std::string buffer;
  if(!is)
    throw Invalid_file(name + ": cannot read (stream is not readable)");
  const std::size_t chunk = std::size_t(1) << 20;
  std::size_t used = 0;
  for(;;) {
    buffer.resize(used + chunk);
    is.read(&buffer[used], static_cast<std::streamsize>(chunk));
    const std::streamsize got = is.gcount();
    used += static_cast<std::size_t>(got);
    if(got < static_cast<std::streamsize>(chunk))
      break;
  }
  if(is.bad())
    throw Invalid_file(name + ": read error");
  buffer.resize(used);
  return buffer;
}

inline std::string read_file_to_string(const std::string& path)
{
  std::ifstream is(path, std::ios::binary);
  if(!is)
    throw Invalid_file(path + ": cannot open file for reading (" + errno_text(errno) + ")");
  std::string buffer;
  is.seekg(0, std::ios::end);
  const std::streamoff size = is.tellg();
  if(size >= 0) {
    is.seekg(0, std::ios::beg);
    buffer.resize(static_cast<std::size_t>(size));
    is.read(&buffer[0], static_cast<std::streamsize>(size));
    if(is.bad() || is.gcount() != static_cast<std::streamsize>(size))
      throw Invalid_file(path + ": read error");
    return buffer;
  }
  is.clear();
  is.seekg(0, std::ios::beg);
  return read_stream_to_string(is, path);
}

// Tokens are separated by any whitespace; '#' starts a comment that runs to
// the end of the line. Every error carries "name:line: ".
class Token_reader {
public:
  Token_reader(const char* begin, const char* end, const std::string& name)
    : p_(begin), end_(end), name_(name)
  {}

  const std::string& name() const { return name_; }
  // line of the last token returned (1-based)
  std::size_t line() const { return token_line_; }
  std::size_t remaining_bytes() const { return static_cast<std::size_t>(end_ - p_); }

  [[noreturn]] void fail(const std::string& what) const { fail_at(token_line_, what); }

  // A token between sections that no section claims: either a count that
  // was too small (a stray number) or garbage.
  [[noreturn]] void fail_stray_token(std::string_view token) const
  {
    if(looks_numeric(token))
      fail("unexpected number '" + shown(token) +
           "' between sections (a section has more entries than its count says?)");
    fail("unexpected token '" + shown(token) + "'");
  }
  [[noreturn]] void fail_at(std::size_t line, const std::string& what) const
  {
    throw Invalid_file(name_ + ":" + std::to_string(line) + ": " + what);
  }

  // false at the end of the input
  bool next(std::string_view& token)
  {
    skip_blanks();
    if(p_ == end_)
      return false; // errors at the end of input name the last token's line
    token_line_ = line_;
    const char* b = p_;
    while(p_ != end_ && !is_separator(*p_))
      ++p_;
    token = std::string_view(b, static_cast<std::size_t>(p_ - b));
    return true;
  }

  // The next token, which must exist; `what` says what was expected.
  std::string_view require(const char* what)
  {
    std::string_view token;
    if(!next(token))
      fail("unexpected end of file while reading " + std::string(what) + " (truncated file?)");
    return token;
  }

  double read_double(const char* what)
  {
    const std::string_view token = require(what);
    const char* b = token.data();
    const char* e = b + token.size();
    // from_chars takes no '+': skip one, but not before another sign ("+-1")
    if(b != e && *b == '+' && (b + 1 == e || (b[1] != '-' && b[1] != '+')))
      ++b;
    double value = 0;
    const std::from_chars_result r = std::from_chars(b, e, value);
    if(r.ec == std::errc::result_out_of_range && r.ptr == e)
      fail("number '" + shown(token) + "' out of the double range in " + what);
    if(r.ec != std::errc() || r.ptr != e)
      fail_not_a_number(token, what);
    return value;
  }

  long long read_integer(const char* what)
  {
    const std::string_view token = require(what);
    const char* b = token.data();
    const char* e = b + token.size();
    if(b != e && *b == '+' && (b + 1 == e || (b[1] != '-' && b[1] != '+')))
      ++b;
    long long value = 0;
    const std::from_chars_result r = std::from_chars(b, e, value);
    if(r.ec != std::errc() || r.ptr != e)
      fail_not_a_number(token, what, "an integer");
    return value;
  }

  [[noreturn]] void fail_not_a_number(std::string_view token, const char* what, const char* kind = "a number") const
  {
    if(is_keyword(token))
      fail(std::string(what) + " ends early: expected " + kind + ", got keyword '" + shown(token) +
           "' (fewer entries than announced, truncated section?)");
    fail("expected " + std::string(kind) + " for " + what + ", got '" + shown(token) + "'");
  }

  int read_int(const char* what)
  {
    const long long v = read_integer(what);
    if(v < INT_MIN || v > INT_MAX)
      fail("integer " + std::to_string(v) + " out of range in " + what);
    return static_cast<int>(v);
  }

  // A section size: a non-negative int. Also bounded by the bytes left
  // (each entry needs at least `min_bytes_per_entry` characters) so that a
  // corrupt count never triggers a huge allocation.
  std::size_t read_count(const char* what, std::size_t min_bytes_per_entry)
  {
    const long long v = read_integer(what);
    if(v < 0 || v > INT_MAX)
      fail("invalid number of entries " + std::to_string(v) + " in " + what);
    const std::size_t n = static_cast<std::size_t>(v);
    if(min_bytes_per_entry > 0 && n > remaining_bytes() / min_bytes_per_entry + 1)
      fail(std::string(what) + " announces " + std::to_string(n) + " entries but the file is too short for them" +
           " (truncated file?)");
    return n;
  }

  // 1-based vertex index in [1, n], returned 0-based.
  int read_vertex_index(const char* what, std::size_t n, std::size_t entry)
  {
    const long long v = read_integer(what);
    if(v < 1 || static_cast<unsigned long long>(v) > n)
      fail(std::string(what) + " entry " + std::to_string(entry) + ": vertex index " + std::to_string(v) +
           " out of range [1, " + std::to_string(n) + "]");
    return static_cast<int>(v - 1);
  }

  static bool is_keyword(std::string_view token)
  {
    if(token.empty() || !((token[0] >= 'A' && token[0] <= 'Z') || (token[0] >= 'a' && token[0] <= 'z')))
      return false;
    for(char c : token)
      if(!((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'))
        return false;
    // from_chars accepts these as numbers
    std::string lower(token);
    for(char& c : lower)
      c = static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
    return lower != "nan" && lower != "inf" && lower != "infinity";
  }

  static bool looks_numeric(std::string_view token)
  {
    const char c = token.empty() ? ' ' : token[0];
    return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.';
  }

  // Skips number tokens up to (not including) the next keyword token.
  // Returns false at end of input. Used for sections whose layout is unknown.
  bool skip_to_next_keyword(std::string_view& keyword)
  {
    std::string_view token;
    while(next(token)) {
      if(is_keyword(token)) {
        keyword = token;
        return true;
      }
      if(!looks_numeric(token))
        fail("unexpected token '" + shown(token) + "'");
    }
    return false;
  }

  static std::string shown(std::string_view token)
  {
    if(token.size() > 40)
      return std::string(token.substr(0, 40)) + "...";
    return std::string(token);
  }

private:
  static bool is_separator(char c)
  {
    return c == ' ' || c == '\n' || c == '\t' || c == '\r' || c == '\f' || c == '\v' || c == '#';
  }

  void skip_blanks()
  {
    while(p_ != end_) {
      const char c = *p_;
      if(c == '\n') {
        ++line_;
        ++p_;
      } else if(c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
        ++p_;
      } else if(c == '#') {
        while(p_ != end_ && *p_ != '\n')
          ++p_;
      } else {
        break;
      }
    }
  }

  const char* p_;
  const char* end_;
  std::string name_;
  std::size_t line_ = 1;
  std::size_t token_line_ = 1;
};

// Buffered, locale-independent number output. Doubles are written in the
// shortest form that reads back to the same value (std::to_chars), so every
// written file round-trips exactly.
class Number_writer {
public:
  explicit Number_writer(std::ostream& os) : os_(os) { buffer_.reserve(capacity + 64); }
  ~Number_writer() = default;
  Number_writer(const Number_writer&) = delete;
  Number_writer& operator=(const Number_writer&) = delete;

  Number_writer& text(std::string_view s)
  {
    buffer_.append(s.data(), s.size());
    maybe_flush();
    return *this;
  }
  Number_writer& put(char c)
  {
    buffer_.push_back(c);
    return *this;
  }
  Number_writer& number(double x)
  {
    char tmp[64];
    const std::to_chars_result r = std::to_chars(tmp, tmp + sizeof(tmp), x);
    buffer_.append(tmp, r.ptr);
    maybe_flush();
    return *this;
  }
  Number_writer& number(long long x)
  {
    char tmp[32];
    const std::to_chars_result r = std::to_chars(tmp, tmp + sizeof(tmp), x);
    buffer_.append(tmp, r.ptr);
    maybe_flush();
    return *this;
  }
  Number_writer& number(int x) { return number(static_cast<long long>(x)); }
  Number_writer& number(std::size_t x) { return number(static_cast<long long>(x)); }

  void flush()
  {
    os_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    buffer_.clear();
  }

private:
  static constexpr std::size_t capacity = std::size_t(1) << 16;
  void maybe_flush()
  {
    if(buffer_.size() >= capacity)
      flush();
  }
  std::ostream& os_;
  std::string buffer_;
};


// Number of integers per record of the MEDIT sections we read past.
inline int skipped_section_record_size(std::string_view keyword)
{
  if(keyword == "Ridges" || keyword == "RequiredVertices" || keyword == "RequiredEdges" ||
     keyword == "RequiredTriangles" || keyword == "RequiredQuadrilaterals" || keyword == "RequiredTetrahedra")
    return 1;
  if(keyword == "NormalAtVertices" || keyword == "TangentAtVertices")
    return 2;
  if(keyword == "Normals" || keyword == "Tangents" || keyword == "NormalAtTriangleVertices" ||
     keyword == "TangentAtEdges")
    return 3;
  if(keyword == "Quadrilaterals")
    return 5;
  if(keyword == "Pyramids")
    return 6;
  if(keyword == "Prisms")
    return 7;
  if(keyword == "Hexahedra")
    return 9;
  return 0;
}

inline Indexed_tet_mesh_3 parse_medit(const char* begin, const char* end, const std::string& name)
{
  Token_reader in(begin, end, name);
  Indexed_tet_mesh_3 mesh;
  bool has_version = false, has_dimension = false, has_vertices = false;
  bool has_edges = false, has_triangles = false, has_tets = false, has_corners = false;
  std::size_t nv = 0;

  auto once = [&in](bool& seen, std::string_view keyword) {
    if(seen)
      in.fail("second " + std::string(keyword) + " section");
    seen = true;
  };
  auto need_vertices = [&](std::string_view keyword) {
    if(!has_vertices)
      in.fail(std::string(keyword) + " section before the Vertices section");
  };

  std::string_view token;
  bool have_token = in.next(token);
  if(!have_token)
    in.fail("empty file (expected MeshVersionFormatted)");
  while(have_token) {
    if(token == "End")
      break;
    if(!has_version && token != "MeshVersionFormatted")
      in.fail("expected MeshVersionFormatted, got '" + Token_reader::shown(token) + "' (not a MEDIT .mesh file?)");

    if(token == "MeshVersionFormatted") {
      once(has_version, token);
      const long long v = in.read_integer("MeshVersionFormatted");
      if(v != 1 && v != 2)
        in.fail("unsupported MeshVersionFormatted " + std::to_string(v) + " (expected 1 or 2)");
    } else if(token == "Dimension") {
      once(has_dimension, token);
      const long long d = in.read_integer("Dimension");
      if(d != 3)
        in.fail("Dimension " + std::to_string(d) + " is not supported (expected 3)");
    } else if(token == "Vertices") {
      if(!has_dimension)
        in.fail("Vertices section before Dimension");
      once(has_vertices, token);
      nv = in.read_count("Vertices", 8);
      mesh.points.resize(nv);
      mesh.point_refs.resize(nv);
      for(std::size_t i = 0; i < nv; ++i) {
        std::array<double, 3>& p = mesh.points[i];
        for(int k = 0; k < 3; ++k) {
          p[k] = in.read_double("Vertices");
          if(!std::isfinite(p[k]))
            in.fail("Vertices entry " + std::to_string(i + 1) + ": coordinate is not finite");
        }
        mesh.point_refs[i] = in.read_int("Vertices");
      }
    } else if(token == "Edges") {
      need_vertices(token);
      once(has_edges, token);
      const std::size_t n = in.read_count("Edges", 6);
      mesh.edges.resize(n);
      mesh.edge_refs.resize(n);
      for(std::size_t i = 0; i < n; ++i) {
        for(int k = 0; k < 2; ++k)
          mesh.edges[i][k] = in.read_vertex_index("Edges", nv, i + 1);
        mesh.edge_refs[i] = in.read_int("Edges");
      }
    } else if(token == "Triangles") {
      need_vertices(token);
      once(has_triangles, token);
      const std::size_t n = in.read_count("Triangles", 8);
      mesh.triangles.resize(n);
      mesh.triangle_refs.resize(n);
      for(std::size_t i = 0; i < n; ++i) {
        for(int k = 0; k < 3; ++k)
          mesh.triangles[i][k] = in.read_vertex_index("Triangles", nv, i + 1);
        mesh.triangle_refs[i] = in.read_int("Triangles");
      }
    } else if(token == "Tetrahedra") {
      need_vertices(token);
      once(has_tets, token);
      const std::size_t n = in.read_count("Tetrahedra", 10);
      mesh.tets.resize(n);
      mesh.tet_refs.resize(n);
      for(std::size_t i = 0; i < n; ++i) {
        for(int k = 0; k < 4; ++k)
          mesh.tets[i][k] = in.read_vertex_index("Tetrahedra", nv, i + 1);
        mesh.tet_refs[i] = in.read_int("Tetrahedra");
      }
    } else if(token == "Corners") {
      need_vertices(token);
      once(has_corners, token);
      const std::size_t n = in.read_count("Corners", 2);
      mesh.corners.resize(n);
      for(std::size_t i = 0; i < n; ++i)
        mesh.corners[i] = in.read_vertex_index("Corners", nv, i + 1);
    } else if(const int record = skipped_section_record_size(token)) {
      const std::string keyword(token);
      const std::size_t n = in.read_count(keyword.c_str(), 2 * static_cast<std::size_t>(record));
      for(std::size_t i = 0; i < n * static_cast<std::size_t>(record); ++i)
        in.read_double(keyword.c_str());
    } else if(Token_reader::is_keyword(token)) {
      // A section we do not know: its layout is unknown, skip its numbers.
      have_token = in.skip_to_next_keyword(token);
      continue;
    } else {
      in.fail_stray_token(token);
    }
    have_token = in.next(token);
  }
  if(!has_dimension)
    in.fail("no Dimension keyword");
  if(!has_vertices)
    in.fail("no Vertices section");
  return mesh;
}

// Throws Invalid_input unless `mesh` can be written (and read back).
inline void check_mesh_for_writing(const Indexed_tet_mesh_3& mesh)
{
  const std::size_t nv = mesh.points.size();
  auto refs_ok = [](std::size_t refs, std::size_t n) { return refs == 0 || refs == n; };
  if(!refs_ok(mesh.point_refs.size(), nv) || !refs_ok(mesh.edge_refs.size(), mesh.edges.size()) ||
     !refs_ok(mesh.triangle_refs.size(), mesh.triangles.size()) ||
     !refs_ok(mesh.tet_refs.size(), mesh.tets.size()))
    throw Invalid_input("Indexed_tet_mesh_3: a reference array is neither empty nor the size of its element array");
  if(nv > static_cast<std::size_t>(INT_MAX))
    throw Invalid_input("Indexed_tet_mesh_3: too many vertices for 32-bit indices");
  for(std::size_t i = 0; i < nv; ++i)
    for(int k = 0; k < 3; ++k)
      if(!std::isfinite(mesh.points[i][k]))
        throw Invalid_input("Indexed_tet_mesh_3: vertex " + std::to_string(i) + " has a non-finite coordinate");
  auto check = [nv](const char* what, std::size_t i, int v) {
    if(v < 0 || static_cast<std::size_t>(v) >= nv)
      throw Invalid_input(std::string("Indexed_tet_mesh_3: ") + what + " " + std::to_string(i) +
                          " (0-based) has vertex index " + std::to_string(v) + " out of range [0, " +
                          std::to_string(nv) + ")");
  };
  for(std::size_t i = 0; i < mesh.edges.size(); ++i)
    for(int v : mesh.edges[i])
      check("edge", i, v);
  for(std::size_t i = 0; i < mesh.triangles.size(); ++i)
    for(int v : mesh.triangles[i])
      check("triangle", i, v);
  for(std::size_t i = 0; i < mesh.tets.size(); ++i)
    for(int v : mesh.tets[i])
      check("tetrahedron", i, v);
  for(std::size_t i = 0; i < mesh.corners.size(); ++i)
    check("corner", i, mesh.corners[i]);
}

} // namespace internal

/// \ingroup PkgBubbleMesh3IO
/// Reads a MEDIT ASCII `.mesh` file from `is`; `name_for_messages` (usually
/// the file name) starts every error message.
///
/// Accepted: `MeshVersionFormatted` 1 or 2 (first keyword), `Dimension 3`,
/// `Vertices` (x y z ref), `Edges` (2 indices + feature-curve ref),
/// `Triangles` (3 indices + surface-patch ref), `Tetrahedra` (4 indices +
/// subdomain ref), `Corners` (indices), `End`. The other MEDIT sections
/// (`Ridges`, `Required*`, `Normals`, `Quadrilaterals`, `Hexahedra`, ...) are
/// read and discarded; unknown keywords are skipped up to the next keyword.
/// Keywords are case-sensitive, tokens may be separated by any whitespace
/// (newlines included) and `#` starts a comment. A missing `End` is accepted.
/// Indices in the file are 1-based; in the result they are 0-based.
///
/// Throws `Invalid_file` with a message `name:line: what is wrong` on any
/// deviation: truncated section, index out of range, non-numeric token,
/// non-finite coordinate, `Dimension` other than 3, missing `Vertices`, an
/// element section before `Vertices`, a repeated section, or extra numbers
/// after a section.
inline Indexed_tet_mesh_3 read_medit(std::istream& is, const std::string& name_for_messages)
{
  const std::string buffer = internal::read_stream_to_string(is, name_for_messages);
  return internal::parse_medit(buffer.data(), buffer.data() + buffer.size(), name_for_messages);
}

/// \ingroup PkgBubbleMesh3IO
/// Reads the MEDIT `.mesh` file `path` (see the stream overload). A file that
/// cannot be opened throws `Invalid_file` (`path: cannot open ...`).
inline Indexed_tet_mesh_3 read_medit(const std::string& path)
{
  const std::string buffer = internal::read_file_to_string(path);
  return internal::parse_medit(buffer.data(), buffer.data() + buffer.size(), path);
}

/// \ingroup PkgBubbleMesh3IO
/// Writes `mesh` in MEDIT ASCII format (`MeshVersionFormatted 2`, 1-based
/// indices). Empty element arrays are omitted; an empty reference array
/// means references 0. Coordinates are written in the shortest form that
/// reads back bitwise identical. Throws `Invalid_input` (before writing
/// anything) if an index is out of range, a reference array has the wrong
/// size or a coordinate is not finite.
inline void write_medit(std::ostream& os, const Indexed_tet_mesh_3& mesh)
{
  internal::check_mesh_for_writing(mesh);
  internal::Number_writer w(os);
  auto ref = [](const std::vector<int>& refs, std::size_t i) { return refs.empty() ? 0 : refs[i]; };
  w.text("MeshVersionFormatted 2\n\nDimension 3\n\nVertices\n").number(mesh.points.size()).put('\n');
  for(std::size_t i = 0; i < mesh.points.size(); ++i) {
    const std::array<double, 3>& p = mesh.points[i];
    w.number(p[0]).put(' ').number(p[1]).put(' ').number(p[2]).put(' ').number(ref(mesh.point_refs, i)).put('\n');
  }
  if(!mesh.edges.empty()) {
    w.text("\nEdges\n").number(mesh.edges.size()).put('\n');
    for(std::size_t i = 0; i < mesh.edges.size(); ++i)
      w.number(mesh.edges[i][0] + 1).put(' ').number(mesh.edges[i][1] + 1).put(' ')
       .number(ref(mesh.edge_refs, i)).put('\n');
  }
  if(!mesh.triangles.empty()) {
    w.text("\nTriangles\n").number(mesh.triangles.size()).put('\n');
    for(std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      const std::array<int, 3>& t = mesh.triangles[i];
      w.number(t[0] + 1).put(' ').number(t[1] + 1).put(' ').number(t[2] + 1).put(' ')
       .number(ref(mesh.triangle_refs, i)).put('\n');
    }
  }
  if(!mesh.tets.empty()) {
    w.text("\nTetrahedra\n").number(mesh.tets.size()).put('\n');
    for(std::size_t i = 0; i < mesh.tets.size(); ++i) {
      const std::array<int, 4>& t = mesh.tets[i];
      w.number(t[0] + 1).put(' ').number(t[1] + 1).put(' ').number(t[2] + 1).put(' ').number(t[3] + 1).put(' ')
       .number(ref(mesh.tet_refs, i)).put('\n');
    }
  }
  if(!mesh.corners.empty()) {
    w.text("\nCorners\n").number(mesh.corners.size()).put('\n');
    for(int c : mesh.corners)
      w.number(c + 1).put('\n');
  }
  w.text("\nEnd\n");
  w.flush();
}

/// \ingroup PkgBubbleMesh3IO
/// Writes `mesh` to the file `path` (see the stream overload). The data go
/// to a temporary file in the same directory, renamed to `path` only once
/// complete: a failed write never leaves a partial file under `path`.
/// Throws `Invalid_file` if the file cannot be written.
inline void write_medit(const std::string& path, const Indexed_tet_mesh_3& mesh)
{
  internal::check_mesh_for_writing(mesh);
  write_file_atomically(path, [&mesh](std::ostream& os) { write_medit(os, mesh); });
}

} // namespace IO
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_IO_MEDIT_H
