// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Tests of improve_anisotropic_mesh_3() (improve_c3t3.h) on meshes of other
// generators: CGAL Mesh_3 (a box with feature edges and corners, an
// implicit sphere whose patch index is a pair) and TetGen (through a MEDIT
// file, improved with improve_mesh()). A second test file because Mesh_3's
// make_mesh_3 instantiations compile slowly.

#include <CGAL/Bubble_mesh_3/IO/medit.h>
#include <CGAL/Bubble_mesh_3/Quality_report.h>
#include <CGAL/Bubble_mesh_3/improve_c3t3.h>
#include <CGAL/Bubble_mesh_3/improve_mesh.h>
#include <CGAL/Bubble_mesh_3/validity.h>
#include <CGAL/Constant_metric_field_3.h>
#include <CGAL/make_anisotropic_mesh_3.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>
#include <CGAL/Polyhedron_3.h>
#include <CGAL/make_mesh_3.h>

#ifdef BUBBLE_MESH_3_HAS_TETGEN
#  ifndef TETLIBRARY
#    define TETLIBRARY
#  endif
#  include <tetgen.h>
#endif

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace BM = CGAL::Bubble_mesh_3;
typedef CGAL::Exact_predicates_inexact_constructions_kernel K;

namespace {

BM::Improvement_options deterministic()
{
  BM::Improvement_options o;
  o.time_limit_seconds = std::numeric_limits<double>::infinity();
  return o;
}

/// the cells of the complex only (ref != 0), with its facets, edges, corners
BM::Indexed_tet_mesh_3 domain_part(BM::Indexed_tet_mesh_3 m)
{
  std::vector<std::array<int, 4>> tets;
  std::vector<int> refs;
  for(std::size_t t = 0; t < m.tets.size(); ++t)
    if(m.tet_refs[t] != 0) {
      tets.push_back(m.tets[t]);
      refs.push_back(m.tet_refs[t]);
    }
  m.tets = tets;
  m.tet_refs = refs;
  return m;
}

std::map<int, double> volumes(const BM::Indexed_tet_mesh_3& m, double& absolute)
{
  std::map<int, std::vector<double>> terms;
  std::vector<double> all;
  for(std::size_t t = 0; t < m.tets.size(); ++t) {
    const auto& T = m.tets[t];
    const double v = BM::signed_volume(m.points[std::size_t(T[0])], m.points[std::size_t(T[1])],
                                       m.points[std::size_t(T[2])], m.points[std::size_t(T[3])]);
    terms[m.tet_refs[t]].push_back(v);
    all.push_back(std::abs(v));
  }
  absolute = BM::internal::compensated_sum(all);
  std::map<int, double> r;
  for(const auto& kv : terms)
    r[kv.first] = BM::internal::compensated_sum(kv.second);
  return r;
}

template <typename C3T3>
std::multiset<typename C3T3::Surface_patch_index> patches_of(const C3T3& c3t3)
{
  std::multiset<typename C3T3::Surface_patch_index> s;
  for(auto f = c3t3.facets_in_complex_begin(); f != c3t3.facets_in_complex_end(); ++f)
    s.insert(c3t3.surface_patch_index(*f));
  return s;
}

/// Improves `in` into a new complex and checks: the facets, feature edges
/// and corners of the complex keep their number and indices, every cell is
/// positive, the triangulation is valid, the domain part passes
/// check_validity(), the volume of each subdomain is unchanged to 1e-12,
/// and the worst quality of the complex's cells does not decrease.
template <typename C3T3_in, typename C3T3_out, typename Field>
BM::Improvement_report improve_and_check(const C3T3_in& in, C3T3_out& out, const Field& field, const std::string& name)
{
  const BM::Indexed_tet_mesh_3 before = domain_part(BM::internal::c3t3_to_indexed_mesh(in).mesh);
  const BM::Quality_report q_before = BM::compute_quality_report(before, field);
  const BM::Improvement_report r = BM::improve_anisotropic_mesh_3(in, out, field, deterministic());
  EXPECT_TRUE(out.triangulation().is_valid()) << name;
  EXPECT_EQ(out.number_of_facets_in_complex(), in.number_of_facets_in_complex()) << name;
  EXPECT_EQ(out.number_of_edges_in_complex(), in.number_of_edges_in_complex()) << name;
  EXPECT_EQ(out.number_of_corners(), in.number_of_corners()) << name;
  EXPECT_EQ(out.triangulation().number_of_vertices(), in.triangulation().number_of_vertices()) << name;
  EXPECT_TRUE(patches_of(out) == patches_of(in)) << name;
  // (throws if a cell is not positively oriented)
  const BM::Indexed_tet_mesh_3 after = domain_part(BM::internal::c3t3_to_indexed_mesh(out).mesh);
  BM::Validity_options vo;
  vo.allow_unused_vertices = true; // vertices of the padding only
  const BM::Validity_report valid = BM::check_validity(after, vo);
  EXPECT_TRUE(valid.is_valid()) << name << ": " << (valid.problems.empty() ? "" : valid.problems[0]);
  double absolute = 0, unused = 0;
  const std::map<int, double> v_before = volumes(before, absolute), v_after = volumes(after, unused);
  EXPECT_EQ(v_before.size(), v_after.size());
  for(const auto& kv : v_before)
    EXPECT_NEAR(v_after.at(kv.first), kv.second, 1e-12 * absolute) << name << " subdomain " << kv.first;
  const BM::Quality_report q_after = BM::compute_quality_report(after, field);
  EXPECT_GE(q_after.min_dihedral.worst, q_before.min_dihedral.worst) << name;
  EXPECT_DOUBLE_EQ(r.worst_before, q_before.min_dihedral.worst) << name;
  EXPECT_DOUBLE_EQ(r.worst_after, q_after.min_dihedral.worst) << name;
  EXPECT_EQ(r.tets_after, after.tets.size()) << name;
  std::printf("[%s] %zu -> %zu cells in the complex: worst %.2f -> %.2f, p01 %.2f -> %.2f, slivers %zu -> %zu, "
              "moves %zu (boundary %zu), flips %zu, %.2f s\n",
              name.c_str(), r.tets_before, r.tets_after, r.worst_before, r.worst_after, r.p01_before, r.p01_after,
              r.slivers_before, r.slivers_after, r.smoothing_moves, r.boundary_moves,
              r.flips_2_3 + r.flips_3_2 + r.flips_4_4 + r.edge_removals, r.seconds);
  return r;
}

typedef CGAL::Polyhedral_mesh_domain_with_features_3<K> Box_domain;
typedef CGAL::Mesh_triangulation_3<Box_domain>::type Box_tr;
typedef CGAL::Mesh_complex_3_in_triangulation_3<Box_tr, Box_domain::Corner_index, Box_domain::Curve_index> Box_c3t3;
typedef CGAL::Mesh_complex_3_in_triangulation_3<CGAL::Anisotropic_mesh_triangulation_3<Box_domain>::type,
                                                Box_domain::Corner_index, Box_domain::Curve_index>
    Box_out_c3t3;

/// a 1 x 0.8 x 0.6 box, triangulated, its 12 edges and 8 corners as features
std::unique_ptr<Box_domain> box_domain()
{
  std::istringstream off("OFF\n8 12 0\n0 0 0\n1 0 0\n1 0.8 0\n0 0.8 0\n0 0 0.6\n1 0 0.6\n1 0.8 0.6\n0 0.8 0.6\n"
                         "3 0 2 1\n3 0 3 2\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n"
                         "3 1 2 6\n3 1 6 5\n3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n");
  Box_domain::Polyhedron polyhedron;
  off >> polyhedron;
  EXPECT_EQ(polyhedron.size_of_facets(), 12u);
  auto domain = std::make_unique<Box_domain>(polyhedron);
  domain->detect_features(60);
  return domain;
}

/// Mesh_3's isotropic mesh of it at size 0.12; no perturbation, no
/// exudation: Mesh_3 leaves its slivers in
Box_c3t3 mesh3_box(const Box_domain& domain)
{
  namespace P = CGAL::parameters;
  CGAL::Mesh_criteria_3<Box_tr> criteria(P::edge_size = 0.12, P::facet_angle = 25, P::facet_size = 0.12,
                                         P::facet_distance = 0.01, P::cell_radius_edge_ratio = 3, P::cell_size = 0.12);
  return CGAL::make_mesh_3<Box_c3t3>(domain, criteria, P::no_perturb(), P::no_exude());
}

} // namespace

