// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_IMPROVE_C3T3_H
#define CGAL_BUBBLE_MESH_3_IMPROVE_C3T3_H

#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/improve_mesh.h>
#include <CGAL/Bubble_mesh_3/internal/c3t3/tet_soup_to_c3t3.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Handle_hash_function.h>

#include <array>
#include <cstddef>
#include <map>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

/// \file improve_c3t3.h
/// `improve_anisotropic_mesh_3()`: the metric improvement of `improve_mesh()`
/// applied to any `Mesh_complex_3_in_triangulation_3`, e.g. the output of
/// CGAL's `make_mesh_3()`, so that meshes of other generators can be
/// post-processed in a metric field.
///
/// **Why a second complex.** The improved mesh is in general not (weighted)
/// Delaunay, and a `Regular_triangulation_3` holding a non-Delaunay mesh
/// fails its own validity postconditions (on copy, and `std::terminate` on
/// move in debug builds). So the result goes into a complex over a plain
/// `Triangulation_3` with the Mesh_3 data structure, e.g.
/// `CGAL::Anisotropic_mesh_triangulation_3<MeshDomain>::type` (the type
/// `make_anisotropic_mesh_3()` produces); the input may be of that type too.
///
/// **What is improved.** All the finite cells of the input triangulation
/// are copied: the cells of the complex (their subdomain as ref) and the
/// cells outside it as *passive* padding (ref 0). The padding keeps the
/// triangulation covering the convex hull: every move must keep it
/// positively oriented, but it is never flipped nor measured. Facets of the
/// complex are the protected triangles (their patches), edges of the
/// complex the feature edges, corners the corners. Then `improve_mesh()`
/// with `ref_0_is_exterior` set: the facets, edges and corners of the
/// complex and their indices are unchanged; vertices move only inside a
/// subdomain, in a planar region of one patch, or along a straight feature
/// line (`boundary_smoothing`); the worst quality of the complex's cells
/// never decreases. Vertex dimensions and indices are copied from the input.

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

/// A complex as an indexed mesh, with the tables that turn the integer refs
/// back into the complex's indices.
template <typename C3T3>
struct C3t3_as_indexed_mesh {
  typedef typename C3T3::Triangulation::Vertex_handle Vertex_handle;
  /// all finite cells (cells outside the complex: ref 0), the facets, edges
  /// and corners of the complex; refs are 1-based positions in the tables
  /// below (cells: their subdomain index as an int)
  Indexed_tet_mesh_3 mesh;
  std::vector<Vertex_handle> vertices;
  std::vector<typename C3T3::Surface_patch_index> patches;
  std::vector<typename C3T3::Curve_index> curves;
  std::vector<typename C3T3::Corner_index> corner_indices; // parallel to mesh.corners
};

/// 1-based position of `value` in `table`, added if missing
template <typename Index>
int ref_of_index(const Index& value, std::vector<Index>& table, std::map<Index, int>& positions)
{
  auto it = positions.find(value);
  if(it != positions.end())
    return it->second;
  table.push_back(value);
  const int ref = int(table.size());
  positions.emplace(value, ref);
  return ref;
}

