// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Anisotropic_advancing_front_3 on its own: given boundary triangles and
// nodes (made here, not by the packer), the tets must form a valid mesh of
// the enclosed volume (project validity checker: positive tets, conformity,
// boundary = the given triangles, volume = enclosed volume), use every inner
// node, and report how they were made. Convex and non-convex domains, a
// cavity, a stretched metric, Schönhardt's twisted prism (no tetrahedrization
// without a Steiner point) and bad boundaries.

#include <CGAL/Anisotropic_advancing_front_3.h>
#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/Quality_report.h>
#include <CGAL/Bubble_mesh_3/internal/front/cavity_filling.h>
#include <CGAL/Bubble_mesh_3/internal/front/front_geometry.h>
#include <CGAL/Bubble_mesh_3/internal/tet_boundary_chain.h>
#include <CGAL/Bubble_mesh_3/validity.h>
#include <CGAL/Constant_metric_field_3.h>
#include <CGAL/Function_metric_field_3.h>

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <map>
#include <random>
#include <set>
#include <vector>

#include "sanitized_build.h"

#if defined(__unix__) || defined(__APPLE__)
#  include <sys/wait.h>
#endif

namespace {

typedef CGAL::Epick K;
typedef K::Point_3 Point;
typedef CGAL::Constant_metric_field_3<K> Field;
typedef CGAL::Anisotropic_advancing_front_3<Field> Front;
typedef CGAL::Bubble_mesh_3::Metric_3 Metric;
namespace BM = CGAL::Bubble_mesh_3;
typedef std::array<int, 3> Tri;

struct Domain {
  std::vector<Point> points;
  std::vector<Tri> boundary; // outward
  double volume = 0;
  std::size_t boundary_nodes = 0;
};

// The six faces of a box of n[0] x n[1] x n[2] grid cells, each square in two
// triangles, outward; vertex(g) gives the node of grid point g.
template <class Vertex>
void add_box_faces(const std::array<int, 3>& n, Vertex&& vertex, std::vector<Tri>& boundary)
{
  for(int axis = 0; axis < 3; ++axis)
    for(int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for(int i = 0; i < n[u]; ++i)
        for(int j = 0; j < n[v]; ++j) {
          std::array<int, 3> g00, g10, g11, g01;
          g00[axis] = g10[axis] = g11[axis] = g01[axis] = side * n[axis];
          g00[u] = i, g00[v] = j;
          g10[u] = i + 1, g10[v] = j;
          g11[u] = i + 1, g11[v] = j + 1;
          g01[u] = i, g01[v] = j + 1;
          const int p00 = vertex(g00), p10 = vertex(g10), p11 = vertex(g11), p01 = vertex(g01);
          // (u, v, axis) is right-handed: counterclockwise in (u, v) faces +axis
          if(side == 1) {
            boundary.push_back({{p00, p10, p11}});
            boundary.push_back({{p00, p11, p01}});
          } else {
            boundary.push_back({{p00, p11, p10}});
            boundary.push_back({{p00, p01, p11}});
          }
        }
    }
}

// A box [0,a]x[0,b]x[0,c] with its faces split into an n-grid (each square
// in two triangles, outward), boundary nodes first, then `inner` jittered
// grid nodes strictly inside at spacing ~h.
Domain box(double a, double b, double c, double h, unsigned seed, double jitter = 0.25)
{
  Domain d;
  std::map<std::array<long, 3>, int> id;
  const std::array<double, 3> size{{a, b, c}};
  std::array<int, 3> n;
  for(int k = 0; k < 3; ++k)
    n[k] = std::max(1, int(std::lround(size[k] / h)));
  auto vertex = [&](std::array<int, 3> g) {
    std::array<long, 3> key{{g[0], g[1], g[2]}};
    auto it = id.emplace(key, int(d.points.size()));
    if(it.second)
      d.points.emplace_back(size[0] * g[0] / n[0], size[1] * g[1] / n[1], size[2] * g[2] / n[2]);
    return it.first->second;
  };
  add_box_faces(n, vertex, d.boundary);
  d.boundary_nodes = d.points.size();
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> U(-jitter, jitter);
  for(int i = 1; i < n[0]; ++i)
    for(int j = 1; j < n[1]; ++j)
      for(int k = 1; k < n[2]; ++k)
        d.points.emplace_back(size[0] * (i + U(gen)) / n[0], size[1] * (j + U(gen)) / n[1],
                              size[2] * (k + U(gen)) / n[2]);
  d.volume = a * b * c;
  return d;
}

template <class Result>
BM::Indexed_tet_mesh_3 as_mesh(const Result& r, const std::vector<Tri>& boundary)
{
  BM::Indexed_tet_mesh_3 m;
  for(const Point& p : r.points)
    m.points.push_back({{p.x(), p.y(), p.z()}});
  m.point_refs.assign(m.points.size(), 0);
  m.tets = r.tets;
  m.tet_refs.assign(m.tets.size(), 1);
  m.triangles = boundary;
  m.triangle_refs.assign(boundary.size(), 1);
  return m;
}

template <class Result>
BM::Validity_report check(const Result& r, const Domain& d)
{
  BM::Validity_options opt;
  opt.require_outward_triangles = true;
  opt.expected_volume = d.volume;
  opt.expected_volume_relative_tolerance = 1e-9;
  const BM::Validity_report rep = BM::check_validity(as_mesh(r, d.boundary), opt);
  if(!rep.is_valid())
    BM::print_validity_summary(std::cerr, rep);
  return rep;
}

// Random points in a ball; the boundary is their convex hull (hull faces are
// always Delaunay faces), so the front must rebuild exactly the Delaunay
// triangulation of the points mapped by Q: compared tet by tet with CGAL's.
void expect_metric_delaunay(const Metric& m, unsigned seed, int n)
{
  std::mt19937 gen(seed);
  std::normal_distribution<double> N(0, 1);
  std::uniform_real_distribution<double> U(0, 1);
  std::vector<Point> pts;
  for(int i = 0; i < n; ++i) {
    double x = N(gen), y = N(gen), z = N(gen);
    const double r = std::cbrt(U(gen)) / std::sqrt(x * x + y * y + z * z);
    pts.emplace_back(r * x, r * y, r * z);
  }
  std::vector<std::pair<Point, int>> mapped;
  for(int i = 0; i < n; ++i) {
    const Eigen::Vector3d q = m.map(Eigen::Vector3d(pts[i].x(), pts[i].y(), pts[i].z()));
    mapped.emplace_back(Point(q[0], q[1], q[2]), i);
  }
  typedef CGAL::Triangulation_vertex_base_with_info_3<int, K> Vb;
  typedef CGAL::Delaunay_triangulation_3<K, CGAL::Triangulation_data_structure_3<Vb>> DTi;
  DTi dt(mapped.begin(), mapped.end());
  ASSERT_EQ(dt.number_of_vertices(), std::size_t(n));
  std::set<std::array<int, 4>> expected;
  for(auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) {
    std::array<int, 4> t{{c->vertex(0)->info(), c->vertex(1)->info(), c->vertex(2)->info(), c->vertex(3)->info()}};
    std::sort(t.begin(), t.end());
    expected.insert(t);
  }
  // hull facets, outward: facet (c, i) of an infinite cell c seen from the finite side
  Domain d;
  d.points = pts;
  for(auto c = dt.all_cells_begin(); c != dt.all_cells_end(); ++c) {
    if(!dt.is_infinite(c))
      continue;
    const int i = c->index(dt.infinite_vertex());
    std::array<int, 3> f;
    for(int k = 0, j = 0; k < 4; ++k)
      if(k != i)
        f[j++] = c->vertex(k)->info();
    d.boundary.push_back(f);
  }
  // orient by the centroid of all points (inside the hull)
  double cx = 0, cy = 0, cz = 0;
  for(const Point& p : pts)
    cx += p.x() / n, cy += p.y() / n, cz += p.z() / n;
  for(Tri& f : d.boundary)
    if(CGAL::orientation(pts[f[0]], pts[f[1]], pts[f[2]], Point(cx, cy, cz)) == CGAL::POSITIVE)
      std::swap(f[1], f[2]);
  double v = 0;
  for(auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c)
    v += std::abs(CGAL::to_double(CGAL::volume(pts[c->vertex(0)->info()], pts[c->vertex(1)->info()],
                                               pts[c->vertex(2)->info()], pts[c->vertex(3)->info()])));
  d.volume = v;
  Field field(m);
  Front front(field);
  const Front::Result r = front.run(d.points, d.boundary);
  EXPECT_TRUE(check(r, d).is_valid());
  std::set<std::array<int, 4>> got;
  for(std::array<int, 4> t : r.tets) {
    std::sort(t.begin(), t.end());
    got.insert(t);
  }
  EXPECT_EQ(r.statistics.delaunay_tets, r.tets.size());
  EXPECT_EQ(r.statistics.best_quality_tets + r.statistics.undo_rounds + r.statistics.cavities, 0u);
  EXPECT_TRUE(got == expected) << got.size() << " tets vs " << expected.size() << " Delaunay tets";
  std::cout << n << " random nodes: " << r.tets.size() << " tets in " << r.statistics.seconds << " s\n";
}

TEST(AdvancingFront, ConvexHullGivesTheDelaunayTriangulation)
{
  expect_metric_delaunay(Metric::isotropic(1.0), 11, 2000);
}

TEST(AdvancingFront, ConvexHullGivesTheMetricDelaunayTriangulation)
{
  // stretched 1:5 along a tilted direction
  Eigen::Matrix3d r = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  expect_metric_delaunay(Metric::from_directions_and_sizes(r, Eigen::Vector3d(1.0, 0.2, 0.3)), 12, 2000);
}

TEST(AdvancingFront, UnitCubeIdentityIsValidAndMostlyDelaunay)
{
  const Domain d = box(1, 1, 1, 0.2, 1);
  Field field(Metric::isotropic(0.2));
  Front front(field);
  const Front::Result r = front.run(d.points, d.boundary);
  EXPECT_TRUE(check(r, d).is_valid());
  const auto& s = r.statistics;
  EXPECT_EQ(s.unused_nodes, 0u);
  EXPECT_EQ(s.steiner_points, 0u);
  EXPECT_EQ(r.points.size(), d.points.size());
  EXPECT_GT(double(s.delaunay_tets), 0.9 * double(r.tets.size()));
  std::cout << "cube: " << d.points.size() << " nodes, " << r.tets.size() << " tets, delaunay " << s.delaunay_tets
            << ", best quality " << s.best_quality_tets << ", undo rounds " << s.undo_rounds << ", search tets " << s.search_tets << ", cavities "
            << s.cavities << ", " << s.seconds << " s\n";
}

TEST(AdvancingFront, UnjitteredGridIsCospherical)
{
  // every cube of the grid has 8 cospherical nodes: the choice rests on the
  // symbolic perturbation alone, and must still give a valid mesh
  const Domain d = box(1, 1, 1, 0.25, 2, 0.0);
  Field field(Metric::isotropic(0.25));
  Front front(field);
  const Front::Result r = front.run(d.points, d.boundary);
  EXPECT_TRUE(check(r, d).is_valid());
  EXPECT_EQ(r.statistics.unused_nodes, 0u);
}

TEST(AdvancingFront, StopsWhenAsked)
{
  // should_stop is asked every 1,000 decisions: a stop after the third ask
  // throws Interrupted; one that never fires changes nothing
  const Domain d = box(1, 1, 1, 0.1, 3);
  Field field(Metric::isotropic(0.1));
  Front::Parameters prm;
  int asked = 0;
  prm.should_stop = [&asked] { return ++asked >= 3; };
  EXPECT_THROW(Front(field, prm).run(d.points, d.boundary), BM::Interrupted);
  EXPECT_EQ(asked, 3);
  prm.should_stop = [] { return false; };
  const Front::Result r = Front(field, prm).run(d.points, d.boundary);
  EXPECT_TRUE(check(r, d).is_valid());
}

TEST(AdvancingFront, WorkBudgetHandsTheRestToTheFillers)
{
  // a front past its work budget stops, and the cavity fillers close what is
  // left: a valid mesh of the whole box, whatever the budget
  const Domain d = box(1, 1, 1, 0.2, 4, 0.3);
  Field field(Metric::from_entries(1.0, 0, 0, 16.0, 0, 16.0));
  for(double per_node : {0.0, 0.5, 2.0, 500.0}) {
    Front::Parameters prm;
    prm.removability_tests_per_node = per_node;
    const Front::Result r = Front(field, prm).run(d.points, d.boundary);
    EXPECT_TRUE(check(r, d).is_valid()) << per_node;
    const auto& s = r.statistics;
    EXPECT_EQ(s.work_limit_reached, per_node < 100) << per_node;
    if(per_node == 0)
      EXPECT_EQ(s.delaunay_tets + s.best_quality_tets, 0u);
    if(s.work_limit_reached)
      EXPECT_GT(s.cavity_tets, 0u) << per_node;
    else
      EXPECT_EQ(s.cavity_tets, 0u);
    if(!s.work_limit_reached)
      EXPECT_LT(s.removability_tests, 3 * r.tets.size()) << "a front that closes well tests about once per tet";
    std::cout << "budget " << per_node << " tests per node: " << s.removability_tests << " tests, front tets "
              << s.delaunay_tets + s.best_quality_tets << ", filled " << s.cavity_tets << "\n";
  }
}

TEST(AdvancingFront, WorkProgressReportsAFrontThatKeepsFailing)
{
  // the same stretched case: its front waits on many triangles; the work
  // reports come every `work_report_interval` tests with the front's state
  const Domain d = box(1, 1, 1, 0.2, 4, 0.3);
  Field field(Metric::from_entries(1.0, 0, 0, 16.0, 0, 16.0));
  Front::Parameters prm;
  prm.work_report_interval = 25;
  std::vector<Front::Work_progress> reports;
  prm.work_progress = [&reports](const Front::Work_progress& w) { reports.push_back(w); };
  const Front::Result r = Front(field, prm).run(d.points, d.boundary);
  EXPECT_TRUE(check(r, d).is_valid());
  const auto& s = r.statistics;
  ASSERT_EQ(reports.size(), s.removability_tests / 25);
  bool waited = false;
  for(std::size_t i = 0; i < reports.size(); ++i) {
    const Front::Work_progress& w = reports[i];
    EXPECT_EQ(w.removability_tests, 25 * (i + 1));
    EXPECT_EQ(w.work_budget, 500.0 * double(std::max<std::size_t>(d.points.size(), 200)));
    EXPECT_GT(w.front_triangles, 0u);
    EXPECT_LE(w.waiting_triangles, w.front_triangles);
    EXPECT_LE(w.tets, r.tets.size());
    EXPECT_LE(w.best_quality_tets, s.best_quality_tets);
    waited = waited || w.waiting_triangles > 0;
    if(i > 0)
      EXPECT_GE(w.best_quality_tets, reports[i - 1].best_quality_tets);
  }
  EXPECT_TRUE(waited) << "the case should make the front wait";
  // no reports without the callback's interval being reached
  Front::Parameters quiet;
  quiet.work_report_interval = 1000000;
  std::size_t calls = 0;
  quiet.work_progress = [&calls](const Front::Work_progress&) { ++calls; };
  Front(field, quiet).run(d.points, d.boundary);
  EXPECT_EQ(calls, 0u);
}

TEST(AdvancingFront, RefusesABadWorkBudget)
{
  Field field(Metric::isotropic(0.2));
  for(double bad : {-1.0, std::nan("")}) {
    Front::Parameters prm;
    prm.removability_tests_per_node = bad;
    EXPECT_THROW(Front(field, prm), BM::Invalid_input) << bad;
  }
}

TEST(AdvancingFront, StretchedMetricAlignsTets)
{
  // a jittered lattice stretched 4x along x, and the metric that sees it as a
  // unit lattice: the metric front must give better tets in that metric than
  // the identity-metric (Euclidean Delaunay) front on the same nodes
  Domain d = box(1, 1, 1, 0.25, 3, 0.3);
  for(Point& p : d.points)
    p = Point(4 * p.x(), p.y(), p.z());
  d.volume = 4;
  Field aniso(Metric::from_entries(1.0, 0, 0, 16.0, 0, 16.0));
  Field iso(Metric::isotropic(0.25));
  Front front_aniso(aniso), front_iso(iso);
  const Front::Result ra = front_aniso.run(d.points, d.boundary);
  const Front::Result ri = front_iso.run(d.points, d.boundary);
  EXPECT_TRUE(check(ra, d).is_valid());
  EXPECT_TRUE(check(ri, d).is_valid());
  const auto qa = BM::compute_quality_report(as_mesh(ra, d.boundary), aniso);
  const auto qi = BM::compute_quality_report(as_mesh(ri, d.boundary), aniso);
  std::cout << "stretched: metric worst/mean min dihedral, metric front " << qa.min_dihedral.worst << " / " << qa.min_dihedral.mean
            << ", identity front " << qi.min_dihedral.worst << " / " << qi.min_dihedral.mean << "\n";
  EXPECT_GT(qa.min_dihedral.mean, qi.min_dihedral.mean + 5);
  EXPECT_GT(qa.min_dihedral.worst, qi.min_dihedral.worst);
}

// A 1:20 shock sheet through the unit cube: z = 0.5 + A sin(2 pi x) (flat
// when A = 0). Normal size h/20 within 0.025 of the sheet, growing by 0.3 per
// unit length to h; h along the sheet. The nodes are what a packer would give:
// layers following the sheet at the metric's normal spacing (bent with it,
// fading to the flat top and bottom), each a jittered grid at spacing h; the
// boundary is the box's faces triangulated on the boundary nodes.
struct Shock_sheet {
  double amplitude, h = 0.1;
  double height(double x) const { return 0.5 + amplitude * std::sin(2 * M_PI * x); }
  double normal_size(double d) const { return std::min(h, h / 20 + 0.3 * std::max(0.0, std::abs(d) - 0.025)); }
  Metric::Matrix operator()(const Point& p) const
  {
    const double slope = 2 * M_PI * amplitude * std::cos(2 * M_PI * p.x());
    Eigen::Vector3d n(-slope, 0, 1);
    const double len = n.norm();
    n /= len;
    const double d = (p.z() - height(p.x())) / len; // distance to the sheet, to first order
    Metric::Matrix r;
    r.col(0) = Eigen::Vector3d(1, 0, slope) / len; // along the sheet
    r.col(1) = Eigen::Vector3d(0, 1, 0);
    r.col(2) = n;
    const Eigen::Vector3d sizes(h, h, normal_size(d));
    return r * Eigen::Vector3d(sizes.cwiseInverse().cwiseAbs2()).asDiagonal() * r.transpose();
  }
};

Domain shock_sheet_nodes(const Shock_sheet& sheet, unsigned seed)
{
  // the layers' heights above and below the sheet (flat), spacing = the normal size
  std::vector<double> zs{0.5};
  for(int side : {-1, 1}) {
    double z = 0.5;
    for(;;) {
      z += side * sheet.normal_size(z - 0.5);
      if(z <= 0.5 * sheet.normal_size(0.5) || z >= 1 - 0.5 * sheet.normal_size(0.5))
        break;
      zs.push_back(z);
    }
    zs.push_back(side < 0 ? 0.0 : 1.0);
  }
  std::sort(zs.begin(), zs.end());
  // too thin a last layer next to the top or bottom is merged
  if(zs[1] - zs[0] < 0.4 * sheet.h)
    zs.erase(zs.begin() + 1);
  if(zs[zs.size() - 1] - zs[zs.size() - 2] < 0.4 * sheet.h)
    zs.erase(zs.end() - 2);
  const int n = int(std::lround(1 / sheet.h)), nz = int(zs.size()) - 1;
  Domain d;
  std::map<std::array<int, 3>, int> id;
  // the sheet's offset fades to zero at the top and bottom: sin(pi z)
  auto place = [&](int i, int j, int k, double jx, double jy, double jz) {
    const double x = (i + jx) / n, y = (j + jy) / n;
    double z = zs[k];
    if(jz != 0)
      z += jz * std::min(zs[k] - zs[k - 1], zs[k + 1] - zs[k]);
    z += (sheet.height(x) - 0.5) * std::sin(M_PI * z);
    return Point(x, y, z);
  };
  auto vertex = [&](std::array<int, 3> g) {
    auto it = id.emplace(g, int(d.points.size()));
    if(it.second)
      d.points.push_back(place(g[0], g[1], g[2], 0, 0, 0));
    return it.first->second;
  };
  const std::array<int, 3> cells{{n, n, nz}};
  add_box_faces(cells, vertex, d.boundary);
  d.boundary_nodes = d.points.size();
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> U(-0.2, 0.2);
  for(int i = 1; i < n; ++i)
    for(int j = 1; j < n; ++j)
      for(int k = 1; k < nz; ++k) {
        const double jx = U(gen), jy = U(gen), jz = U(gen);
        d.points.push_back(place(i, j, k, jx, jy, jz));
      }
  d.volume = 1;
  return d;
}

// The front on a shock layer: always a valid mesh using every node. Where
// the sheet is flat the nodes are nearly a metric lattice and the front must
// close by Delaunay choices with little work; where it is curved the layer is
// thinner than the sagitta of the elements' chords and the front works for
// it, but it must still end in a valid mesh of every node.
TEST(AdvancingFront, ShockLayersRandomized)
{
  for(double amplitude : {0.0, 0.12})
    for(unsigned seed = 1; seed <= (sanitized_build ? 1u : 2u); ++seed) { // 342 s for all four sanitized
      const Shock_sheet sheet{amplitude};
      const Domain d = shock_sheet_nodes(sheet, seed);
      const auto field = CGAL::make_function_metric_field_3<K>(sheet);
      typedef CGAL::Anisotropic_advancing_front_3<std::decay_t<decltype(field)>> Shock_front;
      Shock_front front(field);
      const auto r = front.run(d.points, d.boundary);
      const auto& s = r.statistics;
      std::cout << "shock A=" << amplitude << " seed " << seed << ": " << d.points.size() << " nodes, " << r.tets.size()
                << " tets, delaunay " << s.delaunay_tets << ", best quality " << s.best_quality_tets << ", undo rounds "
                << s.undo_rounds << ", cavities " << s.cavities << ", steiner " << s.steiner_points << ", tests "
                << s.removability_tests << " (fallback " << s.fallback_tests << ", recovery " << s.recovery_tests << "), wakes " << s.wakes
                << ", " << s.seconds << " s\n";
      EXPECT_TRUE(check(r, d).is_valid()) << "A=" << amplitude << " seed " << seed;
      EXPECT_EQ(s.unused_nodes, 0u);
      if(amplitude == 0) {
        EXPECT_LE(double(s.removability_tests), 2.0 * double(r.tets.size()));
        EXPECT_GE(double(s.delaunay_tets), 0.99 * double(r.tets.size()));
      } else {
        // the fallback tests a pair again only when what blocked it is gone
        // (it took 90 tests per tet and ran into the work budget when any
        // tet in a pair's box made it test again)
        EXPECT_FALSE(s.work_limit_reached);
        EXPECT_LE(double(s.removability_tests), 40.0 * double(r.tets.size()));
      }
    }
}

TEST(AdvancingFront, CavityFillersAloneGiveValidMeshes)
{
  // no undo/search rounds: every stuck cavity of these lattices (cyclic
  // prisms at the corners) goes to the fillers (fans, Steiner fans, TetGen)
  std::size_t cavities = 0, tetgen = 0;
  for(int trial = 0; trial < 16; ++trial) {
    const int stretched = trial % 2;
    Domain d = box(1, 1, 1, 0.25, 3 + trial, 0.3);
    if(stretched) {
      for(Point& p : d.points)
        p = Point(4 * p.x(), p.y(), p.z());
      d.volume = 4;
    }
    Field field(trial % 4 == 3 ? Metric::from_entries(1.0, 0, 0, 16.0, 0, 16.0) : Metric::isotropic(0.25));
    Front::Parameters prm;
    prm.maximum_undo_rounds = 0;
    Front front(field, prm);
    const Front::Result r = front.run(d.points, d.boundary);
    EXPECT_TRUE(check(r, d).is_valid());
    const auto& s = r.statistics;
    cavities += s.cavities;
    tetgen += s.tetgen_fills;
    EXPECT_EQ(r.points.size(), d.points.size() + s.steiner_points);
    std::cout << "fillers only: cavities " << s.cavities << ", vertex fans " << s.vertex_star_fills
              << ", Steiner fans " << s.steiner_star_fills << ", TetGen " << s.tetgen_fills << ", Steiner points "
              << s.steiner_points << "\n";
  }
  EXPECT_GT(cavities, 8u);
  if(BM::internal::front::cavity_filling_has_tetgen) {
    EXPECT_GT(tetgen, 0u);
  }
}

TEST(AdvancingFront, LShapeNonConvex)
{
  // an L-shaped prism: the unit square [0,2]x[0,2] minus [1,2]x[1,2], height 1,
  // built from 3 unit cubes with their shared faces removed
  Domain d;
  const double h = 0.2;
  const int n = 5;
  std::map<std::array<long, 3>, int> id;
  auto vertex = [&](long i, long j, long k) {
    auto it = id.emplace(std::array<long, 3>{{i, j, k}}, int(d.points.size()));
    if(it.second)
      d.points.emplace_back(i * h, j * h, k * h);
    return it.first->second;
  };
  auto inside_l = [&](double x, double y, double z) {
    return x > 0 && x < 2 && y > 0 && y < 2 && z > 0 && z < 1 && !(x >= 1 && y >= 1);
  };
  // boundary: every unit grid square face between an inside cell and an outside cell
  auto cell_in = [&](long i, long j, long k) {
    return inside_l((i + 0.5) * h, (j + 0.5) * h, (k + 0.5) * h);
  };
  for(long i = -1; i < 2 * n; ++i)
    for(long j = -1; j < 2 * n; ++j)
      for(long k = -1; k < n; ++k) {
        const bool in = cell_in(i, j, k);
        for(int axis = 0; axis < 3; ++axis) {
          std::array<long, 3> nb{{i, j, k}};
          nb[axis] += 1;
          if(in == cell_in(nb[0], nb[1], nb[2]))
            continue;
          // the square between cell (i,j,k) and its +axis neighbour
          const int u = (axis + 1) % 3, v = (axis + 2) % 3;
          std::array<long, 3> o{{i, j, k}};
          o[axis] += 1;
          auto at = [&](int du, int dv) {
            std::array<long, 3> g = o;
            g[u] += du;
            g[v] += dv;
            return vertex(g[0], g[1], g[2]);
          };
          const int p00 = at(0, 0), p10 = at(1, 0), p11 = at(1, 1), p01 = at(0, 1);
          if(in) { // outward = +axis
            d.boundary.push_back({{p00, p10, p11}});
            d.boundary.push_back({{p00, p11, p01}});
          } else {
            d.boundary.push_back({{p00, p11, p10}});
            d.boundary.push_back({{p00, p01, p11}});
          }
        }
      }
  std::mt19937 gen(4);
  std::uniform_real_distribution<double> U(-0.2, 0.2);
  for(long i = 1; i < 2 * n; ++i)
    for(long j = 1; j < 2 * n; ++j)
      for(long k = 1; k < n; ++k) {
        const double x = (i + U(gen)) * h, y = (j + U(gen)) * h, z = (k + U(gen)) * h;
        if(!(i >= n && j >= n) && inside_l(x, y, z))
          d.points.emplace_back(x, y, z);
      }
  d.volume = 3;
  Field field(Metric::isotropic(h));
  Front front(field);
  const Front::Result r = front.run(d.points, d.boundary);
  EXPECT_TRUE(check(r, d).is_valid());
  EXPECT_EQ(r.statistics.unused_nodes, 0u);
}

TEST(AdvancingFront, CavityInsideBox)
{
  // a box with an inner box-shaped hole: two boundary components, the inner
  // one oriented towards the hole
  Domain outer = box(3, 3, 3, 0.5, 5);
  const Domain inner = box(1, 1, 1, 0.5, 6);
  Domain d;
  d.points.assign(outer.points.begin(), outer.points.begin() + outer.boundary_nodes);
  d.boundary = outer.boundary;
  const int off = int(d.points.size());
  for(std::size_t i = 0; i < inner.boundary_nodes; ++i)
    d.points.emplace_back(inner.points[i].x() + 1, inner.points[i].y() + 1, inner.points[i].z() + 1);
  for(const Tri& t : inner.boundary)
    d.boundary.push_back({{t[0] + off, t[2] + off, t[1] + off}}); // reversed: the hole is outside
  for(std::size_t i = outer.boundary_nodes; i < outer.points.size(); ++i) {
    const Point& p = outer.points[i];
    const bool in_hole = p.x() > 0.9 && p.x() < 2.1 && p.y() > 0.9 && p.y() < 2.1 && p.z() > 0.9 && p.z() < 2.1;
    if(!in_hole)
      d.points.push_back(p);
  }
  d.volume = 27 - 1;
  Field field(Metric::isotropic(0.5));
  Front front(field);
  const Front::Result r = front.run(d.points, d.boundary);
  EXPECT_TRUE(check(r, d).is_valid());
  EXPECT_EQ(r.statistics.unused_nodes, 0u);
}

// Schönhardt's polyhedron: a triangular prism whose top is twisted by 30
// degrees; its boundary (the three side quads split along the "reflex"
// diagonals) admits no tetrahedrization without a Steiner point.
Domain schoenhardt()
{
  Domain d;
  const double pi = std::acos(-1.0);
  for(int k = 0; k < 3; ++k)
    d.points.emplace_back(std::cos(2 * pi * k / 3), std::sin(2 * pi * k / 3), 0);
  for(int k = 0; k < 3; ++k)
    d.points.emplace_back(std::cos(2 * pi * k / 3 + pi / 6), std::sin(2 * pi * k / 3 + pi / 6), 1.0);
  d.boundary = {{{0, 2, 1}}, {{3, 4, 5}}};
  for(int k = 0; k < 3; ++k) {
    const int a = k, b = (k + 1) % 3, a2 = 3 + k, b2 = 3 + (k + 1) % 3;
    // side quad a b b2 a2 (outward), split along the diagonal a-b2
    d.boundary.push_back({{a, b, b2}});
    d.boundary.push_back({{a, b2, a2}});
  }
  // volume by the divergence theorem
  double v = 0;
  for(const Tri& t : d.boundary) {
    const Point& p = d.points[t[0]];
    const Point& q = d.points[t[1]];
    const Point& r = d.points[t[2]];
    v += CGAL::to_double(CGAL::determinant(p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), r.x(), r.y(), r.z())) / 6;
  }
  d.volume = v;
  d.boundary_nodes = 6;
  return d;
}

