// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_C3T3_TET_SOUP_TO_C3T3_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_C3T3_TET_SOUP_TO_C3T3_H

#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_3/tet_soup_to_c3t3.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

// Turns an indexed tet mesh that covers a convex region (the domain padded out
// to a box by `exterior_padding.h`, cells of subdomain 0 outside the domain)
// into a `Mesh_complex_3_in_triangulation_3`.
//
// This is the only place that calls CGAL's tet-soup builder, whose header,
// namespace and signature change after CGAL 5.5 (later releases moved it from
// Mesh_3's internals to the SMDS_3 package): adapt `build_triangulation_adapter()` below and nothing else.
//
// Padding vertices and cells are *not* filtered: they stay in the
// triangulation (cells with subdomain index 0, vertices of dimension 3 with
// the index of subdomain 0), because the triangulation must cover the convex
// hull of its vertices. Writers and quality reports must skip cells that are
// not in the complex and vertices that are incident to no cell of the
// complex (CGAL's `output_to_medit()` does write them).

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

/// Where a vertex of the mesh lies in the complex, as in Mesh_3:
/// `dimension` 0 = corner (`index` = corner id), 1 = on a feature curve
/// (curve id), 2 = on a surface patch (patch id), 3 = inside a subdomain
/// (subdomain id; 0 = padding vertex, outside the domain).
struct C3t3_vertex_location {
  int dimension = 3;
  int index = 0;
};

/// The locations implied by `mesh` itself: the lowest-dimensional element a
/// vertex belongs to wins. Corners get the id `k + 1` where `k` is their
/// position in `mesh.corners`; curves, patches and subdomains get the refs of
/// `edges`, `triangles` and `tets` (the largest subdomain id for a vertex of
/// several subdomains; 0 only for vertices of padding tets only).
inline std::vector<C3t3_vertex_location> vertex_locations(const Indexed_tet_mesh_3& mesh)
{
  const std::size_t n = mesh.points.size();
  std::vector<C3t3_vertex_location> loc(n, C3t3_vertex_location{4, 0});
  auto ref_of = [](const std::vector<int>& refs, std::size_t i) { return i < refs.size() ? refs[i] : 1; };
  auto lower = [&](int v, int dim, int index) {
    if (v < 0 || static_cast<std::size_t>(v) >= n)
      throw Invalid_input("tet_mesh_to_c3t3: vertex index " + std::to_string(v) + " out of range");
    C3t3_vertex_location& l = loc[v];
    if (dim < l.dimension) l = C3t3_vertex_location{dim, index};
    else if (dim == 3 && l.dimension == 3 && index > l.index) l.index = index;
  };
  for (std::size_t k = 0; k < mesh.corners.size(); ++k) lower(mesh.corners[k], 0, static_cast<int>(k) + 1);
  for (std::size_t e = 0; e < mesh.edges.size(); ++e)
    for (int v : mesh.edges[e]) lower(v, 1, ref_of(mesh.edge_refs, e));
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int v : mesh.triangles[t]) lower(v, 2, ref_of(mesh.triangle_refs, t));
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    for (int v : mesh.tets[t]) lower(v, 3, ref_of(mesh.tet_refs, t));
  for (C3t3_vertex_location& l : loc)
    if (l.dimension == 4) l = C3t3_vertex_location{3, 0}; // used by no element
  return loc;
}

/// The C3T3 locations after the improvement: a kept vertex keeps its own
/// (`new_vertex_index`: empty if none was removed), a split vertex gets its
/// curve if on a feature edge, its patch if in a boundary triangle, else
/// its subdomain (`point_refs`: the index).
inline void relocate_after_improvement(const Indexed_tet_mesh_3& m, const std::vector<int>& new_vertex_index,
                                       std::vector<C3t3_vertex_location>& locations)
{
  std::vector<C3t3_vertex_location> moved(m.points.size(), C3t3_vertex_location{3, 0});
  std::vector<char> known(m.points.size(), 0);
  for(std::size_t v = 0; v < locations.size(); ++v) {
    const int w = new_vertex_index.empty() ? int(v) : new_vertex_index[v];
    if(w >= 0) {
      moved[std::size_t(w)] = locations[v];
      known[std::size_t(w)] = 1;
    }
  }
  if(std::find(known.begin(), known.end(), char(0)) != known.end()) {
    std::vector<int> dimension(m.points.size(), 3);
    for(const auto& f : m.triangles)
      for(int v : f)
        dimension[std::size_t(v)] = 2;
    for(const auto& e : m.edges)
      for(int v : e)
        dimension[std::size_t(v)] = 1;
    for(std::size_t v = 0; v < m.points.size(); ++v)
      if(!known[v])
        moved[v] = C3t3_vertex_location{dimension[v], m.point_refs[v]};
  }
  locations = std::move(moved);
}