/// Copies `c3t3` into a `C3t3_as_indexed_mesh` (see there). Triangles are
/// oriented outward from the cell of the larger subdomain index.
template <typename C3T3>
C3t3_as_indexed_mesh<C3T3> c3t3_to_indexed_mesh(const C3T3& c3t3)
{
  typedef typename C3T3::Triangulation Tr;
  typedef typename Tr::Vertex_handle Vertex_handle;
  typedef CGAL::Exact_predicates_inexact_constructions_kernel::Point_3 Bare_point;
  const Tr& tr = c3t3.triangulation();
  if(tr.dimension() != 3)
    throw Invalid_input("improve_anisotropic_mesh_3: the triangulation is not 3-dimensional");
  C3t3_as_indexed_mesh<C3T3> out;
  Indexed_tet_mesh_3& m = out.mesh;
  std::unordered_map<Vertex_handle, int, CGAL::Handle_hash_function> id;
  const auto construct_point = tr.geom_traits().construct_point_3_object();
  for(auto v = tr.finite_vertices_begin(); v != tr.finite_vertices_end(); ++v) {
    const auto p = construct_point(tr.point(v));
    id.emplace(Vertex_handle(v), int(m.points.size()));
    out.vertices.push_back(Vertex_handle(v));
    m.points.push_back({{CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())}});
  }
  auto bare = [&](int i) { return Bare_point(m.points[std::size_t(i)][0], m.points[std::size_t(i)][1], m.points[std::size_t(i)][2]); };
  auto subdomain = [&](typename Tr::Cell_handle c) {
    return !tr.is_infinite(c) && c3t3.is_in_complex(c) ? int(c3t3.subdomain_index(c)) : 0;
  };
  for(auto c = tr.finite_cells_begin(); c != tr.finite_cells_end(); ++c) {
    std::array<int, 4> t;
    for(int i = 0; i < 4; ++i)
      t[std::size_t(i)] = id.at(c->vertex(i));
    if(CGAL::orientation(bare(t[0]), bare(t[1]), bare(t[2]), bare(t[3])) != CGAL::POSITIVE)
      throw Invalid_input("improve_anisotropic_mesh_3: a cell is not positively oriented");
    m.tets.push_back(t);
    m.tet_refs.push_back(subdomain(c));
  }
  std::map<typename C3T3::Surface_patch_index, int> patch_ref;
  for(auto f = c3t3.facets_in_complex_begin(); f != c3t3.facets_in_complex_end(); ++f) {
    typename Tr::Cell_handle c = f->first;
    int i = f->second;
    const auto mirror = tr.mirror_facet(*f);
    if(subdomain(mirror.first) > subdomain(c)) {
      c = mirror.first;
      i = mirror.second;
    }
    // outward: the cell's fourth vertex on the negative side
    std::array<int, 3> t{{id.at(c->vertex((i + 1) & 3)), id.at(c->vertex((i + 2) & 3)), id.at(c->vertex((i + 3) & 3))}};
    const int apex = tr.is_infinite(c->vertex(i)) ? -1 : id.at(c->vertex(i));
    if(apex >= 0 && CGAL::orientation(bare(t[0]), bare(t[1]), bare(t[2]), bare(apex)) != CGAL::NEGATIVE)
      std::swap(t[0], t[1]);
    m.triangles.push_back(t);
    m.triangle_refs.push_back(ref_of_index(c3t3.surface_patch_index(*f), out.patches, patch_ref));
  }
  std::map<typename C3T3::Curve_index, int> curve_ref;
  for(auto e = c3t3.edges_in_complex_begin(); e != c3t3.edges_in_complex_end(); ++e) {
    m.edges.push_back({{id.at(e->first->vertex(e->second)), id.at(e->first->vertex(e->third))}});
    m.edge_refs.push_back(ref_of_index(c3t3.curve_index(*e), out.curves, curve_ref));
  }
  for(auto v = c3t3.vertices_in_complex_begin(); v != c3t3.vertices_in_complex_end(); ++v) {
    const Vertex_handle h = v;
    m.corners.push_back(id.at(h));
    out.corner_indices.push_back(c3t3.corner_index(h));
  }
  m.point_refs.assign(m.points.size(), 0);
  return out;
}

} // namespace internal

namespace internal {

/// The complex's indices of an improved `C3t3_as_indexed_mesh`: refs are
/// 1-based positions in its tables; a vertex of the input keeps its
/// dimension and index, a vertex the improvement added (an edge split) gets
/// the index of the curve, patch or subdomain it lies in.
template <typename C3T3_in, typename C3T3_out>
struct Table_indices {
  typedef typename C3T3_out::Triangulation::Vertex_handle Vertex_handle;
  typedef typename C3T3_out::Triangulation::Vertex::Index Index;
  const C3t3_as_indexed_mesh<C3T3_in>& tables;
  /// the input vertex of each vertex of the improved mesh, -1 for a new one
  std::vector<int> origin;

  typename C3T3_out::Surface_patch_index patch(int ref) const { return entry(tables.patches, ref, "patch"); }
  typename C3T3_out::Curve_index curve(int ref) const { return entry(tables.curves, ref, "curve"); }
  typename C3T3_out::Corner_index corner(int ref) const { return entry(tables.corner_indices, ref, "corner"); }
  /// the table's entry of a 1-based ref (a ref the tables do not hold is a bug of the improvement)
  template <typename Table>
  static typename Table::value_type entry(const Table& table, int ref, const char* what)
  {
    if(ref < 1 || std::size_t(ref) > table.size())
      throw Meshing_failure(std::string("improve_anisotropic_mesh_3: the improved mesh refers to ") + what + " " +
                            std::to_string(ref) + " of " + std::to_string(table.size()));
    return table[std::size_t(ref - 1)];
  }
  void set_vertex(Vertex_handle v, std::size_t i, const C3t3_vertex_location& l) const
  {
    if(origin[i] >= 0) {
      const auto& input = tables.vertices[std::size_t(origin[i])];
      v->set_dimension(input->in_dimension());
      v->set_index(input->index());
      return;
    }
    switch(l.dimension) {
    case 1: v->set_index(Index(curve(l.index))); break;
    case 2: v->set_index(Index(patch(l.index))); break;
    case 3: v->set_index(Index(typename C3T3_out::Subdomain_index(l.index))); break;
    default:
      throw Meshing_failure("improve_anisotropic_mesh_3: the improvement added a vertex of dimension " +
                            std::to_string(l.dimension));
    }
    v->set_dimension(l.dimension);
  }
};

} // namespace internal

