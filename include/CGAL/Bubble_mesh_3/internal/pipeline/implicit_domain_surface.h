// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_IMPLICIT_DOMAIN_SURFACE_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_IMPLICIT_DOMAIN_SURFACE_H

// The surface of an implicit or labelled domain (a Mesh_3 `MeshDomain_3`
// without polyhedra: `Labeled_mesh_domain_3`, with or without
// `Mesh_domain_with_polyline_features_3`) for the pipeline. The boundary
// front connects nodes lying on a triangulated surface, so the stages run on
// a fine polyhedral copy of the domain's boundary (CGAL Mesh_3's surface
// mesh of it: manifold, its feature edges along the domain's curves, chord
// error a fraction of the metric's smallest size), and the boundary vertices
// of the result are then moved onto the domain's own surface and curves
// (bisection of its inside test; closest point on its polylines). A move
// that would turn a tet over is not made (counted in the report).

#include <CGAL/Bubble_mesh_3/Meshing_report.h>
#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/internal/c3t3/tet_soup_to_c3t3.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/domain_mesh.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/run_control.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_polyhedron_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>
#include <CGAL/make_mesh_3.h>
#include <CGAL/refine_mesh_3.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

/// whether a domain has feature curves (`Mesh_domain_with_polyline_features_3`)
template <typename D, typename = void>
struct Has_feature_curves : std::false_type {};
template <typename D>
struct Has_feature_curves<D, std::void_t<decltype(std::declval<const D&>().curves_aabb_tree())>> : std::true_type {};

/// the corner and curve index types of a domain (int, as Mesh_3's complex
/// defaults them, for a domain without features)
template <typename D, typename = void>
struct Feature_index_types {
  typedef int Corner_index;
  typedef int Curve_index;
};
template <typename D>
struct Feature_index_types<D, std::void_t<typename D::Curve_index>> {
  typedef typename D::Corner_index Corner_index;
  typedef typename D::Curve_index Curve_index;
};

/// The chord error of the polyhedral copy: this fraction of the metric's
/// smallest size on the surface, within these fractions of the bounding box
/// diagonal (the finest: about 10^5 triangles on a sphere; the coarsest,
/// about 10^4: a coarser copy saves little time, and the larger moves onto
/// the surface at the end cost worst angles: 40.0 -> 37.7 degrees on a unit
/// sphere at size 0.2 with a fiftieth of the size, 4 times the coarsest)
constexpr double surface_error_per_size() { return 0.02; }
constexpr double finest_relative_surface_error() { return 2e-5; }
constexpr double coarsest_relative_surface_error() { return 1e-4; }

template <typename ImplicitDomain>
class Implicit_domain_surface {
public:
  typedef typename ImplicitDomain::R K;
  typedef typename K::Point_3 Point;
  typedef typename CGAL::Mesh_polyhedron_3<K>::type Polyhedron;
  typedef CGAL::Polyhedral_mesh_domain_with_features_3<K> Meshed_domain;
  typedef typename ImplicitDomain::Surface_patch_index Surface_patch_index;
  typedef typename ImplicitDomain::Subdomain_index Subdomain_index;
  typedef typename Feature_index_types<ImplicitDomain>::Corner_index Corner_index;
  typedef typename Feature_index_types<ImplicitDomain>::Curve_index Curve_index;
  static constexpr bool moves_boundary = true;

  /// Meshes the domain's boundary with CGAL Mesh_3 and builds the
  /// polyhedral domain the stages run on. Throws `Invalid_input` for a domain
  /// of several subdomains, an empty one, or one whose curves leave its
  /// surface.
  template <typename MetricField>
  Implicit_domain_surface(const ImplicitDomain& domain, const MetricField& field, const Run_control& control,
                          Meshing_report& rep)
      : domain_(domain)
  {
    const auto t0 = std::chrono::steady_clock::now();
    const CGAL::Bbox_3 box = domain.bbox();
    diagonal_ = std::sqrt(CGAL::square(box.xmax() - box.xmin()) + CGAL::square(box.ymax() - box.ymin()) +
                          CGAL::square(box.zmax() - box.zmin()));
    if(!(diagonal_ > 0) || !std::isfinite(diagonal_))
      throw Invalid_input("domain: the implicit domain's bounding box is empty or not finite");
    probe();
    // the chord error: a small fraction of the smallest size the metric asks
    // on the surface (sampled at the probe's surface points), so that moving
    // the vertices onto the surface at the end shifts them by a small
    // fraction of their tets' heights
    double smallest = std::numeric_limits<double>::infinity();
    for(const auto& c : crossings_)
      smallest = std::min(smallest, Metric_3(field(c.first)).principal_sizes().minCoeff());
    chord_error_ = std::clamp(surface_error_per_size() * smallest, finest_relative_surface_error() * diagonal_,
                              coarsest_relative_surface_error() * diagonal_);
    const Surface_soup soup = mesh_surface(chord_error_, control);
    control.check("the domain's surface");
    build_meshed_domain(soup);
    rep.implicit_surface_triangles = soup.faces.size();
    rep.implicit_surface_chord_error = chord_error_;
    rep.implicit_surface_seconds = seconds_since(t0);
    control.say("domain surface: " + std::to_string(soup.faces.size()) + " triangles (CGAL Mesh_3, chord error " +
                std::to_string(chord_error_) + "), " + std::to_string(rep.implicit_surface_seconds) + " s");
  }