TEST(AdvancingFront, SchoenhardtPrismNeedsOneSteinerPoint)
{
  Domain d = schoenhardt();
  ASSERT_GT(d.volume, 0);
  // the split along a-b2 must be the non-convex (reflex) one: check that no tet
  // of the 6 vertices is removable at the start, i.e. the prism is untetrahedralizable
  Field field(Metric::isotropic(1.0));
  Front front(field);
  const Front::Result r = front.run(d.points, d.boundary);
  EXPECT_TRUE(check(r, d).is_valid());
  EXPECT_EQ(r.statistics.cavities, 1u);
  EXPECT_EQ(r.statistics.steiner_points, 1u);
  EXPECT_EQ(r.points.size(), 7u);
  EXPECT_EQ(r.statistics.delaunay_tets + r.statistics.best_quality_tets, 0u);
}

TEST(AdvancingFront, WithoutSteinerPointsSchoenhardtFails)
{
  Domain d = schoenhardt();
  Field field(Metric::isotropic(1.0));
  Front::Parameters p;
  p.allow_steiner_points = false;
  Front front(field, p);
  EXPECT_THROW(front.run(d.points, d.boundary), BM::Meshing_failure);
}

TEST(AdvancingFront, RefusesOpenOrInconsistentBoundary)
{
  Domain d = box(1, 1, 1, 0.5, 7);
  Field field(Metric::isotropic(0.5));
  Front front(field);
  std::vector<Tri> open = d.boundary;
  open.pop_back();
  EXPECT_THROW(front.run(d.points, open), BM::Invalid_input);
  std::vector<Tri> flipped = d.boundary;
  std::swap(flipped[0][1], flipped[0][2]);
  EXPECT_THROW(front.run(d.points, flipped), BM::Invalid_input);
  std::vector<Tri> missing = d.boundary;
  missing[0][0] = int(d.points.size());
  EXPECT_THROW(front.run(d.points, missing), BM::Invalid_input);
}

