// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// From an indexed domain mesh to a Mesh_complex_3_in_triangulation_3:
// exterior padding (internal/c3t3/exterior_padding.h) and the tet-soup
// builder adapter (internal/c3t3/tet_soup_to_c3t3.h), on shapes made of unit
// cubes (each cube in the 6 tets around its main diagonal, which conform
// across neighbouring cubes).

#include <CGAL/Bubble_mesh_3/internal/c3t3/exterior_padding.h>
#include <CGAL/Bubble_mesh_3/internal/c3t3/tet_soup_to_c3t3.h>
#include <CGAL/Bubble_mesh_3/validity.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/File_medit.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>
#include <CGAL/Triangulation_3.h>
#include <CGAL/boost/graph/generators.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <array>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

typedef CGAL::Epick K;
typedef CGAL::Polyhedral_mesh_domain_with_features_3<K> Md;
typedef CGAL::Mesh_triangulation_3<Md>::type Rtr; // only to borrow its TDS and traits
typedef CGAL::Triangulation_3<Rtr::Geom_traits, Rtr::Triangulation_data_structure> Tr;
typedef CGAL::Mesh_complex_3_in_triangulation_3<Tr, Md::Corner_index, Md::Curve_index> C3t3;

namespace BM = CGAL::Bubble_mesh_3;
namespace BMI = CGAL::Bubble_mesh_3::internal;

typedef std::array<int, 3> Ijk;

// The builder only calls the domain's index_from_*(): any instance will do.
const Md& index_domain()
{
  static const Md domain = [] {
    Md::Polyhedron tet;
    CGAL::make_tetrahedron(K::Point_3(0, 0, 0), K::Point_3(1, 0, 0), K::Point_3(0, 1, 0), K::Point_3(0, 0, 1), tet);
    return Md(tet);
  }();
  return domain;
}

