// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_IO_READ_POLYGON_SOUP_H
#define CGAL_BUBBLE_MESH_3_IO_READ_POLYGON_SOUP_H

// Polygon-soup parsers for the surface formats the tool accepts (OFF, OBJ,
// STL, PLY), written for untrusted input: every count is checked against the
// bytes left in the file before anything is allocated, integers are parsed
// with overflow checks, truncated files are refused, and every refusal is an
// `Invalid_file` with one line naming the file, the format and the problem.

#include <CGAL/Bubble_mesh_3/exceptions.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <utility>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace IO {

/// \ingroup PkgBubbleMesh3IO
/// Points and polygons as read from a surface file: `polygons[f]` lists the
/// 0-based indices into `points` of the corners of face `f`. The PLY parser
/// does not check them against `points.size()` (the OFF, OBJ and STL parsers
/// give only indices in range).
struct Polygon_soup {
  std::vector<std::array<double, 3>> points;
  std::vector<std::vector<std::size_t>> polygons;
};

/// \ingroup PkgBubbleMesh3IO
/// The surface file formats of `read_polygon_soup()`.
enum class Surface_file_format { OFF, OBJ, STL, PLY };

namespace internal {

inline std::string lowercase_extension(const std::string& path)
{
  const std::size_t slash = path.find_last_of("/\\");
  const std::size_t dot = path.find_last_of('.');
  if(dot == std::string::npos || (slash != std::string::npos && dot < slash))
    return std::string();
  std::string ext = path.substr(dot + 1);
  for(char& c : ext)
    c = static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
  return ext;
}

namespace soup {

// ------------------------------------------------------------ errors

// Who is being parsed: "NAME: cannot parse as FORMAT: WHAT".
struct Context {
  const std::string& name;
  const char* format;

  [[noreturn]] void fail(const std::string& what) const
  {
    throw Invalid_file(name + ": cannot parse as " + format + ": " + what);
  }
  [[noreturn]] void fail_at(std::size_t line, const std::string& what) const
  {
    fail("line " + std::to_string(line) + ": " + what);
  }
};

// A token for a message: quoted, at most 40 characters, non-printable bytes
// as \xHH (the message stays one printable line whatever the input).
inline std::string quote(std::string_view t)
{
  static const char* const hex = "0123456789abcdef";
  std::string r = "'";
  const std::size_t n = std::min<std::size_t>(t.size(), 40);
  for(std::size_t i = 0; i < n; ++i) {
    const unsigned char c = static_cast<unsigned char>(t[i]);
    if(c >= 0x20 && c < 0x7f && c != '\\') {
      r += static_cast<char>(c);
    } else {
      r += "\\x";
      r += hex[c >> 4];
      r += hex[c & 15];
    }
  }
  if(t.size() > n)
    r += "...";
  return r + "'";
}

inline std::string str(std::uint64_t n) { return std::to_string(n); }

// ------------------------------------------------------------ numbers

// A decimal floating-point number filling the whole token (std::from_chars
// syntax plus an optional leading '+'; also "nan" and "inf", which the
// callers refuse where a finite value is needed). Values that underflow are
// accepted (as denormals or zero), values that overflow become infinite.
inline bool parse_double(std::string_view t, double& x)
{
  const char* b = t.data();
  const char* const e = b + t.size();
  if(b != e && *b == '+') {
    ++b;
    if(b == e || *b == '+' || *b == '-')
      return false;
  }
  if(b == e)
    return false;
  const std::from_chars_result r = std::from_chars(b, e, x);
  if(r.ptr != e)
    return false;
  if(r.ec == std::errc())
    return true;
  if(r.ec == std::errc::result_out_of_range) {
    // the syntax is valid: let strtod give the overflowed or underflowed value
    const std::string s(b, e);
    char* end = nullptr;
    x = std::strtod(s.c_str(), &end);
    return end == s.c_str() + s.size();
  }
  return false;
}

// A decimal integer filling the whole token, optional leading '+', no
// overflow (std::from_chars checks the range of I).
template <typename I>
bool parse_integer(std::string_view t, I& v)
{
  const char* b = t.data();
  const char* const e = b + t.size();
  if(b != e && *b == '+') {
    ++b;
    if(b == e || *b < '0' || *b > '9')
      return false;
  }
  if(b == e)
    return false;
  const std::from_chars_result r = std::from_chars(b, e, v);
  return r.ec == std::errc() && r.ptr == e;
}

inline bool finite(const std::array<double, 3>& p)
{
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

// ------------------------------------------------------------ text scanning

inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }
inline bool is_space(char c) { return is_blank(c) || c == '\n'; }

inline bool equal_ignoring_case(std::string_view a, const char* b)
{
  const std::size_t n = std::strlen(b);
  if(a.size() != n)
    return false;
  for(std::size_t i = 0; i < n; ++i) {
    char c = a[i];
    if(c >= 'A' && c <= 'Z')
      c = static_cast<char>(c - 'A' + 'a');
    if(c != b[i])
      return false;
  }
  return true;
}

// The lines of a text, numbered from 1, with `comment` (if not 0) and what
// follows it on the line removed.
class Lines {
public:
  Lines(const char* data, std::size_t size, char comment) : p_(data), end_(data + size), comment_(comment) {}