TEST(TetBoundaryChain, TilingsAndNonTilings)
{
  namespace BMI = BM::internal;
  // the unit cube split into 6 positive tets around the diagonal 0-7 (vertex
  // k = (k&1, (k>>1)&1, (k>>2)&1)) and its 12 outward boundary triangles
  const std::vector<std::array<int, 4>> cube{{{0, 1, 3, 7}}, {{0, 3, 2, 7}}, {{0, 2, 6, 7}},
                                             {{0, 6, 4, 7}}, {{0, 4, 5, 7}}, {{0, 5, 1, 7}}};
  std::vector<Point> p;
  for(int k = 0; k < 8; ++k)
    p.emplace_back(k & 1, (k >> 1) & 1, (k >> 2) & 1);
  for(const auto& t : cube)
    ASSERT_EQ(CGAL::orientation(p[t[0]], p[t[1]], p[t[2]], p[t[3]]), CGAL::POSITIVE);
  std::vector<Tri> chain;
  ASSERT_TRUE(BMI::boundary_chain(cube, chain));
  EXPECT_EQ(chain.size(), 12u);
  for(const Tri& f : chain) { // outward: the cube's centre is on the negative side
    EXPECT_EQ(CGAL::orientation(p[f[0]], p[f[1]], p[f[2]], Point(0.5, 0.5, 0.5)), CGAL::NEGATIVE);
  }
  EXPECT_TRUE(BMI::tets_tile_surface(cube, chain));
  std::vector<Tri> reversed;
  for(const Tri& f : chain)
    reversed.push_back({{f[0], f[2], f[1]}});
  EXPECT_FALSE(BMI::tets_tile_surface(cube, reversed));
  // a hole: one tet dropped
  std::vector<std::array<int, 4>> holed(cube.begin(), cube.end() - 1);
  EXPECT_FALSE(BMI::tets_tile_surface(holed, chain));
  // stacked: one tet twice (its faces count twice)
  std::vector<std::array<int, 4>> stacked = cube;
  stacked.push_back(cube[2]);
  EXPECT_FALSE(BMI::boundary_chain(stacked, reversed));
  EXPECT_FALSE(BMI::tets_tile_surface(stacked, chain));
  // a stray tet whose faces cancel nothing
  std::vector<std::array<int, 4>> stray = cube;
  stray.push_back({{8, 9, 10, 11}});
  EXPECT_FALSE(BMI::tets_tile_surface(stray, chain));
  // the same cube split differently (5 tets) has the same chain on its
  // 12 triangles only if the square faces are split the same way: here not
  const std::vector<std::array<int, 4>> five{{{0, 1, 2, 4}}, {{1, 3, 2, 7}}, {{1, 4, 5, 7}},
                                             {{2, 6, 4, 7}}, {{1, 2, 4, 7}}};
  std::vector<Tri> five_chain;
  ASSERT_TRUE(BMI::boundary_chain(five, five_chain));
  EXPECT_EQ(five_chain.size(), 12u);
  EXPECT_FALSE(BMI::tets_tile_surface(five, chain));
  EXPECT_TRUE(BMI::tets_tile_surface(five, five_chain));
}