// A union of unit cubes at integer positions, each with its subdomain.
// Boundary triangles get one patch per (plane, subdomain); interface
// triangles one patch per pair of subdomains. Feature edges are the edges
// of the surface whose triangles do not all belong to one patch, or that
// have other than 2 triangles; curves are chains of feature edges between
// corners; corners are feature vertices of degree != 2 or where the chain
// turns.
BM::Indexed_tet_mesh_3 cube_union(const std::vector<std::pair<Ijk, int>>& cubes)
{
  BM::Indexed_tet_mesh_3 m;
  std::map<Ijk, int> id;
  auto vertex = [&](const Ijk& p) {
    auto it = id.emplace(p, static_cast<int>(m.points.size()));
    if (it.second) {
      m.points.push_back({double(p[0]), double(p[1]), double(p[2])});
      m.point_refs.push_back(0);
    }
    return it.first->second;
  };
  // the 6 tets of a cube around the diagonal 0-7 (bit k of a corner = +1 along axis k)
  static const int kuhn[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};
  typedef CGAL::Epick::Point_3 P;
  for (const auto& cube : cubes) {
    int c[8];
    for (int b = 0; b < 8; ++b)
      c[b] = vertex({cube.first[0] + (b & 1), cube.first[1] + ((b >> 1) & 1), cube.first[2] + ((b >> 2) & 1)});
    for (const auto& t : kuhn) {
      std::array<int, 4> tet{c[t[0]], c[t[1]], c[t[2]], c[t[3]]};
      auto pt = [&](int v) { return P(m.points[v][0], m.points[v][1], m.points[v][2]); };
      if (CGAL::orientation(pt(tet[0]), pt(tet[1]), pt(tet[2]), pt(tet[3])) == CGAL::NEGATIVE)
        std::swap(tet[2], tet[3]);
      m.tets.push_back(tet);
      m.tet_refs.push_back(cube.second);
    }
  }
  // faces: outward from each tet
  static const int face_of[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};
  std::map<std::array<int, 3>, std::vector<std::pair<std::array<int, 3>, int>>> faces;
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    for (const auto& f : face_of) {
      std::array<int, 3> o{m.tets[t][f[0]], m.tets[t][f[1]], m.tets[t][f[2]]}, key = o;
      std::sort(key.begin(), key.end());
      faces[key].push_back({o, m.tet_refs[t]});
    }
  std::map<std::array<int, 5>, int> patch_id;
  auto patch = [&](const std::array<int, 5>& key) {
    return patch_id.emplace(key, static_cast<int>(patch_id.size()) + 1).first->second;
  };
  for (const auto& kv : faces) {
    const auto& inc = kv.second;
    if (inc.size() == 2 && inc[0].second == inc[1].second) continue;
    const auto& o = inc[0].first;
    if (inc.size() == 2) { // interface, oriented from the lower subdomain
      const int a = std::min(inc[0].second, inc[1].second), b = std::max(inc[0].second, inc[1].second);
      m.triangles.push_back(inc[0].second == a ? o : inc[1].first);
      m.triangle_refs.push_back(patch({3, 0, 0, a, b}));
      continue;
    }
    // plane of the face: the axis along which all 3 vertices agree
    int axis = 0;
    for (int k = 0; k < 3; ++k)
      if (m.points[o[0]][k] == m.points[o[1]][k] && m.points[o[0]][k] == m.points[o[2]][k]) axis = k;
    const P p0(m.points[o[0]][0], m.points[o[0]][1], m.points[o[0]][2]);
    const P p1(m.points[o[1]][0], m.points[o[1]][1], m.points[o[1]][2]);
    const P p2(m.points[o[2]][0], m.points[o[2]][1], m.points[o[2]][2]);
    const int sign = CGAL::cross_product(p1 - p0, p2 - p0)[axis] > 0 ? 1 : 0;
    m.triangles.push_back(o);
    m.triangle_refs.push_back(patch({axis, sign, int(m.points[o[0]][axis]), inc[0].second, 0}));
  }
  // feature edges
  std::map<std::array<int, 2>, std::set<int>> edge_patches;
  std::map<std::array<int, 2>, int> edge_count;
  for (std::size_t f = 0; f < m.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      std::array<int, 2> e{m.triangles[f][k], m.triangles[f][(k + 1) % 3]};
      if (e[0] > e[1]) std::swap(e[0], e[1]);
      edge_patches[e].insert(m.triangle_refs[f]);
      ++edge_count[e];
    }
  std::vector<std::array<int, 2>> features;
  for (const auto& kv : edge_patches)
    if (kv.second.size() > 1 || edge_count[kv.first] != 2) features.push_back(kv.first);
  std::map<int, std::vector<int>> incident; // vertex -> feature edges
  for (std::size_t e = 0; e < features.size(); ++e)
    for (int v : features[e]) incident[v].push_back(static_cast<int>(e));
  auto direction = [&](int e, int from) {
    const int to = features[e][0] == from ? features[e][1] : features[e][0];
    return std::array<double, 3>{m.points[to][0] - m.points[from][0], m.points[to][1] - m.points[from][1],
                                 m.points[to][2] - m.points[from][2]};
  };
  std::vector<int> parent(features.size());
  for (std::size_t e = 0; e < parent.size(); ++e) parent[e] = static_cast<int>(e);
  auto find = [&](int e) {
    while (parent[e] != e) e = parent[e] = parent[parent[e]];
    return e;
  };
  for (const auto& kv : incident) {
    bool corner = kv.second.size() != 2;
    if (!corner) {
      const auto a = direction(kv.second[0], kv.first), b = direction(kv.second[1], kv.first);
      corner = !(a[0] == -b[0] && a[1] == -b[1] && a[2] == -b[2]); // unit grid edges: straight iff opposite
    }
    if (corner) m.corners.push_back(kv.first);
    else parent[find(kv.second[0])] = find(kv.second[1]);
  }
  std::map<int, int> curve_id;
  for (std::size_t e = 0; e < features.size(); ++e) {
    m.edges.push_back(features[e]);
    m.edge_refs.push_back(curve_id.emplace(find(static_cast<int>(e)), static_cast<int>(curve_id.size()) + 1)
                              .first->second);
  }
  return m;
}

struct Expected {
  std::size_t points, tets, triangles, interface_triangles, features, curves, corners, subdomains;
  std::size_t exterior_tets; // measured with TetGen 1.5 (libtet1.5-dev); may change with TetGen
};

std::size_t count_distinct(const std::vector<int>& v) { return std::set<int>(v.begin(), v.end()).size(); }

std::array<int, 3> sorted3(std::array<int, 3> a)
{
  std::sort(a.begin(), a.end());
  return a;
}