  bool next(std::string_view& line)
  {
    if(p_ == end_)
      return false;
    const char* b = p_;
    const char* nl = static_cast<const char*>(std::memchr(b, '\n', std::size_t(end_ - b)));
    const char* e = nl ? nl : end_;
    p_ = nl ? nl + 1 : end_;
    ++number_;
    if(comment_ != 0)
      if(const char* h = static_cast<const char*>(std::memchr(b, comment_, std::size_t(e - b))))
        e = h;
    line = std::string_view(b, std::size_t(e - b));
    return true;
  }
  // The next line that is not blank (after comment removal).
  bool next_content(std::string_view& line)
  {
    while(next(line))
      for(char c : line)
        if(!is_blank(c))
          return true;
    return false;
  }
  std::size_t number() const { return number_; }
  std::size_t bytes_left() const { return std::size_t(end_ - p_); }

private:
  const char* p_;
  const char* end_;
  char comment_;
  std::size_t number_ = 0;
};

// Blank-separated fields of one line.
class Fields {
public:
  explicit Fields(std::string_view line) : p_(line.data()), end_(line.data() + line.size()) {}
  bool next(std::string_view& t)
  {
    while(p_ != end_ && is_blank(*p_))
      ++p_;
    if(p_ == end_)
      return false;
    const char* b = p_;
    while(p_ != end_ && !is_blank(*p_))
      ++p_;
    t = std::string_view(b, std::size_t(p_ - b));
    return true;
  }
  std::string_view rest() const { return std::string_view(p_, std::size_t(end_ - p_)); }

private:
  const char* p_;
  const char* end_;
};

// Whitespace-separated tokens of a text (newlines included), with the line
// number of the last token.
class Tokens {
public:
  Tokens(const char* data, std::size_t size, std::size_t first_line = 1)
      : p_(data), end_(data + size), line_(first_line)
  {
  }
  bool next(std::string_view& t)
  {
    while(p_ != end_ && is_space(*p_)) {
      if(*p_ == '\n')
        ++line_;
      ++p_;
    }
    if(p_ == end_)
      return false;
    const char* b = p_;
    while(p_ != end_ && !is_space(*p_))
      ++p_;
    t = std::string_view(b, std::size_t(p_ - b));
    return true;
  }
  // Skips to the beginning of the next line.
  void skip_line()
  {
    const char* nl = static_cast<const char*>(std::memchr(p_, '\n', std::size_t(end_ - p_)));
    if(nl) {
      p_ = nl + 1;
      ++line_;
    } else {
      p_ = end_;
    }
  }
  std::size_t line() const { return line_; }
  std::size_t bytes_left() const { return std::size_t(end_ - p_); }

private:
  const char* p_;
  const char* end_;
  std::size_t line_;
};

// ------------------------------------------------------------ OFF

// [ST][C][N][4][n]OFF, in any order, each letter at most once.
struct Off_header {
  bool homogeneous = false; // 4: x y z w
  bool dimension = false;   // n: the dimension follows the keyword
};

inline bool parse_off_keyword(std::string_view k, Off_header& h)
{
  if(k.size() < 3 || k.substr(k.size() - 3) != "OFF")
    return false;
  const std::string_view prefix = k.substr(0, k.size() - 3);
  bool st = false, c = false, n = false;
  for(std::size_t i = 0; i < prefix.size(); ++i) {
    bool* flag = nullptr;
    if(prefix[i] == 'S' && i + 1 < prefix.size() && prefix[i + 1] == 'T') {
      flag = &st;
      ++i;
    } else if(prefix[i] == 'C') {
      flag = &c;
    } else if(prefix[i] == 'N') {
      flag = &n;
    } else if(prefix[i] == '4') {
      flag = &h.homogeneous;
    } else if(prefix[i] == 'n') {
      flag = &h.dimension;
    }
    if(flag == nullptr || *flag)
      return false;
    *flag = true;
  }
  return true;
}

inline Polygon_soup parse_off(const char* data, std::size_t size, const std::string& name)
{
  const Context cx{name, "off"};
  Polygon_soup soup;
  Lines lines(data, size, '#');
  std::string_view line, t;
  if(!lines.next_content(line))
    cx.fail(size == 0 ? "empty file" : "no OFF header (the file holds only comments and blank lines)");

  // Header: keyword (optional), [dimension], V F [E]; the dimension and the
  // counts may follow the keyword on its line.
  std::vector<std::string_view> header;
  Fields fields(line);
  fields.next(t);
  Off_header h;
  std::size_t header_line = lines.number();
  if(parse_off_keyword(t, h)) {
    while(fields.next(t))
      header.push_back(t);
    if(!header.empty() && header[0] == "BINARY")
      cx.fail_at(header_line, "binary OFF is not supported; convert the file to ASCII OFF");
  } else if(t.empty() || ((t[0] < '0' || t[0] > '9') && t[0] != '+')) {
    cx.fail_at(header_line, "expected an OFF header keyword such as OFF, COFF, NOFF or STOFF, got " + quote(t));
  } else {
    header.push_back(t); // no keyword: the counts come first
    while(fields.next(t))
      header.push_back(t);
  }
  std::size_t next = 0;
  auto header_token = [&]() -> std::string_view {
    if(next == header.size()) {
      if(!lines.next_content(line))
        cx.fail("unexpected end of file: expected the counts line 'VERTICES FACES EDGES'");
      header_line = lines.number();
      header.clear();
      next = 0;
      Fields f(line);
      while(f.next(t))
        header.push_back(t);
    }
    return header[next++];
  };
  if(h.dimension) {
    const std::string_view d = header_token();
    std::uint64_t dimension = 0;
    if(!parse_integer(d, dimension))
      cx.fail_at(header_line, "expected the dimension of nOFF, got " + quote(d));
    if(dimension != 3)
      cx.fail_at(header_line, "nOFF of dimension " + std::string(d) + " is not supported; only dimension 3");
  }
  std::uint64_t counts[2] = {0, 0};
  const char* const count_names[2] = {"vertex count", "face count"};
  for(int i = 0; i < 2; ++i) {
    const std::string_view c = header_token();
    if(!parse_integer(c, counts[i]))
      cx.fail_at(header_line, std::string("expected the ") + count_names[i] +
                                  " (a non-negative integer) in the counts line 'VERTICES FACES EDGES', got " +
                                  quote(c));
  }
  if(next < header.size()) {
    std::uint64_t edges = 0;
    if(!parse_integer(header[next], edges))
      cx.fail_at(header_line, "expected the edge count (a non-negative integer) in the counts line, got " +
                                  quote(header[next]));
    ++next;
  }
  if(next < header.size())
    cx.fail_at(header_line, "unexpected " + quote(header[next]) + " after the counts 'VERTICES FACES EDGES'");

  // Every vertex line holds at least 3 numbers ("0 0 0\n": 6 bytes), every
  // face line at least its size ("0\n"): refuse counts the file cannot hold
  // before allocating anything.
  const std::uint64_t nv = counts[0], nf = counts[1], left = lines.bytes_left();
  if(nv > left || nf > left || 6 * nv + 2 * nf > left + 1)
    cx.fail_at(header_line, "the header announces " + str(nv) + " vertices and " + str(nf) +
                                " faces, more than the " + str(left) + " bytes that follow can hold (truncated file?)");
  soup.points.reserve(std::size_t(nv));
  soup.polygons.reserve(std::size_t(nf));

  const int coordinates = h.homogeneous ? 4 : 3;
  for(std::uint64_t i = 0; i < nv; ++i) {
    if(!lines.next_content(line))
      cx.fail("unexpected end of file: expected vertex " + str(i) + " (0-based) of " + str(nv));
    Fields f(line);
    double x[4] = {0, 0, 0, 1};
    for(int k = 0; k < coordinates; ++k) {
      if(!f.next(t))
        cx.fail_at(lines.number(), "expected " + std::to_string(coordinates) + " coordinates for vertex " + str(i) +
                                       " (0-based), got only " + std::to_string(k));
      if(!parse_double(t, x[k]))
        cx.fail_at(lines.number(), "expected " + std::to_string(coordinates) + " coordinates for vertex " + str(i) +
                                       " (0-based), got " + quote(t));
      if(!std::isfinite(x[k]))
        cx.fail_at(lines.number(), "vertex " + str(i) + " (0-based) has a non-finite coordinate " + quote(t));
    }
    double extra;
    while(f.next(t))
      if(!parse_double(t, extra)) // normals, colours, texture coordinates: numbers
        cx.fail_at(lines.number(), "unexpected " + quote(t) + " after the coordinates of vertex " + str(i) +
                                       " (0-based)");
    std::array<double, 3> p = {{x[0], x[1], x[2]}};
    if(h.homogeneous) {
      if(x[3] == 0)
        cx.fail_at(lines.number(), "vertex " + str(i) + " (0-based) has homogeneous coordinate w = 0");
      for(double& c : p)
        c /= x[3];
      if(!finite(p))
        cx.fail_at(lines.number(), "vertex " + str(i) + " (0-based): x/w, y/w or z/w is not finite");
    }
    soup.points.push_back(p);
  }

  for(std::uint64_t i = 0; i < nf; ++i) {
    if(!lines.next_content(line))
      cx.fail("unexpected end of file: expected face " + str(i) + " (0-based) of " + str(nf));
    Fields f(line);
    f.next(t);
    std::uint64_t n = 0;
    if(!parse_integer(t, n))
      cx.fail_at(lines.number(), "expected the number of vertices of face " + str(i) +
                                     " (0-based, a non-negative integer), got " + quote(t));
    if(n > line.size() / 2) // each index takes a blank and a digit
      cx.fail_at(lines.number(), "face " + str(i) + " (0-based) announces " + str(n) +
                                     " vertices, more than its line holds");
    std::vector<std::size_t> face;
    face.reserve(std::size_t(n));
    for(std::uint64_t k = 0; k < n; ++k) {
      std::uint64_t v = 0;
      if(!f.next(t))
        cx.fail_at(lines.number(), "expected " + str(n) + " vertex indices for face " + str(i) + " (0-based), got only " +
                                       str(k));
      if(!parse_integer(t, v))
        cx.fail_at(lines.number(), "expected " + str(n) + " vertex indices for face " + str(i) +
                                       " (0-based, non-negative integers), got " + quote(t));
      if(v >= nv)
        cx.fail_at(lines.number(), "face " + str(i) + " (0-based) has vertex index " + str(v) + " out of range [0, " +
                                       str(nv) + ")");
      face.push_back(std::size_t(v));
    }
    double colour;
    while(f.next(t))
      if(!parse_double(t, colour))
        cx.fail_at(lines.number(), "unexpected " + quote(t) + " after the " + str(n) + " vertex indices of face " +
                                       str(i) + " (0-based)");
    soup.polygons.push_back(std::move(face));
  }
  return soup; // what follows the last face is ignored
}

// ------------------------------------------------------------ OBJ

inline Polygon_soup parse_obj(const char* data, std::size_t size, const std::string& name)
{
  const Context cx{name, "obj"};
  Polygon_soup soup;
  Lines lines(data, size, '#');
  std::string_view line, t;
  while(lines.next(line)) {
    Fields f(line);
    if(!f.next(t))
      continue;
    if(t == "v") {
      std::array<double, 3> p;
      for(int k = 0; k < 3; ++k) {
        if(!f.next(t))
          cx.fail_at(lines.number(), "expected 3 coordinates for vertex " + str(soup.points.size() + 1) +
                                         " (1-based), got only " + std::to_string(k));
        if(!parse_double(t, p[k]))
          cx.fail_at(lines.number(), "expected 3 coordinates for vertex " + str(soup.points.size() + 1) +
                                         " (1-based), got " + quote(t));
        if(!std::isfinite(p[k]))
          cx.fail_at(lines.number(), "vertex " + str(soup.points.size() + 1) +
                                         " (1-based) has a non-finite coordinate " + quote(t));
      }
      double extra; // a weight w, or colours
      while(f.next(t))
        if(!parse_double(t, extra))
          cx.fail_at(lines.number(), "unexpected " + quote(t) + " after the coordinates of vertex " +
                                         str(soup.points.size() + 1) + " (1-based)");
      soup.points.push_back(p);
    } else if(t == "f") {
      std::vector<std::size_t> face;
      while(f.next(t)) {
        // v, v/vt, v/vt/vn or v//vn; only v is used, the others must be integers
        std::string_view parts[3];
        std::size_t n_parts = 0, start = 0;
        for(;;) {
          const std::size_t slash = t.find('/', start);
          if(n_parts == 3)
            cx.fail_at(lines.number(), "malformed face vertex " + quote(t) + " (expected v, v/vt, v/vt/vn or v//vn)");
          parts[n_parts++] = t.substr(start, slash == std::string_view::npos ? std::string_view::npos : slash - start);
          if(slash == std::string_view::npos)
            break;
          start = slash + 1;
        }
        std::int64_t v = 0, other = 0;
        bool ok = parse_integer(parts[0], v);
        if(n_parts == 2)
          ok = ok && parse_integer(parts[1], other);
        if(n_parts == 3)
          ok = ok && (parts[1].empty() || parse_integer(parts[1], other)) && parse_integer(parts[2], other);
        if(!ok)
          cx.fail_at(lines.number(), "malformed face vertex " + quote(t) + " (expected v, v/vt, v/vt/vn or v//vn)");
        const std::uint64_t count = soup.points.size();
        if(v == 0)
          cx.fail_at(lines.number(), "vertex index 0 in face " + str(soup.polygons.size()) +
                                         " (0-based); OBJ indices start at 1 (or are negative, relative)");
        std::uint64_t index;
        if(v > 0) {
          index = std::uint64_t(v) - 1;
        } else {
          const std::uint64_t back = std::uint64_t(-(v + 1)) + 1; // |v| without overflow
          if(back > count)
            cx.fail_at(lines.number(), "relative vertex index " + std::to_string(v) + " in face " +
                                           str(soup.polygons.size()) + " (0-based) refers before the first vertex (" +
                                           str(count) + " vertices so far)");
          index = count - back;
        }
        face.push_back(std::size_t(index));
      }
      if(face.empty())
        cx.fail_at(lines.number(), "face " + str(soup.polygons.size()) + " (0-based) has no vertices");
      soup.polygons.push_back(std::move(face));
    }
    // vn, vt, vp, g, o, s, usemtl, mtllib, l, p and the rest: not geometry of
    // a triangle surface, ignored
  }
  const std::size_t n = soup.points.size();
  for(std::size_t i = 0; i < soup.polygons.size(); ++i)
    for(std::size_t v : soup.polygons[i])
      if(v >= n)
        cx.fail("face " + str(i) + " (0-based) refers to vertex " + str(std::uint64_t(v) + 1) +
                " (1-based), but the file defines " + str(n) + " vertices");
  return soup;
}

// ------------------------------------------------------------ STL

// Corners are merged into one vertex when their coordinates are equal (as
// values: -0 and 0 are the same corner).
class Corner_merger {
public:
  explicit Corner_merger(Polygon_soup& soup) : soup_(soup) {}
  std::size_t operator()(std::array<double, 3> p)
  {
    Key k;
    for(int i = 0; i < 3; ++i) {
      p[i] += 0.0; // -0 -> +0
      std::memcpy(&k[i], &p[i], sizeof(double));
    }
    const auto r = index_.emplace(k, soup_.points.size());
    if(r.second)
      soup_.points.push_back(p);
    return r.first->second;
  }

private:
  typedef std::array<std::uint64_t, 3> Key;
  struct Hash {
    std::size_t operator()(const Key& k) const
    {
      std::uint64_t h = k[0] * 0x9E3779B97F4A7C15ull;
      h = (h ^ (h >> 29) ^ k[1]) * 0xBF58476D1CE4E5B9ull;
      h = (h ^ (h >> 31) ^ k[2]) * 0x94D049BB133111EBull;
      return std::size_t(h ^ (h >> 32));
    }
  };
  Polygon_soup& soup_;
  std::unordered_map<Key, std::size_t, Hash> index_;
};

inline std::uint32_t load_le32(const unsigned char* b)
{
  return std::uint32_t(b[0]) | (std::uint32_t(b[1]) << 8) | (std::uint32_t(b[2]) << 16) | (std::uint32_t(b[3]) << 24);
}

inline float load_le_float(const unsigned char* b)
{
  const std::uint32_t u = load_le32(b);
  float f;
  std::memcpy(&f, &u, sizeof f);
  return f;
}

inline Polygon_soup parse_stl_binary(const unsigned char* data, const Context& cx)
{
  const std::uint64_t n = load_le32(data + 80);
  Polygon_soup soup;
  soup.polygons.reserve(std::size_t(n));
  Corner_merger merge(soup);
  for(std::uint64_t i = 0; i < n; ++i) {
    const unsigned char* b = data + 84 + 50 * i + 12; // after the normal
    std::vector<std::size_t> face(3);
    for(int k = 0; k < 3; ++k) {
      std::array<double, 3> p;
      for(int c = 0; c < 3; ++c)
        p[c] = double(load_le_float(b + 12 * k + 4 * c));
      if(!finite(p))
        cx.fail("binary STL: triangle " + str(i) + " (0-based) has a non-finite coordinate");
      face[k] = merge(p);
    }
    soup.polygons.push_back(std::move(face));
  }
  return soup;
}

inline Polygon_soup parse_stl_ascii(const char* data, std::size_t size, const Context& cx)
{
  Polygon_soup soup;
  Corner_merger merge(soup);
  Tokens tokens(data, size);
  std::string_view t;
  auto expect = [&](const char* keyword) {
    if(!tokens.next(t))
      cx.fail(std::string("unexpected end of file: expected '") + keyword + "' in facet " +
                                    str(soup.polygons.size()) + " (0-based)");
    if(!equal_ignoring_case(t, keyword))
      cx.fail_at(tokens.line(), std::string("expected '") + keyword + "' in facet " + str(soup.polygons.size()) +
                                    " (0-based), got " + quote(t));
  };
  auto number = [&](const char* what) {
    double x = 0;
    if(!tokens.next(t))
      cx.fail(std::string("unexpected end of file: expected ") + what + " in facet " +
                                    str(soup.polygons.size()) + " (0-based)");
    if(!parse_double(t, x))
      cx.fail_at(tokens.line(), std::string("expected ") + what + " in facet " + str(soup.polygons.size()) +
                                    " (0-based), got " + quote(t));
    return x;
  };
  tokens.next(t); // "solid", checked by the caller
  tokens.skip_line(); // the solid's name
  for(;;) {
    if(!tokens.next(t))
      cx.fail("unexpected end of file: expected 'facet' or 'endsolid' (truncated file?)");
    if(equal_ignoring_case(t, "endsolid")) {
      tokens.skip_line();
      if(!tokens.next(t))
        break;
      if(!equal_ignoring_case(t, "solid"))
        cx.fail_at(tokens.line(), "unexpected " + quote(t) + " after 'endsolid'");
      tokens.skip_line(); // another solid follows
      continue;
    }
    if(!equal_ignoring_case(t, "facet"))
      cx.fail_at(tokens.line(), "expected 'facet' or 'endsolid', got " + quote(t));
    expect("normal");
    for(int c = 0; c < 3; ++c)
      number("a normal coordinate");
    expect("outer");
    expect("loop");
    std::vector<std::size_t> face(3);
    for(int k = 0; k < 3; ++k) {
      expect("vertex");
      std::array<double, 3> p;
      for(int c = 0; c < 3; ++c) {
        p[c] = number("a vertex coordinate");
        if(!std::isfinite(p[c]))
          cx.fail_at(tokens.line(), "facet " + str(soup.polygons.size()) + " (0-based) has a non-finite coordinate " +
                                        quote(t));
      }
      face[k] = merge(p);
    }
    expect("endloop");
    expect("endfacet");
    soup.polygons.push_back(std::move(face));
  }
  return soup;
}

inline Polygon_soup parse_stl(const char* data, std::size_t size, const std::string& name)
{
  const Context cx{name, "stl"};
  const unsigned char* u = reinterpret_cast<const unsigned char*>(data);
  std::size_t i = 0;
  while(i < size && is_space(data[i]))
    ++i;
  const bool solid = size - i >= 5 && equal_ignoring_case(std::string_view(data + i, 5), "solid") &&
                     (size - i == 5 || is_space(data[i + 5]));
  // Text: no control byte other than white space (binary STL data has
  // zeros: in 1.0f, 0.0f and the attribute bytes).
  bool text = true;
  for(std::size_t k = 0; k < size && text; ++k)
    text = u[k] >= 0x20 || is_space(data[k]);
  const std::uint64_t announced = size >= 84 ? load_le32(u + 80) : 0;
  const bool binary_size = size >= 84 && 84 + 50 * announced == size;
  if(binary_size && !(solid && text))
    return parse_stl_binary(u, cx);
  if(solid && text)
    return parse_stl_ascii(data, size, cx);
  if(size == 0)
    cx.fail("empty file");
  const std::string as_binary = solid ? "it starts with 'solid' but holds binary data, so it is read as binary STL: "
                                      : "it does not start with 'solid', so it is read as binary STL: ";
  if(size < 84)
    cx.fail(as_binary + str(size) + " bytes, shorter than the 84-byte header");
  cx.fail(as_binary + "the header announces " + str(announced) + " triangles, i.e. 84 + 50 x " + str(announced) +
          " = " + str(84 + 50 * announced) + " bytes, but the file has " + str(size) +
          " bytes (truncated or corrupt)");
}

// ------------------------------------------------------------ PLY

enum class Ply_type { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

inline bool ply_type(std::string_view n, Ply_type& t)
{
  static const struct {
    const char* a;
    const char* b;
    Ply_type t;
  } names[] = {{"char", "int8", Ply_type::int8},       {"uchar", "uint8", Ply_type::uint8},
               {"short", "int16", Ply_type::int16},    {"ushort", "uint16", Ply_type::uint16},
               {"int", "int32", Ply_type::int32},      {"uint", "uint32", Ply_type::uint32},
               {"float", "float32", Ply_type::float32}, {"double", "float64", Ply_type::float64}};
  for(const auto& e : names)
    if(n == e.a || n == e.b) {
      t = e.t;
      return true;
    }
  return false;
}

inline std::size_t ply_size(Ply_type t)
{
  switch(t) {
  case Ply_type::int8:
  case Ply_type::uint8: return 1;
  case Ply_type::int16:
  case Ply_type::uint16: return 2;
  case Ply_type::int32:
  case Ply_type::uint32:
  case Ply_type::float32: return 4;
  case Ply_type::float64: return 8;
  }
  return 8;
}

inline bool ply_integer(Ply_type t) { return t != Ply_type::float32 && t != Ply_type::float64; }

struct Ply_property {
  std::string name;
  bool list = false;
  Ply_type type = Ply_type::float32;       // the value type (entries of a list)
  Ply_type count_type = Ply_type::uint8;   // lists only
  int role = -1;                           // 0, 1, 2: x, y, z of the vertex element; 3: face indices
};

struct Ply_element {
  std::string name;
  std::uint64_t count = 0;
  std::size_t line = 0;
  std::vector<Ply_property> properties;
};

// Binary values, either byte order.
class Ply_binary {
public:
  Ply_binary(const unsigned char* p, const unsigned char* end, bool big_endian)
      : p_(p), end_(end), begin_(p)
  {
    const std::uint16_t one = 1;
    unsigned char first;
    std::memcpy(&first, &one, 1);
    swap_ = (first == 1) == big_endian;
  }
  std::size_t left() const { return std::size_t(end_ - p_); }
  std::size_t offset() const { return std::size_t(p_ - begin_); }
  void skip(std::size_t n) { p_ += n; } // n <= left(), checked by the caller