  /// the polyhedral domain the stages mesh
  const Meshed_domain& meshed_domain() const { return *meshed_; }

  /// Moves the boundary vertices of `out` onto the domain's surface (patch
  /// vertices, along their normal, by bisection of the inside test) and
  /// curves (closest point), and gives corners, curve vertices, feature
  /// edges, interior vertices and tets the domain's indices. Patch refs stay
  /// those of the polyhedral copy (`c3t3_indices()` maps them).
  void project_boundary(Domain_mesh& out, Meshing_report& rep) const
  {
    Indexed_tet_mesh_3& m = out.mesh;
    relabel(out);
    const std::vector<std::vector<int>> tets_of = incident_tets(m);
    const std::vector<Eigen::Vector3d> normals = vertex_normals(m);
    std::size_t snapped = 0, kept = 0;
    double largest = 0;
    auto move = [&](std::size_t v, const Eigen::Vector3d& target) {
      const std::array<double, 3> old = m.points[v];
      m.points[v] = {{target.x(), target.y(), target.z()}};
      if(!positive(m, tets_of[v])) {
        m.points[v] = old;
        ++kept;
        return;
      }
      ++snapped;
      largest = std::max(largest, (target - Eigen::Vector3d(old[0], old[1], old[2])).norm());
    };
    for(int dimension : {1, 2})
      for(std::size_t v = 0; v < m.points.size(); ++v) {
        if(out.locations[v].dimension != dimension)
          continue;
        const Eigen::Vector3d p(m.points[v][0], m.points[v][1], m.points[v][2]);
        Eigen::Vector3d target;
        if(dimension == 1 ? point_on_curves(p, target) : point_on_surface(p, normals[v], target))
          move(v, target);
        else
          ++kept;
      }
    rep.snapped_boundary_vertices = snapped;
    rep.unsnapped_boundary_vertices = kept;
    rep.largest_snap = largest;
  }

  /// The complex's indices of a mesh that went through `project_boundary()`.
  template <typename C3T3>
  struct Indices {
    const Implicit_domain_surface& surface;
    typename C3T3::Surface_patch_index patch(int ref) const
    {
      const auto it = surface.patch_of_.find(ref);
      if(it == surface.patch_of_.end())
        throw Invalid_input("tet_mesh_to_c3t3: surface patch " + std::to_string(ref) + " is not one of the domain's");
      return it->second;
    }
    typename C3T3::Curve_index curve(int ref) const { return typename C3T3::Curve_index(ref); }
    typename C3T3::Corner_index corner(int ref) const { return typename C3T3::Corner_index(ref); }
    void set_vertex(typename C3T3::Vertex_handle v, std::size_t i, const C3t3_vertex_location& l) const
    {
      const ImplicitDomain& d = surface.domain_;
      if constexpr(Has_feature_curves<ImplicitDomain>::value) {
        if(l.dimension == 0)
          v->set_index(d.index_from_corner_index(corner(l.index)));
        if(l.dimension == 1)
          v->set_index(d.index_from_curve_index(curve(l.index)));
      } else if(l.dimension < 2)
        throw Invalid_input("tet_mesh_to_c3t3: a vertex on a curve of a domain without curves");
      switch(l.dimension) {
      case 0:
      case 1: break;
      case 2: v->set_index(d.index_from_surface_patch_index(patch(l.index))); break;
      case 3: v->set_index(d.index_from_subdomain_index(Subdomain_index(l.index))); break;
      default:
        throw Invalid_input("tet_mesh_to_c3t3: vertex " + std::to_string(i) + " has dimension " +
                            std::to_string(l.dimension));
      }
      v->set_dimension(l.dimension);
    }
  };
  template <typename C3T3>
  Indices<C3T3> c3t3_indices() const
  {
    return Indices<C3T3>{*this};
  }

private:
  struct Surface_soup {
    std::vector<Point> points;
    std::vector<std::array<std::size_t, 3>> faces; // outward
    std::vector<Surface_patch_index> face_patches;
    std::vector<std::pair<std::array<std::size_t, 2>, Curve_index>> feature_edges;
    std::vector<std::pair<std::size_t, Corner_index>> corners;
  };

