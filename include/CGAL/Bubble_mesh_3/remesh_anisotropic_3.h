// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_REMESH_ANISOTROPIC_3_H
#define CGAL_BUBBLE_MESH_3_REMESH_ANISOTROPIC_3_H

// Regenerating a mesh of the domain of an existing tet mesh, for another
// metric (the step of a solution-adaptive loop): the input's boundary is the
// surface meshed, its references are carried over.

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Bubble_mesh_3/IO/read_triangle_surface.h>
#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/detect_features.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/improve_c3t3.h>
#include <CGAL/Bubble_mesh_3/parameters.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Interpolated_metric_field_3.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/copy_face_graph.h>
#include <CGAL/make_anisotropic_mesh_3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {

namespace internal {

/// The boundary of a tet mesh: the faces of exactly one tet, oriented
/// outward, with the reference the input's triangle list gives them.
struct Tet_mesh_boundary {
  std::vector<std::array<int, 3>> triangles; ///< vertex indices of the input mesh, outward
  std::vector<int> refs;                     ///< from the input's triangles (0 where not listed)
  bool refs_given = false;                   ///< whether any boundary face was in the input's triangle list
  std::vector<int> subdomains;               ///< the distinct tet references, sorted
};

/// Checks `mesh` (indices, finite points, no flat tet, conforming faces, no
/// interface between two subdomains) and returns its boundary. Throws
/// `Invalid_input` naming the problem.
inline Tet_mesh_boundary tet_mesh_boundary(const Indexed_tet_mesh_3& mesh)
{
  typedef CGAL::Exact_predicates_inexact_constructions_kernel::Point_3 P;
  const std::size_t n = mesh.points.size();
  if(mesh.tets.empty())
    throw Invalid_input("the input mesh has no tetrahedra");
  for(std::size_t i = 0; i < n; ++i)
    for(double c : mesh.points[i])
      if(!std::isfinite(c))
        throw Invalid_input("the input mesh's vertex " + std::to_string(i + 1) + " has a non-finite coordinate");
  if(!mesh.tet_refs.empty() && mesh.tet_refs.size() != mesh.tets.size())
    throw Invalid_input("the input mesh has " + std::to_string(mesh.tet_refs.size()) + " tet references for " +
                        std::to_string(mesh.tets.size()) + " tets");
  auto point = [&](int i) { return P(mesh.points[std::size_t(i)][0], mesh.points[std::size_t(i)][1], mesh.points[std::size_t(i)][2]); };
  auto tet_ref = [&](std::size_t t) { return mesh.tet_refs.empty() ? 1 : mesh.tet_refs[t]; };
  // every face as (sorted vertices, 4 * tet + opposite corner)
  std::vector<std::pair<std::array<int, 3>, std::size_t>> faces;
  faces.reserve(4 * mesh.tets.size());
  for(std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const std::array<int, 4>& v = mesh.tets[t];
    for(int k = 0; k < 4; ++k)
      if(v[std::size_t(k)] < 0 || std::size_t(v[std::size_t(k)]) >= n)
        throw Invalid_input("the input mesh's tet " + std::to_string(t + 1) + " has a vertex index out of range");
    if(CGAL::orientation(point(v[0]), point(v[1]), point(v[2]), point(v[3])) == CGAL::COPLANAR)
      throw Invalid_input("the input mesh's tet " + std::to_string(t + 1) + " is flat (zero volume)");
    for(int i = 0; i < 4; ++i) {
      std::array<int, 3> f = {{v[std::size_t((i + 1) & 3)], v[std::size_t((i + 2) & 3)], v[std::size_t((i + 3) & 3)]}};
      std::sort(f.begin(), f.end());
      faces.emplace_back(f, 4 * t + std::size_t(i));
    }
  }
  std::sort(faces.begin(), faces.end());
  std::map<std::array<int, 3>, int> listed;
  for(std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    std::array<int, 3> f = mesh.triangles[i];
    std::sort(f.begin(), f.end());
    listed.emplace(f, mesh.triangle_refs.size() == mesh.triangles.size() ? mesh.triangle_refs[i] : 0);
  }
  Tet_mesh_boundary b;
  std::set<int> subdomains;
  for(std::size_t t = 0; t < mesh.tets.size(); ++t)
    subdomains.insert(tet_ref(t));
  b.subdomains.assign(subdomains.begin(), subdomains.end());
  for(std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while(j < faces.size() && faces[j].first == faces[i].first)
      ++j;
    if(j - i > 2)
      throw Invalid_input("the input mesh is not conforming: a triangle (vertices " +
                          std::to_string(faces[i].first[0] + 1) + ", " + std::to_string(faces[i].first[1] + 1) +
                          ", " + std::to_string(faces[i].first[2] + 1) + ") is a face of " + std::to_string(j - i) +
                          " tets");
    if(j - i == 2) {
      if(tet_ref(faces[i].second / 4) != tet_ref(faces[i + 1].second / 4))
        throw Invalid_input("the input mesh has an interface between subdomains " +
                            std::to_string(tet_ref(faces[i].second / 4)) + " and " +
                            std::to_string(tet_ref(faces[i + 1].second / 4)) +
                            "; remeshing keeps subdomains that do not touch, not internal interfaces (yet)");
    } else {
      const std::size_t t = faces[i].second / 4;
      const int corner = int(faces[i].second % 4);
      const std::array<int, 4>& v = mesh.tets[t];
      std::array<int, 3> f = {{v[std::size_t((corner + 1) & 3)], v[std::size_t((corner + 2) & 3)],
                               v[std::size_t((corner + 3) & 3)]}};
      // outward: the tet's fourth vertex on the negative side
      if(CGAL::orientation(point(f[0]), point(f[1]), point(f[2]), point(v[std::size_t(corner)])) != CGAL::NEGATIVE)
        std::swap(f[0], f[1]);
      b.triangles.push_back(f);
      const auto it = listed.find(faces[i].first);
      b.refs_given = b.refs_given || it != listed.end();
      b.refs.push_back(it == listed.end() ? 0 : it->second);
    }
    i = j;
  }
  return b;
}

} // namespace internal

