// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_IO_READ_TRIANGLE_SURFACE_H
#define CGAL_BUBBLE_MESH_3_IO_READ_TRIANGLE_SURFACE_H

#include <CGAL/Bubble_mesh_3/IO/read_polygon_soup.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>

#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/shape_predicates.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/number_utils.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <array>
#include <boost/iterator/function_output_iterator.hpp>
#include <functional>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <sstream>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace IO {
namespace internal {

struct Pair_hash {
  std::size_t operator()(const std::pair<std::size_t, std::size_t>& e) const
  {
    return std::hash<std::size_t>()(e.first * 0x9E3779B97F4A7C15ull ^ e.second);
  }
};

} // namespace internal

/// \ingroup PkgBubbleMesh3IO
/// What `check_triangle_surface()` (and `read_triangle_surface()`) found and repaired.
struct Surface_check_report {
  std::size_t components = 0;         ///< connected components of the surface
  std::size_t cavities = 0;           ///< components inside an odd number of others (holes of the volume)
  bool reoriented_faces = false;      ///< inconsistently oriented faces were flipped (reader only)
  std::size_t reversed_components = 0; ///< components reversed so that the surface bounds a volume
  double volume = 0;                  ///< the enclosed volume (after any reorientation)
};

namespace internal {

// Signed volume of every connected component (double arithmetic: used for
// the flatness test and the report only, never for a decision that needs
// exactness), and the bounding box diagonal of each component.
template <typename Mesh, typename ComponentMap>
void component_volumes(const Mesh& mesh, const ComponentMap& component, std::size_t n,
                       std::vector<double>& volume, std::vector<double>& diagonal)
{
  volume.assign(n, 0.0);
  std::vector<std::array<double, 6>> box(n, {{1e300, 1e300, 1e300, -1e300, -1e300, -1e300}});
  // each component's volume relative to its first point: far from the origin
  // (1e6) the absolute terms would cancel to noise larger than the volume
  std::vector<std::array<double, 3>> origin(n);
  std::vector<char> has_origin(n, 0);
  for(auto f : faces(mesh)) {
    std::array<std::array<double, 3>, 3> p;
    int k = 0;
    for(auto v : vertices_around_face(halfedge(f, mesh), mesh)) {
      const auto& q = mesh.point(v);
      p[k] = {{CGAL::to_double(q.x()), CGAL::to_double(q.y()), CGAL::to_double(q.z())}};
      ++k;
    }
    const std::size_t c = component[f];
    if(!has_origin[c]) {
      origin[c] = p[0];
      has_origin[c] = 1;
    }
    std::array<std::array<double, 3>, 3> r;
    for(int j = 0; j < 3; ++j)
      for(int a = 0; a < 3; ++a)
        r[j][a] = p[j][a] - origin[c][a];
    volume[c] += (r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
                  r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0])) / 6;
    for(const auto& x : p)
      for(int a = 0; a < 3; ++a) {
        box[c][a] = std::min(box[c][a], x[a]);
        box[c][a + 3] = std::max(box[c][a + 3], x[a]);
      }
  }
  diagonal.assign(n, 0.0);
  for(std::size_t c = 0; c < n; ++c)
    diagonal[c] = std::sqrt(CGAL::square(box[c][3] - box[c][0]) + CGAL::square(box[c][4] - box[c][1]) +
                            CGAL::square(box[c][5] - box[c][2]));
}

} // namespace internal