TEST(ImproveC3t3, Mesh3BoxWithFeatures)
{
  typedef Box_out_c3t3 Out_c3t3;
  const std::unique_ptr<Box_domain> domain = box_domain();
  const Box_c3t3 c3t3 = mesh3_box(*domain);
  ASSERT_GT(c3t3.number_of_edges_in_complex(), 0u);
  ASSERT_EQ(c3t3.number_of_corners(), 8u);
  CGAL::Constant_metric_field_3<K> field(BM::Metric_3::isotropic(0.12));
  Out_c3t3 out;
  const BM::Improvement_report r = improve_and_check(c3t3, out, field, "Mesh_3 box, isotropic");
  EXPECT_GT(r.worst_after, r.worst_before + 5);
  EXPECT_GT(r.boundary_moves, 0u) << "the box's faces are planar: their vertices may slide";
  // improving the result again (same complex type) keeps everything
  Out_c3t3 again;
  const BM::Improvement_report r2 = improve_and_check(out, again, field, "Mesh_3 box, second round");
  EXPECT_GE(r2.worst_after, r.worst_after);
}

TEST(ImproveC3t3, ComplexWithoutCellsIsInvalidInput)
{
  // an empty complex (dimension -1) and a complex of four points only
  // (dimension 2 at most): the documented Invalid_input, nothing written
  CGAL::Constant_metric_field_3<K> field(BM::Metric_3::isotropic(0.1));
  Box_c3t3 empty;
  Box_out_c3t3 out;
  EXPECT_THROW(BM::improve_anisotropic_mesh_3(empty, out, field), BM::Invalid_input);
  Box_c3t3 flat;
  for(const auto& p : {Box_tr::Point(0, 0, 0), Box_tr::Point(1, 0, 0), Box_tr::Point(0, 1, 0), Box_tr::Point(1, 1, 0)})
    flat.triangulation().insert(p);
  ASSERT_EQ(flat.triangulation().dimension(), 2);
  EXPECT_THROW(BM::improve_anisotropic_mesh_3(flat, out, field), BM::Invalid_input);
  EXPECT_EQ(out.triangulation().number_of_vertices(), 0u);
}

