// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_IO_READ_TRIANGLE_SURFACE_H
#define CGAL_BUBBLE_MESH_3_IO_READ_TRIANGLE_SURFACE_H

#include <CGAL/Bubble_mesh_3/exceptions.h>

#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/number_utils.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace IO {
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

struct Pair_hash {
  std::size_t operator()(const std::pair<std::size_t, std::size_t>& e) const
  {
    return std::hash<std::size_t>()(e.first * 0x9E3779B97F4A7C15ull ^ e.second);
  }
};

} // namespace internal

/// \ingroup PkgBubbleMesh3IO
/// Reads the closed triangle surface `path` into a `Surface_mesh`. The format
/// is chosen by the extension (case-insensitive): `.off` (OFF and COFF),
/// `.obj`, `.stl` (ASCII or binary; duplicated corners are merged by CGAL's
/// reader) or `.ply`, read through `CGAL::IO::read_polygon_soup()`.
///
/// The surface must be made of triangles only, have finite coordinates, and
/// be closed and manifold: every edge shared by exactly two faces and every
/// vertex with a single fan of faces. If the faces are not consistently
/// oriented they are reoriented (only their vertex order changes); whether the
/// result is outward-oriented is not checked here.
///
/// Throws `Invalid_file` naming `path` and the reason: the file cannot be
/// opened or parsed, unknown extension, no faces, a face that is not a
/// triangle (which face, how many vertices), a degenerate face (repeated
/// vertex), a non-finite coordinate, boundary edges (how many), edges shared
/// by more than two faces (how many), non-manifold vertices, or a
/// non-orientable surface.
///
/// \tparam K a CGAL kernel whose `Point_3` is the point type of the result.
template <typename K>
CGAL::Surface_mesh<typename K::Point_3> read_triangle_surface(const std::string& path)
{
  typedef typename K::Point_3 Point_3;
  typedef CGAL::Surface_mesh<Point_3> Mesh;

  {
    std::ifstream probe(path, std::ios::binary);
    if(!probe)
      throw Invalid_file(path + ": cannot open file for reading");
  }
  const std::string ext = internal::lowercase_extension(path);
  if(ext != "off" && ext != "obj" && ext != "stl" && ext != "ply")
    throw Invalid_file(path + ": unknown surface file extension '" + ext +
                       "' (expected .off, .obj, .stl or .ply)");

  std::vector<Point_3> points;
  std::vector<std::vector<std::size_t>> polygons;
  bool ok = false;
  try {
    ok = CGAL::IO::read_polygon_soup(path, points, polygons);
  } catch(const std::exception& e) {
    throw Invalid_file(path + ": cannot parse as " + ext + " (" + e.what() + ")");
  }
  if(!ok)
    throw Invalid_file(path + ": cannot parse as " + ext + " (malformed or unsupported file)");
  if(polygons.empty())
    throw Invalid_file(path + ": the surface has no faces");

  for(std::size_t i = 0; i < points.size(); ++i)
    if(!std::isfinite(CGAL::to_double(points[i].x())) || !std::isfinite(CGAL::to_double(points[i].y())) ||
       !std::isfinite(CGAL::to_double(points[i].z())))
      throw Invalid_file(path + ": vertex " + std::to_string(i) + " (0-based) has a non-finite coordinate");

  for(std::size_t f = 0; f < polygons.size(); ++f) {
    const std::vector<std::size_t>& face = polygons[f];
    if(face.size() != 3)
      throw Invalid_file(path + ": face " + std::to_string(f) + " (0-based) has " + std::to_string(face.size()) +
                         " vertices; only triangle surfaces are accepted (triangulate it first)");
    for(std::size_t v : face)
      if(v >= points.size())
        throw Invalid_file(path + ": face " + std::to_string(f) + " (0-based) has vertex index " +
                           std::to_string(v) + " out of range [0, " + std::to_string(points.size()) + ")");
    if(face[0] == face[1] || face[1] == face[2] || face[0] == face[2])
      throw Invalid_file(path + ": face " + std::to_string(f) + " (0-based) is degenerate (repeated vertex)");
  }

  // Edge incidences, independent of orientation.
  std::unordered_map<std::pair<std::size_t, std::size_t>, int, internal::Pair_hash> edge_faces;
  edge_faces.reserve(polygons.size() * 2);
  for(const std::vector<std::size_t>& face : polygons)
    for(int k = 0; k < 3; ++k) {
      const std::size_t a = face[k], b = face[(k + 1) % 3];
      ++edge_faces[std::make_pair(std::min(a, b), std::max(a, b))];
    }
  std::size_t boundary = 0, non_manifold = 0;
  std::pair<std::size_t, std::size_t> boundary_example, non_manifold_example;
  for(const auto& e : edge_faces) {
    if(e.second == 1 && boundary++ == 0)
      boundary_example = e.first;
    if(e.second > 2 && non_manifold++ == 0)
      non_manifold_example = e.first;
  }
  auto edge_text = [](const std::pair<std::size_t, std::size_t>& e) {
    return "(vertices " + std::to_string(e.first) + " and " + std::to_string(e.second) + ", 0-based)";
  };
  if(non_manifold > 0)
    throw Invalid_file(path + ": non-manifold surface: " + std::to_string(non_manifold) +
                       " edges are shared by more than two faces, e.g. " + edge_text(non_manifold_example));
  if(boundary > 0)
    throw Invalid_file(path + ": the surface is not closed: " + std::to_string(boundary) +
                       " boundary edges, e.g. " + edge_text(boundary_example));

  namespace PMP = CGAL::Polygon_mesh_processing;
  if(!PMP::is_polygon_soup_a_polygon_mesh(polygons)) {
    // Either inconsistent face orientations (repaired by reorienting) or
    // pinched vertices / a non-orientable surface (refused).
    std::vector<Point_3> oriented_points = points;
    const bool oriented = PMP::orient_polygon_soup(oriented_points, polygons);
    if(!oriented || oriented_points.size() != points.size()) {
      const std::size_t duplicated = oriented_points.size() - points.size();
      if(duplicated > 0)
        throw Invalid_file(path + ": non-manifold surface: " + std::to_string(duplicated) +
                           " vertex copies needed to make it a manifold (pinched vertices or a non-orientable"
                           " surface)");
      throw Invalid_file(path + ": the surface is not orientable or not manifold");
    }
    if(!PMP::is_polygon_soup_a_polygon_mesh(polygons))
      throw Invalid_file(path + ": the faces cannot be assembled into a manifold polygon mesh");
  }

  Mesh mesh;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
  if(!CGAL::is_closed(mesh) || !CGAL::is_valid_polygon_mesh(mesh))
    throw Invalid_file(path + ": the faces do not form a valid closed polygon mesh");

  // Later issue: refuse self-intersecting surfaces
  // (CGAL::Polygon_mesh_processing::does_self_intersect) and orient the
  // surface outward (is_outward_oriented / orient_to_bound_a_volume) here,
  // with the same Invalid_file messages naming `path`.

  return mesh;
}

} // namespace IO
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_IO_READ_TRIANGLE_SURFACE_H