  /// The domain's labels and surface points on the edges of a grid over its
  /// bounding box (`probe_cells()` per side): refuses an empty domain or
  /// several subdomains before any meshing, and gives the points where
  /// Mesh_3 must have found a surface (its initial points come from rays
  /// shot from the centre, which miss components hidden behind others).
  void probe()
  {
    const CGAL::Bbox_3 box = domain_.bbox();
    const int n = probe_cells();
    auto grid_point = [&](int i, int j, int k) {
      return Point(box.xmin() + (box.xmax() - box.xmin()) * i / n, box.ymin() + (box.ymax() - box.ymin()) * j / n,
                   box.zmin() + (box.zmax() - box.zmin()) * k / n);
    };
    const auto is_in = domain_.is_in_domain_object();
    std::vector<int> label(std::size_t(n + 1) * (n + 1) * (n + 1), 0);
    std::map<int, Subdomain_index> labels;
    auto at = [n](int i, int j, int k) { return (std::size_t(i) * (n + 1) + std::size_t(j)) * (n + 1) + std::size_t(k); };
    for(int i = 0; i <= n; ++i)
      for(int j = 0; j <= n; ++j)
        for(int k = 0; k <= n; ++k) {
          const auto l = is_in(grid_point(i, j, k));
          if(!l)
            continue;
          int& number = label[at(i, j, k)];
          const auto it = std::find_if(labels.begin(), labels.end(), [&](const auto& e) { return e.second == *l; });
          number = it != labels.end() ? it->first : int(labels.size()) + 1;
          labels.emplace(number, *l);
        }
    if(labels.empty())
      throw Invalid_input("domain: no point of the implicit domain found in its bounding box (probed on a " +
                          std::to_string(n) + "^3 grid): is the domain empty, or thinner than the grid?");
    if(labels.size() > 1)
      throw Invalid_input("domain: the implicit domain has " + std::to_string(labels.size()) +
                          " subdomains (labels); make_anisotropic_mesh_3 meshes domains of one subdomain "
                          "(interfaces between materials are not supported yet)");
    const auto intersect = domain_.construct_intersection_object();
    for(int i = 0; i <= n; ++i)
      for(int j = 0; j <= n; ++j)
        for(int k = 0; k <= n; ++k)
          for(int d = 0; d < 3; ++d) {
            const int i2 = i + (d == 0), j2 = j + (d == 1), k2 = k + (d == 2);
            if(i2 > n || j2 > n || k2 > n || label[at(i, j, k)] == label[at(i2, j2, k2)])
              continue;
            const auto hit = intersect(typename K::Segment_3(grid_point(i, j, k), grid_point(i2, j2, k2)));
            if(std::get<2>(hit) == 2)
              crossings_.push_back({std::get<0>(hit), std::get<1>(hit)});
          }
  }
  static constexpr int probe_cells() { return 48; }