TEST(ImproveC3t3, NamedParametersSetTheImprovementOptions)
{
  const BM::Improvement_options defaults;
  const BM::Improvement_options plain = BM::improvement_options(CGAL::parameters::default_values());
  EXPECT_EQ(plain.maximum_passes, defaults.maximum_passes);
  EXPECT_EQ(plain.edge_splits, defaults.edge_splits);
  EXPECT_EQ(plain.target_angle, defaults.target_angle);
  EXPECT_FALSE(plain.surface_projection);
  int stops = 0;
  const BM::Improvement_options o = BM::improvement_options(
      BM::parameters::number_of_iterations(3)
          .improvement_time_limit(7.5)
          .random_seed(11u)
          .target_angle(33.0)
          .flips(false)
          .smoothing(false)
          .boundary_smoothing(false)
          .boundary_flips(false)
          .curved_boundary_flips(false)
          .sliver_moves(false)
          .edge_splits(true)
          .split_below_angle(12.0)
          .edge_collapses(true)
          .keep_edges_in_range(true)
          .flips_keep_edges_in_range(true)
          .edge_lengths(true)
          .maximum_ring_size(6)
          .smoothing_iterations(4)
          .should_stop(std::function<bool()>([&stops] { return ++stops > 0; }))
          .surface_projection(std::function<bool(int, const std::array<double, 3>&, std::array<double, 3>&)>(
              [](int, const std::array<double, 3>& p, std::array<double, 3>& q) {
                q = p;
                return true;
              })));
  EXPECT_EQ(o.maximum_passes, 3);
  EXPECT_EQ(o.time_limit_seconds, 7.5);
  EXPECT_EQ(o.random_seed, 11u);
  EXPECT_EQ(o.target_angle, 33.0);
  EXPECT_FALSE(o.flips || o.smoothing || o.boundary_smoothing || o.boundary_flips || o.curved_boundary_flips ||
               o.sliver_moves);
  EXPECT_TRUE(o.edge_splits && o.edge_collapses && o.keep_edges_in_range && o.flips_keep_edges_in_range &&
              o.edge_lengths);
  EXPECT_EQ(o.split_below_angle, 12.0);
  EXPECT_EQ(o.maximum_ring_size, 6);
  EXPECT_EQ(o.smoothing_iterations, 4);
  ASSERT_TRUE(o.should_stop);
  EXPECT_TRUE(o.should_stop());
  EXPECT_EQ(stops, 1);
  ASSERT_TRUE(o.surface_projection);
  EXPECT_FALSE(o.curve_projection);
}

