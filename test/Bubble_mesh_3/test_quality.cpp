// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Tests of the metric quality measures (metric_quality.h) and of the mesh
// quality report (Quality_report.h).

#include <CGAL/Bubble_mesh_3/Quality_report.h>
#include <CGAL/Bubble_mesh_3/metric_quality.h>
#include <CGAL/Constant_metric_field_3.h>
#include <CGAL/Function_metric_field_3.h>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Simple_cartesian.h>

#ifdef CGAL_LINKED_WITH_TBB
#include <tbb/global_control.h>
#endif

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <numeric>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace BM = CGAL::Bubble_mesh_3;
typedef CGAL::Exact_predicates_inexact_constructions_kernel Epick;
typedef CGAL::Exact_predicates_exact_constructions_kernel Epeck;
typedef CGAL::Simple_cartesian<double> Sc;
typedef Eigen::Vector3d V3;
typedef Eigen::Matrix3d M3;

namespace {

const double pi = 3.14159265358979323846;
const double regular_angle = std::acos(1.0 / 3.0) * 180 / pi;   // 70.528779...
const double corner_angle = std::acos(1 / std::sqrt(3.0)) * 180 / pi; // 54.735610...

// Regular tet of edge 2 sqrt(2), positively oriented.
std::array<V3, 4> regular_tet()
{
  return {{V3(1, 1, 1), V3(-1, 1, -1), V3(1, -1, -1), V3(-1, -1, 1)}};
}

// The corner tet (0,0,0),(1,0,0),(0,1,0),(0,0,1).
std::array<V3, 4> corner_tet()
{
  return {{V3(0, 0, 0), V3(1, 0, 0), V3(0, 1, 0), V3(0, 0, 1)}};
}

// A random SPD metric: random rotation, sizes in [0.05, 20] (anisotropy up to 400).
BM::Metric_3 random_metric(std::mt19937& rng)
{
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_real_distribution<double> log_size(std::log(0.05), std::log(20.0));
  M3 a;
  for(int i = 0; i < 3; ++i)
    for(int j = 0; j < 3; ++j)
      a(i, j) = u(rng);
  Eigen::HouseholderQR<M3> qr(a);
  const M3 r = qr.householderQ();
  const V3 sizes(std::exp(log_size(rng)), std::exp(log_size(rng)), std::exp(log_size(rng)));
  return BM::Metric_3::from_directions_and_sizes(r, sizes);
}

std::array<V3, 4> mapped(const std::array<V3, 4>& t, const M3& map)
{
  return {{map * t[0], map * t[1], map * t[2], map * t[3]}};
}

// n^3 unit cubes of side h, each split into the 6 Kuhn tets around its main
// diagonal, all positively oriented. Conforming.
BM::Indexed_tet_mesh_3 kuhn_grid(int n, double h = 1.0)
{
  BM::Indexed_tet_mesh_3 mesh;
  const int m = n + 1;
  auto index = [m](int i, int j, int k) { return i + m * (j + m * k); };
  for(int k = 0; k < m; ++k)
    for(int j = 0; j < m; ++j)
      for(int i = 0; i < m; ++i)
        mesh.points.push_back({{h * i, h * j, h * k}});
  mesh.point_refs.assign(mesh.points.size(), 0);
  const int permutations[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
  for(int k = 0; k < n; ++k)
    for(int j = 0; j < n; ++j)
      for(int i = 0; i < n; ++i)
        for(int p = 0; p < 6; ++p) {
          std::array<int, 3> c = {{i, j, k}};
          std::array<int, 4> tet;
          tet[0] = index(c[0], c[1], c[2]);
          for(int s = 0; s < 3; ++s) {
            ++c[static_cast<std::size_t>(permutations[p][s])];
            tet[static_cast<std::size_t>(s + 1)] = index(c[0], c[1], c[2]);
          }
          if(p >= 3) // odd permutation: negatively oriented, swap two vertices
            std::swap(tet[2], tet[3]);
          mesh.tets.push_back(tet);
          mesh.tet_refs.push_back(1);
        }
  return mesh;
}

std::size_t kuhn_grid_edges(std::size_t n)
{
  // axis edges + one diagonal per grid face + one body diagonal per cube
  return 3 * n * (n + 1) * (n + 1) + 3 * n * n * (n + 1) + n * n * n;
}

// ---------------------------------------------------------------------------
// A minimal JSON parser (objects, arrays, strings, numbers, literals), enough
// to check that to_json() writes valid JSON and to read the values back.
struct Json {
  enum Type { Null, Bool, Number, String, Array, Object } type = Null;
  bool boolean = false;
  double number = 0;
  std::string string;
  std::vector<Json> array;
  std::map<std::string, Json> object;

  const Json& operator[](const std::string& key) const
  {
    auto it = object.find(key);
    if(type != Object || it == object.end())
      throw std::runtime_error("missing key " + key);
    return it->second;
  }
  bool has(const std::string& key) const { return type == Object && object.count(key) > 0; }
};

class Json_parser {
public:
  explicit Json_parser(const std::string& s) : s_(s) {}
  Json parse()
  {
    Json v = value();
    skip();
    if(i_ != s_.size())
      fail("trailing characters");
    return v;
  }

private:
  void fail(const std::string& what) const
  {
    throw std::runtime_error("JSON error at " + std::to_string(i_) + ": " + what);
  }
  void skip()
  {
    while(i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\n' || s_[i_] == '\r' || s_[i_] == '\t'))
      ++i_;
  }
  char peek()
  {
    skip();
    if(i_ >= s_.size())
      fail("unexpected end");
    return s_[i_];
  }
  void expect(char c)
  {
    if(peek() != c)
      fail(std::string("expected ") + c);
    ++i_;
  }
  Json value()
  {
    const char c = peek();
    Json v;
    if(c == '{') {
      v.type = Json::Object;
      ++i_;
      if(peek() == '}') {
        ++i_;
        return v;
      }
      for(;;) {
        Json key = string_value();
        expect(':');
        if(v.object.count(key.string))
          fail("duplicate key " + key.string);
        v.object[key.string] = value();
        if(peek() == ',') {
          ++i_;
          continue;
        }
        expect('}');
        return v;
      }
    }
    if(c == '[') {
      v.type = Json::Array;
      ++i_;
      if(peek() == ']') {
        ++i_;
        return v;
      }
      for(;;) {
        v.array.push_back(value());
        if(peek() == ',') {
          ++i_;
          continue;
        }
        expect(']');
        return v;
      }
    }
    if(c == '"')
      return string_value();
    for(const char* literal : {"true", "false", "null"})
      if(s_.compare(i_, std::string(literal).size(), literal) == 0) {
        i_ += std::string(literal).size();
        v.type = literal[0] == 'n' ? Json::Null : Json::Bool;
        v.boolean = literal[0] == 't';
        return v;
      }
    // number: -?(0|[1-9][0-9]*)(\.[0-9]+)?([eE][+-]?[0-9]+)?
    const std::size_t start = i_;
    if(s_[i_] == '-')
      ++i_;
    auto digits = [&]() {
      const std::size_t d = i_;
      while(i_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[i_])))
        ++i_;
      if(i_ == d)
        fail("digit expected");
    };
    if(i_ < s_.size() && s_[i_] == '0')
      ++i_;
    else
      digits();
    if(i_ < s_.size() && s_[i_] == '.') {
      ++i_;
      digits();
    }
    if(i_ < s_.size() && (s_[i_] == 'e' || s_[i_] == 'E')) {
      ++i_;
      if(i_ < s_.size() && (s_[i_] == '+' || s_[i_] == '-'))
        ++i_;
      digits();
    }
    v.type = Json::Number;
    v.number = std::strtod(s_.substr(start, i_ - start).c_str(), nullptr);
    return v;
  }
  Json string_value()
  {
    expect('"');
    Json v;
    v.type = Json::String;
    while(i_ < s_.size() && s_[i_] != '"') {
      if(static_cast<unsigned char>(s_[i_]) < 0x20)
        fail("control character in string");
      if(s_[i_] == '\\') {
        ++i_;
        if(i_ >= s_.size())
          fail("bad escape");
        const char e = s_[i_];
        if(e == 'u') {
          v.string += '?';
          i_ += 4;
        } else {
          const std::string from = "\"\\/bfnrt";
          const std::string to = "\"\\/\b\f\n\r\t";
          const std::size_t k = from.find(e);
          if(k == std::string::npos)
            fail("bad escape");
          v.string += to[k];
        }
        ++i_;
      } else {
        v.string += s_[i_++];
      }
    }
    expect('"');
    return v;
  }

  const std::string& s_;
  std::size_t i_ = 0;
};

bool same_report(const BM::Quality_report& a, const BM::Quality_report& b)
{
  return a.vertices == b.vertices && a.tets == b.tets && a.min_dihedral.worst == b.min_dihedral.worst &&
         a.min_dihedral.worst_tet == b.min_dihedral.worst_tet && a.min_dihedral.p01 == b.min_dihedral.p01 &&
         a.min_dihedral.mean == b.min_dihedral.mean && a.min_dihedral.below5 == b.min_dihedral.below5 &&
         a.min_dihedral.below10 == b.min_dihedral.below10 && a.min_dihedral.below15 == b.min_dihedral.below15 &&
         a.histogram_5deg == b.histogram_5deg && a.edge_length.min == b.edge_length.min &&
         a.edge_length.max == b.edge_length.max && a.edge_length.mean == b.edge_length.mean &&
         a.edge_length.in_range_fraction == b.edge_length.in_range_fraction &&
         a.edge_length.number_of_edges == b.edge_length.number_of_edges && a.inverted_tets == b.inverted_tets &&
         a.degenerate_tets == b.degenerate_tets && a.volume == b.volume && a.metric_volume == b.metric_volume &&
         a.metric_description == b.metric_description;
}

// A smoothly varying anisotropic field (non-constant, so centroid and vertex
// evaluations matter).
M3 graded_metric(const Epick::Point_3& p)
{
  const double hx = 0.3 + 0.2 * std::sin(p.x() + 0.5 * p.y());
  const double hy = 0.6 + 0.1 * p.z();
  const double hz = 0.9;
  const double c = std::cos(0.3 * p.z());
  const double s = std::sin(0.3 * p.z());
  M3 r;
  r << c, -s, 0, s, c, 0, 0, 0, 1;
  const V3 l(1 / (hx * hx), 1 / (hy * hy), 1 / (hz * hz));
  return r * l.asDiagonal() * r.transpose();
}

} // namespace