// Sets BUBBLE_MESH_3_INJECT_FAULT (tetgen_isolated.h) for one scope: every
// TetGen call then fails the way it names.
class Injected_fault_scope {
public:
  explicit Injected_fault_scope(const char* mode) { ::setenv("BUBBLE_MESH_3_INJECT_FAULT", mode, 1); }
  ~Injected_fault_scope() { ::unsetenv("BUBBLE_MESH_3_INJECT_FAULT"); }
};

// A U-shaped prism (x, y: the U of width 3 and height 3 with a 1 x 2 notch;
// z in [0, 1]) as a cavity, its triangles facing in: no vertex sees all of
// it, its centroids lie in the notch, so only TetGen fills it.
std::vector<Tri> u_prism_cavity(std::vector<Point>& pts)
{
  const double xy[8][2] = {{0, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}};
  pts.clear();
  for(int z = 0; z < 2; ++z)
    for(const auto& q : xy)
      pts.emplace_back(q[0], q[1], z);
  // the U split into triangles, counterclockwise seen from +z
  const int u[6][3] = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {0, 4, 5}, {0, 5, 7}, {5, 6, 7}};
  std::vector<Tri> outward;
  for(const auto& t : u) {
    outward.push_back({{t[0], t[2], t[1]}});         // bottom, facing -z
    outward.push_back({{t[0] + 8, t[1] + 8, t[2] + 8}}); // top, facing +z
  }
  for(int k = 0; k < 8; ++k) {
    const int a = k, b = (k + 1) % 8;
    outward.push_back({{a, b, b + 8}});
    outward.push_back({{a, b + 8, a + 8}});
  }
  std::vector<Tri> cavity;
  for(const Tri& f : outward)
    cavity.push_back({{f[0], f[2], f[1]}});
  return cavity;
}