TEST(ImproveC3t3, SplitsAndCollapsesWithNamedParameters)
{
  // Mesh_3's isotropic box in a 1:4 metric, improved with vertex insertion
  // and removal: the vertices change, and the result must still be a checked
  // complex whose new vertices carry the index of what they lie in
  typedef Box_domain Domain;
  typedef Box_out_c3t3 Out_c3t3;
  typedef Out_c3t3::Vertex_handle Vertex_handle;
  const std::unique_ptr<Box_domain> box = box_domain();
  const Box_domain& domain = *box;
  const Box_c3t3 in = mesh3_box(domain);
  const BM::Metric_3 metric =
      BM::Metric_3::from_directions_and_sizes(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.06, 0.12, 0.24));
  CGAL::Constant_metric_field_3<K> field(metric);
  const BM::Indexed_tet_mesh_3 before = domain_part(BM::internal::c3t3_to_indexed_mesh(in).mesh);
  Out_c3t3 out;
  const BM::Improvement_report r = BM::improve_anisotropic_mesh_3(
      in, out, field,
      BM::parameters::edge_splits(true).edge_collapses(true).edge_lengths(true).improvement_time_limit(
          std::numeric_limits<double>::infinity()));
  ASSERT_GT(r.edge_splits, 0u) << "the 1:4 metric asks for vertices";
  EXPECT_GT(r.edge_collapses, 0u) << "and for fewer along the long axis";
  EXPECT_TRUE(out.triangulation().is_valid());
  EXPECT_EQ(out.triangulation().number_of_vertices(),
            in.triangulation().number_of_vertices() + r.edge_splits - r.edge_collapses);
  EXPECT_EQ(out.number_of_corners(), 8u);
  const auto patches_out = patches_of(out), patches_in = patches_of(in);
  EXPECT_TRUE(std::set<Domain::Surface_patch_index>(patches_out.begin(), patches_out.end()) ==
              std::set<Domain::Surface_patch_index>(patches_in.begin(), patches_in.end()));
  // every vertex: the dimension and index of the lowest element of the
  // complex it is on (a corner, a curve, a patch, else its subdomain)
  std::map<Vertex_handle, Out_c3t3::Index> lowest;
  std::map<Vertex_handle, int> dimension;
  auto offer = [&](Vertex_handle v, int d, const Out_c3t3::Index& index) {
    if(!dimension.count(v) || d < dimension[v]) {
      dimension[v] = d;
      lowest[v] = index;
    }
  };
  for(auto c = out.cells_in_complex_begin(); c != out.cells_in_complex_end(); ++c)
    for(int k = 0; k < 4; ++k)
      offer(c->vertex(k), 3, domain.index_from_subdomain_index(out.subdomain_index(c)));
  for(auto f = out.facets_in_complex_begin(); f != out.facets_in_complex_end(); ++f)
    for(int k = 1; k < 4; ++k)
      offer(f->first->vertex((f->second + k) % 4), 2, domain.index_from_surface_patch_index(out.surface_patch_index(*f)));
  for(auto e = out.edges_in_complex_begin(); e != out.edges_in_complex_end(); ++e)
    for(int k : {e->second, e->third})
      offer(e->first->vertex(k), 1, domain.index_from_curve_index(out.curve_index(*e)));
  for(auto v = out.vertices_in_complex_begin(); v != out.vertices_in_complex_end(); ++v)
    offer(v, 0, domain.index_from_corner_index(out.corner_index(v)));
  std::size_t mismatched = 0;
  for(const auto& kv : dimension)
    if(kv.first->in_dimension() != kv.second || !(kv.first->index() == lowest[kv.first]))
      ++mismatched;
  EXPECT_EQ(mismatched, 0u);
  // the domain's part: valid, same volume, no worse
  const BM::Indexed_tet_mesh_3 after = domain_part(BM::internal::c3t3_to_indexed_mesh(out).mesh);
  BM::Validity_options vo;
  vo.allow_unused_vertices = true;
  const BM::Validity_report valid = BM::check_validity(after, vo);
  EXPECT_TRUE(valid.is_valid()) << (valid.problems.empty() ? "" : valid.problems[0]);
  double absolute = 0, unused = 0;
  const std::map<int, double> v_before = volumes(before, absolute), v_after = volumes(after, unused);
  for(const auto& kv : v_before)
    EXPECT_NEAR(v_after.at(kv.first), kv.second, 1e-12 * absolute);
  EXPECT_GE(BM::compute_quality_report(after, field).min_dihedral.worst,
            BM::compute_quality_report(before, field).min_dihedral.worst);
  EXPECT_GT(r.edges_in_range_after, r.edges_in_range_before);
  std::printf("[1:4 box with splits and collapses] %zu splits, %zu collapses, edges in range %.1f -> %.1f %%, "
              "worst %.2f -> %.2f\n",
              r.edge_splits, r.edge_collapses, 100 * r.edges_in_range_before, 100 * r.edges_in_range_after,
              r.worst_before, r.worst_after);
}