/// \ingroup PkgBubbleMesh3IO
/// Checks that the closed triangle surface `mesh` bounds a volume that can
/// be meshed, and returns an empty string if it does, otherwise one line
/// (without `name`) saying what is wrong:
/// - a face of zero area (exact collinearity test): `face F (0-based) has zero area`;
/// - a component enclosing no volume (|volume| <= 1e-10 d^3, d the diagonal of
///   its bounding box): `the surface encloses no volume`;
/// - two faces that intersect other than along their shared edge or vertex
///   (`CGAL::Polygon_mesh_processing::self_intersections()`):
///   `the surface intersects itself`;
/// - components whose orientation does not match their nesting (an outer
///   boundary must face out, a cavity in, as decided by
///   `CGAL::Polygon_mesh_processing::volume_connected_components()`): if
///   `repair_orientation`, they are reversed (`orient_to_bound_a_volume()`,
///   counted in `report->reversed_components`); otherwise the surface is
///   accepted only when all components are reversed (a surface oriented
///   inward throughout, which the mesher turns around), and refused with
///   `the components are not oriented consistently with their nesting`.
///
/// Several disjoint components are accepted (one subdomain), and so are
/// nested ones: a component inside an odd number of others bounds a cavity.
/// `mesh` must be closed and made of triangles.
template <typename Point_3>
std::string check_triangle_surface(CGAL::Surface_mesh<Point_3>& mesh, bool repair_orientation,
                                   Surface_check_report* report = nullptr)
{
  namespace PMP = CGAL::Polygon_mesh_processing;
  typedef CGAL::Surface_mesh<Point_3> Mesh;
  typedef typename Mesh::Face_index Face_index;
  Surface_check_report local;
  Surface_check_report& r = report ? *report : local;

  if(!CGAL::is_closed(mesh) || !CGAL::is_triangle_mesh(mesh))
    return "the surface is not a closed triangle surface";
  for(Face_index f : faces(mesh))
    if(PMP::is_degenerate_triangle_face(f, mesh))
      return "face " + std::to_string(std::size_t(f)) + " (0-based) has zero area (its three vertices are collinear)";

  std::vector<std::size_t> component_of(num_faces(mesh), 0);
  auto component_map = CGAL::make_property_map(component_of);
  const std::size_t n = PMP::connected_components(mesh, component_map);
  std::vector<double> volume, diagonal;
  internal::component_volumes(mesh, component_map, n, volume, diagonal);
  r.components = n;
  for(std::size_t c = 0; c < n; ++c)
    if(!(std::abs(volume[c]) > 1e-10 * diagonal[c] * diagonal[c] * diagonal[c])) {
      std::ostringstream o;
      o << "the surface encloses no volume: component " << c << " (of " << n << ") is flat (volume " << volume[c]
        << ", bounding box diagonal " << diagonal[c] << ")";
      return o.str();
    }

  if(PMP::does_self_intersect(mesh)) {
    std::size_t pairs = 0;
    std::pair<std::size_t, std::size_t> first(0, 0);
    PMP::self_intersections(mesh, boost::make_function_output_iterator([&](const std::pair<Face_index, Face_index>& p) {
                              if(pairs++ == 0)
                                first = std::make_pair(std::min(std::size_t(p.first), std::size_t(p.second)),
                                                       std::max(std::size_t(p.first), std::size_t(p.second)));
                            }));
    return "the surface intersects itself: " + std::to_string(pairs) + " pairs of faces intersect, e.g. faces " +
           std::to_string(first.first) + " and " + std::to_string(first.second) + " (0-based)";
  }

  // Orientation against nesting. The components are numbered again by
  // volume_connected_components (same definition: faces joined by edges).
  std::vector<std::size_t> nesting;
  std::vector<bool> outward;
  {
    std::vector<std::size_t> volume_of(num_faces(mesh), 0);
    PMP::volume_connected_components(mesh, CGAL::make_property_map(volume_of),
                                     CGAL::parameters::nesting_levels(std::ref(nesting))
                                         .is_cc_outward_oriented(std::ref(outward))
                                         .face_connected_component_map(component_map));
  }
  std::size_t wrong = 0;
  r.cavities = 0;
  for(std::size_t c = 0; c < nesting.size(); ++c) {
    const bool cavity = nesting[c] % 2 == 1;
    r.cavities += cavity ? 1 : 0;
    if(c < outward.size() && outward[c] == cavity)
      ++wrong;
  }
  double total = 0;
  internal::component_volumes(mesh, component_map, n, volume, diagonal);
  for(double v : volume)
    total += v;
  if(wrong > 0) {
    if(repair_orientation) {
      PMP::orient_to_bound_a_volume(mesh);
      r.reversed_components = wrong;
      total = 0;
      internal::component_volumes(mesh, component_map, n, volume, diagonal);
      for(double v : volume)
        total += v;
    } else if(wrong != nesting.size()) {
      return "the components are not oriented consistently with their nesting (" + std::to_string(wrong) + " of " +
             std::to_string(nesting.size()) +
             " face the wrong way; an outer boundary must face out, a cavity in): orient them with "
             "CGAL::Polygon_mesh_processing::orient_to_bound_a_volume()";
    }
  }
  r.volume = std::abs(total);
  return std::string();
}