/// Throws `Invalid_input` unless the tets, closed by one infinite vertex
/// joined to their boundary (what CGAL's builder does), satisfy what
/// `tds().is_valid()` checks globally: every point used, no face on more
/// than two tets, and the Euler relation `v - e + f - c == 0` of the closed
/// complex. A soup of several components, or with a cavity, fails it: pad
/// it first (`pad_to_box()`).
inline void check_closable_into_sphere(const std::vector<std::array<int, 4>>& tets, std::size_t number_of_points)
{
  std::map<std::array<int, 3>, int> faces;
  std::set<std::array<int, 2>> edges;
  std::vector<char> used(number_of_points, 0);
  for (const std::array<int, 4>& t : tets) {
    for (int i = 0; i < 4; ++i) {
      used[t[i]] = 1;
      for (int j = i + 1; j < 4; ++j) edges.insert({std::min(t[i], t[j]), std::max(t[i], t[j])});
      std::array<int, 3> f;
      for (int k = 0, m = 0; k < 4; ++k)
        if (k != i) f[m++] = t[k];
      std::sort(f.begin(), f.end());
      if (++faces[f] > 2) throw Invalid_input("tet_mesh_to_c3t3: a face is shared by more than two tets");
    }
  }
  const std::size_t unused = static_cast<std::size_t>(std::count(used.begin(), used.end(), 0));
  if (unused != 0)
    throw Invalid_input("tet_mesh_to_c3t3: " + std::to_string(unused) + " points are used by no tet");
  std::set<std::array<int, 2>> boundary_edges;
  std::set<int> boundary_vertices;
  long boundary_faces = 0;
  for (const auto& kv : faces)
    if (kv.second == 1) {
      ++boundary_faces;
      const std::array<int, 3>& f = kv.first; // sorted
      boundary_edges.insert({f[0], f[1]});
      boundary_edges.insert({f[0], f[2]});
      boundary_edges.insert({f[1], f[2]});
      boundary_vertices.insert(f.begin(), f.end());
    }
  const long v = static_cast<long>(number_of_points) + 1;
  const long e = static_cast<long>(edges.size() + boundary_vertices.size());
  const long f = static_cast<long>(faces.size() + boundary_edges.size());
  const long c = static_cast<long>(tets.size()) + boundary_faces;
  if (v - e + f - c != 0)
    throw Invalid_input("tet_mesh_to_c3t3: the tets do not form a ball (Euler characteristic " +
                        std::to_string(v - e + f - c) +
                        " of the closed complex instead of 0); pad the domain out to a convex box first");
}

/// The version adapter around CGAL 5.5's `CGAL::build_triangulation()`
/// (`CGAL/Mesh_3/tet_soup_to_c3t3.h`). Vertex `i` is `handles[i + 1]`;
/// `handles[0]` is the infinite vertex. Returns `tds().is_valid()`.
template <class Tr>
bool build_triangulation_adapter(Tr& tr, const std::vector<typename Tr::Point>& points,
                                 const std::vector<std::array<int, 5>>& cells,
                                 const std::map<std::array<int, 3>, typename Tr::Cell::Surface_patch_index>& border,
                                 std::vector<typename Tr::Vertex_handle>& handles)
{
  return CGAL::build_triangulation<Tr, false>(tr, points, cells, border, handles, false);
}

/// The complex's indices of a mesh whose refs are the domain's own ids (the
/// pipeline's meshes): patch, curve and corner ids are the index values, and
/// a vertex's index comes from `domain.index_from_*()`.
template <class C3T3, class MeshDomain>
struct Domain_indices {
  typedef typename C3T3::Triangulation::Vertex_handle Vertex_handle;
  const MeshDomain& domain;

  typename C3T3::Surface_patch_index patch(int ref) const { return typename C3T3::Surface_patch_index(ref); }
  typename C3T3::Curve_index curve(int ref) const { return typename C3T3::Curve_index(ref); }
  typename C3T3::Corner_index corner(int ref) const { return typename C3T3::Corner_index(ref); }
  void set_vertex(Vertex_handle v, std::size_t i, const C3t3_vertex_location& l) const
  {
    switch(l.dimension) {
    case 0: v->set_index(domain.index_from_corner_index(corner(l.index))); break;
    case 1: v->set_index(domain.index_from_curve_index(curve(l.index))); break;
    case 2: v->set_index(domain.index_from_surface_patch_index(patch(l.index))); break;
    case 3: v->set_index(domain.index_from_subdomain_index(l.index)); break;
    default:
      throw Invalid_input("tet_mesh_to_c3t3: vertex " + std::to_string(i) + " has dimension " +
                          std::to_string(l.dimension));
    }
    v->set_dimension(l.dimension);
  }
};