// Pads, builds the C3T3 and checks it against the domain mesh.
void check_shape(const BM::Indexed_tet_mesh_3& domain, const Expected& x, const std::string& name)
{
  SCOPED_TRACE(name);
  // the domain mesh itself
  ASSERT_EQ(domain.points.size(), x.points);
  ASSERT_EQ(domain.tets.size(), x.tets);
  ASSERT_EQ(domain.triangles.size(), x.triangles);
  ASSERT_EQ(domain.edges.size(), x.features);
  ASSERT_EQ(count_distinct(domain.edge_refs), x.curves);
  ASSERT_EQ(domain.corners.size(), x.corners);
  ASSERT_EQ(count_distinct(domain.tet_refs), x.subdomains);
  const BM::Validity_report domain_report = BM::check_validity(domain);
  ASSERT_TRUE(domain_report.is_valid()) << (domain_report.problems.empty() ? std::string() : domain_report.problems.front());
  EXPECT_EQ(domain_report.interface_faces, x.interface_triangles);

  if constexpr (!BMI::has_exterior_padding) {
    EXPECT_THROW(BMI::pad_to_box(domain), BM::Invalid_input);
    GTEST_SKIP() << "exterior padding needs TetGen";
  }

  // 1. padding
  const BMI::Padded_tet_mesh_3 padded = BMI::pad_to_box(domain);
  const BM::Indexed_tet_mesh_3& pm = padded.mesh;
  EXPECT_EQ(padded.number_of_domain_points, x.points);
  EXPECT_EQ(padded.number_of_domain_tets, x.tets);
  EXPECT_EQ(pm.points.size(), x.points + 8 + padded.number_of_steiner_points);
  for (std::size_t i = 0; i < x.points; ++i) EXPECT_EQ(pm.points[i], domain.points[i]);
  for (std::size_t t = 0; t < x.tets; ++t) {
    EXPECT_EQ(pm.tets[t], domain.tets[t]);
    EXPECT_EQ(pm.tet_refs[t], domain.tet_refs[t]);
  }
  EXPECT_EQ(pm.tets.size() - x.tets, x.exterior_tets);
  EXPECT_EQ(padded.number_of_steiner_points, 0u);
  EXPECT_EQ(padded.box_triangles.size(), 12u);
  for (std::size_t t = x.tets; t < pm.tets.size(); ++t) EXPECT_EQ(pm.tet_refs[t], 0);
  EXPECT_EQ(pm.triangles, domain.triangles);
  std::cout << "[ measured ] " << name << ": " << pm.tets.size() - x.tets << " exterior tets, "
            << padded.number_of_steiner_points << " Steiner points, " << padded.box_triangles.size()
            << " box triangles" << std::endl;
  {
    // the padded soup, exterior tets included, is a valid mesh of the box
    BM::Indexed_tet_mesh_3 with_box = pm;
    for (const auto& f : padded.box_triangles) {
      with_box.triangles.push_back(f);
      with_box.triangle_refs.push_back(0);
    }
    const BM::Validity_report r = BM::check_validity(with_box);
    EXPECT_TRUE(r.is_valid()) << (r.problems.empty() ? std::string() : r.problems.front());
    EXPECT_EQ(r.boundary_faces, padded.box_triangles.size());
    EXPECT_EQ(r.interface_faces, x.triangles); // domain boundary + interfaces between subdomains
    EXPECT_EQ(r.number_of_boundary_components, 1u);
    const double box_volume = (padded.box_max[0] - padded.box_min[0]) * (padded.box_max[1] - padded.box_min[1]) *
                              (padded.box_max[2] - padded.box_min[2]);
    EXPECT_NEAR(r.tet_volume, box_volume, 1e-9 * box_volume);
  }

  // 2. the C3T3 over the plain Triangulation_3
  const Md& md = index_domain();
  C3t3 c3t3;
  std::vector<C3t3::Vertex_handle> vh;
  BMI::tet_mesh_to_c3t3(pm, md, c3t3, &vh);
  ASSERT_EQ(vh.size(), pm.points.size());
  const Tr& tr = c3t3.triangulation();
  EXPECT_TRUE(tr.tds().is_valid());
  EXPECT_TRUE(tr.is_valid());
  EXPECT_EQ(tr.number_of_vertices(), pm.points.size());
  EXPECT_EQ(tr.number_of_finite_cells(), pm.tets.size());

  std::map<C3t3::Vertex_handle, int> id;
  for (std::size_t i = 0; i < vh.size(); ++i) id[vh[i]] = static_cast<int>(i);

  // cells in complex == domain tets, with their subdomains
  EXPECT_EQ(c3t3.number_of_cells_in_complex(), x.tets);
  std::map<std::array<int, 4>, int> expected_cells, cells;
  for (std::size_t t = 0; t < x.tets; ++t) {
    std::array<int, 4> k = domain.tets[t];
    std::sort(k.begin(), k.end());
    expected_cells[k] = domain.tet_refs[t];
  }
  for (auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c) {
    std::array<int, 4> k{id[c->vertex(0)], id[c->vertex(1)], id[c->vertex(2)], id[c->vertex(3)]};
    std::sort(k.begin(), k.end());
    cells[k] = c3t3.subdomain_index(c);
  }
  EXPECT_EQ(cells, expected_cells);

  // facets in complex == boundary + interface triangles, with their patches
  EXPECT_EQ(c3t3.number_of_facets_in_complex(), x.triangles);
  std::map<std::array<int, 3>, int> expected_facets, facets;
  for (std::size_t f = 0; f < domain.triangles.size(); ++f)
    expected_facets[sorted3(domain.triangles[f])] = domain.triangle_refs[f];
  for (auto f = c3t3.facets_in_complex_begin(); f != c3t3.facets_in_complex_end(); ++f) {
    std::array<int, 3> k;
    for (int j = 0, n = 0; j < 4; ++j)
      if (j != f->second) k[n++] = id[f->first->vertex(j)];
    facets[sorted3(k)] = c3t3.surface_patch_index(*f);
  }
  EXPECT_EQ(facets, expected_facets);

  // feature edges with their curves, corners with their ids
  EXPECT_EQ(c3t3.number_of_edges_in_complex(), x.features);
  for (std::size_t e = 0; e < domain.edges.size(); ++e)
    EXPECT_EQ(c3t3.curve_index(vh[domain.edges[e][0]], vh[domain.edges[e][1]]), domain.edge_refs[e]);
  EXPECT_EQ(c3t3.number_of_corners(), x.corners);
  for (std::size_t k = 0; k < domain.corners.size(); ++k) {
    EXPECT_TRUE(c3t3.is_in_complex(vh[domain.corners[k]]));
    EXPECT_EQ(c3t3.corner_index(vh[domain.corners[k]]), static_cast<int>(k) + 1);
  }

  // vertex dimensions: corners 0, curves 1, surfaces 2, inside and padding 3
  const std::vector<BMI::C3t3_vertex_location> loc = BMI::vertex_locations(pm);
  std::array<std::size_t, 4> per_dimension{0, 0, 0, 0};
  for (std::size_t i = 0; i < vh.size(); ++i) {
    EXPECT_EQ(vh[i]->in_dimension(), loc[i].dimension);
    ++per_dimension[vh[i]->in_dimension()];
    if (i >= x.points) {
      EXPECT_EQ(loc[i].index, 0); // padding vertex: subdomain 0
    }
  }
  EXPECT_EQ(per_dimension[0], x.corners);

  // every hull vertex is on the box
  std::vector<C3t3::Vertex_handle> hull;
  tr.adjacent_vertices(tr.infinite_vertex(), std::back_inserter(hull));
  EXPECT_GE(hull.size(), 8u);
  for (auto v : hull) {
    const auto& p = v->point();
    bool on_box = false;
    for (int k = 0; k < 3; ++k)
      on_box = on_box || p[k] == padded.box_min[k] || p[k] == padded.box_max[k];
    EXPECT_TRUE(on_box);
    EXPECT_GE(id[v], static_cast<int>(x.points)); // no domain vertex on the hull
  }

  // copy and move (the regular triangulation would assert / terminate here in debug)
  C3t3 copy(c3t3);
  EXPECT_TRUE(copy.triangulation().is_valid());
  EXPECT_EQ(copy.number_of_cells_in_complex(), x.tets);
  EXPECT_EQ(copy.number_of_facets_in_complex(), x.triangles);
  EXPECT_EQ(copy.number_of_edges_in_complex(), x.features);
  EXPECT_EQ(copy.number_of_corners(), x.corners);
  C3t3 moved(std::move(copy));
  EXPECT_TRUE(moved.triangulation().is_valid());
  EXPECT_EQ(moved.number_of_cells_in_complex(), x.tets);
  C3t3 assigned;
  assigned = std::move(moved);
  EXPECT_EQ(assigned.number_of_cells_in_complex(), x.tets);
  EXPECT_EQ(assigned.triangulation().number_of_vertices(), pm.points.size());

  // MEDIT output: every finite vertex (padding included, see 6.3 item 10),
  // the complex's cells only, each surface facet twice
  std::ostringstream os;
  CGAL::IO::output_to_medit(os, c3t3);
  const std::string s = os.str();
  EXPECT_NE(s.find("Vertices\n" + std::to_string(pm.points.size()) + "\n"), std::string::npos);
  EXPECT_NE(s.find("Tetrahedra\n" + std::to_string(x.tets) + "\n"), std::string::npos);
  EXPECT_NE(s.find("Triangles\n" + std::to_string(2 * x.triangles) + "\n"), std::string::npos);
}