TEST(FaultInjection, CavityFillingRejectsEveryTetGenFailure)
{
  namespace F = BM::internal::front;
  if(!F::cavity_filling_has_tetgen)
    GTEST_SKIP() << "this build has no TetGen";
  K traits;
  std::vector<Point> pts;
  const std::vector<Tri> cavity = u_prism_cavity(pts);
  {
    F::Cavity_fill_statistics stats;
    std::vector<Point> filled_pts = pts;
    const std::vector<F::Tet> tets = F::fill_cavities(cavity, {}, filled_pts, true, traits, stats);
    EXPECT_EQ(stats.tetgen_fills, 1u);
    EXPECT_EQ(stats.vertex_star_fills + stats.steiner_star_fills, 0u);
    std::vector<Tri> outward;
    for(const Tri& f : cavity)
      outward.push_back({{f[0], f[2], f[1]}});
    EXPECT_TRUE(BM::internal::tets_tile_surface(tets, outward));
    double volume = 0;
    for(const F::Tet& t : tets)
      volume += CGAL::to_double(CGAL::volume(filled_pts[t[0]], filled_pts[t[1]], filled_pts[t[2]], filled_pts[t[3]]));
    EXPECT_NEAR(volume, 7.0, 1e-12);
  }
  for(const char* mode : {"abort", "crash", "error", "wrong", "unknown-mode"}) {
    Injected_fault_scope fault(mode);
    F::Cavity_fill_statistics stats;
    std::vector<Point> filled_pts = pts;
    try {
      F::fill_cavities(cavity, {}, filled_pts, true, traits, stats);
      ADD_FAILURE() << mode << ": a failed TetGen call gave tets";
    } catch(const BM::Meshing_failure& e) {
      const std::string what = e.what();
      std::cout << "[ measured ] " << mode << ": " << what << "\n";
      EXPECT_NE(what.find("TetGen"), std::string::npos) << what;
    }
  }
}