/// \ingroup PkgBubbleMesh3Functions
/// P1 interpolation of vertex values: `values` (one per vertex of `mesh`)
/// interpolated linearly at each of `points` (arrays of 3 doubles) inside
/// the tet of `mesh` that contains it; a point outside `mesh` takes the
/// value of the nearest vertex. Throws `Invalid_input` for a bad mesh or a
/// count mismatch.
inline std::vector<double> interpolate_vertex_values(const Indexed_tet_mesh_3& mesh, const std::vector<double>& values,
                                                     const std::vector<std::array<double, 3>>& points)
{
  typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
  if(values.size() != mesh.points.size())
    throw Invalid_input("interpolate_vertex_values: " + std::to_string(values.size()) + " values for a mesh of " +
                        std::to_string(mesh.points.size()) + " vertices");
  const Interpolated_metric_field_3<K> locator(
      mesh, std::vector<Metric_3>(mesh.points.size(), Metric_3(Metric_3::Matrix::Identity())), "interpolation mesh");
  std::vector<double> out;
  out.reserve(points.size());
  for(const auto& q : points) {
    const K::Point_3 p(q[0], q[1], q[2]);
    std::array<int, 4> v;
    std::array<double, 4> w;
    if(locator.locate(p, v, w) < 0) {
      out.push_back(values[locator.nearest_vertex(p)]);
      continue;
    }
    double sum = 0, total = 0;
    for(int k = 0; k < 4; ++k) {
      const double wk = std::max(0.0, w[std::size_t(k)]);
      sum += wk * values[std::size_t(v[std::size_t(k)])];
      total += wk;
    }
    out.push_back(sum / total);
  }
  return out;
}