TEST(ImproveC3t3, Mesh3ImplicitSphereAnisotropic)
{
  typedef CGAL::Labeled_mesh_domain_3<K> Domain;
  typedef CGAL::Mesh_triangulation_3<Domain>::type Tr;
  typedef CGAL::Mesh_complex_3_in_triangulation_3<Tr> C3t3;
  typedef CGAL::Mesh_criteria_3<Tr> Criteria;
  typedef CGAL::Anisotropic_mesh_triangulation_3<Domain>::type Out_tr;
  typedef CGAL::Mesh_complex_3_in_triangulation_3<Out_tr> Out_c3t3;
  namespace P = CGAL::parameters;
  auto ball = [](const K::Point_3& p) { return p.x() * p.x() + p.y() * p.y() + p.z() * p.z() - 1.0; };
  Domain domain = Domain::create_implicit_mesh_domain(ball, K::Sphere_3(CGAL::ORIGIN, 4.0),
                                                      P::relative_error_bound = 1e-6);
  Criteria criteria(P::facet_angle = 25, P::facet_size = 0.3, P::facet_distance = 0.02, P::cell_radius_edge_ratio = 3,
                    P::cell_size = 0.3);
  const C3t3 c3t3 = CGAL::make_mesh_3<C3t3>(domain, criteria, P::no_perturb(), P::no_exude());
  ASSERT_GT(c3t3.number_of_cells_in_complex(), 100u);
  // a metric stretched 1:2 along z: Mesh_3's isotropic cells are poor in it
  const BM::Metric_3 metric =
      BM::Metric_3::from_directions_and_sizes(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.3, 0.3, 0.6));
  CGAL::Constant_metric_field_3<K> field(metric);
  Out_c3t3 out;
  const BM::Improvement_report r = improve_and_check(c3t3, out, field, "Mesh_3 implicit sphere, 1:2");
  EXPECT_GT(r.worst_after, r.worst_before);
  EXPECT_GT(r.p01_after, r.p01_before);
}