TEST(C3t3, CubeInSixTets)
{
  const auto m = cube_union({{{0, 0, 0}, 1}});
  check_shape(m, Expected{8, 6, 12, 0, 12, 12, 8, 1, 36}, "cube");
}

TEST(C3t3, LShape)
{
  const auto m = cube_union({{{0, 0, 0}, 1}, {{1, 0, 0}, 1}, {{0, 1, 0}, 1}});
  check_shape(m, Expected{16, 18, 28, 0, 22, 18, 12, 1, 62}, "L-shape");
}

TEST(C3t3, TwoDisjointCubes)
{
  const auto m = cube_union({{{0, 0, 0}, 1}, {{2, 0, 0}, 1}});
  check_shape(m, Expected{16, 12, 24, 0, 24, 24, 16, 1, 66}, "two disjoint cubes");
}

TEST(C3t3, CubeWithCubicCavity)
{
  std::vector<std::pair<Ijk, int>> cubes;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        if (!(i == 1 && j == 1 && k == 1)) cubes.push_back({{i, j, k}, 1});
  const auto m = cube_union(cubes);
  check_shape(m, Expected{64, 156, 120, 0, 48, 24, 16, 1, 162}, "cube with a cavity");
}

TEST(C3t3, TwoSubdomainsWithInterface)
{
  const auto m = cube_union({{{0, 0, 0}, 1}, {{1, 0, 0}, 2}});
  check_shape(m, Expected{12, 12, 22, 2, 20, 20, 12, 2, 48}, "two subdomains");
}