/// \ingroup PkgBubbleMesh3Functions
/// A new anisotropic mesh of the domain of the tet mesh `input`, for the
/// metric `field` (typically a `Hessian_metric_field_3` of a solution on
/// `input`): the step of a solution-adaptive loop. The mesh is regenerated
/// (bubble packing, fronts), not patched.
///
/// - The surface meshed is the boundary of `input` (the faces of exactly one
///   tet). Feature curves: the edges between boundary faces of different
///   references (from `input.triangles` / `triangle_refs`), and those sharper
///   than `feature_angle` (detect_features()).
/// - The output's boundary triangles carry the reference of the input
///   boundary face nearest their centroid (the pipeline's patch numbers if
///   `input` lists no boundary triangle); its tets the reference of the
///   input tet containing their centroid.
///
/// Named parameters: those of `make_anisotropic_mesh_3()` and of
/// `detect_features()` (`feature_angle`, `minimum_feature_length`), except
/// that `surface_distance` is automatic by default (negative: the bounding
/// box diagonal times `default_relative_surface_distance`; 0 turns the bound
/// off): the input's boundary is the geometry, and a loop of remeshings
/// without a bound wears curved parts away.
///
/// Throws `Invalid_input` when `input` is not a valid conforming tet mesh
/// (index out of range, non-finite point, flat tet, a face shared by three
/// tets), has an interface between subdomains of different references (not
/// supported yet), or a boundary that is not a closed manifold surface
/// (tets meeting at an edge or a vertex only); otherwise as
/// `make_anisotropic_mesh_3()`.
template <typename MetricField, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Indexed_tet_mesh_3 remesh_anisotropic_3(const Indexed_tet_mesh_3& input, const MetricField& field,
                                        const NamedParameters& np = CGAL::parameters::default_values())
{
  typedef typename MetricField::Kernel K;
  typedef typename K::Point_3 Point_3;
  typedef CGAL::Polyhedral_mesh_domain_with_features_3<K> Domain;
  namespace PMP = CGAL::Polygon_mesh_processing;

  const internal::Tet_mesh_boundary boundary = internal::tet_mesh_boundary(input);

  // the boundary as a surface of its own vertices
  std::vector<int> local(input.points.size(), -1);
  std::vector<Point_3> points;
  std::vector<std::vector<std::size_t>> polygons;
  for(const auto& t : boundary.triangles) {
    polygons.emplace_back();
    for(int v : t) {
      if(local[std::size_t(v)] < 0) {
        local[std::size_t(v)] = int(points.size());
        const auto& c = input.points[std::size_t(v)];
        points.emplace_back(c[0], c[1], c[2]);
      }
      polygons.back().push_back(std::size_t(local[std::size_t(v)]));
    }
  }
  if(!PMP::is_polygon_soup_a_polygon_mesh(polygons))
    throw Invalid_input("the boundary of the input mesh is not a manifold surface (tets meeting only at an edge "
                        "or a vertex)");
  CGAL::Surface_mesh<Point_3> surface;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, surface);
  {
    const std::string problem = IO::check_triangle_surface(surface, false);
    if(!problem.empty())
      throw Invalid_input("the boundary of the input mesh: " + problem);
  }
  typename Domain::Polyhedron polyhedron;
  CGAL::copy_face_graph(surface, polyhedron);

  // the edges between faces of different references are features whatever
  // their angle (detect_features() keeps features already marked)
  std::map<std::pair<std::size_t, std::size_t>, int> edge_face_ref;
  std::set<std::array<double, 6>> ref_edges;
  for(std::size_t f = 0; f < polygons.size(); ++f)
    for(int k = 0; k < 3; ++k) {
      std::size_t a = polygons[f][std::size_t(k)], b = polygons[f][std::size_t((k + 1) % 3)];
      if(a > b)
        std::swap(a, b);
      const auto inserted = edge_face_ref.emplace(std::make_pair(a, b), boundary.refs[f]);
      if(!inserted.second && inserted.first->second != boundary.refs[f]) {
        const Point_3& p = points[a];
        const Point_3& q = points[b];
        std::array<double, 6> key = {{p.x(), p.y(), p.z(), q.x(), q.y(), q.z()}};
        ref_edges.insert(key);
        std::swap_ranges(key.begin(), key.begin() + 3, key.begin() + 3);
        ref_edges.insert(key);
      }
    }
  if(!ref_edges.empty()) {
    auto eif = get(CGAL::edge_is_feature, polyhedron);
    for(auto e : edges(polyhedron)) {
      const Point_3& p = source(e, polyhedron)->point();
      const Point_3& q = target(e, polyhedron)->point();
      if(ref_edges.count({{p.x(), p.y(), p.z(), q.x(), q.y(), q.z()}}))
        put(eif, e, true);
    }
  }
  const Detected_features<Point_3> features = detect_features(polyhedron, field, np);
  Domain domain(polyhedron);
  features.add_to(domain);

  // The input's boundary is the geometry: unless told otherwise, the new
  // boundary stays within the automatic distance of it. Without a bound the
  // metric's sizes alone decide, and each remeshing of a loop chords curved
  // parts a little more (knot1 at 7,300 vertices: 9.4 % of the volume lost in
  // one remeshing, 30 % without gradation).
  const double distance =
      CGAL::parameters::choose_parameter(CGAL::parameters::get_parameter(np, internal_np::surface_distance), -1.0);
  const CGAL::Named_function_parameters<double, internal_np::surface_distance_t, NamedParameters> bounded(distance,
                                                                                                         np);
  Indexed_tet_mesh_3 mesh = make_indexed_anisotropic_mesh_3(domain, field, bounded);

  // references carried over
  if(boundary.refs_given) {
    typedef CGAL::Exact_predicates_inexact_constructions_kernel EK;
    std::vector<EK::Triangle_3> input_triangles;
    input_triangles.reserve(boundary.triangles.size());
    auto ep = [&](int v) {
      const auto& c = input.points[std::size_t(v)];
      return EK::Point_3(c[0], c[1], c[2]);
    };
    for(const auto& t : boundary.triangles)
      input_triangles.emplace_back(ep(t[0]), ep(t[1]), ep(t[2]));
    typedef CGAL::AABB_triangle_primitive<EK, typename std::vector<EK::Triangle_3>::const_iterator> Primitive;
    CGAL::AABB_tree<CGAL::AABB_traits<EK, Primitive>> tree(input_triangles.cbegin(), input_triangles.cend());
    tree.accelerate_distance_queries();
    for(std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      const auto& t = mesh.triangles[i];
      std::array<double, 3> c{{0, 0, 0}};
      for(int v : t)
        for(int k = 0; k < 3; ++k)
          c[std::size_t(k)] += mesh.points[std::size_t(v)][std::size_t(k)] / 3;
      const auto nearest = tree.closest_point_and_primitive(EK::Point_3(c[0], c[1], c[2]));
      mesh.triangle_refs[i] = boundary.refs[std::size_t(nearest.second - input_triangles.cbegin())];
    }
  }
  if(boundary.subdomains.size() == 1) {
    mesh.tet_refs.assign(mesh.tets.size(), boundary.subdomains.front());
  } else {
    std::vector<std::array<double, 3>> centroids;
    centroids.reserve(mesh.tets.size());
    for(const auto& t : mesh.tets) {
      std::array<double, 3> c{{0, 0, 0}};
      for(int v : t)
        for(int k = 0; k < 3; ++k)
          c[std::size_t(k)] += mesh.points[std::size_t(v)][std::size_t(k)] / 4;
      centroids.push_back(c);
    }
    // the reference of the containing input tet, through its vertices' values:
    // no interface, so the four vertices of an input tet have its reference
    std::vector<double> vertex_ref(input.points.size(), 0);
    for(std::size_t t = 0; t < input.tets.size(); ++t)
      for(int v : input.tets[t])
        vertex_ref[std::size_t(v)] = input.tet_refs[t];
    const std::vector<double> refs = interpolate_vertex_values(input, vertex_ref, centroids);
    for(std::size_t t = 0; t < mesh.tets.size(); ++t)
      mesh.tet_refs[t] = int(std::lround(refs[t]));
  }
  return mesh;
}