// ---------------------------------------------------------------------------
// Dihedral angles

TEST(DihedralAngles, RegularTetInIdentityMetric)
{
  const auto t = regular_tet();
  EXPECT_NEAR(regular_angle, 70.528779365509308, 1e-12);
  const std::array<double, 6> a = BM::dihedral_angles(t[0], t[1], t[2], t[3]);
  for(double x : a)
    EXPECT_NEAR(x, regular_angle, 1e-12);
  EXPECT_NEAR(BM::minimum_dihedral_angle(t[0], t[1], t[2], t[3]), regular_angle, 1e-12);
  const BM::Metric_3 identity;
  EXPECT_NEAR(BM::metric_minimum_dihedral_angle(t[0], t[1], t[2], t[3], identity), regular_angle, 1e-12);
  // An isotropic metric does not change angles.
  EXPECT_NEAR(BM::metric_minimum_dihedral_angle(t[0], t[1], t[2], t[3], BM::Metric_3::isotropic(0.01)),
              regular_angle, 1e-12);
}

TEST(DihedralAngles, RegularTetMappedByQInverseIsRegularInTheMetric)
{
  std::mt19937 rng(12345);
  const auto t = regular_tet();
  for(int trial = 0; trial < 50; ++trial) {
    const BM::Metric_3 m = random_metric(rng);
    // Translate too, so that translation invariance is exercised.
    const V3 shift(10 * trial, -3.0 * trial, 0.5);
    auto s = mapped(t, m.Q_inverse());
    for(V3& p : s)
      p += shift;
    const std::array<double, 6> a = BM::metric_dihedral_angles(s[0], s[1], s[2], s[3], m);
    for(double x : a)
      EXPECT_NEAR(x, regular_angle, 1e-9) << "trial " << trial;
    EXPECT_NEAR(BM::metric_minimum_dihedral_angle(s[0], s[1], s[2], s[3], m), regular_angle, 1e-9);
    // In the Euclidean metric the stretched tet is not regular: the mapping
    // is really used.
    if(m.anisotropy_ratio() > 2) {
      EXPECT_LT(BM::minimum_dihedral_angle(s[0], s[1], s[2], s[3]), regular_angle - 1);
    }
  }
}

TEST(DihedralAngles, CornerTetAllSixAngles)
{
  const auto t = corner_tet();
  const std::array<double, 6> a = BM::dihedral_angles(t[0], t[1], t[2], t[3]);
  // Edges (0,1), (0,2), (0,3) lie on the axes: right angles between the
  // coordinate planes. Edges (1,2), (1,3), (2,3) join a coordinate plane and
  // the slanted face x + y + z = 1: acos(1/sqrt 3).
  EXPECT_NEAR(a[0], 90, 1e-12);
  EXPECT_NEAR(a[1], 90, 1e-12);
  EXPECT_NEAR(a[2], 90, 1e-12);
  EXPECT_NEAR(a[3], corner_angle, 1e-12);
  EXPECT_NEAR(a[4], corner_angle, 1e-12);
  EXPECT_NEAR(a[5], corner_angle, 1e-12);
  EXPECT_NEAR(corner_angle, 54.735610317245346, 1e-12);
  EXPECT_NEAR(BM::minimum_dihedral_angle(t[0], t[1], t[2], t[3]), corner_angle, 1e-12);

  // Orientation does not matter: the mirror image has the same angles on the
  // same (relabelled) edges. Swapping vertices 2 and 3 maps edge order
  // (01,02,03,12,13,23) to (01,03,02,13,12,23).
  const std::array<double, 6> b = BM::dihedral_angles(t[0], t[1], t[3], t[2]);
  EXPECT_NEAR(b[0], 90, 1e-12);
  EXPECT_NEAR(b[5], corner_angle, 1e-12);
  EXPECT_NEAR(b[3], corner_angle, 1e-12);

  // A non-symmetric tet to pin the edge order: (0,0,0),(2,0,0),(0,1,0),(0,0,1).
  // Edge (1,2) joins face z=0 and the face 0.5x + y + z = 1: cos = 1/|(0.5,1,1)| = 2/3.
  // Edge (1,3) joins face y=0 and the same slanted face: also 2/3.
  // Edge (2,3) joins face x=0 and the slanted face: cos = 0.5/1.5 = 1/3.
  const std::array<double, 6> c = BM::dihedral_angles(V3(0, 0, 0), V3(2, 0, 0), V3(0, 1, 0), V3(0, 0, 1));
  EXPECT_NEAR(c[0], 90, 1e-12);
  EXPECT_NEAR(c[1], 90, 1e-12);
  EXPECT_NEAR(c[2], 90, 1e-12);
  EXPECT_NEAR(c[3], std::acos(2.0 / 3.0) * 180 / pi, 1e-12);
  EXPECT_NEAR(c[4], std::acos(2.0 / 3.0) * 180 / pi, 1e-12);
  EXPECT_NEAR(c[5], std::acos(1.0 / 3.0) * 180 / pi, 1e-12);
}