  // The next value (the caller checked that there is room).
  template <typename T>
  T load()
  {
    unsigned char b[sizeof(T)];
    std::memcpy(b, p_, sizeof(T));
    p_ += sizeof(T);
    if(swap_)
      std::reverse(b, b + sizeof(T));
    T v;
    std::memcpy(&v, b, sizeof(T));
    return v;
  }
  double load_double(Ply_type t)
  {
    switch(t) {
    case Ply_type::int8: return load<std::int8_t>();
    case Ply_type::uint8: return load<std::uint8_t>();
    case Ply_type::int16: return load<std::int16_t>();
    case Ply_type::uint16: return load<std::uint16_t>();
    case Ply_type::int32: return load<std::int32_t>();
    case Ply_type::uint32: return load<std::uint32_t>();
    case Ply_type::float32: return double(load<float>());
    case Ply_type::float64: return load<double>();
    }
    return 0;
  }
  std::int64_t load_integer(Ply_type t) // t is an integer type
  {
    switch(t) {
    case Ply_type::int8: return load<std::int8_t>();
    case Ply_type::uint8: return load<std::uint8_t>();
    case Ply_type::int16: return load<std::int16_t>();
    case Ply_type::uint16: return load<std::uint16_t>();
    case Ply_type::int32: return load<std::int32_t>();
    default: return load<std::uint32_t>();
    }
  }

private:
  const unsigned char* p_;
  const unsigned char* end_;
  const unsigned char* begin_;
  bool swap_;
};

enum Ply_format { ply_none, ply_ascii, ply_little, ply_big };

struct Ply_header {
  Ply_format format = ply_none;
  std::string format_text;
  std::vector<Ply_element> elements;
};

// The header after the 'ply' line, up to 'end_header' (refused: unknown or
// repeated lines, bad types, a missing format).
inline Ply_header read_ply_header(Lines& lines, const Context& cx)
{
  std::string_view line, t;
  Ply_header h;
  bool end_header = false;
  while(!end_header && lines.next(line)) {
    const std::size_t ln = lines.number();
    Fields f(line);
    std::vector<std::string_view> w;
    if(f.next(t)) {
      w.push_back(t);
      if(t == "comment" || t == "obj_info")
        continue;
      while(f.next(t))
        w.push_back(t);
    }
    if(w.empty())
      continue; // blank header line
    if(w[0] != "end_header" && lines.bytes_left() == 0)
      cx.fail("the header has no 'end_header' line (truncated file?)");
    if(w[0] == "end_header") {
      if(w.size() != 1)
        cx.fail_at(ln, "unexpected " + quote(w[1]) + " after 'end_header'");
      end_header = true;
    } else if(w[0] == "format") {
      if(h.format != ply_none)
        cx.fail_at(ln, "a second 'format' line");
      if(w.size() != 3)
        cx.fail_at(ln, "expected 'format ascii|binary_little_endian|binary_big_endian 1.0', got " + quote(line));
      if(w[1] == "ascii")
        h.format = ply_ascii;
      else if(w[1] == "binary_little_endian")
        h.format = ply_little;
      else if(w[1] == "binary_big_endian")
        h.format = ply_big;
      else
        cx.fail_at(ln, "unknown format " + quote(w[1]) + " (expected ascii, binary_little_endian or binary_big_endian)");
      if(w[2] != "1.0" && w[2] != "1")
        cx.fail_at(ln, "unsupported PLY version " + quote(w[2]) + " (expected 1.0)");
      h.format_text = std::string(w[1]);
    } else if(w[0] == "element") {
      if(w.size() != 3)
        cx.fail_at(ln, "expected 'element NAME COUNT', got " + quote(line));
      Ply_element e;
      e.name = std::string(w[1]);
      e.line = ln;
      if(!parse_integer(w[2], e.count))
        cx.fail_at(ln, "expected the count of element " + quote(e.name) + " (a non-negative integer), got " + quote(w[2]));
      for(const Ply_element& o : h.elements)
        if(o.name == e.name && (e.name == "vertex" || e.name == "face"))
          cx.fail_at(ln, "a second " + quote(e.name) + " element");
      h.elements.push_back(std::move(e));
    } else if(w[0] == "property") {
      if(h.elements.empty())
        cx.fail_at(ln, "'property' before any 'element' line");
      Ply_property p;
      if(w.size() == 3) {
        if(!ply_type(w[1], p.type))
          cx.fail_at(ln, "unknown property type " + quote(w[1]));
        p.name = std::string(w[2]);
      } else if(w.size() == 5 && w[1] == "list") {
        if(!ply_type(w[2], p.count_type))
          cx.fail_at(ln, "unknown list count type " + quote(w[2]));
        if(!ply_integer(p.count_type))
          cx.fail_at(ln, "the list count type must be an integer type, got " + quote(w[2]));
        if(!ply_type(w[3], p.type))
          cx.fail_at(ln, "unknown list entry type " + quote(w[3]));
        p.list = true;
        p.name = std::string(w[4]);
      } else {
        cx.fail_at(ln, "expected 'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME', got " + quote(line));
      }
      Ply_element& e = h.elements.back();
      for(const Ply_property& o : e.properties)
        if(o.name == p.name)
          cx.fail_at(ln, "a second property " + quote(p.name) + " in element " + quote(e.name));
      if(e.name == "vertex" && (p.name == "x" || p.name == "y" || p.name == "z")) {
        if(p.list)
          cx.fail_at(ln, "vertex coordinate " + quote(p.name) + " is a list");
        p.role = p.name[0] - 'x';
      }
      if(e.name == "face" && (p.name == "vertex_indices" || p.name == "vertex_index")) {
        if(!p.list)
          cx.fail_at(ln, "face property " + quote(p.name) + " is not a list");
        if(!ply_integer(p.type))
          cx.fail_at(ln, "the vertex indices must have an integer type, got " + quote(w[3]));
        for(const Ply_property& o : e.properties)
          if(o.role == 3)
            cx.fail_at(ln, "face element with both 'vertex_indices' and 'vertex_index'");
        p.role = 3;
      }
      e.properties.push_back(std::move(p));
    } else {
      cx.fail_at(ln, "unknown header line " + quote(line));
    }
  }
  if(!end_header)
    cx.fail("the header has no 'end_header' line (truncated file?)");
  if(h.format == ply_none)
    cx.fail("the header has no 'format' line");

  return h;
}

// The 'vertex' element (with x, y and z) and the 'face' element (with its
// index list) if there is one.
inline void find_ply_elements(const Ply_header& h, const Context& cx, const Ply_element*& vertex,
                              const Ply_element*& face)
{
  vertex = nullptr;
  face = nullptr;
  for(const Ply_element& e : h.elements) {
    if(e.name == "vertex")
      vertex = &e;
    if(e.name == "face")
      face = &e;
  }
  if(vertex == nullptr)
    cx.fail("the header declares no 'vertex' element");
  for(int c = 0; c < 3; ++c) {
    bool found = false;
    for(const Ply_property& p : vertex->properties)
      found = found || p.role == c;
    if(!found)
      cx.fail_at(vertex->line, std::string("the 'vertex' element has no property '") + char('x' + c) + "'");
  }
  if(face != nullptr) {
    bool found = false;
    for(const Ply_property& p : face->properties)
      found = found || p.role == 3;
    if(!found)
      cx.fail_at(face->line, "the 'face' element has no 'vertex_indices' (or 'vertex_index') list");
  }

}

inline void check_ply_counts(const Ply_header& h, std::size_t data_size, const Context& cx)
{
  // Every item takes at least its minimum size (binary: the scalars and the
  // list counts; ASCII: one digit and one blank per property), and the
  // elements follow each other: refuse counts the data cannot hold before
  // allocating anything.
  std::uint64_t budget = std::uint64_t(data_size) + (h.format == ply_ascii ? 1 : 0); // the last blank may be missing
  for(const Ply_element& e : h.elements) {
    std::uint64_t minimum = 0;
    for(const Ply_property& p : e.properties)
      minimum += h.format == ply_ascii ? 2 : ply_size(p.list ? p.count_type : p.type);
    if(minimum == 0)
      continue;
    if(e.count > budget / minimum)
      cx.fail_at(e.line, "element " + quote(e.name) + " announces " + str(e.count) + " items of at least " +
                             str(minimum) + " bytes, more than the " + str(data_size) + " bytes of data hold" +
                             (budget < data_size ? " after the elements before it" : "") + " (truncated file?)");
    budget -= e.count * minimum;
  }
}

inline std::string ply_item_text(const Ply_element& e, std::uint64_t i)
{
  return "element " + quote(e.name) + " item " + str(i) + " (0-based) of " + str(e.count);
}

// Calls `read(e, i, p, is_vertex, is_face, point, polygon)` for every
// property of every item of every element of the data, in order, and keeps
// the vertices' points and the faces' index lists.
template <typename Read_property>
void for_each_ply_property(const Ply_header& h, const Ply_element* vertex, const Ply_element* face,
                           Polygon_soup& soup, const Read_property& read)
{
  for(const Ply_element& e : h.elements) {
    if(e.properties.empty())
      continue;
    const bool is_vertex = &e == vertex, is_face = &e == face;
    for(std::uint64_t i = 0; i < e.count; ++i) {
      std::array<double, 3> point = {{0, 0, 0}};
      std::vector<std::size_t> polygon;
      for(const Ply_property& p : e.properties) {
        read(e, i, p, is_vertex, is_face, point, polygon);
      }
      if(is_vertex)
        soup.points.push_back(point);
      if(is_face)
        soup.polygons.push_back(std::move(polygon));
    }
  }
}

// The ASCII data after the header (what follows the last element is ignored).
inline void read_ply_ascii(const char* data, std::size_t size, std::size_t first_line, const Ply_header& h,
                           const Ply_element* vertex, const Ply_element* face, const Context& cx, Polygon_soup& soup)
{
  std::string_view t;
  Tokens tokens(data, size, first_line);
  for_each_ply_property(h, vertex, face, soup,
                        [&](const Ply_element& e, std::uint64_t i, const Ply_property& p, bool is_vertex,
                            bool is_face, std::array<double, 3>& point, std::vector<std::size_t>& polygon) {
    auto next = [&](const char* what) {
      if(!tokens.next(t))
        cx.fail("unexpected end of file in " + ply_item_text(e, i) + ": expected " + what +
                                      " of property " + quote(p.name));
    };
    if(!p.list) {
      next("the value");
      double x = 0;
      if(!parse_double(t, x))
        cx.fail_at(tokens.line(), "expected a number for property " + quote(p.name) + " of " + ply_item_text(e, i) +
                                      ", got " + quote(t));
      if(is_vertex && p.role >= 0) {
        if(!std::isfinite(x))
          cx.fail_at(tokens.line(), "vertex " + str(i) + " (0-based) has a non-finite coordinate " + quote(t));
        point[std::size_t(p.role)] = x;
      }
      return; // the next property
    }
    next("the list length");
    std::uint64_t n = 0;
    if(!parse_integer(t, n))
      cx.fail_at(tokens.line(), "expected the list length (a non-negative integer) of property " + quote(p.name) +
                                    " of " + ply_item_text(e, i) + ", got " + quote(t));
    if(n > (tokens.bytes_left() + 1) / 2)
      cx.fail_at(tokens.line(), "the list " + quote(p.name) + " of " + ply_item_text(e, i) + " announces " + str(n) +
                                    " entries, more than the rest of the file holds");
    const bool indices = is_face && p.role == 3;
    if(indices)
      polygon.reserve(std::size_t(n));
    for(std::uint64_t k = 0; k < n; ++k) {
      next("a list entry");
      if(indices) {
        std::uint64_t v = 0;
        if(!parse_integer(t, v))
          cx.fail_at(tokens.line(), "expected a vertex index (a non-negative integer) in face " + str(i) +
                                        " (0-based), got " + quote(t));
        polygon.push_back(std::size_t(v));
      } else {
        double x;
        if(!parse_double(t, x))
          cx.fail_at(tokens.line(), "expected a number in the list " + quote(p.name) + " of " + ply_item_text(e, i) +
                                        ", got " + quote(t));
      }
    }
                        });
}

// The binary data, from byte `data_offset` of the file (messages name it with
// `where`).
inline void read_ply_binary(const char* data, std::size_t size, std::size_t data_offset, const Ply_header& h,
                            const Ply_element* vertex, const Ply_element* face, const std::string& where,
                            const Context& cx, Polygon_soup& soup)
{
  Ply_binary in(reinterpret_cast<const unsigned char*>(data + data_offset),
                reinterpret_cast<const unsigned char*>(data + size), h.format == ply_big);
  for_each_ply_property(h, vertex, face, soup,
                        [&](const Ply_element& e, std::uint64_t i, const Ply_property& p, bool is_vertex,
                            bool is_face, std::array<double, 3>& point, std::vector<std::size_t>& polygon) {
    auto need = [&](std::uint64_t bytes, const char* what) {
      if(bytes > in.left())
        cx.fail(where + "the file ends inside " + ply_item_text(e, i) + " (" + what + " of property " + quote(p.name) +
                " at byte " + str(data_offset + in.offset()) + " needs " + str(bytes) + " bytes, " +
                str(in.left()) + " left; truncated file?)");
    };
    if(!p.list) {
      need(ply_size(p.type), "the value");
      if(is_vertex && p.role >= 0)
        point[std::size_t(p.role)] = in.load_double(p.type);
      else
        in.skip(ply_size(p.type));
      return; // the next property
    }
    need(ply_size(p.count_type), "the list length");
    const std::int64_t n = in.load_integer(p.count_type);
    if(n < 0)
      cx.fail(where + "negative list length " + std::to_string(n) + " of property " + quote(p.name) + " in " +
              ply_item_text(e, i));
    const std::uint64_t entry = ply_size(p.type);
    if(std::uint64_t(n) > in.left() / entry)
      cx.fail(where + "the list " + quote(p.name) + " of " + ply_item_text(e, i) + " announces " + std::to_string(n) +
              " entries (" + str(std::uint64_t(n) * entry) + " bytes), more than the " + str(in.left()) +
              " bytes left (truncated or corrupt file)");
    if(is_face && p.role == 3) {
      polygon.reserve(std::size_t(n));
      for(std::int64_t k = 0; k < n; ++k) {
        const std::int64_t v = in.load_integer(p.type);
        if(v < 0)
          cx.fail(where + "face " + str(i) + " (0-based) has a negative vertex index " + std::to_string(v));
        polygon.push_back(std::size_t(v));
      }
    } else {
      in.skip(std::size_t(std::uint64_t(n) * entry));
    }
                        });
}

inline Polygon_soup parse_ply(const char* data, std::size_t size, const std::string& name)
{
  const Context cx{name, "ply"};
  Lines lines(data, size, 0);
  std::string_view line, t;
  if(size == 0)
    cx.fail("empty file");
  lines.next(line);
  {
    Fields f(line);
    if(!f.next(t) || t != "ply" || f.next(t))
      cx.fail_at(1, "expected 'ply' on the first line, got " + quote(line));
  }
  const Ply_header h = read_ply_header(lines, cx);
  const Ply_element* vertex = nullptr;
  const Ply_element* face = nullptr;
  find_ply_elements(h, cx, vertex, face);
  const std::size_t data_size = lines.bytes_left();
  const std::size_t data_offset = size - data_size;
  check_ply_counts(h, data_size, cx);
  Polygon_soup soup;
  soup.points.reserve(std::size_t(vertex->count));
  if(face != nullptr)
    soup.polygons.reserve(std::size_t(face->count));
  if(h.format == ply_ascii)
    read_ply_ascii(data + data_offset, data_size, lines.number() + 1, h, vertex, face, cx, soup);
  else
    read_ply_binary(data, size, data_offset, h, vertex, face, h.format_text + " data: ", cx, soup);
  return soup;
}

} // namespace soup

// The whole file, read once. Throws `Invalid_file` if it cannot be opened
// or read (a directory, an I/O error).
inline std::string read_file_contents(const std::string& path)
{
  std::error_code ec;
  if(std::filesystem::is_directory(path, ec))
    throw Invalid_file(path + ": cannot read file (it is a directory)");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if(f == nullptr)
    throw Invalid_file(path + ": cannot open file for reading");
  std::string data;
  const std::uintmax_t announced = std::filesystem::file_size(path, ec);
  if(!ec && announced < (std::uintmax_t(1) << 40))
    data.reserve(std::size_t(announced)); // a regular file; otherwise read until the end
  char buffer[1 << 16];
  std::size_t n;
  while((n = std::fread(buffer, 1, sizeof buffer, f)) > 0)
    data.append(buffer, n);
  const bool failed = std::ferror(f) != 0;
  const int error = errno;
  std::fclose(f);
  if(failed)
    throw Invalid_file(path + ": cannot read file (" + std::strerror(error) + ")");
  return data;
}

} // namespace internal

/// \ingroup PkgBubbleMesh3IO
/// Parses the surface file held in `data[0, size)` as `format`; `name` (the
/// file path) starts every error message. The parsers (the package's own,
/// not CGAL's) accept:
/// - OFF: ASCII, header keyword `OFF` with any of the prefixes `ST`, `C`,
///   `N`, `4` (homogeneous coordinates, divided by `w`) and `n` (dimension 3
///   only), or no keyword; `#` comments; the counts line `V F [E]`; one
///   vertex per line (extra numbers after the coordinates, i.e. normals,
///   colours and texture coordinates, are ignored); one face per line
///   `n i1 ... in [colour]`. Binary OFF is refused.
/// - OBJ: `v x y z [w]` (`w` and any further numbers ignored), `f` with
///   `v`, `v/vt`, `v/vt/vn` or `v//vn` corners and negative (relative)
///   indices, `#` comments; every other statement is ignored (no `\` line
///   continuation).
/// - STL: ASCII (`solid` ... `endsolid`, keywords case-insensitive, several
///   solids) and binary (80-byte header, count, 50 bytes per triangle; the
///   size must be exactly 84 + 50 n). A file is binary if its size matches
///   and it does not start with `solid` followed by text only. Corners with
///   equal coordinates are merged into one vertex.
/// - PLY: `ascii`, `binary_little_endian` and `binary_big_endian` 1.0, every
///   scalar type name of the specification, `comment` and `obj_info` lines;
///   the `vertex` element's `x`, `y`, `z` and the `face` element's
///   `vertex_indices` (or `vertex_index`) list are read, every other
///   property and element is skipped.
///
/// Every count is checked against the bytes left before anything is
/// allocated, integers are checked for overflow, truncated files are
/// refused, ASCII coordinates must be finite. Throws `Invalid_file`:
/// `NAME: cannot parse as FORMAT: [line L: ]PROBLEM` (FORMAT: off, obj, stl
/// or ply).
inline Polygon_soup parse_polygon_soup(const char* data, std::size_t size, Surface_file_format format,
                                       const std::string& name)
{
  switch(format) {
  case Surface_file_format::OFF: return internal::soup::parse_off(data, size, name);
  case Surface_file_format::OBJ: return internal::soup::parse_obj(data, size, name);
  case Surface_file_format::STL: return internal::soup::parse_stl(data, size, name);
  case Surface_file_format::PLY: return internal::soup::parse_ply(data, size, name);
  }
  return Polygon_soup();
}

/// \ingroup PkgBubbleMesh3IO
/// Reads the surface file `path` (read once into memory) with
/// `parse_polygon_soup()`, the format chosen by the extension
/// (case-insensitive): `.off`, `.obj`, `.stl` or `.ply`. Throws
/// `Invalid_file` if the file cannot be opened or read, has another
/// extension, or does not parse.
inline Polygon_soup read_polygon_soup(const std::string& path)
{
  const std::string ext = internal::lowercase_extension(path);
  Surface_file_format format;
  if(ext == "off")
    format = Surface_file_format::OFF;
  else if(ext == "obj")
    format = Surface_file_format::OBJ;
  else if(ext == "stl")
    format = Surface_file_format::STL;
  else if(ext == "ply")
    format = Surface_file_format::PLY;
  else
    throw Invalid_file(path + ": unknown surface file extension '" + ext + "' (expected .off, .obj, .stl or .ply)");
  const std::string data = internal::read_file_contents(path);
  return parse_polygon_soup(data.data(), data.size(), format, path);
}

} // namespace IO
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_IO_READ_POLYGON_SOUP_H