#if defined(CGAL_BUBBLE_MESH_3_CAVITY_USES_TETGEN) && defined(CGAL_BUBBLE_MESH_3_TETGEN_FORK)
// true if this process has no child left (a killed TetGen must be reaped)
bool no_child_left()
{
  int status = 0;
  return ::waitpid(-1, &status, WNOHANG) < 0 && errno == ECHILD;
}

// A unit tetrahedron as a TetGen PLC (4 points, 4 triangular facets).
void tetrahedron_plc(tetgenio& in)
{
  const double xyz[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  in.firstnumber = 0;
  in.numberofpoints = 4;
  in.pointlist = new REAL[12];
  std::copy(xyz, xyz + 12, in.pointlist);
  in.numberoffacets = 4;
  in.facetlist = new tetgenio::facet[4];
  in.facetmarkerlist = new int[4];
  for(int f = 0; f < 4; ++f) {
    tetgenio::facet& facet = in.facetlist[f];
    tetgenio::init(&facet);
    facet.numberofpolygons = 1;
    facet.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&facet.polygonlist[0]);
    facet.polygonlist[0].numberofvertices = 3;
    facet.polygonlist[0].vertexlist = new int[3];
    std::copy(faces[f], faces[f] + 3, facet.polygonlist[0].vertexlist);
    in.facetmarkerlist[f] = 1;
  }
}