TEST(DihedralAngles, KuhnTetAngles)
{
  // The path tet of the cube: 90 on BC, AC, BD; 45 on AB, CD; 60 on AD.
  const std::array<double, 6> a = BM::dihedral_angles(V3(0, 0, 0), V3(1, 0, 0), V3(1, 1, 0), V3(1, 1, 1));
  const double expected[6] = {45, 90, 60, 90, 90, 45};
  for(int i = 0; i < 6; ++i)
    EXPECT_NEAR(a[static_cast<std::size_t>(i)], expected[i], 1e-12) << "edge " << i;
}

TEST(DihedralAngles, OtherPointTypes)
{
  const auto t = corner_tet();
  const double expected = BM::minimum_dihedral_angle(t[0], t[1], t[2], t[3]);
  const std::array<double, 3> a0 = {{0, 0, 0}}, a1 = {{1, 0, 0}}, a2 = {{0, 1, 0}}, a3 = {{0, 0, 1}};
  EXPECT_EQ(BM::minimum_dihedral_angle(a0, a1, a2, a3), expected);
  const Epick::Point_3 k0(0, 0, 0), k1(1, 0, 0), k2(0, 1, 0), k3(0, 0, 1);
  EXPECT_EQ(BM::minimum_dihedral_angle(k0, k1, k2, k3), expected);
  const Epeck::Point_3 e0(0, 0, 0), e1(1, 0, 0), e2(0, 1, 0), e3(0, 0, 1);
  EXPECT_EQ(BM::minimum_dihedral_angle(e0, e1, e2, e3), expected);
  const Sc::Point_3 s0(0, 0, 0), s1(1, 0, 0), s2(0, 1, 0), s3(0, 0, 1);
  const BM::Metric_3 m = BM::Metric_3::from_entries(2, 0.3, 0.1, 1, 0.2, 3);
  EXPECT_EQ(BM::metric_minimum_dihedral_angle(s0, s1, s2, s3, m),
            BM::metric_minimum_dihedral_angle(t[0], t[1], t[2], t[3], m));
  EXPECT_EQ(BM::metric_dihedral_angles(a0, a1, a2, a3, m), BM::metric_dihedral_angles(t[0], t[1], t[2], t[3], m));
  EXPECT_EQ(BM::signed_volume(k0, k1, k2, k3), 1.0 / 6.0);
  EXPECT_EQ(BM::radius_ratio(a0, a1, a2, a3), BM::radius_ratio(t[0], t[1], t[2], t[3]));
  EXPECT_EQ(BM::mean_ratio(e0, e1, e2, e3), BM::mean_ratio(t[0], t[1], t[2], t[3]));
  // Eigen expressions are accepted too.
  EXPECT_EQ(BM::minimum_dihedral_angle(t[0] + V3(1, 1, 1), t[1] + V3(1, 1, 1), t[2] + V3(1, 1, 1),
                                       t[3] + V3(1, 1, 1)),
            expected);
}

TEST(DihedralAngles, FlatTetsGiveZeroNotNaN)
{
  const BM::Metric_3 m = BM::Metric_3::from_entries(4, 1, 0, 3, 0.5, 2);
  const std::vector<std::array<V3, 4>> flats = {
      {{V3(0, 0, 0), V3(1, 0, 0), V3(1, 1, 0), V3(0, 1, 0)}},       // convex quad
      {{V3(0, 0, 0), V3(3, 0, 0), V3(0, 3, 0), V3(1, 1, 0)}},       // point inside a triangle
      {{V3(0, 0, 0), V3(1, 0, 0), V3(2, 0, 0), V3(0, 1, 0)}},       // three collinear
      {{V3(0, 0, 0), V3(1, 0, 0), V3(2, 0, 0), V3(3, 0, 0)}},       // all collinear
      {{V3(1, 2, 3), V3(1, 2, 3), V3(0, 1, 0), V3(0, 0, 1)}},       // repeated vertex
      {{V3(1, 2, 3), V3(1, 2, 3), V3(1, 2, 3), V3(1, 2, 3)}},       // one point
      {{V3(0, 0, 0), V3(1, 1, 1), V3(2, 3, 4), V3(3, 4, 5)}},       // coplanar, slanted
      {{V3(0.1, 0.7, 0.3), V3(1.1, 0.7, 0.3), V3(0.1, 1.7, 0.3), V3(0.35, 0.95, 0.3)}}, // plane z = 0.3
  };
  for(std::size_t i = 0; i < flats.size(); ++i) {
    const auto& t = flats[i];
    for(double a : BM::dihedral_angles(t[0], t[1], t[2], t[3]))
      EXPECT_TRUE(std::isfinite(a)) << "case " << i;
    // Exactly flat: every angle is exactly 0 or 180, also after mapping by Q.
    for(double a : BM::metric_dihedral_angles(t[0], t[1], t[2], t[3], m))
      EXPECT_TRUE(a == 0 || a == 180) << "case " << i << ": " << a;
    for(double a : BM::dihedral_angles(t[0], t[1], t[2], t[3]))
      EXPECT_TRUE(a == 0 || a == 180) << "case " << i << ": " << a;
    EXPECT_EQ(BM::minimum_dihedral_angle(t[0], t[1], t[2], t[3]), 0) << "case " << i;
    EXPECT_EQ(BM::metric_minimum_dihedral_angle(t[0], t[1], t[2], t[3], m), 0) << "case " << i;
    EXPECT_EQ(BM::radius_ratio(t[0], t[1], t[2], t[3]), 0) << "case " << i;
    EXPECT_EQ(BM::mean_ratio(t[0], t[1], t[2], t[3]), 0) << "case " << i;
    EXPECT_EQ(BM::metric_radius_ratio(t[0], t[1], t[2], t[3], m), 0) << "case " << i;
  }
  // Nearly flat: small but positive, and shrinking with the height.
  const double a1 = BM::minimum_dihedral_angle(V3(0, 0, 0), V3(1, 0, 0), V3(0, 1, 0), V3(0.3, 0.3, 1e-3));
  const double a2 = BM::minimum_dihedral_angle(V3(0, 0, 0), V3(1, 0, 0), V3(0, 1, 0), V3(0.3, 0.3, 1e-6));
  EXPECT_GT(a1, 0);
  EXPECT_GT(a2, 0);
  EXPECT_LT(a2, a1);
  EXPECT_LT(a1, 1);
  // A sliver with four well-spread vertices: min angle near 0 and its
  // complement near 180, all finite.
  const std::array<double, 6> s = BM::dihedral_angles(V3(0, 0, 0), V3(1, 1, 1e-7), V3(1, 0, 0), V3(0, 1, 0));
  EXPECT_LT(*std::min_element(s.begin(), s.end()), 1e-3);
  EXPECT_GT(*std::max_element(s.begin(), s.end()), 180 - 1e-3);
}

// ---------------------------------------------------------------------------
// Radius ratio, mean ratio, volumes

