// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// JSON formatting shared by the reports (quality, validity): shortest
// round-trip numbers (non-finite as null) and string escaping.
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_JSON_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_JSON_H

#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <system_error>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

inline std::string format_json_number(double x)
{
  if(!std::isfinite(x))
    return "null";
  char buffer[64];
  const std::to_chars_result r = std::to_chars(buffer, buffer + sizeof(buffer), x);
  if(r.ec != std::errc())
    return "null";
  return std::string(buffer, r.ptr);
}

inline std::string escape_json(const std::string& s)
{
  std::string out;
  out.reserve(s.size() + 2);
  for(unsigned char ch : s) {
    switch(ch) {
    case '"': out += "\\\""; break;
    case '\\': out += "\\\\"; break;
    case '\n': out += "\\n"; break;
    case '\r': out += "\\r"; break;
    case '\t': out += "\\t"; break;
    default:
      if(ch < 0x20) {
        char u[8];
        std::snprintf(u, sizeof(u), "\\u%04x", static_cast<unsigned>(ch));
        out += u;
      } else {
        out += static_cast<char>(ch);
      }
    }
  }
  return out;
}

/// `s` escaped and quoted
inline std::string json_string(const std::string& s)
{
  return "\"" + escape_json(s) + "\"";
}

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_JSON_H