#ifdef BUBBLE_MESH_3_HAS_TETGEN
TEST(ImproveC3t3, TetgenMeshFromMeditFile)
{
  // TetGen's quality mesh of a box (-pq1.4a), written as MEDIT and read
  // back, improved in a 1:3 metric with improve_mesh()
  tetgenio in, out;
  in.firstnumber = 0;
  in.numberofpoints = 8;
  in.pointlist = new REAL[24];
  const double box[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  for(int i = 0; i < 8; ++i)
    for(int k = 0; k < 3; ++k)
      in.pointlist[3 * i + k] = box[i][k];
  const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  in.numberoffacets = 6;
  in.facetlist = new tetgenio::facet[6];
  in.facetmarkerlist = new int[6];
  for(int f = 0; f < 6; ++f) {
    tetgenio::facet& facet = in.facetlist[f];
    tetgenio::init(&facet);
    facet.numberofpolygons = 1;
    facet.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&facet.polygonlist[0]);
    facet.polygonlist[0].numberofvertices = 4;
    facet.polygonlist[0].vertexlist = new int[4];
    for(int k = 0; k < 4; ++k)
      facet.polygonlist[0].vertexlist[k] = quads[f][k];
    in.facetmarkerlist[f] = f + 1;
  }
  char switches[] = "pq1.4a0.002Q";
  tetrahedralize(switches, &in, &out);
  BM::Indexed_tet_mesh_3 tetgen;
  for(int i = 0; i < out.numberofpoints; ++i)
    tetgen.points.push_back({{out.pointlist[3 * i], out.pointlist[3 * i + 1], out.pointlist[3 * i + 2]}});
  tetgen.point_refs.assign(tetgen.points.size(), 0);
  for(int t = 0; t < out.numberoftetrahedra; ++t) {
    std::array<int, 4> T;
    for(int k = 0; k < 4; ++k)
      T[std::size_t(k)] = out.tetrahedronlist[4 * t + k];
    if(BM::signed_volume(tetgen.points[std::size_t(T[0])], tetgen.points[std::size_t(T[1])],
                         tetgen.points[std::size_t(T[2])], tetgen.points[std::size_t(T[3])]) < 0)
      std::swap(T[0], T[1]);
    tetgen.tets.push_back(T);
    tetgen.tet_refs.push_back(1);
  }
  for(int f = 0; f < out.numberoftrifaces; ++f) {
    tetgen.triangles.push_back({{out.trifacelist[3 * f], out.trifacelist[3 * f + 1], out.trifacelist[3 * f + 2]}});
    tetgen.triangle_refs.push_back(out.trifacemarkerlist ? out.trifacemarkerlist[f] : 1);
  }
  for(int c = 0; c < 8; ++c)
    tetgen.corners.push_back(c);
  ASSERT_GT(tetgen.tets.size(), 500u);
  const std::string path = std::string(BUBBLE_MESH_3_BINARY_DIR) + "/test_improve_c3t3_tetgen.mesh";
  BM::IO::write_medit(path, tetgen);
  BM::Indexed_tet_mesh_3 mesh = BM::IO::read_medit(path);
  ASSERT_EQ(mesh.tets.size(), tetgen.tets.size());

  const BM::Metric_3 metric =
      BM::Metric_3::from_directions_and_sizes(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.3, 0.1, 0.1));
  CGAL::Constant_metric_field_3<K> field(metric);
  BM::Validity_options vo;
  ASSERT_TRUE(BM::check_validity(mesh, vo).is_valid());
  const BM::Indexed_tet_mesh_3 before = mesh;
  double absolute = 0, unused = 0;
  const double v_before = volumes(before, absolute).at(1);
  const BM::Improvement_report r = BM::improve_mesh(mesh, field, deterministic());
  const BM::Validity_report valid = BM::check_validity(mesh, vo);
  EXPECT_TRUE(valid.is_valid()) << (valid.problems.empty() ? "" : valid.problems[0]);
  EXPECT_NEAR(volumes(mesh, unused).at(1), v_before, 1e-12 * absolute);
  // boundary flips (the box faces are planar) replace triangles in place:
  // same number, same patch refs, same area per patch
  EXPECT_EQ(mesh.triangles.size(), before.triangles.size());
  EXPECT_EQ(mesh.triangle_refs, before.triangle_refs);
  if(r.boundary_flips == 0) {
    EXPECT_EQ(mesh.triangles, before.triangles);
  }
  auto areas = [](const BM::Indexed_tet_mesh_3& m) {
    std::map<int, std::vector<double>> terms;
    for(std::size_t i = 0; i < m.triangles.size(); ++i) {
      auto at = [&](int v) {
        const auto& p = m.points[std::size_t(v)];
        return Eigen::Vector3d(p[0], p[1], p[2]);
      };
      const auto& t = m.triangles[i];
      terms[m.triangle_refs[i]].push_back(0.5 * (at(t[1]) - at(t[0])).cross(at(t[2]) - at(t[0])).norm());
    }
    std::map<int, double> r;
    for(const auto& kv : terms)
      r[kv.first] = BM::internal::compensated_sum(kv.second);
    return r;
  };
  const std::map<int, double> area_before = areas(before), area_after = areas(mesh);
  for(const auto& kv : area_before)
    EXPECT_NEAR(area_after.at(kv.first), kv.second, 1e-12 * 6) << "patch " << kv.first;
  EXPECT_GE(r.worst_after, r.worst_before);
  EXPECT_GT(r.p01_after, r.p01_before + 5);
  EXPECT_GT(r.boundary_moves, 0u);
  std::printf("[TetGen box, 1:3] %zu -> %zu tets: worst %.2f -> %.2f, p01 %.2f -> %.2f, slivers %zu -> %zu, "
              "moves %zu (boundary %zu), boundary flips %zu, %.2f s\n",
              r.tets_before, r.tets_after, r.worst_before, r.worst_after, r.p01_before, r.p01_after,
              r.slivers_before, r.slivers_after, r.smoothing_moves, r.boundary_moves, r.boundary_flips, r.seconds);
}
#endif