TEST(ShapeMeasures, RadiusAndMeanRatio)
{
  const auto t = regular_tet();
  EXPECT_NEAR(BM::radius_ratio(t[0], t[1], t[2], t[3]), 1, 1e-14);
  EXPECT_NEAR(BM::mean_ratio(t[0], t[1], t[2], t[3]), 1, 1e-14);
  const auto c = corner_tet();
  // r = 1/(3+sqrt 3), R = sqrt(3)/2  =>  3r/R = sqrt(3) - 1
  EXPECT_NEAR(BM::radius_ratio(c[0], c[1], c[2], c[3]), std::sqrt(3.0) - 1, 1e-14);
  // 3V = 1/2, sum l^2 = 3 + 6 = 9  =>  12 (1/2)^(2/3) / 9
  EXPECT_NEAR(BM::mean_ratio(c[0], c[1], c[2], c[3]), 12 * std::pow(0.5, 2.0 / 3.0) / 9, 1e-14);
  // A stretched regular tet is worse in both measures.
  const auto s = mapped(t, Eigen::Vector3d(1, 1, 3).asDiagonal().toDenseMatrix());
  EXPECT_LT(BM::radius_ratio(s[0], s[1], s[2], s[3]), 0.95);
  EXPECT_LT(BM::mean_ratio(s[0], s[1], s[2], s[3]), 0.95);
  EXPECT_GT(BM::radius_ratio(s[0], s[1], s[2], s[3]), 0);
  // Scale and orientation invariance.
  EXPECT_NEAR(BM::radius_ratio(V3(0, 0, 0), V3(0, 0, 7), V3(0, 7, 0), V3(7, 0, 0)), std::sqrt(3.0) - 1, 1e-14);
  EXPECT_NEAR(BM::mean_ratio(V3(0, 0, 0), V3(0, 0, 7), V3(0, 7, 0), V3(7, 0, 0)),
              12 * std::pow(0.5, 2.0 / 3.0) / 9, 1e-14);
}

TEST(ShapeMeasures, InvarianceUnderQMapping)
{
  std::mt19937 rng(777);
  const auto t = regular_tet();
  const auto c = corner_tet();
  const double corner_rr = BM::radius_ratio(c[0], c[1], c[2], c[3]);
  const double corner_mr = BM::mean_ratio(c[0], c[1], c[2], c[3]);
  const std::array<double, 6> corner_angles = BM::dihedral_angles(c[0], c[1], c[2], c[3]);
  for(int trial = 0; trial < 30; ++trial) {
    const BM::Metric_3 m = random_metric(rng);
    const auto s = mapped(t, m.Q_inverse());
    EXPECT_NEAR(BM::metric_radius_ratio(s[0], s[1], s[2], s[3], m), 1, 1e-9);
    EXPECT_NEAR(BM::metric_mean_ratio(s[0], s[1], s[2], s[3], m), 1, 1e-9);
    const auto d = mapped(c, m.Q_inverse());
    EXPECT_NEAR(BM::metric_radius_ratio(d[0], d[1], d[2], d[3], m), corner_rr, 1e-9);
    EXPECT_NEAR(BM::metric_mean_ratio(d[0], d[1], d[2], d[3], m), corner_mr, 1e-9);
    const std::array<double, 6> a = BM::metric_dihedral_angles(d[0], d[1], d[2], d[3], m);
    for(std::size_t e = 0; e < 6; ++e)
      EXPECT_NEAR(a[e], corner_angles[e], 1e-9);
    // Another factor of M (R Q for a rotation R) gives the same measures:
    // evaluate the Euclidean measures on R Q d.
    Eigen::HouseholderQR<M3> qr(M3::Random());
    const M3 rq = M3(qr.householderQ()) * m.Q();
    const auto e = mapped(d, rq);
    EXPECT_NEAR(BM::mean_ratio(e[0], e[1], e[2], e[3]), corner_mr, 1e-9);
  }
}

TEST(ShapeMeasures, SignedAndMetricVolume)
{
  const auto c = corner_tet();
  EXPECT_DOUBLE_EQ(BM::signed_volume(c[0], c[1], c[2], c[3]), 1.0 / 6);
  EXPECT_DOUBLE_EQ(BM::signed_volume(c[0], c[1], c[3], c[2]), -1.0 / 6);
  // Agrees in sign with CGAL::orientation.
  EXPECT_EQ(CGAL::orientation(Epick::Point_3(0, 0, 0), Epick::Point_3(1, 0, 0), Epick::Point_3(0, 1, 0),
                              Epick::Point_3(0, 0, 1)),
            CGAL::POSITIVE);
  // Isotropic size h: sqrt(det M) = h^-3.
  EXPECT_NEAR(BM::metric_signed_volume(c[0], c[1], c[2], c[3], BM::Metric_3::isotropic(0.5)), 8.0 / 6, 1e-14);
  EXPECT_NEAR(BM::metric_signed_volume(c[0], c[1], c[3], c[2], BM::Metric_3::isotropic(0.5)), -8.0 / 6, 1e-14);
  // Diagonal metric diag(4, 9, 1): factor 6.
  const BM::Metric_3 d = BM::Metric_3::from_entries(4, 0, 0, 9, 0, 1);
  EXPECT_NEAR(BM::metric_signed_volume(c[0], c[1], c[2], c[3], d), 1.0, 1e-14);
  // The image by Q^-1 of a tet has, in the metric, the Euclidean volume of the tet.
  std::mt19937 rng(99);
  const auto t = regular_tet();
  const double v = BM::signed_volume(t[0], t[1], t[2], t[3]);
  EXPECT_NEAR(v, 8.0 / 3, 1e-14);
  for(int trial = 0; trial < 20; ++trial) {
    const BM::Metric_3 m = random_metric(rng);
    const auto s = mapped(t, m.Q_inverse());
    EXPECT_NEAR(BM::metric_signed_volume(s[0], s[1], s[2], s[3], m), v, 1e-9 * v);
    EXPECT_NEAR(BM::metric_signed_volume(s[0], s[1], s[2], s[3], m),
                BM::signed_volume(s[0], s[1], s[2], s[3]) * std::sqrt(m.matrix().determinant()), 1e-9 * v);
  }
}

// ---------------------------------------------------------------------------
// Edge lengths

TEST(EdgeLength, ConstantMetricBothVariantsExact)
{
  std::mt19937 rng(4242);
  std::uniform_real_distribution<double> u(-5, 5);
  for(int trial = 0; trial < 20; ++trial) {
    const BM::Metric_3 m = random_metric(rng);
    const CGAL::Constant_metric_field_3<Epick> field(m);
    const V3 p(u(rng), u(rng), u(rng));
    const V3 q(u(rng), u(rng), u(rng));
    const V3 v = q - p;
    const double exact = std::sqrt(v.dot(m.matrix() * v));
    EXPECT_NEAR(BM::metric_edge_length(p, q, m), exact, 1e-12 * exact);
    EXPECT_NEAR(BM::metric_edge_length(p, q, m, m), exact, 1e-12 * exact);
    EXPECT_NEAR(BM::integrated_metric_edge_length(p, q, field), exact, 1e-12 * exact);
    EXPECT_NEAR(BM::integrated_metric_edge_length(p, q, field, 1), exact, 1e-12 * exact);
    // CGAL points
    const Epick::Point_3 cp(p[0], p[1], p[2]), cq(q[0], q[1], q[2]);
    EXPECT_NEAR(BM::integrated_metric_edge_length(cp, cq, field), exact, 1e-12 * exact);
    EXPECT_NEAR(BM::metric_edge_length(cp, cq, m, m), exact, 1e-12 * exact);
  }
}

