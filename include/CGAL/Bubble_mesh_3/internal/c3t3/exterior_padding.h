// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_C3T3_EXTERIOR_PADDING_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_C3T3_EXTERIOR_PADDING_H

#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/internal/tet_boundary_chain.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#if defined(BUBBLE_MESH_3_HAS_TETGEN) || defined(TETLIBRARY)
#  ifndef TETLIBRARY
#    define TETLIBRARY
#  endif
#  include <CGAL/Bubble_mesh_3/internal/tetgen_isolated.h>
#  define CGAL_BUBBLE_MESH_3_PADDING_USES_TETGEN 1
#endif

// Pads a domain tet mesh out to an axis-aligned box with tets of subdomain 0,
// so that the tets cover a convex region and CGAL's tet-soup builder accepts
// any topology (several components, cavities): a triangulation fills the
// convex hull of its vertices.
//
// The domain tets are kept as they are. The exterior (box minus domain) is
// tetrahedralized by TetGen with the piecewise linear complex made of the
// domain's boundary triangles and the 6 box faces; `-Y` forbids Steiner points
// on those facets, so the exterior tets share the domain's boundary faces
// exactly. Steiner points may appear strictly inside the exterior only. The
// domain itself is carved out with one hole point per face-connected
// component of domain tets (the centroid of one of its tets), so no region
// labelling is needed and cavities (interior exterior components) are padded
// too. Until the advancing front pads the exterior itself, this needs TetGen
// (AGPL): without it `pad_to_box()` throws `Invalid_input`. A self-intersecting
// domain boundary is refused (TetGen's `-d` pass) before tetrahedralizing.
// TetGen runs in a child process (tetgen_isolated.h) and its tets are checked
// to tile the box minus the domain before they are used.

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

/// Whether `pad_to_box()` is available in this build.
#ifdef CGAL_BUBBLE_MESH_3_PADDING_USES_TETGEN
constexpr bool has_exterior_padding = true;
#else
constexpr bool has_exterior_padding = false;
#endif

struct Padding_options {
  /// the box is the bounding box of the domain enlarged on each side by
  /// `relative_margin` times its largest extent
  double relative_margin = 0.25;
  /// asked every 100 ms while TetGen runs; true (or an exception it throws)
  /// stops TetGen and ends the padding with `Interrupted`
  std::function<bool()> should_stop;
};

/// The padded mesh and what is needed to tell its parts apart.
struct Padded_tet_mesh_3 {
  /// Points: the domain's points with unchanged ids, then the 8 box corners,
  /// then TetGen's exterior Steiner points. Tets: the domain tets unchanged
  /// (same order, same refs), then the exterior tets with ref 0, all
  /// positively oriented. Triangles, edges, corners: those of the domain.
  Indexed_tet_mesh_3 mesh;
  std::size_t number_of_domain_points = 0;
  std::size_t number_of_domain_tets = 0;
  std::size_t number_of_steiner_points = 0;
  std::array<double, 3> box_min{}, box_max{};
  /// the faces of the box (the convex hull), outward oriented
  std::vector<std::array<int, 3>> box_triangles;
};

/// The faces of exactly one tet of `tets`, each oriented outward from its tet.
/// Throws `Invalid_input` if a face has more than two tets.
inline std::vector<std::array<int, 3>> single_faces(const std::vector<std::array<int, 4>>& tets)
{
  // outward faces of a positively oriented tet (a,b,c,d)
  static const int face_of[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};
  std::map<std::array<int, 3>, std::pair<int, std::array<int, 3>>> faces;
  for (const std::array<int, 4>& t : tets)
    for (const auto& f : face_of) {
      std::array<int, 3> oriented{t[f[0]], t[f[1]], t[f[2]]};
      std::array<int, 3> key = oriented;
      std::sort(key.begin(), key.end());
      auto& entry = faces[key];
      if (++entry.first == 1) entry.second = oriented;
      else if (entry.first > 2)
        throw Invalid_input("exterior padding: a face is shared by more than two tets");
    }
  std::vector<std::array<int, 3>> result;
  for (const auto& kv : faces)
    if (kv.second.first == 1) result.push_back(kv.second.second);
  return result;
}

