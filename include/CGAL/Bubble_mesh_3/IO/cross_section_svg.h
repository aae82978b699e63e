// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_IO_CROSS_SECTION_SVG_H
#define CGAL_BUBBLE_MESH_3_IO_CROSS_SECTION_SVG_H

#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/IO/write_file_atomically.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/internal/json.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace IO {

/// An axis-aligned cutting plane: coordinate `axis` (0 x, 1 y, 2 z) equals `value`.
struct Section_plane {
  int axis = 1;
  double value = 0;
};

namespace internal_svg {
// red (0) -> yellow -> green -> blue (1)
inline std::string color(double t)
{
  t = std::min(1.0, std::max(0.0, t));
  const double stops[4][3] = {{215, 48, 39}, {254, 224, 99}, {102, 189, 99}, {49, 104, 170}};
  const double x = t * 3;
  const int k = std::min(2, int(x));
  const double f = x - k;
  char buffer[16];
  std::snprintf(buffer, sizeof(buffer), "#%02x%02x%02x", int(stops[k][0] + f * (stops[k + 1][0] - stops[k][0])),
                int(stops[k][1] + f * (stops[k + 1][1] - stops[k][1])),
                int(stops[k][2] + f * (stops[k + 1][2] - stops[k][2])));
  return buffer;
}
} // namespace internal_svg

/// \ingroup PkgBubbleMesh3IO
/// Writes the section of the tets by `plane` as an SVG picture: each cut tet
/// is a polygon filled by its value in `tet_values` (e.g. the metric minimum
/// dihedral angle, colour scale from `value_min` red to `value_max` blue),
/// edges drawn thin. The two remaining axes are drawn in increasing order
/// (horizontal, vertical upwards). Throws `Invalid_input` if `tet_values` is
/// not parallel to `mesh.tets` or no tet meets the plane.
inline void write_cross_section_svg(const std::string& path, const Indexed_tet_mesh_3& mesh, const Section_plane& plane,
                                    const std::vector<double>& tet_values, const std::string& title,
                                    double value_min = 0, double value_max = 70)
{
  if(tet_values.size() != mesh.tets.size())
    throw Invalid_input("cross section: " + std::to_string(tet_values.size()) + " values for " +
                        std::to_string(mesh.tets.size()) + " tets");
  if(plane.axis < 0 || plane.axis > 2)
    throw Invalid_input("cross section: axis must be 0, 1 or 2");
  const int u = plane.axis == 0 ? 1 : 0;
  const int v = plane.axis == 2 ? 1 : 2;
  struct Polygon {
    std::vector<std::array<double, 2>> p;
    double value;
  };
  std::vector<Polygon> polygons;
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  static const int edges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  for(std::size_t t = 0; t < mesh.tets.size(); ++t) {
    std::array<double, 4> s;
    for(int i = 0; i < 4; ++i)
      s[i] = mesh.points[mesh.tets[t][i]][plane.axis] - plane.value;
    if(*std::min_element(s.begin(), s.end()) > 0 || *std::max_element(s.begin(), s.end()) < 0)
      continue;
    Polygon poly;
    poly.value = tet_values[t];
    for(int i = 0; i < 4; ++i)
      if(s[i] == 0) {
        const auto& p = mesh.points[mesh.tets[t][i]];
        poly.p.push_back({{p[u], p[v]}});
      }
    for(const auto& e : edges) {
      const double a = s[e[0]], b = s[e[1]];
      if(!((a < 0 && b > 0) || (a > 0 && b < 0)))
        continue;
      const auto& p = mesh.points[mesh.tets[t][e[0]]];
      const auto& q = mesh.points[mesh.tets[t][e[1]]];
      const double f = a / (a - b);
      poly.p.push_back({{p[u] + f * (q[u] - p[u]), p[v] + f * (q[v] - p[v])}});
    }
    if(poly.p.size() < 3)
      continue;
    double cx = 0, cy = 0;
    for(const auto& p : poly.p) {
      cx += p[0] / double(poly.p.size());
      cy += p[1] / double(poly.p.size());
    }
    std::sort(poly.p.begin(), poly.p.end(), [&](const std::array<double, 2>& a, const std::array<double, 2>& b) {
      return std::atan2(a[1] - cy, a[0] - cx) < std::atan2(b[1] - cy, b[0] - cx);
    });
    for(const auto& p : poly.p)
      for(int k = 0; k < 2; ++k) {
        lo[k] = std::min(lo[k], p[k]);
        hi[k] = std::max(hi[k], p[k]);
      }
    polygons.push_back(std::move(poly));
  }
  if(polygons.empty())
    throw Invalid_input("cross section: no tet meets the plane " + std::string(1, "xyz"[plane.axis]) + " = " +
                        Bubble_mesh_3::internal::format_json_number(plane.value));
  const double width = 800, margin = 40, legend = 60;
  const double extent = std::max(hi[0] - lo[0], hi[1] - lo[1]);
  const double scale = extent > 0 ? (width - 2 * margin) / extent : 1;
  const double height = (hi[1] - lo[1]) * scale + 2 * margin + legend;
  auto X = [&](double x) { return margin + (x - lo[0]) * scale; };
  auto Y = [&](double y) { return margin + 20 + (hi[1] - y) * scale; };
  std::ostringstream svg;
  svg.setf(std::ios::fixed);
  svg.precision(2);
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height + 20
      << "\" viewBox=\"0 0 " << width << ' ' << height + 20 << "\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  std::string escaped;
  for(char c : title)
    escaped += c == '<' ? std::string("&lt;") : c == '&' ? std::string("&amp;") : std::string(1, c);
  svg << "<text x=\"" << margin << "\" y=\"24\" font-family=\"sans-serif\" font-size=\"16\">" << escaped << " — section "
      << "xyz"[plane.axis] << " = " << Bubble_mesh_3::internal::format_json_number(plane.value) << ", " << polygons.size()
      << " tets</text>\n<g stroke=\"#222\" stroke-width=\"0.4\">\n";
  for(const Polygon& poly : polygons) {
    svg << "<polygon fill=\"" << internal_svg::color((poly.value - value_min) / (value_max - value_min))
        << "\" points=\"";
    for(const auto& p : poly.p)
      svg << X(p[0]) << ',' << Y(p[1]) << ' ';
    svg << "\"/>\n";
  }
  svg << "</g>\n";
  // colour bar
  const double y0 = height - legend + 25;
  for(int i = 0; i < 100; ++i)
    svg << "<rect x=\"" << margin + i * 5 << "\" y=\"" << y0 << "\" width=\"5\" height=\"14\" fill=\""
        << internal_svg::color(i / 99.0) << "\"/>\n";
  svg << "<text x=\"" << margin << "\" y=\"" << y0 + 30 << "\" font-family=\"sans-serif\" font-size=\"12\">"
      << value_min << "</text><text x=\"" << margin + 470 << "\" y=\"" << y0 + 30
      << "\" font-family=\"sans-serif\" font-size=\"12\">" << value_max
      << "</text><text x=\"" << margin + 520 << "\" y=\"" << y0 + 12
      << "\" font-family=\"sans-serif\" font-size=\"12\">metric min dihedral angle (deg)</text>\n</svg>\n";
  write_text_file(path, svg.str());
}

} // namespace IO
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_IO_CROSS_SECTION_SVG_H