TEST(EdgeLength, GradedFieldIntegratedMatchesAnalytic)
{
  // Isotropic size h(x) = 0.5 + x: along p + t v, with x = t (v_x = 1),
  // length = |v| * integral_0^1 dt / (0.5 + t) = |v| ln 3.
  auto field = CGAL::make_function_metric_field_3<Epick>([](const Epick::Point_3& p) {
    const double h = 0.5 + p.x();
    return M3(M3::Identity() / (h * h));
  });
  const V3 p(0, 0, 0);
  const V3 q(1, 2, 2); // |q - p| = 3
  const double analytic = 3 * std::log(3.0);
  EXPECT_NEAR(BM::integrated_metric_edge_length(p, q, field), analytic, 1e-6);
  EXPECT_NEAR(BM::integrated_metric_edge_length(p, q, field, 32), analytic, 1e-10);
  // Reversing the edge gives the same length.
  EXPECT_NEAR(BM::integrated_metric_edge_length(q, p, field), analytic, 1e-6);
  // Convergence: more segments, smaller error.
  const double e1 = std::abs(BM::integrated_metric_edge_length(p, q, field, 1) - analytic);
  const double e4 = std::abs(BM::integrated_metric_edge_length(p, q, field, 4) - analytic);
  EXPECT_LT(e4, e1 / 100);
  // The end-point average is a different (cruder) estimate here:
  // 3 (1/0.5 + 1/1.5) / 2 = 4.
  EXPECT_NEAR(BM::metric_edge_length(p, q, field(Epick::Point_3(0, 0, 0)), field(Epick::Point_3(1, 2, 2))), 4.0,
              1e-12);
  EXPECT_THROW(BM::integrated_metric_edge_length(p, q, field, 0), BM::Invalid_input);

  // Anisotropic grading along z only: M = diag(1, 1, (1 + z)^2). Along the
  // z axis from 0 to 2 the length is integral_0^2 (1 + z) dz = 4.
  auto field2 = CGAL::make_function_metric_field_3<Epick>([](const Epick::Point_3& p) {
    M3 m = M3::Identity();
    m(2, 2) = (1 + p.z()) * (1 + p.z());
    return m;
  });
  EXPECT_NEAR(BM::integrated_metric_edge_length(V3(0, 0, 0), V3(0, 0, 2), field2), 4.0, 1e-12);
  // Edge (0,0,0)-(3,0,4): v = (3,0,4), z = 4t; sqrt(9 + 16 (1+4t)^2).
  // Antiderivative of sqrt(9 + u^2) (u = 4 + 16t, du = 16 dt):
  // F(u) = (u sqrt(9+u^2) + 9 asinh(u/3)) / 2, length = (F(20) - F(4)) / 16.
  auto F = [](double u) { return 0.5 * (u * std::sqrt(9 + u * u) + 9 * std::asinh(u / 3)); };
  const double analytic2 = (F(20) - F(4)) / 16;
  EXPECT_NEAR(BM::integrated_metric_edge_length(V3(0, 0, 0), V3(3, 0, 4), field2), analytic2, 1e-6);
}

// ---------------------------------------------------------------------------
// Percentiles

TEST(Percentile, NearestRank)
{
  std::vector<double> v(1000);
  std::iota(v.begin(), v.end(), 1.0); // 1 .. 1000
  std::mt19937 rng(5);
  std::shuffle(v.begin(), v.end(), rng);
  EXPECT_EQ(BM::nearest_rank_percentile(v, 1), 10);
  EXPECT_EQ(BM::nearest_rank_percentile(v, 50), 500);
  EXPECT_EQ(BM::nearest_rank_percentile(v, 100), 1000);
  EXPECT_EQ(BM::nearest_rank_percentile(v, 0), 1);
  EXPECT_EQ(BM::nearest_rank_percentile(v, 0.05), 1);
  EXPECT_EQ(BM::nearest_rank_percentile(v, 0.15), 2); // ceil(1.5) = 2
  std::vector<double> w(101);
  std::iota(w.begin(), w.end(), 0.0); // 0 .. 100
  EXPECT_EQ(BM::nearest_rank_percentile(w, 1), 1);   // rank ceil(1.01) = 2
  EXPECT_EQ(BM::nearest_rank_percentile(w, 25), 25); // rank ceil(25.25) = 26
  EXPECT_EQ(BM::nearest_rank_percentile({7.0}, 1), 7);
  EXPECT_THROW(BM::nearest_rank_percentile({}, 1), BM::Invalid_input);
  EXPECT_THROW(BM::nearest_rank_percentile(v, 101), BM::Invalid_input);
  EXPECT_THROW(BM::nearest_rank_percentile(v, -1), BM::Invalid_input);
}

// ---------------------------------------------------------------------------
// Quality report

TEST(QualityReport, UnitCubeInIdentityMetric)
{
  const BM::Indexed_tet_mesh_3 mesh = kuhn_grid(1);
  ASSERT_EQ(mesh.tets.size(), 6u);
  const CGAL::Constant_metric_field_3<Epick> field;
  const BM::Quality_report r = BM::compute_quality_report(mesh, field, "identity");
  EXPECT_EQ(r.vertices, 8u);
  EXPECT_EQ(r.tets, 6u);
  EXPECT_EQ(r.metric_description, "identity");
  EXPECT_NEAR(r.volume, 1.0, 1e-15);
  EXPECT_NEAR(r.metric_volume, 1.0, 1e-15);
  EXPECT_EQ(r.inverted_tets, 0u);
  EXPECT_EQ(r.degenerate_tets, 0u);
  // Every Kuhn tet has dihedral angles 45, 45, 60, 90, 90, 90.
  EXPECT_NEAR(r.min_dihedral.worst, 45, 1e-9);
  EXPECT_NEAR(r.min_dihedral.p01, 45, 1e-9);
  EXPECT_NEAR(r.min_dihedral.mean, 45, 1e-9);
  EXPECT_EQ(r.min_dihedral.below5, 0u);
  EXPECT_EQ(r.min_dihedral.below10, 0u);
  EXPECT_EQ(r.min_dihedral.below15, 0u);
  for(int i = 0; i < 18; ++i)
    EXPECT_EQ(r.histogram_5deg[static_cast<std::size_t>(i)], i == 9 ? 6u : 0u) << "bin " << i;
  // Kuhn tet: squared edges 1, 1, 1, 2, 2, 3 (sum 10), 3 V = 1/2
  const double kuhn_ratio = 12 * std::cbrt(0.25) / 10;
  EXPECT_NEAR(r.mean_ratio.worst, kuhn_ratio, 1e-14);
  EXPECT_NEAR(r.mean_ratio.p01, kuhn_ratio, 1e-14);
  EXPECT_NEAR(r.mean_ratio.mean, kuhn_ratio, 1e-14);
  EXPECT_EQ(r.mean_ratio.worst_tet, 0u);
  // 12 cube edges (1), 6 face diagonals (sqrt 2), 1 body diagonal (sqrt 3).
  EXPECT_EQ(r.edge_length.number_of_edges, 19u);
  EXPECT_NEAR(r.edge_length.min, 1, 1e-15);
  EXPECT_NEAR(r.edge_length.max, std::sqrt(3.0), 1e-15);
  EXPECT_NEAR(r.edge_length.mean, (12 + 6 * std::sqrt(2.0) + std::sqrt(3.0)) / 19, 1e-15);
  // [1/sqrt 2, sqrt 2] includes its bounds: only the body diagonal is out.
  EXPECT_DOUBLE_EQ(r.edge_length.in_range_fraction, 18.0 / 19);
  EXPECT_DOUBLE_EQ(r.edge_length.short_fraction, 0);
  EXPECT_DOUBLE_EQ(r.edge_length.long_fraction, 1.0 / 19);
}