  /// CGAL Mesh_3's manifold surface mesh of the domain, chord error
  /// `distance`; the probe's surface points it did not reach seed a second
  /// refinement.
  Surface_soup mesh_surface(double distance, const Run_control& control)
  {
    typedef typename CGAL::Mesh_triangulation_3<ImplicitDomain>::type Tr;
    typedef CGAL::Mesh_complex_3_in_triangulation_3<Tr, Corner_index, Curve_index> C3t3;
    typedef CGAL::Mesh_criteria_3<Tr> Criteria;
    namespace P = CGAL::parameters;
    // curves get chords of the same error as the patches on a unit radius
    const Criteria criteria(P::edge_size = std::sqrt(distance * diagonal_), P::facet_angle = 25,
                            P::facet_size = diagonal_ / 40, P::facet_distance = distance);
    C3t3 c3t3 = CGAL::make_mesh_3<C3t3>(domain_, criteria, P::no_perturb(), P::no_exude(), P::manifold());
    for(int round = 0;; ++round) {
      Surface_soup soup = surface_of(c3t3);
      const std::vector<std::size_t> missed = unreached_crossings(soup, 10 * distance);
      if(missed.empty())
        return soup;
      if(round == 2)
        throw Meshing_failure("domain: CGAL Mesh_3 did not reach every part of the implicit domain's surface (" +
                              std::to_string(missed.size()) + " surface points of the probe left)");
      control.say("domain surface: CGAL Mesh_3 missed " + std::to_string(missed.size()) +
                  " surface points of the probe; refined again from them");
      // seed each missed part: its probe points at least a facet size apart
      Tr& tr = c3t3.triangulation();
      std::vector<Point> seeds;
      for(std::size_t c : missed) {
        const Point& p = crossings_[c].first;
        if(std::any_of(seeds.begin(), seeds.end(), [&](const Point& q) {
             return CGAL::squared_distance(p, q) < CGAL::square(diagonal_ / 40);
           }))
          continue;
        seeds.push_back(p);
        const auto v = tr.insert(tr.geom_traits().construct_weighted_point_3_object()(p));
        c3t3.set_dimension(v, 2);
        c3t3.set_index(v, crossings_[c].second);
      }
      CGAL::refine_mesh_3(c3t3, domain_, criteria, P::no_perturb(), P::no_exude(), P::manifold());
    }
  }

  /// the probe's surface points farther than `tolerance` from `soup`
  std::vector<std::size_t> unreached_crossings(const Surface_soup& soup, double tolerance) const
  {
    typedef std::vector<typename K::Triangle_3> Triangles;
    typedef CGAL::AABB_triangle_primitive<K, typename Triangles::const_iterator> Primitive;
    Triangles triangles;
    for(const auto& f : soup.faces)
      triangles.emplace_back(soup.points[f[0]], soup.points[f[1]], soup.points[f[2]]);
    std::vector<std::size_t> missed;
    if(triangles.empty()) {
      for(std::size_t c = 0; c < crossings_.size(); ++c)
        missed.push_back(c);
      return missed;
    }
    CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>> tree(triangles.begin(), triangles.end());
    tree.accelerate_distance_queries();
    for(std::size_t c = 0; c < crossings_.size(); ++c)
      if(CGAL::to_double(tree.squared_distance(crossings_[c].first)) > tolerance * tolerance)
        missed.push_back(c);
    return missed;
  }