TEST(C3t3, TwoFlatTetsNotDelaunay)
{
  // two flat tets on a common face: e lies inside the circumsphere of abcd,
  // so the mesh is not Delaunay; a regular triangulation would assert on
  // copy and terminate on move in debug builds (cgal_conventions.md 6.3 item 8)
  BM::Indexed_tet_mesh_3 m;
  m.points = {{0, 0, 0}, {4, 0, 0}, {2, 4, 0}, {2, 1.5, 0.3}, {2, 1.5, -0.3}};
  m.point_refs.assign(5, 0);
  m.tets = {{0, 1, 2, 3}, {0, 2, 1, 4}};
  m.tet_refs = {1, 1};
  m.triangles = {{0, 1, 3}, {1, 2, 3}, {2, 0, 3}, {0, 4, 1}, {1, 4, 2}, {2, 4, 0}};
  m.triangle_refs.assign(6, 1);
  typedef K::Point_3 P;
  ASSERT_EQ(CGAL::side_of_bounded_sphere(P(0, 0, 0), P(4, 0, 0), P(2, 4, 0), P(2, 1.5, 0.3), P(2, 1.5, -0.3)),
            CGAL::ON_BOUNDED_SIDE);
  check_shape(m, Expected{5, 2, 6, 0, 0, 0, 0, 1, 29}, "two flat tets");
}