TEST(QualityReport, UnitCubeInIsotropicAndAnisotropicMetrics)
{
  const BM::Indexed_tet_mesh_3 mesh = kuhn_grid(1);
  {
    // Size 0.8: lengths 1.25 (12 edges, in range), 1.25 sqrt 2 = 1.77 and
    // 1.25 sqrt 3 (out); volume 1 / 0.8^3; angles unchanged.
    const BM::Quality_report r = BM::compute_quality_report(mesh, CGAL::Constant_metric_field_3<Epick>::isotropic(0.8));
    EXPECT_DOUBLE_EQ(r.edge_length.in_range_fraction, 12.0 / 19);
    EXPECT_DOUBLE_EQ(r.edge_length.long_fraction, 7.0 / 19);
    EXPECT_NEAR(r.edge_length.min, 1.25, 1e-14);
    EXPECT_NEAR(r.edge_length.max, 1.25 * std::sqrt(3.0), 1e-14);
    EXPECT_NEAR(r.metric_volume, 1 / 0.512, 1e-13);
    EXPECT_NEAR(r.volume, 1, 1e-15);
    EXPECT_NEAR(r.min_dihedral.worst, 45, 1e-9);
  }
  {
    // M = diag(1, 1, 1/16): the cube looks like a 1 x 1 x 0.25 box. Edges:
    // 8 of length 1 (in), 4 of 0.25 (out), 2 face diagonals sqrt 2 in the xy
    // faces (in), 4 of sqrt(1 + 1/16) = 1.0308 (in), 1 of sqrt(2.0625) (out):
    // 14 / 19. The angles are those of the Kuhn tets of the flattened box,
    // i.e. the Euclidean angles of the scaled points.
    const BM::Metric_3 m = BM::Metric_3::from_entries(1, 0, 0, 1, 0, 1.0 / 16);
    const BM::Quality_report r = BM::compute_quality_report(mesh, CGAL::Constant_metric_field_3<Epick>(m));
    EXPECT_DOUBLE_EQ(r.edge_length.in_range_fraction, 14.0 / 19);
    EXPECT_DOUBLE_EQ(r.edge_length.short_fraction, 4.0 / 19);
    EXPECT_DOUBLE_EQ(r.edge_length.long_fraction, 1.0 / 19);
    EXPECT_NEAR(r.edge_length.min, 0.25, 1e-15);
    EXPECT_NEAR(r.metric_volume, 0.25, 1e-15);
    double worst = 180;
    for(const auto& t : mesh.tets) {
      auto p = [&](int i) {
        const auto& a = mesh.points[static_cast<std::size_t>(t[static_cast<std::size_t>(i)])];
        return V3(a[0], a[1], 0.25 * a[2]);
      };
      worst = std::min(worst, BM::minimum_dihedral_angle(p(0), p(1), p(2), p(3)));
    }
    EXPECT_LT(worst, 40);
    EXPECT_NEAR(r.min_dihedral.worst, worst, 1e-12);
  }
}

TEST(QualityReport, InvertedFlatAndUnusedVertices)
{
  BM::Indexed_tet_mesh_3 mesh = kuhn_grid(1);
  std::swap(mesh.tets[2][0], mesh.tets[2][1]); // invert one tet
  mesh.points.push_back({{5, 5, 5}});          // unused point
  mesh.points.push_back({{0.7, 0.2, 0}});      // used by the flat tet only
  const int centre = static_cast<int>(mesh.points.size()) - 1;
  mesh.tets.push_back({{0, 1, 3, centre}});    // flat: in the face z = 0
  const BM::Quality_report r = BM::compute_quality_report(mesh, CGAL::Constant_metric_field_3<Epick>());
  EXPECT_EQ(r.tets, 7u);
  EXPECT_EQ(r.vertices, 9u);
  EXPECT_EQ(r.inverted_tets, 1u);
  EXPECT_EQ(r.degenerate_tets, 1u);
  EXPECT_NEAR(r.volume, 1.0 - 2.0 / 6, 1e-15);
  EXPECT_EQ(r.min_dihedral.worst, 0);
  EXPECT_EQ(r.min_dihedral.worst_tet, 6u);
  EXPECT_EQ(r.min_dihedral.below5, 1u);
  EXPECT_EQ(r.min_dihedral.below10, 1u);
  EXPECT_EQ(r.min_dihedral.below15, 1u);
  EXPECT_EQ(r.histogram_5deg[0], 1u);
  EXPECT_EQ(r.histogram_5deg[9], 6u); // the inverted tet keeps its 45 degrees
  EXPECT_NEAR(r.min_dihedral.mean, 6 * 45.0 / 7, 1e-9);
  EXPECT_EQ(r.mean_ratio.worst, 0); // the flat tet, exactly
  EXPECT_EQ(r.mean_ratio.worst_tet, 6u);
  // 19 + 3 new edges to the centre point (0-c, 1-c, 3-c); 0-1, 0-3, 1-3 exist.
  EXPECT_EQ(r.edge_length.number_of_edges, 22u);

  // A nearly-inverted tet whose double volume may round either way is still
  // classified exactly: a tiny negative orientation.
  BM::Indexed_tet_mesh_3 sliver;
  sliver.points = {{{0, 0, 0}}, {{1, 0, 0}}, {{0, 1, 0}}, {{0.25, 0.25, -1e-300}}};
  sliver.tets = {{{0, 1, 2, 3}}};
  const BM::Quality_report s = BM::compute_quality_report(sliver, CGAL::Constant_metric_field_3<Epick>());
  EXPECT_EQ(s.inverted_tets, 1u);
  EXPECT_EQ(s.degenerate_tets, 0u);
}

// A needle: an equilateral base and an apex 20 above its centre. No dihedral
// angle is small (60 degrees between the long faces, nearly 90 at the base),
// but the tet is 20 times longer than wide: the mean ratio says so. In the
// metric that shrinks z to the regular tet's height it is regular.
TEST(QualityReport, MeanRatioSeesNeedlesTheAngleDoesNot)
{
  BM::Indexed_tet_mesh_3 needle;
  const double height = 20, regular_height = std::sqrt(2.0 / 3);
  needle.points = {{{0, 0, 0}}, {{1, 0, 0}}, {{0.5, std::sqrt(3.0) / 2, 0}},
                   {{0.5, std::sqrt(3.0) / 6, height}}};
  needle.tets = {{{0, 1, 2, 3}}};
  const BM::Quality_report r = BM::compute_quality_report(needle, CGAL::Constant_metric_field_3<Epick>());
  EXPECT_GT(r.min_dihedral.worst, 59.5);
  // sum of squared edges 3 + 3 (400 + 1/3), 3 V = height sqrt(3) / 4
  const double expected = 12 * std::cbrt(std::pow(height * std::sqrt(3.0) / 4, 2)) / (3 + 3 * (400 + 1.0 / 3));
  EXPECT_NEAR(r.mean_ratio.worst, expected, 1e-12);
  EXPECT_LT(r.mean_ratio.worst, 0.05);

  const double s = regular_height / height;
  const BM::Metric_3 flatten = BM::Metric_3::from_entries(1, 0, 0, 1, 0, s * s);
  const BM::Quality_report m = BM::compute_quality_report(needle, CGAL::Constant_metric_field_3<Epick>(flatten));
  EXPECT_NEAR(m.mean_ratio.worst, 1, 1e-12);
  EXPECT_NEAR(m.min_dihedral.worst, std::acos(1.0 / 3) * 180 / CGAL_PI, 1e-9);

  // the worst of two: a regular tet (index 0) and the needle (index 1)
  BM::Indexed_tet_mesh_3 two = needle;
  two.points.push_back({{0.5, std::sqrt(3.0) / 6, -regular_height}});
  two.tets = {{{0, 2, 1, 4}}, {{0, 1, 2, 3}}};
  const BM::Quality_report t = BM::compute_quality_report(two, CGAL::Constant_metric_field_3<Epick>());
  EXPECT_EQ(t.mean_ratio.worst_tet, 1u);
  EXPECT_NEAR(t.mean_ratio.mean, (1 + expected) / 2, 1e-12);
  EXPECT_NEAR(t.mean_ratio.p01, expected, 1e-12);
}