/// Fills `c3t3` (which must be empty) from `mesh`, the refs turned into the
/// complex's indices by `indices` (`Domain_indices` or another type with its
/// four members: `patch(ref)`, `curve(ref)`, `corner(ref)` and
/// `set_vertex(handle, i, location)`; tets' refs are subdomain indices).
///
/// `mesh` must cover a convex region: the tets of the domain (refs > 0) plus
/// padding tets of ref 0 out to a convex box (see `pad_to_box()`); every tet
/// positively oriented. Its triangles (with their patch refs) become the
/// facets of the complex (boundary and interface facets), its edges (with
/// their curve refs) the feature edges. `locations[i]` gives the dimension
/// and ref of vertex `i` (see `vertex_locations()`). Corners are added
/// with their refs. If `handles` is not null it receives the id -> handle map
/// (`(*handles)[i]` is the handle of vertex `i`).
///
/// Throws `Invalid_input` before building if a tet is not positively
/// oriented (exact test), an index is out of range, or `locations` has the
/// wrong size, or if the tets do not form a ball (typically: the mesh was
/// not padded; see `check_closable_into_sphere()`); after building if the
/// TDS is not valid or the hull is not convex, if a listed triangle is no face, if a face
/// between two subdomains (0 included) is not listed, or if a feature edge
/// is no edge. The complex is left partially filled when it throws.
template <class C3T3, class Indices>
void indexed_mesh_to_c3t3(const Indexed_tet_mesh_3& mesh, const std::vector<C3t3_vertex_location>& locations,
                          const Indices& indices, C3T3& c3t3,
                          std::vector<typename C3T3::Vertex_handle>* handles = nullptr)
{
  typedef typename C3T3::Triangulation Tr;
  typedef typename Tr::Vertex_handle Vertex_handle;
  typedef CGAL::Exact_predicates_inexact_constructions_kernel::Point_3 Bare_point;

  const std::size_t n = mesh.points.size();
  if (n == 0 || mesh.tets.empty()) throw Invalid_input("tet_mesh_to_c3t3: empty mesh");
  if (locations.size() != n)
    throw Invalid_input("tet_mesh_to_c3t3: " + std::to_string(locations.size()) + " vertex locations for " +
                        std::to_string(n) + " points");
  if (c3t3.triangulation().number_of_vertices() != 0)
    throw Invalid_input("tet_mesh_to_c3t3: the output complex must be empty");
  auto check_index = [n](int v) {
    if (v < 0 || static_cast<std::size_t>(v) >= n)
      throw Invalid_input("tet_mesh_to_c3t3: vertex index " + std::to_string(v) + " out of range");
  };

  std::vector<Bare_point> bare;
  bare.reserve(n);
  for (const auto& p : mesh.points) bare.emplace_back(p[0], p[1], p[2]);

  // 1. refuse non-positive tets (CGAL only asserts this in debug builds)
  std::vector<std::array<int, 5>> cells;
  cells.reserve(mesh.tets.size());
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const std::array<int, 4>& q = mesh.tets[t];
    for (int v : q) check_index(v);
    if (CGAL::orientation(bare[q[0]], bare[q[1]], bare[q[2]], bare[q[3]]) != CGAL::POSITIVE)
      throw Invalid_input("tet_mesh_to_c3t3: tet " + std::to_string(t) + " is not positively oriented");
    cells.push_back({q[0], q[1], q[2], q[3], t < mesh.tet_refs.size() ? mesh.tet_refs[t] : 1});
  }

  // 2. refuse what the builder cannot close into a 3-sphere, before CGAL
  //    asserts on it in debug builds (6.3 item 6)
  check_closable_into_sphere(mesh.tets, n);

  // 3. border facets, keyed by their sorted ids (the builder's input format)
  std::map<std::array<int, 3>, typename Tr::Cell::Surface_patch_index> border;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    std::array<int, 3> key = mesh.triangles[f];
    for (int v : key) check_index(v);
    std::sort(key.begin(), key.end());
    border[key] = indices.patch(f < mesh.triangle_refs.size() ? mesh.triangle_refs[f] : 1);
  }

  // 4. build
  std::vector<typename Tr::Point> points;
  points.reserve(n);
  for (const Bare_point& p : bare) points.push_back(typename Tr::Point(p));
  std::vector<Vertex_handle> vh;
  if (!build_triangulation_adapter(c3t3.triangulation(), points, cells, border, vh))
    throw Invalid_input("tet_mesh_to_c3t3: the tets do not form a valid triangulation of a ball "
                        "(pad the domain out to a convex box first)");

  //    the hull must be convex (Triangulation_3's invariant, which no
  //    is_valid() checks, 6.3 item 7): no hull vertex in front of the
  //    hull facet next to it (coplanar is fine: the box faces are flat)
  {
    const Tr& tr = c3t3.triangulation();
    auto bare_of = [](Vertex_handle v) {
      const auto& p = v->point();
      return Bare_point(p.x(), p.y(), p.z());
    };
    for (auto c = tr.all_cells_begin(); c != tr.all_cells_end(); ++c) {
      if (!tr.is_infinite(c)) continue;
      const int inf = c->index(tr.infinite_vertex());
      for (int j = 0; j < 4; ++j) {
        if (j == inf) continue;
        const auto nb = c->neighbor(j); // the infinite cell over the next hull facet
        const Vertex_handle w = nb->vertex(nb->index(c));
        std::array<Bare_point, 4> q;
        for (int m = 0; m < 4; ++m) q[m] = bare_of(m == inf ? w : c->vertex(m));
        if (CGAL::orientation(q[0], q[1], q[2], q[3]) == CGAL::POSITIVE)
          throw Invalid_input("tet_mesh_to_c3t3: the tets do not cover a convex region "
                              "(pad the domain out to a convex box first)");
      }
    }
  }

  // 5. vertex dimension and index (not derived by the builder, 6.3 item 3)
  for (std::size_t i = 0; i < n; ++i) indices.set_vertex(vh[i + 1], i, locations[i]);

  // 6. count cells and facets; corners come back with Corner_index(1) ...
  c3t3.rescan_after_load_of_triangulation();
  //    the builder silently ignores listed triangles that are no face, and
  //    drops interfaces that are not listed (6.3 item 2): refuse both
  if (c3t3.number_of_facets_in_complex() != border.size())
    throw Invalid_input("tet_mesh_to_c3t3: " + std::to_string(border.size() - c3t3.number_of_facets_in_complex()) +
                        " listed triangles are no face of the tets");
  for (auto f = c3t3.triangulation().finite_facets_begin(); f != c3t3.triangulation().finite_facets_end(); ++f) {
    const auto mirror = c3t3.triangulation().mirror_facet(*f);
    if (c3t3.subdomain_index(f->first) != c3t3.subdomain_index(mirror.first) && !c3t3.is_in_complex(*f))
      throw Invalid_input("tet_mesh_to_c3t3: a face between two subdomains is not listed in the triangles");
  }
  // ... so re-add them with their ids (6.3 item 4)
  for (std::size_t i = 0; i < n; ++i)
    if (locations[i].dimension == 0) {
      Vertex_handle v = vh[i + 1];
      c3t3.remove_from_complex(v);
      c3t3.add_to_complex(v, indices.corner(locations[i].index));
    }
  // 7. feature edges (never rebuilt by the rescan)
  for (std::size_t e = 0; e < mesh.edges.size(); ++e) {
    const std::array<int, 2>& ab = mesh.edges[e];
    check_index(ab[0]);
    check_index(ab[1]);
    typename Tr::Cell_handle c;
    int i = 0, j = 0;
    if (!c3t3.triangulation().tds().is_edge(vh[ab[0] + 1], vh[ab[1] + 1], c, i, j))
      throw Invalid_input("tet_mesh_to_c3t3: feature edge " + std::to_string(e) + " is no edge of the tets");
    c3t3.add_to_complex(vh[ab[0] + 1], vh[ab[1] + 1],
                        indices.curve(e < mesh.edge_refs.size() ? mesh.edge_refs[e] : 1));
  }
  if (handles != nullptr) handles->assign(vh.begin() + 1, vh.end());
}

/// `indexed_mesh_to_c3t3()` with the domain's own ids (`Domain_indices`).
template <class C3T3, class MeshDomain>
void tet_mesh_to_c3t3(const Indexed_tet_mesh_3& mesh, const std::vector<C3t3_vertex_location>& locations,
                      const MeshDomain& domain, C3T3& c3t3,
                      std::vector<typename C3T3::Vertex_handle>* handles = nullptr)
{
  indexed_mesh_to_c3t3(mesh, locations, Domain_indices<C3T3, MeshDomain>{domain}, c3t3, handles);
}

/// Same, with the locations implied by `mesh` (`vertex_locations(mesh)`).
template <class C3T3, class MeshDomain>
void tet_mesh_to_c3t3(const Indexed_tet_mesh_3& mesh, const MeshDomain& domain, C3T3& c3t3,
                      std::vector<typename C3T3::Vertex_handle>* handles = nullptr)
{
  tet_mesh_to_c3t3(mesh, vertex_locations(mesh), domain, c3t3, handles);
}

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_C3T3_TET_SOUP_TO_C3T3_H