TEST(C3t3, RefusesUnlistedInterfaceAndStrayTriangle)
{
  auto m = cube_union({{{0, 0, 0}, 1}, {{1, 0, 0}, 2}});
  {
    auto unlisted = m; // drop the 2 interface triangles
    std::vector<std::array<int, 3>> tri;
    std::vector<int> ref;
    for (std::size_t f = 0; f < m.triangles.size(); ++f) {
      bool interface = true;
      for (int v : m.triangles[f]) interface = interface && m.points[v][0] == 1.0;
      if (!interface) {
        tri.push_back(m.triangles[f]);
        ref.push_back(m.triangle_refs[f]);
      }
    }
    ASSERT_EQ(tri.size(), 20u);
    unlisted.triangles = tri;
    unlisted.triangle_refs = ref;
    C3t3 c3t3;
    EXPECT_THROW(BMI::tet_mesh_to_c3t3(unlisted, index_domain(), c3t3), BM::Invalid_input);
  }
  {
    auto stray = m; // a triangle that is no face of the tets
    stray.triangles.push_back({0, 1, 2});
    stray.triangle_refs.push_back(99);
    bool is_face = false;
    for (const auto& t : m.tets) {
      std::set<int> s(t.begin(), t.end());
      is_face = is_face || (s.count(0) && s.count(1) && s.count(2));
    }
    ASSERT_FALSE(is_face);
    C3t3 c3t3;
    EXPECT_THROW(BMI::tet_mesh_to_c3t3(stray, index_domain(), c3t3), BM::Invalid_input);
  }
}

TEST(C3t3, RefusesNegativeTet)
{
  auto m = cube_union({{{0, 0, 0}, 1}});
  std::swap(m.tets[3][0], m.tets[3][1]);
  const Md& md = index_domain();
  C3t3 c3t3;
  EXPECT_THROW(BMI::tet_mesh_to_c3t3(m, md, c3t3), BM::Invalid_input);
  EXPECT_EQ(c3t3.triangulation().number_of_vertices(), 0u); // refused before building
}

TEST(C3t3, RefusesFlatTet)
{
  auto m = cube_union({{{0, 0, 0}, 1}});
  m.points.push_back({0.5, 0.5, 0.0});
  m.tets.push_back({0, 1, 2, static_cast<int>(m.points.size()) - 1});
  m.tet_refs.push_back(1);
  const Md& md = index_domain();
  C3t3 c3t3;
  EXPECT_THROW(BMI::tet_mesh_to_c3t3(m, md, c3t3), BM::Invalid_input);
}

TEST(C3t3, RefusesWrongLocationCount)
{
  const auto m = cube_union({{{0, 0, 0}, 1}});
  const Md& md = index_domain();
  C3t3 c3t3;
  std::vector<BMI::C3t3_vertex_location> loc(3);
  EXPECT_THROW(BMI::tet_mesh_to_c3t3(m, loc, md, c3t3), BM::Invalid_input);
}

TEST(C3t3, UnpaddedCubeBuildsWithoutPadding)
{
  // a single ball needs no padding (cgal_conventions.md 6.3 item 6)
  const auto m = cube_union({{{0, 0, 0}, 1}});
  const Md& md = index_domain();
  C3t3 c3t3;
  BMI::tet_mesh_to_c3t3(m, md, c3t3);
  EXPECT_TRUE(c3t3.triangulation().is_valid());
  EXPECT_EQ(c3t3.number_of_cells_in_complex(), 6u);
  EXPECT_EQ(c3t3.number_of_facets_in_complex(), 12u);
  EXPECT_EQ(c3t3.number_of_edges_in_complex(), 12u);
  EXPECT_EQ(c3t3.number_of_corners(), 8u);
}