/// Step 1 of the padding: the box around the domain's tets, `options`'
/// relative margin (at least 1e-3) of their largest extent away.
inline void padding_box(const Indexed_tet_mesh_3& domain, const Padding_options& options, Padded_tet_mesh_3& result)
{
  std::array<double, 3> lo = domain.points[domain.tets[0][0]], hi = lo;
  for (const auto& t : domain.tets)
    for (int v : t)
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], domain.points[v][k]);
        hi[k] = std::max(hi[k], domain.points[v][k]);
      }
  double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  if (!(extent > 0) || !std::isfinite(extent)) throw Invalid_input("exterior padding: degenerate bounding box");
  const double margin = std::max(options.relative_margin, 1e-3) * extent;
  for (int k = 0; k < 3; ++k) {
    result.box_min[k] = lo[k] - margin;
    result.box_max[k] = hi[k] + margin;
  }
}

/// Step 3: one point inside each face-connected component of the domain's
/// tets (the centroid of one of its tets): TetGen's hole points.
inline std::vector<std::array<double, 3>> one_point_in_each_component(const Indexed_tet_mesh_3& domain)
{
  std::vector<int> parent(domain.tets.size());
  for (std::size_t t = 0; t < parent.size(); ++t) parent[t] = static_cast<int>(t);
  auto find = [&parent](int t) {
    while (parent[t] != t) t = parent[t] = parent[parent[t]];
    return t;
  };
  {
    std::map<std::array<int, 3>, int> face_tet;
    for (std::size_t t = 0; t < domain.tets.size(); ++t)
      for (int skip = 0; skip < 4; ++skip) {
        std::array<int, 3> key;
        for (int k = 0, j = 0; k < 4; ++k)
          if (k != skip) key[j++] = domain.tets[t][k];
        std::sort(key.begin(), key.end());
        auto it = face_tet.emplace(key, static_cast<int>(t));
        if (!it.second) parent[find(static_cast<int>(t))] = find(it.first->second);
      }
  }
  std::vector<std::array<double, 3>> holes;
  for (std::size_t t = 0; t < domain.tets.size(); ++t)
    if (find(static_cast<int>(t)) == static_cast<int>(t)) {
      std::array<double, 3> c{0, 0, 0};
      for (int v : domain.tets[t])
        for (int k = 0; k < 3; ++k) c[k] += 0.25 * domain.points[v][k];
      holes.push_back(c);
    }
  return holes;
}

#ifdef CGAL_BUBBLE_MESH_3_PADDING_USES_TETGEN
/// Step 6: TetGen's tets into `result` (the PLC's first `nb` points are
/// the domain's `domain_of`, then the 8 box corners from `first_box_id`):
/// input points keep their ids, Steiner points are appended when used, every
/// tet is made positive (exact test). Returns the points of the padded mesh.
inline std::vector<CGAL::Exact_predicates_inexact_constructions_kernel::Point_3>
append_tetgen_tets(const Tetgen_output& out, const std::vector<int>& domain_of, int first_box_id,
                   Padded_tet_mesh_3& result)
{
  typedef CGAL::Exact_predicates_inexact_constructions_kernel::Point_3 Point;
  const int nb = static_cast<int>(domain_of.size());
  const int number_of_points = static_cast<int>(out.points.size() / 3);
  std::vector<int> padded_of(static_cast<std::size_t>(number_of_points), -1);
  for (int i = 0; i < nb; ++i) padded_of[i] = domain_of[i];
  for (int c = 0; c < 8; ++c) padded_of[nb + c] = first_box_id + c;
  std::vector<Point> pts;
  pts.reserve(result.mesh.points.size());
  for (const auto& p : result.mesh.points) pts.emplace_back(p[0], p[1], p[2]);
  for (std::size_t t = 0; 4 * t + 3 < out.tets.size(); ++t) {
    std::array<int, 4> tet;
    for (int k = 0; k < 4; ++k) {
      const int o = out.tets[4 * t + static_cast<std::size_t>(k)];
      if (o < 0 || o >= number_of_points) throw Meshing_failure("exterior padding: bad TetGen vertex id");
      if (padded_of[o] < 0) {
        padded_of[o] = static_cast<int>(result.mesh.points.size());
        result.mesh.points.push_back({out.points[3 * o], out.points[3 * o + 1], out.points[3 * o + 2]});
        pts.emplace_back(out.points[3 * o], out.points[3 * o + 1], out.points[3 * o + 2]);
        ++result.number_of_steiner_points;
      }
      tet[k] = padded_of[o];
    }
    switch (CGAL::orientation(pts[tet[0]], pts[tet[1]], pts[tet[2]], pts[tet[3]])) {
    case CGAL::NEGATIVE: std::swap(tet[2], tet[3]); break;
    case CGAL::POSITIVE: break;
    default: throw Meshing_failure("exterior padding: TetGen returned a flat tet");
    }
    result.mesh.tets.push_back(tet);
    result.mesh.tet_refs.push_back(0);
  }
  result.mesh.point_refs.resize(result.mesh.points.size(), 0);

  return pts;
}