  /// the boundary facets of Mesh_3's complex, oriented outward
  template <typename C3t3>
  Surface_soup surface_of(const C3t3& c3t3)
  {
    typedef typename C3t3::Triangulation Tr;
    const Tr& tr = c3t3.triangulation();
    std::set<Subdomain_index> subdomains;
    for(auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c)
      subdomains.insert(c3t3.subdomain_index(c));
    if(subdomains.size() > 1)
      throw Invalid_input("domain: the implicit domain has " + std::to_string(subdomains.size()) +
                          " subdomains; make_anisotropic_mesh_3 meshes domains of one subdomain (interfaces "
                          "between materials are not supported yet)");
    if(!subdomains.empty())
      subdomain_ = *subdomains.begin();

    Surface_soup soup;
    std::map<typename Tr::Vertex_handle, std::size_t> id;
    auto vertex_id = [&](typename Tr::Vertex_handle v) {
      const auto inserted = id.emplace(v, soup.points.size());
      if(inserted.second)
        soup.points.push_back(tr.geom_traits().construct_point_3_object()(v->point()));
      return inserted.first->second;
    };
    for(auto f = c3t3.facets_in_complex_begin(); f != c3t3.facets_in_complex_end(); ++f) {
      typename Tr::Cell_handle c = f->first;
      int i = f->second;
      if(!c3t3.is_in_complex(c)) {
        const typename Tr::Cell_handle n = c->neighbor(i);
        i = n->index(c);
        c = n;
      }
      if(!c3t3.is_in_complex(c))
        throw Meshing_failure("domain: a facet of CGAL Mesh_3's surface of the implicit domain bounds no cell of it");
      std::array<typename Tr::Vertex_handle, 3> t{{c->vertex((i + 1) & 3), c->vertex((i + 2) & 3),
                                                   c->vertex((i + 3) & 3)}};
      auto bare = [&](typename Tr::Vertex_handle v) { return tr.geom_traits().construct_point_3_object()(v->point()); };
      // outward: the cell's fourth vertex (inside) on the negative side
      if(CGAL::orientation(bare(t[0]), bare(t[1]), bare(t[2]), bare(c->vertex(i))) != CGAL::NEGATIVE)
        std::swap(t[1], t[2]);
      soup.faces.push_back({{vertex_id(t[0]), vertex_id(t[1]), vertex_id(t[2])}});
      soup.face_patches.push_back(c3t3.surface_patch_index(*f));
    }
    const std::size_t surface_vertices = soup.points.size();
    for(auto e = c3t3.edges_in_complex_begin(); e != c3t3.edges_in_complex_end(); ++e) {
      const std::size_t a = vertex_id(e->first->vertex(e->second)), b = vertex_id(e->first->vertex(e->third));
      if(a >= surface_vertices || b >= surface_vertices)
        throw Invalid_input("domain: a feature curve of the implicit domain leaves its surface");
      soup.feature_edges.push_back({{{a, b}}, c3t3.curve_index(*e)});
    }
    for(auto v = c3t3.vertices_in_complex_begin(); v != c3t3.vertices_in_complex_end(); ++v) {
      const std::size_t a = vertex_id(v);
      if(a >= surface_vertices)
        throw Invalid_input("domain: a corner of the implicit domain lies off its surface");
      soup.corners.push_back({a, c3t3.corner_index(v)});
    }
    if(soup.faces.empty() || subdomains.empty())
      throw Invalid_input("domain: CGAL Mesh_3 found no surface in the implicit domain's bounding box (is the "
                          "domain thinner than the surface's resolution?)");
    return soup;
  }