TEST(QualityReport, InvalidInput)
{
  const CGAL::Constant_metric_field_3<Epick> field;
  BM::Indexed_tet_mesh_3 empty;
  EXPECT_THROW(BM::compute_quality_report(empty, field), BM::Invalid_input);
  empty.points = {{{0, 0, 0}}, {{1, 0, 0}}};
  EXPECT_THROW(BM::compute_quality_report(empty, field), BM::Invalid_input);
  BM::Indexed_tet_mesh_3 bad = kuhn_grid(1);
  bad.tets.push_back({{0, 1, 2, 8}});
  EXPECT_THROW(BM::compute_quality_report(bad, field), BM::Invalid_input);
  bad = kuhn_grid(1);
  bad.tets.push_back({{0, 1, -1, 2}});
  EXPECT_THROW(BM::compute_quality_report(bad, field), BM::Invalid_input);
  bad = kuhn_grid(1);
  bad.points[3][1] = std::nan("");
  EXPECT_THROW(BM::compute_quality_report(bad, field), BM::Invalid_input);
  // A field error propagates as Invalid_metric.
  auto broken = CGAL::make_function_metric_field_3<Epick>([](const Epick::Point_3& p) {
    return M3(p.x() > 0.5 ? M3(-M3::Identity()) : M3(M3::Identity()));
  });
  EXPECT_THROW(BM::compute_quality_report(kuhn_grid(2), broken), BM::Invalid_metric);
}

TEST(QualityReport, GridCountsPercentileAndHistogramSum)
{
  const int n = 4;
  BM::Indexed_tet_mesh_3 mesh = kuhn_grid(n, 0.25);
  const std::size_t good = mesh.tets.size(); // 384
  // One flat tet: with 385 tets the 1st percentile is the ceil(3.85) = 4th
  // smallest value, 45; with 4 flat tets it is 0.
  mesh.tets.push_back({{0, 1, 2, 3}}); // four points on the x axis
  const CGAL::Constant_metric_field_3<Epick> field = CGAL::Constant_metric_field_3<Epick>::isotropic(0.25);
  BM::Quality_report r = BM::compute_quality_report(mesh, field);
  EXPECT_EQ(r.tets, good + 1);
  EXPECT_EQ(r.vertices, 125u);
  EXPECT_EQ(r.edge_length.number_of_edges, kuhn_grid_edges(n) + 3); // 0-2, 0-3, 1-3 are new
  EXPECT_NEAR(r.volume, 1, 1e-14);
  EXPECT_NEAR(r.metric_volume, 64, 1e-12);
  EXPECT_EQ(r.min_dihedral.worst, 0);
  EXPECT_NEAR(r.min_dihedral.p01, 45, 1e-9);
  std::size_t sum = 0;
  for(std::size_t c : r.histogram_5deg)
    sum += c;
  EXPECT_EQ(sum, r.tets);
  for(int extra = 0; extra < 3; ++extra)
    mesh.tets.push_back({{0, 1, 2, 3}});
  r = BM::compute_quality_report(mesh, field);
  EXPECT_EQ(r.min_dihedral.p01, 0); // rank ceil(3.88) = 4: the 4 flat tets
  EXPECT_EQ(r.histogram_5deg[0], 4u);
  EXPECT_EQ(r.degenerate_tets, 4u);

  // Edge count formula on a bigger grid, graded field: histogram sums to tets.
  const BM::Indexed_tet_mesh_3 big = kuhn_grid(7, 0.3);
  auto graded = CGAL::make_function_metric_field_3<Epick>(graded_metric);
  const BM::Quality_report g = BM::compute_quality_report(big, graded);
  EXPECT_EQ(g.edge_length.number_of_edges, kuhn_grid_edges(7));
  EXPECT_EQ(g.vertices, 512u);
  sum = 0;
  for(std::size_t c : g.histogram_5deg)
    sum += c;
  EXPECT_EQ(sum, g.tets);
  EXPECT_NEAR(g.volume, 2.1 * 2.1 * 2.1, 1e-12);
  // The per-tet angles are those of the single-tet function with the metric
  // at the centroid.
  const std::vector<double> angles = BM::metric_minimum_dihedral_angles(big, graded);
  ASSERT_EQ(angles.size(), big.tets.size());
  const auto& t = big.tets[100];
  V3 p[4];
  for(int i = 0; i < 4; ++i) {
    const auto& a = big.points[static_cast<std::size_t>(t[static_cast<std::size_t>(i)])];
    p[i] = V3(a[0], a[1], a[2]);
  }
  const V3 c = (p[0] + p[1] + p[2] + p[3]) / 4;
  EXPECT_EQ(angles[100],
            BM::metric_minimum_dihedral_angle(p[0], p[1], p[2], p[3], graded(Epick::Point_3(c[0], c[1], c[2]))));
  EXPECT_EQ(g.min_dihedral.worst, *std::min_element(angles.begin(), angles.end()));
  // Edge lengths use the mean of the end-vertex metrics.
  const auto& a0 = big.points[0];
  const auto& a1 = big.points[1];
  const double l01 =
      BM::metric_edge_length(V3(a0[0], a0[1], a0[2]), V3(a1[0], a1[1], a1[2]), graded(Epick::Point_3(a0[0], a0[1], a0[2])),
                             graded(Epick::Point_3(a1[0], a1[1], a1[2])));
  EXPECT_LE(g.edge_length.min, l01);
  EXPECT_GE(g.edge_length.max, l01);
}