/// \ingroup PkgBubbleMesh3Functions
/// Improves the cells of the complex `in` in the metric `field` (a model of
/// `MetricField_3`) by the flips and smoothing of `improve_mesh()` and
/// writes the result into `out` (cleared first); see the file
/// documentation. `in` is not modified; it may be the output of CGAL's
/// `make_mesh_3()` (regular triangulation) or of
/// `make_anisotropic_mesh_3()`.
///
/// \tparam C3T3_in a `Mesh_complex_3_in_triangulation_3` over a 3D
///   triangulation with the Mesh_3 data structure
/// \tparam C3T3_out a `Mesh_complex_3_in_triangulation_3` over
///   `CGAL::Anisotropic_mesh_triangulation_3<MeshDomain>::type` (not a regular
///   triangulation: the result is not Delaunay), with the same vertex index,
///   subdomain, surface patch, curve and corner index types as `C3T3_in`
///
/// `options.ref_0_is_exterior` is forced on. With `edge_splits` (and
/// `edge_lengths`) the improvement may add vertices: inside a subdomain, and
/// on patches and curves only with a `surface_projection` /
/// `curve_projection`; they get the index of what they lie in. With
/// `edge_collapses` it may remove vertices. The result goes through the
/// same checked conversion as `make_anisotropic_mesh_3()`'s. Returns what was
/// done; the qualities of the report are those of the complex's cells only.
/// Throws `Invalid_input` if `in` is not a 3D triangulation with positively
/// oriented cells, `Meshing_failure` if the improved cells do not make a
/// valid complex (a bug: please report it); exceptions of `field` propagate.
template <typename C3T3_in, typename C3T3_out, typename MetricField_3>
Improvement_report improve_anisotropic_mesh_3(const C3T3_in& in, C3T3_out& out, const MetricField_3& field,
                                              Improvement_options options = {})
{
  internal::C3t3_as_indexed_mesh<C3T3_in> copy = internal::c3t3_to_indexed_mesh(in);
  Indexed_tet_mesh_3& m = copy.mesh;
  std::vector<internal::C3t3_vertex_location> locations = internal::vertex_locations(m);
  options.ref_0_is_exterior = true;
  const Improvement_report report = improve_mesh(m, field, options);
  internal::Table_indices<C3T3_in, C3T3_out> indices{copy, std::vector<int>(m.points.size(), -1)};
  for(std::size_t v = 0; v < copy.vertices.size(); ++v) {
    const int w = report.new_vertex_index.empty() ? int(v) : report.new_vertex_index[v];
    if(w >= 0)
      indices.origin[std::size_t(w)] = int(v);
  }
  internal::relocate_after_improvement(m, report.new_vertex_index, locations);
  out.clear();
  try {
    internal::indexed_mesh_to_c3t3(m, locations, indices, out);
  } catch(const Invalid_input& e) {
    out.clear();
    throw Meshing_failure(std::string("improve_anisotropic_mesh_3: the improved cells: ") + e.what());
  }
  return report;
}

/// \ingroup PkgBubbleMesh3Functions
/// Same, with named parameters (`improvement_options()` lists them), e.g.
/// `CGAL::Bubble_mesh_3::parameters::number_of_iterations(20).edge_splits(true)`.
template <typename C3T3_in, typename C3T3_out, typename MetricField_3, typename NamedParameters>
Improvement_report improve_anisotropic_mesh_3(const C3T3_in& in, C3T3_out& out, const MetricField_3& field,
                                              const NamedParameters& np)
{
  return improve_anisotropic_mesh_3(in, out, field, improvement_options(np));
}

} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_IMPROVE_C3T3_H