  /// The polyhedron of `soup`, its feature edges marked, a patch per
  /// component between them, and the polyhedral domain with its curves.
  void build_meshed_domain(const Surface_soup& soup)
  {
    typedef boost::graph_traits<Polyhedron> GT;
    typedef typename GT::vertex_descriptor vertex_descriptor;
    typedef typename GT::halfedge_descriptor halfedge_descriptor;
    typedef typename GT::face_descriptor face_descriptor;
    Polyhedron polyhedron;
    std::vector<std::vector<std::size_t>> polygons;
    for(const auto& f : soup.faces)
      polygons.push_back({f[0], f[1], f[2]});
    CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(soup.points, polygons, polyhedron);
    if(num_faces(polyhedron) != soup.faces.size() || !CGAL::is_closed(polyhedron))
      throw Invalid_input("domain: CGAL Mesh_3's surface of the implicit domain is not a closed manifold");
    std::map<Point, std::size_t> id_at;
    for(std::size_t i = 0; i < soup.points.size(); ++i)
      id_at.emplace(soup.points[i], i);
    std::vector<vertex_descriptor> vertex_of(soup.points.size());
    for(vertex_descriptor v : vertices(polyhedron))
      vertex_of[id_at.at(v->point())] = v;

    // feature edges, and the domain's curve of each
    auto eif = get(CGAL::edge_is_feature, polyhedron);
    std::map<std::pair<std::size_t, std::size_t>, Curve_index> curve_of_edge;
    std::vector<std::vector<std::pair<std::size_t, Curve_index>>> around(soup.points.size());
    for(const auto& e : soup.feature_edges) {
      const auto h = halfedge(vertex_of[e.first[0]], vertex_of[e.first[1]], polyhedron);
      if(!h.second)
        throw Invalid_input("domain: a feature curve of the implicit domain does not follow its surface mesh");
      put(eif, edge(h.first, polyhedron), true);
      curve_of_edge[std::minmax(e.first[0], e.first[1])] = e.second;
      around[e.first[0]].push_back({e.first[1], e.second});
      around[e.first[1]].push_back({e.first[0], e.second});
    }

    // patches: the components between feature edges, numbered from 1
    auto pid = get(CGAL::face_patch_id_t<int>(), polyhedron);
    auto fim = get_initialized_face_index_map(polyhedron);
    std::vector<std::size_t> component(num_faces(polyhedron));
    CGAL::Polygon_mesh_processing::connected_components(
        polyhedron, boost::make_iterator_property_map(component.begin(), fim),
        CGAL::parameters::edge_is_constrained_map(eif).face_index_map(fim));
    std::map<std::array<std::size_t, 3>, std::size_t> face_at;
    for(std::size_t f = 0; f < soup.faces.size(); ++f) {
      std::array<std::size_t, 3> key = soup.faces[f];
      std::sort(key.begin(), key.end());
      face_at.emplace(key, f);
    }
    for(face_descriptor f : faces(polyhedron)) {
      const int patch = int(component[get(fim, f)]) + 1;
      put(pid, f, patch);
      std::array<std::size_t, 3> key;
      halfedge_descriptor h = halfedge(f, polyhedron);
      for(int k = 0; k < 3; ++k, h = next(h, polyhedron))
        key[k] = id_at.at(target(h, polyhedron)->point());
      std::sort(key.begin(), key.end());
      patch_of_.emplace(patch, soup.face_patches[face_at.at(key)]);
    }

    // polylines: chains of one curve between corners (or where curves meet)
    std::set<std::size_t> is_corner;
    for(const auto& c : soup.corners) {
      is_corner.insert(c.first);
      corner_at_[to_array(soup.points[c.first])] = c.second;
    }
    auto terminal = [&](std::size_t v) {
      return is_corner.count(v) > 0 || around[v].size() != 2 || !(around[v][0].second == around[v][1].second);
    };
    std::set<std::pair<std::size_t, std::size_t>> used;
    typedef std::pair<std::vector<Point>, std::vector<int>> Polyline; // points, incident patches
    std::vector<Polyline> polylines;
    std::vector<Curve_index> polyline_curves;
    auto patches_beside = [&](std::size_t a, std::size_t b, std::set<int>& out) {
      const halfedge_descriptor h = halfedge(vertex_of[a], vertex_of[b], polyhedron).first;
      out.insert(get(pid, face(h, polyhedron)));
      out.insert(get(pid, face(opposite(h, polyhedron), polyhedron)));
    };
    auto trace = [&](std::size_t start, std::size_t next_vertex, const Curve_index& curve) {
      std::vector<Point> line{soup.points[start]};
      std::set<int> patches;
      std::size_t a = start, b = next_vertex;
      for(;;) {
        used.insert(std::minmax(a, b));
        patches_beside(a, b, patches);
        line.push_back(soup.points[b]);
        if(b == start || terminal(b))
          break;
        const auto& nb = around[b];
        const std::size_t c = nb[0].first == a ? nb[1].first : nb[0].first;
        a = b;
        b = c;
      }
      polylines.emplace_back(std::move(line), std::vector<int>(patches.begin(), patches.end()));
      polyline_curves.push_back(curve);
    };
    for(int pass = 0; pass < 2; ++pass) // from terminal vertices, then the closed chains
      for(std::size_t v = 0; v < around.size(); ++v)
        if(pass == 1 || terminal(v))
          for(const auto& e : around[v])
            if(!used.count(std::minmax(v, e.first)))
              trace(v, e.first, e.second);

    meshed_ = std::make_unique<Meshed_domain>(polyhedron);
    std::vector<typename Meshed_domain::Curve_index> ids;
    meshed_->add_features_and_incidences(polylines.begin(), polylines.end(),
                                         CGAL::First_of_pair_property_map<Polyline>(),
                                         CGAL::Second_of_pair_property_map<Polyline>(), std::back_inserter(ids));
    for(std::size_t i = 0; i < ids.size(); ++i)
      curve_of_.emplace(int(ids[i]), polyline_curves[i]);
  }

  /// corners, curves, subdomains: the domain's indices instead of the copy's
  void relabel(Domain_mesh& out) const
  {
    Indexed_tet_mesh_3& m = out.mesh;
    auto curve = [&](int ref) {
      const auto it = curve_of_.find(ref);
      if(it == curve_of_.end())
        throw Meshing_failure("implicit domain: feature edge on curve " + std::to_string(ref) +
                              ", not a curve of the domain's surface mesh");
      return int(it->second);
    };
    for(std::size_t v = 0; v < m.points.size(); ++v) {
      C3t3_vertex_location& l = out.locations[v];
      if(l.dimension == 0) {
        const auto it = corner_at_.find(m.points[v]);
        if(it != corner_at_.end()) // else a corner of the copy only (curves meeting): its own index
          l.index = int(it->second);
      } else if(l.dimension == 1)
        l.index = curve(l.index);
      else if(l.dimension == 3)
        l.index = int(subdomain_);
      m.point_refs[v] = l.index;
    }
    for(int& r : m.edge_refs)
      r = curve(r);
    m.tet_refs.assign(m.tets.size(), int(subdomain_));
  }

