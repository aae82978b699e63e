// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// End to end: make_anisotropic_mesh_3 on polyhedral domains with features
// (packing, boundary front, advancing front, padding, C3T3). The mesh must
// pass the project's validity checker with the volume of the input surface,
// its boundary must be the boundary front (patch ids of the input), its
// feature edges the curves, and CGAL's own C3T3 tools must accept it.

#include <CGAL/make_anisotropic_mesh_3.h>

#include <CGAL/Bubble_mesh_3/Quality_report.h>
#include <CGAL/Bubble_mesh_3/validity.h>
#include <CGAL/Constant_metric_field_3.h>
#include <CGAL/Function_metric_field_3.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/File_medit.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <sstream>
#include <string>

namespace {

typedef CGAL::Epick K;
typedef CGAL::Polyhedral_mesh_domain_with_features_3<K> Domain;
typedef Domain::Polyhedron Polyhedron;
typedef CGAL::Anisotropic_mesh_triangulation_3<Domain>::type Tr;
typedef CGAL::Mesh_complex_3_in_triangulation_3<Tr, Domain::Corner_index, Domain::Curve_index> C3t3;
typedef CGAL::Bubble_mesh_3::Metric_3 Metric;
namespace BM = CGAL::Bubble_mesh_3;

Polyhedron from_off(const std::string& off)
{
  std::istringstream in(off);
  Polyhedron p;
  in >> p;
  return p;
}

// [0,a] x [0,b] x [0,c], 12 triangles
std::string box_off(double a, double b, double c)
{
  std::ostringstream o;
  o << "OFF\n8 12 0\n";
  for(int k = 0; k < 8; ++k)
    o << (k & 1 ? a : 0) << ' ' << (k & 2 ? b : 0) << ' ' << (k & 4 ? c : 0) << '\n';
  const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for(const auto& f : q)
    o << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << "\n3 " << f[0] << ' ' << f[2] << ' ' << f[3] << '\n';
  return o.str();
}

// an L-shaped prism: [0,2]x[0,2] minus [1,2]x[1,2], height 1 (non-convex)
std::string l_shape_off()
{
  std::ostringstream o;
  const double xy[6][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  o << "OFF\n12 20 0\n";
  for(int z = 0; z < 2; ++z)
    for(const auto& p : xy)
      o << p[0] << ' ' << p[1] << ' ' << z << '\n';
  // bottom (z=0, outward -z) and top: the L split into 4 triangles
  const int t[4][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}};
  for(const auto& f : t)
    o << "3 " << f[0] << ' ' << f[2] << ' ' << f[1] << '\n';
  for(const auto& f : t)
    o << "3 " << f[0] + 6 << ' ' << f[1] + 6 << ' ' << f[2] + 6 << '\n';
  for(int k = 0; k < 6; ++k) {
    const int a = k, b = (k + 1) % 6;
    o << "3 " << a << ' ' << b << ' ' << b + 6 << "\n3 " << a << ' ' << b + 6 << ' ' << a + 6 << '\n';
  }
  return o.str();
}

struct Outcome {
  BM::Indexed_tet_mesh_3 mesh;
  BM::Meshing_report report;
  BM::Validity_report validity;
};

template <typename Field>
Outcome mesh_indexed(const std::string& off, const Field& field, double volume, int threads = 1)
{
  Polyhedron p = from_off(off);
  Domain domain(p);
  domain.detect_features(60);
  Outcome o;
  o.mesh = BM::make_indexed_anisotropic_mesh_3(
      domain, field, BM::parameters::number_of_threads(threads).meshing_report(&o.report).random_seed(3u));
  BM::Validity_options opt;
  opt.require_outward_triangles = true;
  opt.expected_volume = volume;
  opt.expected_volume_relative_tolerance = 1e-9;
  o.validity = BM::check_validity(o.mesh, opt);
  if(!o.validity.is_valid())
    BM::print_validity_summary(std::cerr, o.validity);
  return o;
}

void print(const char* name, const Outcome& o, const BM::Quality_report& q)
{
  const auto& r = o.report;
  std::cout << name << ": nodes " << r.nodes[0] << "/" << r.nodes[1] << "/" << r.nodes[2] << "/" << r.nodes[3]
            << ", tets " << r.tets << " (delaunay " << r.delaunay_tets << ", best quality " << r.best_quality_tets
            << ", undo rounds " << r.undo_rounds << ", cavities " << r.cavities << ", steiner " << r.steiner_points
            << "), metric min dihedral worst " << q.min_dihedral.worst << " p01 " << q.min_dihedral.p01 << " mean "
            << q.min_dihedral.mean << ", edges in range " << q.edge_length.in_range_fraction << ", times pack "
            << r.packing_seconds[0] + r.packing_seconds[1] + r.packing_seconds[2] + r.packing_seconds[3]
            << " s, boundary " << r.boundary_seconds << " s, front " << r.front_seconds << " s\n";
}

TEST(MakeMesh, CubeIdentity)
{
  CGAL::Constant_metric_field_3<K> field(Metric::isotropic(0.25));
  const Outcome o = mesh_indexed(box_off(1, 1, 1), field, 1.0);
  EXPECT_TRUE(o.validity.is_valid());
  EXPECT_EQ(o.report.unused_nodes, 0u);
  EXPECT_EQ(o.mesh.corners.size(), 8u);
  std::set<int> patches(o.mesh.triangle_refs.begin(), o.mesh.triangle_refs.end());
  EXPECT_EQ(patches.size(), 6u);
  std::set<int> curves(o.mesh.edge_refs.begin(), o.mesh.edge_refs.end());
  EXPECT_EQ(curves.size(), 12u);
  const auto q = BM::compute_quality_report(o.mesh, field);
  print("cube identity", o, q);
  EXPECT_GT(q.min_dihedral.worst, 0.0);
  EXPECT_GT(q.edge_length.in_range_fraction, 0.8);
}

TEST(MakeMesh, BoxStretched1to3)
{
  // a 3 x 1 x 1 box with a metric 3x longer along x: the same mesh as the
  // unit cube in metric space
  CGAL::Constant_metric_field_3<K> field(Metric::from_entries(1.0 / (0.75 * 0.75), 0, 0, 16, 0, 16));
  const Outcome o = mesh_indexed(box_off(3, 1, 1), field, 3.0);
  EXPECT_TRUE(o.validity.is_valid());
  const auto q = BM::compute_quality_report(o.mesh, field);
  print("box 1:3", o, q);
  EXPECT_GT(q.edge_length.in_range_fraction, 0.8);
}

TEST(MakeMesh, LShapeNonConvexGraded)
{
  auto f = [](const K::Point_3& p) { return Metric::isotropic(0.15 + 0.1 * CGAL::to_double(p.x())); };
  auto field = CGAL::make_function_metric_field_3<K>(f);
  const Outcome o = mesh_indexed(l_shape_off(), field, 3.0);
  EXPECT_TRUE(o.validity.is_valid());
  const auto q = BM::compute_quality_report(o.mesh, field);
  print("L graded", o, q);
}

TEST(MakeMesh, C3t3ForCgalTools)
{
  Polyhedron p = from_off(l_shape_off());
  Domain domain(p);
  domain.detect_features(60);
  CGAL::Constant_metric_field_3<K> field(Metric::isotropic(0.3));
  BM::Meshing_report rep;
  C3t3 c3t3 = CGAL::make_anisotropic_mesh_3<C3t3>(domain, field, BM::parameters::meshing_report(&rep));
  EXPECT_TRUE(c3t3.triangulation().is_valid());
  EXPECT_EQ(c3t3.number_of_cells_in_complex(), rep.tets);
  EXPECT_EQ(c3t3.number_of_facets_in_complex(), rep.boundary_triangles);
  EXPECT_GT(c3t3.number_of_edges_in_complex(), 0u);
  EXPECT_EQ(c3t3.number_of_vertices_in_complex(), rep.nodes[0]);
  // the complex's cells: volume of the domain
  double v = 0;
  for(auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c)
    v += CGAL::to_double(c3t3.triangulation().tetrahedron(c).volume());
  EXPECT_NEAR(v, 3.0, 1e-9);
  std::ostringstream medit;
  CGAL::IO::output_to_medit(medit, c3t3);
  EXPECT_GT(medit.str().size(), 1000u);
}

TEST(MakeMesh, SameMeshWithOneAndTwoThreads)
{
  CGAL::Constant_metric_field_3<K> field(Metric::isotropic(0.3));
  const Outcome a = mesh_indexed(box_off(1, 1, 1), field, 1.0, 1);
  const Outcome b = mesh_indexed(box_off(1, 1, 1), field, 1.0, 2);
  EXPECT_TRUE(a.mesh.points == b.mesh.points);
  EXPECT_TRUE(a.mesh.tets == b.mesh.tets);
  EXPECT_TRUE(a.mesh.triangles == b.mesh.triangles);
}

} // namespace