TEST(C3t3, UnpaddedDisjointCubesAndCavityAreRefused)
{
  // two balls, or a shell, are no 3-sphere once the infinite vertex is
  // added: refused before CGAL's builder would assert (debug) or fail
  const auto two = cube_union({{{0, 0, 0}, 1}, {{2, 0, 0}, 1}});
  EXPECT_THROW(BMI::check_closable_into_sphere(two.tets, two.points.size()), BM::Invalid_input);
  C3t3 c3t3;
  EXPECT_THROW(BMI::tet_mesh_to_c3t3(two, index_domain(), c3t3), BM::Invalid_input);
  EXPECT_EQ(c3t3.triangulation().number_of_vertices(), 0u);

  std::vector<std::pair<Ijk, int>> cubes;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        if (!(i == 1 && j == 1 && k == 1)) cubes.push_back({{i, j, k}, 1});
  const auto shell = cube_union(cubes);
  C3t3 c3t3_shell;
  EXPECT_THROW(BMI::tet_mesh_to_c3t3(shell, index_domain(), c3t3_shell), BM::Invalid_input);

  const auto one = cube_union({{{0, 0, 0}, 1}});
  EXPECT_NO_THROW(BMI::check_closable_into_sphere(one.tets, one.points.size()));
  auto unused = one;
  unused.points.push_back({5, 5, 5});
  unused.point_refs.push_back(0);
  EXPECT_THROW(BMI::check_closable_into_sphere(unused.tets, unused.points.size()), BM::Invalid_input);
}

TEST(C3t3, UnpaddedLShapeIsRefused)
{
  // a non-convex ball passes every is_valid() of CGAL, yet breaks the
  // convex-hull invariant of Triangulation_3 (cgal_conventions.md 6.3 item 7)
  const auto l = cube_union({{{0, 0, 0}, 1}, {{1, 0, 0}, 1}, {{0, 1, 0}, 1}});
  EXPECT_NO_THROW(BMI::check_closable_into_sphere(l.tets, l.points.size()));
  C3t3 c3t3;
  EXPECT_THROW(BMI::tet_mesh_to_c3t3(l, index_domain(), c3t3), BM::Invalid_input);
}

TEST(C3t3, PaddingRefusesBadDomains)
{
  BM::Indexed_tet_mesh_3 empty;
  EXPECT_THROW(BMI::pad_to_box(empty), BM::Invalid_input);

  // three tets on one face
  BM::Indexed_tet_mesh_3 fan;
  fan.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 0.2, 1}, {0.2, 0.2, -1}, {0.3, 0.3, 2}};
  fan.tets = {{0, 1, 2, 3}, {0, 2, 1, 4}, {0, 1, 2, 5}};
  fan.tet_refs = {1, 1, 1};
  EXPECT_THROW(BMI::pad_to_box(fan), BM::Invalid_input);

  if constexpr (BMI::has_exterior_padding) {
    // two overlapping cubes (separate vertices): the boundary self-intersects
    auto a = cube_union({{{0, 0, 0}, 1}});
    const auto b = cube_union({{{0, 0, 0}, 1}});
    const int offset = static_cast<int>(a.points.size());
    for (const auto& p : b.points) a.points.push_back({p[0] + 0.5, p[1] + 0.25, p[2] + 0.125});
    for (auto t : b.tets) {
      for (int& v : t) v += offset;
      a.tets.push_back(t);
      a.tet_refs.push_back(1);
    }
    EXPECT_THROW(BMI::pad_to_box(a), BM::Invalid_input);
  }
}

TEST(FaultInjection, PaddingFailsCleanlyWhenTetGenFails)
{
  // every TetGen call failing (tetgen_isolated.h): the padding retries on
  // larger boxes, then throws Meshing_failure; never a crash, never tets
  // that do not tile the box
  if constexpr (!BMI::has_exterior_padding) {
    GTEST_SKIP() << "exterior padding needs TetGen";
  } else {
    const auto l = cube_union({{{0, 0, 0}, 1}, {{1, 0, 0}, 1}, {{0, 1, 0}, 1}});
    EXPECT_NO_THROW(BMI::pad_to_box(l));
    for (const char* mode : {"abort", "crash", "error", "wrong"}) {
      ::setenv("BUBBLE_MESH_3_INJECT_FAULT", mode, 1);
      try {
        BMI::pad_to_box(l);
        ADD_FAILURE() << mode << ": padding succeeded with a failing TetGen";
      } catch (const BM::Meshing_failure& e) {
        std::cout << "[ measured ] " << mode << ": " << e.what() << std::endl;
        EXPECT_NE(std::string(e.what()).find("TetGen"), std::string::npos) << e.what();
      } catch (const std::exception& e) {
        ADD_FAILURE() << mode << ": " << e.what();
      }
      ::unsetenv("BUBBLE_MESH_3_INJECT_FAULT");
    }
  }
}

} // namespace