TEST(QualityReport, JsonIsValidAndHoldsTheValues)
{
  BM::Indexed_tet_mesh_3 mesh = kuhn_grid(2);
  std::swap(mesh.tets[5][2], mesh.tets[5][3]);
  const BM::Quality_report r =
      BM::compute_quality_report(mesh, CGAL::make_function_metric_field_3<Epick>(graded_metric),
                                 "graded \"test\" field\\1");
  const std::string json = BM::to_json(r);
  // Braces and brackets balance (outside strings).
  int braces = 0, brackets = 0;
  bool in_string = false;
  for(std::size_t i = 0; i < json.size(); ++i) {
    const char ch = json[i];
    if(in_string) {
      if(ch == '\\')
        ++i;
      else if(ch == '"')
        in_string = false;
      continue;
    }
    if(ch == '"')
      in_string = true;
    braces += (ch == '{') - (ch == '}');
    brackets += (ch == '[') - (ch == ']');
    ASSERT_GE(braces, 0);
    ASSERT_GE(brackets, 0);
  }
  EXPECT_EQ(braces, 0);
  EXPECT_EQ(brackets, 0);
  EXPECT_FALSE(in_string);

  Json j;
  ASSERT_NO_THROW(j = Json_parser(json).parse()) << json;
  ASSERT_EQ(j.type, Json::Object);
  for(const char* key : {"vertices", "tets", "min_dihedral", "mean_ratio", "histogram_5deg", "edge_length",
                         "inverted_tets", "volume", "metric_volume", "metric", "degenerate_tets"})
    EXPECT_TRUE(j.has(key)) << key;
  EXPECT_EQ(j["vertices"].number, 27);
  EXPECT_EQ(j["tets"].number, 48);
  EXPECT_EQ(j["inverted_tets"].number, 1);
  EXPECT_EQ(j["metric"].string, "graded \"test\" field\\1");
  // Doubles read back bit-exactly.
  EXPECT_EQ(j["volume"].number, r.volume);
  EXPECT_EQ(j["metric_volume"].number, r.metric_volume);
  const Json& md = j["min_dihedral"];
  for(const char* key : {"worst", "p01", "mean", "below5", "below10", "below15"})
    EXPECT_TRUE(md.has(key)) << key;
  EXPECT_EQ(md["worst"].number, r.min_dihedral.worst);
  EXPECT_EQ(md["p01"].number, r.min_dihedral.p01);
  EXPECT_EQ(md["mean"].number, r.min_dihedral.mean);
  EXPECT_EQ(md["below10"].number, static_cast<double>(r.min_dihedral.below10));
  const Json& h = j["histogram_5deg"];
  ASSERT_EQ(h.type, Json::Array);
  ASSERT_EQ(h.array.size(), 18u);
  double sum = 0;
  for(std::size_t i = 0; i < 18; ++i) {
    EXPECT_EQ(h.array[i].number, static_cast<double>(r.histogram_5deg[i]));
    sum += h.array[i].number;
  }
  EXPECT_EQ(sum, 48);
  const Json& el = j["edge_length"];
  const auto& ratio = j["mean_ratio"];
  for(const char* key : {"worst", "worst_tet", "p01", "mean"})
    EXPECT_TRUE(ratio.has(key)) << key;
  EXPECT_EQ(ratio["worst"].number, r.mean_ratio.worst);
  EXPECT_EQ(ratio["p01"].number, r.mean_ratio.p01);
  EXPECT_EQ(ratio["mean"].number, r.mean_ratio.mean);
  EXPECT_EQ(ratio["worst_tet"].number, static_cast<double>(r.mean_ratio.worst_tet));
  for(const char* key : {"min", "max", "mean", "in_range_fraction", "short_fraction", "long_fraction"})
    EXPECT_TRUE(el.has(key)) << key;
  EXPECT_EQ(el["short_fraction"].number, r.edge_length.short_fraction);
  EXPECT_EQ(el["long_fraction"].number, r.edge_length.long_fraction);
  EXPECT_EQ(el["min"].number, r.edge_length.min);
  EXPECT_EQ(el["max"].number, r.edge_length.max);
  EXPECT_EQ(el["mean"].number, r.edge_length.mean);
  EXPECT_EQ(el["in_range_fraction"].number, r.edge_length.in_range_fraction);
  EXPECT_EQ(el["number_of_edges"].number, static_cast<double>(kuhn_grid_edges(2)));

  // The parser itself rejects broken JSON (so the checks above can fail).
  EXPECT_THROW(Json_parser("{\"a\": 1,}").parse(), std::runtime_error);
  EXPECT_THROW(Json_parser("{\"a\": [1, 2}").parse(), std::runtime_error);
  EXPECT_THROW(Json_parser("{\"a\": nan}").parse(), std::runtime_error);
}

TEST(QualityReport, SummaryAndSvg)
{
  const BM::Quality_report r =
      BM::compute_quality_report(kuhn_grid(3), CGAL::Constant_metric_field_3<Epick>(), "identity");
  std::ostringstream os;
  BM::print_quality_summary(os, r);
  const std::string text = os.str();
  EXPECT_NE(text.find("162 tets"), std::string::npos) << text;
  EXPECT_NE(text.find("worst 45.00"), std::string::npos) << text;
  EXPECT_NE(text.find("mean ratio: worst 0.756 (tet 0), p01 0.756, mean 0.756"), std::string::npos) << text;
  // The 45-50 bin holds all tets: a full bar of 50 '#' and the count.
  const std::size_t line = text.find("45-50)");
  ASSERT_NE(line, std::string::npos) << text;
  const std::string bar_line = text.substr(line, text.find('\n', line) - line);
  EXPECT_NE(bar_line.find(std::string(50, '#')), std::string::npos) << bar_line;
  EXPECT_NE(bar_line.find(" 162"), std::string::npos) << bar_line;
  const std::size_t other = text.find("40-45)");
  ASSERT_NE(other, std::string::npos);
  EXPECT_EQ(text.substr(other, text.find('\n', other) - other).find('#'), std::string::npos);
  EXPECT_LT(std::count(text.begin(), text.end(), '\n'), 30);

  const std::string path = std::string(BUBBLE_MESH_3_BINARY_DIR) + "/test_quality_histogram.svg";
  std::remove(path.c_str());
  BM::write_histogram_svg(path, r, "Kuhn cube <3x3x3> & identity");
  std::ifstream in(path);
  ASSERT_TRUE(in.good());
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string svg = buffer.str();
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg.find("<svg xmlns=\"http://www.w3.org/2000/svg\""), std::string::npos);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_NE(svg.find("Kuhn cube &lt;3x3x3&gt; &amp; identity"), std::string::npos);
  EXPECT_NE(svg.find("worst 45.00"), std::string::npos);
  EXPECT_NE(svg.find("p01 45.00"), std::string::npos);
  EXPECT_NE(svg.find("minimum dihedral angle"), std::string::npos);
  EXPECT_NE(svg.find("[45, 50): 162"), std::string::npos);
  EXPECT_EQ(std::count(svg.begin(), svg.end(), '<') , std::count(svg.begin(), svg.end(), '>'));
  EXPECT_FALSE(std::ifstream(path + ".tmp").good());
  EXPECT_THROW(BM::write_histogram_svg("/nonexistent-dir/x/h.svg", r, "t"), BM::Invalid_file);
}

TEST(QualityReport, IdenticalForAnyNumberOfThreads)
{
  const BM::Indexed_tet_mesh_3 mesh = kuhn_grid(12, 0.2);
  auto field = CGAL::make_function_metric_field_3<Epick>(graded_metric);
#ifdef CGAL_LINKED_WITH_TBB
  BM::Quality_report one, two, many;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = BM::compute_quality_report(mesh, field, "graded");
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = BM::compute_quality_report(mesh, field, "graded");
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 8);
    many = BM::compute_quality_report(mesh, field, "graded");
  }
  EXPECT_TRUE(same_report(one, two));
  EXPECT_TRUE(same_report(one, many));
  EXPECT_EQ(BM::to_json(one), BM::to_json(two));
  EXPECT_EQ(BM::to_json(one), BM::to_json(many));
#else
  const BM::Quality_report a = BM::compute_quality_report(mesh, field, "graded");
  const BM::Quality_report b = BM::compute_quality_report(mesh, field, "graded");
  EXPECT_TRUE(same_report(a, b));
  GTEST_SKIP() << "built without TBB";
#endif
}

// Timing on about a million tets. Disabled by default; run with
//   test_quality --gtest_also_run_disabled_tests --gtest_filter='*Timing*'
TEST(QualityReport, DISABLED_TimingOneMillionTets)
{
  const int n = 55; // 55^3 * 6 = 998250 tets
  const BM::Indexed_tet_mesh_3 mesh = kuhn_grid(n, 1.0 / n);
  const auto start = std::chrono::steady_clock::now();
  const BM::Quality_report r = BM::compute_quality_report(mesh, CGAL::Constant_metric_field_3<Epick>::isotropic(1.0 / n));
  const auto middle = std::chrono::steady_clock::now();
  auto field = CGAL::make_function_metric_field_3<Epick>(graded_metric);
  const BM::Quality_report g = BM::compute_quality_report(mesh, field);
  const auto end = std::chrono::steady_clock::now();
  std::cout << "tets " << r.tets << ", vertices " << r.vertices << ", edges " << r.edge_length.number_of_edges
            << "\nconstant field: " << std::chrono::duration<double>(middle - start).count() << " s"
            << "\nfunction field (validated per evaluation): " << std::chrono::duration<double>(end - middle).count()
            << " s\n";
  BM::print_quality_summary(std::cout, r);
  EXPECT_EQ(r.edge_length.number_of_edges, kuhn_grid_edges(static_cast<std::size_t>(n)));
  EXPECT_EQ(g.tets, r.tets);
}