  static std::vector<std::vector<int>> incident_tets(const Indexed_tet_mesh_3& m)
  {
    std::vector<std::vector<int>> of(m.points.size());
    for(std::size_t t = 0; t < m.tets.size(); ++t)
      for(int v : m.tets[t])
        of[std::size_t(v)].push_back(int(t));
    return of;
  }

  /// outward normal of each boundary vertex: the area-weighted sum over its
  /// boundary triangles
  static std::vector<Eigen::Vector3d> vertex_normals(const Indexed_tet_mesh_3& m)
  {
    std::vector<Eigen::Vector3d> n(m.points.size(), Eigen::Vector3d::Zero());
    auto at = [&](int v) { return Eigen::Vector3d(m.points[v][0], m.points[v][1], m.points[v][2]); };
    for(const auto& t : m.triangles) {
      const Eigen::Vector3d a = (at(t[1]) - at(t[0])).cross(at(t[2]) - at(t[0]));
      for(int v : t)
        n[std::size_t(v)] += a;
    }
    for(auto& x : n)
      if(x.norm() > 0)
        x.normalize();
    return n;
  }

  static bool positive(const Indexed_tet_mesh_3& m, const std::vector<int>& tets)
  {
    typedef CGAL::Exact_predicates_inexact_constructions_kernel::Point_3 EP;
    auto at = [&](int v) { return EP(m.points[v][0], m.points[v][1], m.points[v][2]); };
    for(int t : tets) {
      const auto& q = m.tets[std::size_t(t)];
      if(CGAL::orientation(at(q[0]), at(q[1]), at(q[2]), at(q[3])) != CGAL::POSITIVE)
        return false;
    }
    return true;
  }

  bool inside(const Eigen::Vector3d& x) const
  {
    return bool(domain_.is_in_domain_object()(Point(x.x(), x.y(), x.z())));
  }

  /// The domain's surface point on the line through `p` along `normal`:
  /// bracketed within a few chord errors, then bisected to rounding.
  bool point_on_surface(const Eigen::Vector3d& p, const Eigen::Vector3d& normal, Eigen::Vector3d& out) const
  {
    if(!(normal.norm() > 0))
      return false;
    double t = 2 * chord_error_;
    Eigen::Vector3d in, off;
    bool bracketed = false;
    for(int k = 0; k < 8 && !bracketed; ++k, t *= 2) {
      in = p - t * normal;
      off = p + t * normal;
      bracketed = inside(in) && !inside(off);
    }
    if(!bracketed)
      return false;
    for(int k = 0; k < 200 && (off - in).norm() > 4 * std::numeric_limits<double>::epsilon() * diagonal_; ++k) {
      const Eigen::Vector3d mid = (in + off) / 2;
      (inside(mid) ? in : off) = mid;
    }
    out = (in + off) / 2;
    return true;
  }

  bool point_on_curves(const Eigen::Vector3d& p, Eigen::Vector3d& out) const
  {
    if constexpr(Has_feature_curves<ImplicitDomain>::value) {
      typedef typename std::decay_t<decltype(domain_.curves_aabb_tree())>::Point Tree_point;
      const Tree_point q = domain_.curves_aabb_tree().closest_point(Tree_point(p.x(), p.y(), p.z()));
      out = Eigen::Vector3d(CGAL::to_double(q.x()), CGAL::to_double(q.y()), CGAL::to_double(q.z()));
      return true;
    } else {
      (void)p;
      (void)out;
      return false;
    }
  }

  static std::array<double, 3> to_array(const Point& p)
  {
    return {{CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())}};
  }

  const ImplicitDomain& domain_;
  double diagonal_ = 0, chord_error_ = 0;
  std::unique_ptr<Meshed_domain> meshed_;
  std::map<int, Surface_patch_index> patch_of_;        // patch of the copy -> the domain's
  std::map<int, Curve_index> curve_of_;                // curve of the copy -> the domain's
  std::map<std::array<double, 3>, Corner_index> corner_at_;
  Subdomain_index subdomain_{};
  std::vector<std::pair<Point, typename ImplicitDomain::Index>> crossings_; // the probe's surface points
};

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_IMPLICIT_DOMAIN_SURFACE_H