/// Step 7: TetGen's tets are used only if they tile the box exactly
/// (positive, checked in step 6, and their boundary chain with the domain's
/// tets is made of faces on the box, each once: tet_boundary_chain.h), so
/// that a wrong result is caught here, not in CGAL's C3T3 builder.
inline void check_padding_tiles_box(const std::vector<CGAL::Exact_predicates_inexact_constructions_kernel::Point_3>& pts,
                                    Padded_tet_mesh_3& result)
{
  if (!boundary_chain(result.mesh.tets, result.box_triangles))
    throw Meshing_failure("exterior padding: TetGen's exterior tets overlap the domain or each other");
  for (const auto& f : result.box_triangles) {
    bool on_box = false;
    for (int k = 0; k < 3 && !on_box; ++k)
      on_box = (pts[f[0]][k] == result.box_min[k] && pts[f[1]][k] == result.box_min[k] &&
                pts[f[2]][k] == result.box_min[k]) ||
               (pts[f[0]][k] == result.box_max[k] && pts[f[1]][k] == result.box_max[k] &&
                pts[f[2]][k] == result.box_max[k]);
    if (!on_box)
      throw Meshing_failure("exterior padding: TetGen's exterior tets do not match the domain boundary");
  }
}

#endif

/// One padding with the box margin of `options` (see `pad_to_box()`).
inline Padded_tet_mesh_3 pad_to_box_once(const Indexed_tet_mesh_3& domain, const Padding_options& options)
{
#ifndef CGAL_BUBBLE_MESH_3_PADDING_USES_TETGEN
  (void)domain;
  (void)options;
  throw Invalid_input("exterior padding needs TetGen until the advancing front pads "
                      "(build with BUBBLE_MESH_3_HAS_TETGEN and link -ltet)");
#else
  const std::size_t n = domain.points.size();
  if (n == 0 || domain.tets.empty()) throw Invalid_input("exterior padding: empty domain mesh");
  for (const auto& t : domain.tets)
    for (int v : t)
      if (v < 0 || static_cast<std::size_t>(v) >= n) throw Invalid_input("exterior padding: vertex index out of range");

  Padded_tet_mesh_3 result;
  result.mesh = domain;
  result.number_of_domain_points = n;
  result.number_of_domain_tets = domain.tets.size();
  if (result.mesh.tet_refs.size() != domain.tets.size()) result.mesh.tet_refs.resize(domain.tets.size(), 1);

  padding_box(domain, options, result);

  // 2. the PLC: boundary vertices (renumbered), the 8 box corners, the
  //    boundary triangles and the 6 box quads
  const std::vector<std::array<int, 3>> boundary = single_faces(domain.tets);
  std::vector<int> plc_of(n, -1), domain_of; // domain id <-> PLC id
  for (const auto& f : boundary)
    for (int v : f)
      if (plc_of[v] < 0) {
        plc_of[v] = static_cast<int>(domain_of.size());
        domain_of.push_back(v);
      }
  const int nb = static_cast<int>(domain_of.size());
  const int first_box_id = static_cast<int>(n); // in the padded mesh
  for (int c = 0; c < 8; ++c)
    result.mesh.points.push_back({(c & 1) ? result.box_max[0] : result.box_min[0],
                                  (c & 2) ? result.box_max[1] : result.box_min[1],
                                  (c & 4) ? result.box_max[2] : result.box_min[2]});
  result.mesh.point_refs.resize(result.mesh.points.size(), 0);

  tetgenio in;
  in.firstnumber = 0;
  in.numberofpoints = nb + 8;
  in.pointlist = new REAL[3 * in.numberofpoints];
  for (int i = 0; i < nb; ++i)
    for (int k = 0; k < 3; ++k) in.pointlist[3 * i + k] = domain.points[domain_of[i]][k];
  for (int c = 0; c < 8; ++c)
    for (int k = 0; k < 3; ++k) in.pointlist[3 * (nb + c) + k] = result.mesh.points[first_box_id + c][k];

  static const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  in.numberoffacets = static_cast<int>(boundary.size()) + 6;
  in.facetlist = new tetgenio::facet[in.numberoffacets];
  in.facetmarkerlist = new int[in.numberoffacets];
  for (int f = 0; f < in.numberoffacets; ++f) {
    tetgenio::facet& facet = in.facetlist[f];
    tetgenio::init(&facet);
    facet.numberofpolygons = 1;
    facet.polygonlist = new tetgenio::polygon[1];
    tetgenio::polygon& poly = facet.polygonlist[0];
    tetgenio::init(&poly);
    const bool is_box = f >= static_cast<int>(boundary.size());
    poly.numberofvertices = is_box ? 4 : 3;
    poly.vertexlist = new int[poly.numberofvertices];
    for (int k = 0; k < poly.numberofvertices; ++k)
      poly.vertexlist[k] = is_box ? nb + quads[f - boundary.size()][k] : plc_of[boundary[f][k]];
    in.facetmarkerlist[f] = is_box ? 2 : 1;
  }

  const std::vector<std::array<double, 3>> holes = one_point_in_each_component(domain);
  in.numberofholes = static_cast<int>(holes.size());
  in.holelist = new REAL[3 * holes.size()];
  for (std::size_t h = 0; h < holes.size(); ++h)
    for (int k = 0; k < 3; ++k) in.holelist[3 * h + k] = holes[h][k];

  // 4. TetGen 1.5 crashes (in its own clean-up) on a self-intersecting
  //    PLC, so detect self-intersections first: -d outputs the faces that
  //    intersect, and no tets
  {
    Tetgen_output intersecting;
    std::string error;
    if (!tetrahedralize_isolated("pdMzQ", in, intersecting, error, options.should_stop))
      throw Meshing_failure("exterior padding: TetGen failed to check the domain boundary (" + error + ")");
    if (intersecting.intersecting_faces > 0)
      throw Invalid_input("exterior padding: the domain boundary self-intersects (" +
                          std::to_string(intersecting.intersecting_faces) + " intersecting faces)");
  }

  // 5. tetrahedralize: p = PLC, Y = no Steiner point on the facets,
  //    M = do not merge coplanar facets or close vertices (the domain's
  //    triangles must come back as they are), z = 0-based, Q = quiet; in a
  //    child process (tetgen_isolated.h)
  Tetgen_output out;
  {
    std::string error;
    if (!tetrahedralize_isolated("pYMzQ", in, out, error, options.should_stop))
      throw Meshing_failure("exterior padding: TetGen failed on the domain boundary (" + error + ")");
  }

  const auto pts = append_tetgen_tets(out, domain_of, first_box_id, result);

  check_padding_tiles_box(pts, result);
  return result;
#endif
}

/// Pads `domain` (a valid tet mesh: positive tets, conforming, closed
/// boundary) out to a box. See `Padded_tet_mesh_3` for the numbering.
/// Throws `Invalid_input` without TetGen, for a bad domain mesh or a domain
/// boundary that intersects itself, and `Meshing_failure` if TetGen fails,
/// dies or returns tets that do not tile the box minus the domain, on the
/// requested box and on two larger ones (another input to TetGen).
inline Padded_tet_mesh_3 pad_to_box(const Indexed_tet_mesh_3& domain, const Padding_options& options = {})
{
  Padding_options o = options;
  for (int attempt = 0;; ++attempt) {
    try {
      return pad_to_box_once(domain, o);
    } catch (const Meshing_failure&) {
      if (attempt == 2) throw;
      o.relative_margin = 2 * std::max(o.relative_margin, 1e-3);
    }
  }
}

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_C3T3_EXTERIOR_PADDING_H