TEST(FaultInjection, TetGenThatNeverAnswersIsStopped)
{
  namespace BMI = BM::internal;
  using clock = std::chrono::steady_clock;
  auto seconds = [](clock::time_point t0) { return std::chrono::duration<double>(clock::now() - t0).count(); };
  {
    // the plain call works, well within its budget
    tetgenio in;
    tetrahedron_plc(in);
    BMI::Tetgen_output out;
    std::string error;
    ASSERT_TRUE(BMI::tetrahedralize_isolated("pYMzQ", in, out, error)) << error;
    EXPECT_EQ(out.tets.size(), 4u);
    EXPECT_GE(BMI::tetgen_time_budget(in), 20.0);
  }
  Injected_fault_scope fault("hang");
  {
    // its time budget ends a TetGen that loops: an error, no child left
    tetgenio in;
    tetrahedron_plc(in);
    BMI::Tetgen_output out;
    std::string error;
    const auto t0 = clock::now();
    EXPECT_FALSE(BMI::tetrahedralize_isolated("pYMzQ", in, out, error, {}, 0.5));
    const double t = seconds(t0);
    std::cout << "[ measured ] budget 0.5 s: returned after " << t << " s: " << error << "\n";
    EXPECT_GE(t, 0.5);
    EXPECT_LT(t, 5.0);
    EXPECT_NE(error.find("budget"), std::string::npos) << error;
    EXPECT_TRUE(no_child_left());
  }
  {
    // the caller's stop request ends it sooner: Interrupted, no child left
    tetgenio in;
    tetrahedron_plc(in);
    BMI::Tetgen_output out;
    std::string error;
    const auto t0 = clock::now();
    auto stop = [&] { return seconds(t0) > 0.3; };
    EXPECT_THROW(BMI::tetrahedralize_isolated("pYMzQ", in, out, error, stop), BM::Interrupted);
    EXPECT_LT(seconds(t0), 5.0);
    EXPECT_TRUE(no_child_left());
  }
  {
    // through the cavity filler: a stop request that throws (as the
    // pipeline's time limit does) passes through, the child killed first
    namespace F = BMI::front;
    K traits;
    std::vector<Point> pts;
    const std::vector<Tri> cavity = u_prism_cavity(pts);
    F::Cavity_fill_statistics stats;
    const auto t0 = clock::now();
    auto stop = [&]() -> bool {
      if(seconds(t0) > 0.3)
        throw BM::Time_limit_exceeded("test time limit");
      return false;
    };
    EXPECT_THROW(F::fill_cavities(cavity, {}, pts, true, traits, stats, stop), BM::Time_limit_exceeded);
    EXPECT_LT(seconds(t0), 5.0);
    EXPECT_TRUE(no_child_left());
  }
}
#endif