/// \ingroup PkgBubbleMesh3IO
/// Reads the closed triangle surface `path` into a `Surface_mesh`. The format
/// is chosen by the extension (case-insensitive): `.off` (ASCII OFF and its
/// variants COFF, NOFF, STOFF, 4OFF...), `.obj`, `.stl` (ASCII or binary;
/// corners with equal coordinates are merged) or `.ply` (ASCII or binary,
/// either byte order), read with the package's own parsers
/// (`read_polygon_soup()`, which refuses malformed and truncated files with
/// the line or byte where they go wrong, and never allocates more than a
/// small multiple of the file size), not with CGAL's readers.
///
/// The surface must be made of triangles only (other polygons are refused,
/// not triangulated), have finite coordinates, be closed and manifold (every
/// edge shared by exactly two faces, every vertex with a single fan of faces),
/// have no face of zero area, enclose a volume and not intersect itself; then
/// it passes `check_triangle_surface()`. Orientation is repaired, not
/// refused: inconsistently oriented faces are flipped, then whole components
/// are reversed so that outer boundaries face out and cavities (components
/// nested in an odd number of others) face in; `report` says what was done.
/// Several components, disjoint or nested, are accepted.
///
/// Throws `Invalid_file` naming `path` and the reason: the file cannot be
/// opened or read, unknown extension, the file does not parse
/// (`cannot parse as EXT: ...`, also a truncated or empty file, binary OFF,
/// a non-finite coordinate in an ASCII file), no faces, a face that is not a
/// triangle (which face, how many vertices), a repeated vertex in a face, a
/// face vertex index out of range, a non-finite coordinate, boundary edges
/// (how many), edges shared by more than two faces (how many), non-manifold
/// vertices, a non-orientable surface, or any problem found by
/// `check_triangle_surface()`.
///
/// \tparam K a CGAL kernel whose `Point_3` is the point type of the result.
template <typename K>
CGAL::Surface_mesh<typename K::Point_3> read_triangle_surface(const std::string& path,
                                                               Surface_check_report* report = nullptr)
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

  Polygon_soup soup = read_polygon_soup(path);
  std::vector<Point_3> points;
  points.reserve(soup.points.size());
  for(const std::array<double, 3>& p : soup.points)
    points.emplace_back(p[0], p[1], p[2]);
  soup.points = std::vector<std::array<double, 3>>();
  std::vector<std::vector<std::size_t>> polygons = std::move(soup.polygons);
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
  bool reoriented = false;
  if(!PMP::is_polygon_soup_a_polygon_mesh(polygons)) {
    // Either inconsistent face orientations (repaired by reorienting) or
    // pinched vertices / a non-orientable surface (refused).
    reoriented = true;
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

  Surface_check_report local;
  Surface_check_report& r = report ? *report : local;
  r = Surface_check_report();
  const std::string problem = check_triangle_surface(mesh, true, &r);
  if(!problem.empty())
    throw Invalid_file(path + ": " + problem);
  r.reoriented_faces = reoriented;
  return mesh;
}

} // namespace IO
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_IO_READ_TRIANGLE_SURFACE_H