/// \ingroup PkgBubbleMesh3Functions
/// The same from a `Mesh_complex_3_in_triangulation_3` (e.g. the output of
/// `make_mesh_3()` or `make_anisotropic_mesh_3()`): its cells in the complex
/// are the input mesh (subdomain index as tet reference), its facets in the
/// complex the boundary triangles (surface patch index as reference, when
/// it converts to `int`; otherwise its position among the complex's patch
/// indices, from 1). `field`'s vertex values, if it was built on a mesh,
/// must come from the same mesh (`Bubble_mesh_3::internal::c3t3_to_indexed_mesh()`
/// order). Returns the new mesh as plain arrays.
template <typename C3T3, typename MetricField, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Indexed_tet_mesh_3 remesh_anisotropic_3(const C3T3& c3t3, const MetricField& field,
                                        const NamedParameters& np = CGAL::parameters::default_values())
{
  const auto in = internal::c3t3_to_indexed_mesh(c3t3);
  // the complex's cells only, their vertices renumbered
  Indexed_tet_mesh_3 mesh;
  std::vector<int> id(in.mesh.points.size(), -1);
  auto local = [&](int v) {
    if(id[std::size_t(v)] < 0) {
      id[std::size_t(v)] = int(mesh.points.size());
      mesh.points.push_back(in.mesh.points[std::size_t(v)]);
    }
    return id[std::size_t(v)];
  };
  for(std::size_t t = 0; t < in.mesh.tets.size(); ++t) {
    if(in.mesh.tet_refs[t] == 0)
      continue;
    std::array<int, 4> tet;
    for(int k = 0; k < 4; ++k)
      tet[std::size_t(k)] = local(in.mesh.tets[t][std::size_t(k)]);
    mesh.tets.push_back(tet);
    mesh.tet_refs.push_back(in.mesh.tet_refs[t]);
  }
  for(std::size_t i = 0; i < in.mesh.triangles.size(); ++i) {
    const auto& t = in.mesh.triangles[i];
    if(id[std::size_t(t[0])] < 0 || id[std::size_t(t[1])] < 0 || id[std::size_t(t[2])] < 0)
      continue;
    mesh.triangles.push_back({{id[std::size_t(t[0])], id[std::size_t(t[1])], id[std::size_t(t[2])]}});
    int ref = in.mesh.triangle_refs[i];
    if constexpr(std::is_convertible<typename C3T3::Surface_patch_index, int>::value)
      ref = int(in.patches[std::size_t(ref - 1)]);
    mesh.triangle_refs.push_back(ref);
  }
  return remesh_anisotropic_3(mesh, field, np);
}

} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_REMESH_ANISOTROPIC_3_H