TEST(FaultInjection, FrontEndsInAValidMeshOrMeshingFailure)
{
  // the lattices whose stuck cavities go to the fillers (as in
  // CavityFillersAloneGiveValidMeshes), with every TetGen call failing: the
  // front must recover by its own means (undo more, search, advance, fans)
  // or throw Meshing_failure; on these lattices it recovers every time
  if(!BM::internal::front::cavity_filling_has_tetgen)
    GTEST_SKIP() << "this build has no TetGen";
  for(const char* mode : {"abort", "crash", "error", "wrong"}) {
    Injected_fault_scope fault(mode);
    int valid = 0, failed = 0;
    std::size_t enlargements = 0;
    for(int trial = 0; trial < 8; ++trial) {
      Domain d = box(1, 1, 1, 0.25, 3 + trial, 0.3);
      Field field(Metric::isotropic(0.25));
      Front::Parameters prm;
      prm.maximum_undo_rounds = 0;
      Front front(field, prm);
      try {
        const Front::Result r = front.run(d.points, d.boundary);
        EXPECT_TRUE(check(r, d).is_valid()) << mode << " trial " << trial;
        EXPECT_EQ(r.statistics.tetgen_fills, 0u);
        enlargements += r.statistics.cavity_enlargements;
        ++valid;
      } catch(const BM::Meshing_failure& e) {
        EXPECT_NE(std::string(e.what()).find("TetGen"), std::string::npos) << e.what();
        ++failed;
      }
    }
    std::cout << "[ measured ] " << mode << ": " << valid << " valid meshes (" << enlargements
              << " cavity enlargements), " << failed << " Meshing_failure\n";
    EXPECT_EQ(valid, 8);
    EXPECT_GT(enlargements, 0u);
  }
}

TEST(FrontGeometry, TrianglesSharingVerticesOrNot)
{
  std::vector<Point> p = {Point(0, 0, 0), Point(1, 0, 0), Point(0, 1, 0), Point(1, 1, 0),
                          Point(0.2, 0.2, 0), Point(0.2, 0.2, 1), Point(0.2, 0.2, -1), Point(-1, -1, 0)};
  namespace F = BM::internal::front;
  K k;
  // shared edge, coplanar, opposite sides: fine; same side: overlap
  EXPECT_FALSE(F::triangles_meet_beyond_shared(Tri{{0, 1, 2}}, Tri{{1, 2, 3}}, p, k));
  EXPECT_TRUE(F::triangles_meet_beyond_shared(Tri{{0, 1, 2}}, Tri{{1, 2, 4}}, p, k));
  // shared edge, not coplanar
  EXPECT_FALSE(F::triangles_meet_beyond_shared(Tri{{0, 1, 2}}, Tri{{1, 2, 5}}, p, k));
  // shared vertex 0, the other's far edge pierces: (0, 5, 6) crosses the plane at (0.2, 0.2, 0) inside (0,1,2)
  EXPECT_TRUE(F::triangles_meet_beyond_shared(Tri{{0, 1, 2}}, Tri{{0, 5, 6}}, p, k));
  // shared vertex 0, coplanar, pointing away
  EXPECT_FALSE(F::triangles_meet_beyond_shared(Tri{{1, 0, 2}}, Tri{{0, 7, 6}}, p, k));
  // no shared vertex, crossing
  EXPECT_TRUE(F::triangles_meet_beyond_shared(Tri{{0, 1, 2}}, Tri{{3, 5, 6}}, p, k) ==
              CGAL::do_intersect(K::Triangle_3(p[0], p[1], p[2]), K::Triangle_3(p[3], p[5], p[6])));
  // closed point-in-tet: on a face counts
  std::vector<Point> q = {Point(0, 0, 0), Point(1, 0, 0), Point(0, 1, 0), Point(0, 0, 1), Point(0.2, 0.2, 0),
                          Point(0.2, 0.2, 0.2), Point(1, 1, 1)};
  EXPECT_TRUE(F::in_closed_tet(q[4], {{0, 1, 2, 3}}, q, k));
  EXPECT_TRUE(F::in_closed_tet(q[5], {{0, 1, 2, 3}}, q, k));
  EXPECT_FALSE(F::in_closed_tet(q[6], {{0, 1, 2, 3}}, q, k));
}

} // namespace
