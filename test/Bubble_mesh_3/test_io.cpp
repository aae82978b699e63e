// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Tests of the file formats (MEDIT .mesh and .sol, VTU, triangle surfaces)
// and of Interpolated_metric_field_3.

#include <CGAL/Bubble_mesh_3/IO/medit.h>
#include <CGAL/Bubble_mesh_3/IO/read_triangle_surface.h>
#include <CGAL/Bubble_mesh_3/IO/sol.h>
#include <CGAL/Bubble_mesh_3/IO/vtu.h>
#include <CGAL/Interpolated_metric_field_3.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

namespace {

namespace BM = CGAL::Bubble_mesh_3;
namespace fs = std::filesystem;
typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_3 Point_3;
typedef BM::Metric_3 Metric;
typedef CGAL::Interpolated_metric_field_3<K> Field;

// ---------------------------------------------------------------- helpers

// A fresh directory per test program run, removed at exit.
class Scratch_directory : public ::testing::Environment {
public:
  static const fs::path& path()
  {
    static const fs::path dir = [] {
      std::random_device rd;
      fs::path d = fs::temp_directory_path() / ("bubble_mesh_3_test_io_" + std::to_string(rd()) + "_" +
                                                std::to_string(rd()));
      fs::create_directories(d);
      return d;
    }();
    return dir;
  }
  void TearDown() override
  {
    std::error_code ec;
    fs::remove_all(path(), ec);
  }
};
const ::testing::Environment* const scratch_environment =
  ::testing::AddGlobalTestEnvironment(new Scratch_directory);

std::string scratch(const std::string& file_name) { return (Scratch_directory::path() / file_name).string(); }

std::string data_file(const std::string& file_name) { return std::string(BUBBLE_MESH_3_TEST_DATA) + "/" + file_name; }

void write_text(const std::string& path, const std::string& text)
{
  std::ofstream os(path, std::ios::binary);
  os << text;
  ASSERT_TRUE(bool(os)) << path;
}

std::string read_text(const std::string& path)
{
  std::ifstream is(path, std::ios::binary);
  std::ostringstream ss;
  ss << is.rdbuf();
  return ss.str();
}

// Files in the scratch directory whose name starts with `prefix` (to check
// that no temporary file is left behind).
std::vector<std::string> files_starting_with(const std::string& prefix)
{
  std::vector<std::string> r;
  for(const auto& e : fs::directory_iterator(Scratch_directory::path()))
    if(e.path().filename().string().rfind(prefix, 0) == 0)
      r.push_back(e.path().filename().string());
  std::sort(r.begin(), r.end());
  return r;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

bool same_bits(const Metric& a, const Metric& b)
{
  for(int i = 0; i < 3; ++i)
    for(int j = 0; j < 3; ++j)
      if(!same_bits(a(i, j), b(i, j)))
        return false;
  return true;
}

double relative_difference(const Metric::Matrix& a, const Metric::Matrix& b) { return (a - b).norm() / b.norm(); }

// Runs `f`, expects an exception of type E whose message contains every
// string of `needles`; returns the message.
template <typename E>
std::string expect_error(const std::function<void()>& f, const std::vector<std::string>& needles)
{
  try {
    f();
  } catch(const E& e) {
    const std::string what = e.what();
    for(const std::string& n : needles)
      EXPECT_NE(what.find(n), std::string::npos) << "message '" << what << "' lacks '" << n << "'";
    return what;
  } catch(const std::exception& e) {
    ADD_FAILURE() << "wrong exception type, message: " << e.what();
    return std::string();
  }
  ADD_FAILURE() << "no exception thrown";
  return std::string();
}

// Structured tet mesh of [0, size]^3 with n^3 cubes, each split into 6
// positively oriented tets around its main diagonal (conforming).
BM::Indexed_tet_mesh_3 cube_mesh(int n, double size = 1.0)
{
  BM::Indexed_tet_mesh_3 m;
  auto id = [n](int i, int j, int k) { return (k * (n + 1) + j) * (n + 1) + i; };
  for(int k = 0; k <= n; ++k)
    for(int j = 0; j <= n; ++j)
      for(int i = 0; i <= n; ++i) {
        m.points.push_back({{size * i / n, size * j / n, size * k / n}});
        m.point_refs.push_back((i == 0) + 2 * (j == 0));
      }
  const int permutations[6][3] = {{1, 2, 4}, {1, 4, 2}, {2, 1, 4}, {2, 4, 1}, {4, 1, 2}, {4, 2, 1}};
  for(int k = 0; k < n; ++k)
    for(int j = 0; j < n; ++j)
      for(int i = 0; i < n; ++i) {
        auto corner = [&](int bits) { return id(i + (bits & 1), j + ((bits >> 1) & 1), k + ((bits >> 2) & 1)); };
        for(const auto& p : permutations) {
          std::array<int, 4> t = {{corner(0), corner(p[0]), corner(p[0] | p[1]), corner(7)}};
          auto P = [&m](int v) { return Point_3(m.points[v][0], m.points[v][1], m.points[v][2]); };
          if(CGAL::orientation(P(t[0]), P(t[1]), P(t[2]), P(t[3])) == CGAL::NEGATIVE)
            std::swap(t[2], t[3]);
          m.tets.push_back(t);
          m.tet_refs.push_back(1 + (i + j + k) % 3);
        }
      }
  return m;
}

Metric random_metric(std::mt19937& gen)
{
  std::uniform_real_distribution<double> u(-1, 1), size(0.01, 2);
  Metric::Matrix r;
  for(int i = 0; i < 3; ++i)
    for(int j = 0; j < 3; ++j)
      r(i, j) = u(gen);
  return Metric::from_directions_and_sizes(r, Metric::Vector(size(gen), size(gen), size(gen)));
}

void expect_same_mesh(const BM::Indexed_tet_mesh_3& a, const BM::Indexed_tet_mesh_3& b)
{
  ASSERT_EQ(a.points.size(), b.points.size());
  for(std::size_t i = 0; i < a.points.size(); ++i)
    for(int k = 0; k < 3; ++k)
      ASSERT_TRUE(same_bits(a.points[i][k], b.points[i][k])) << "vertex " << i << " coordinate " << k;
  EXPECT_EQ(a.point_refs, b.point_refs);
  EXPECT_EQ(a.edges, b.edges);
  EXPECT_EQ(a.edge_refs, b.edge_refs);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.triangle_refs, b.triangle_refs);
  EXPECT_EQ(a.tets, b.tets);
  EXPECT_EQ(a.tet_refs, b.tet_refs);
  EXPECT_EQ(a.corners, b.corners);
}

const char* const good_header = "MeshVersionFormatted 2\nDimension 3\n";

// ---------------------------------------------------------------- MEDIT .mesh

TEST(Medit, RoundTripIsExact)
{
  BM::Indexed_tet_mesh_3 m = cube_mesh(3);
  // awkward coordinates: shortest decimal forms must still read back exactly
  m.points[1] = {{0.1, 1.0 / 3.0, -2.0 / 7.0}};
  m.points[2] = {{1e-300, -1.7976931348623157e308, 4.9406564584124654e-324}};
  m.points[3] = {{-0.0, 123456789.123456789, std::nextafter(1.0, 2.0)}};
  m.point_refs[5] = -17;
  m.edges = {{{0, 1}}, {{1, 2}}, {{5, 6}}};
  m.edge_refs = {3, -4, 2147483647};
  m.triangles = {{{0, 1, 4}}, {{2, 3, 7}}};
  m.triangle_refs = {11, -12};
  m.corners = {0, 3, 63};
  m.tet_refs[0] = -2147483647 - 1;

  const std::string path = scratch("roundtrip.mesh");
  BM::IO::write_medit(path, m);
  expect_same_mesh(BM::IO::read_medit(path), m);
  EXPECT_EQ(files_starting_with("roundtrip.mesh"), std::vector<std::string>{"roundtrip.mesh"})
    << "a temporary file was left behind";

  // the stream overloads give the same text and data
  std::stringstream ss;
  BM::IO::write_medit(ss, m);
  EXPECT_EQ(ss.str(), read_text(path));
  expect_same_mesh(BM::IO::read_medit(ss, "stream"), m);
}

TEST(Medit, EmptyRefArraysAreWrittenAsZero)
{
  BM::Indexed_tet_mesh_3 m = cube_mesh(1);
  m.point_refs.clear();
  m.tet_refs.clear();
  std::stringstream ss;
  BM::IO::write_medit(ss, m);
  const BM::Indexed_tet_mesh_3 r = BM::IO::read_medit(ss, "stream");
  EXPECT_EQ(r.point_refs, std::vector<int>(8, 0));
  EXPECT_EQ(r.tet_refs, std::vector<int>(6, 0));
  EXPECT_EQ(r.tets, m.tets);
}

TEST(Medit, ReadsHandWrittenFileWithAllSections)
{
  const BM::Indexed_tet_mesh_3 m = BM::IO::read_medit(data_file("io_all_sections.mesh"));
  const std::vector<std::array<double, 3>> points = {
    {{0, 0, 0}}, {{1, 0, 0}}, {{0, 1, 0}}, {{0, 0, 1}}, {{0.25, 0.25, 0.25}}};
  EXPECT_EQ(m.points, points);
  EXPECT_EQ(m.point_refs, (std::vector<int>{1, 2, 3, 4, -5}));
  EXPECT_EQ(m.edges, (std::vector<std::array<int, 2>>{{{0, 1}}}));
  EXPECT_EQ(m.edge_refs, (std::vector<int>{7}));
  EXPECT_EQ(m.triangles, (std::vector<std::array<int, 3>>{{{0, 1, 2}}, {{0, 1, 3}}}));
  EXPECT_EQ(m.triangle_refs, (std::vector<int>{10, 11}));
  EXPECT_EQ(m.tets, (std::vector<std::array<int, 4>>{{{0, 1, 2, 4}}, {{0, 1, 3, 4}}}));
  EXPECT_EQ(m.tet_refs, (std::vector<int>{1, 2}));
  EXPECT_EQ(m.corners, (std::vector<int>{0, 1}));
}

TEST(Medit, ToleratesCrlfTabsAndMissingEnd)
{
  const std::string text = "MeshVersionFormatted 1\r\n\r\nDimension\r\n3\r\nVertices\r\n4\r\n"
                           "0 0 0 0\r\n1 0 0 0\r\n0 1 0 0\r\n0\t0\t1\t0\r\nTetrahedra 1 1 2 3 4 9\r\n";
  std::istringstream is(text);
  const BM::Indexed_tet_mesh_3 m = BM::IO::read_medit(is, "crlf");
  ASSERT_EQ(m.points.size(), 4u);
  EXPECT_EQ(m.points[3], (std::array<double, 3>{{0, 0, 1}}));
  EXPECT_EQ(m.tets, (std::vector<std::array<int, 4>>{{{0, 1, 2, 3}}}));
  EXPECT_EQ(m.tet_refs, (std::vector<int>{9}));
}

struct Bad_medit_case {
  const char* file;
  std::string text;
  int line;
  const char* needle;
};

TEST(Medit, ErrorsNameFileAndLine)
{
  const std::string h = good_header; // lines 1-2
  const std::string v4 = "Vertices\n4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n"; // lines 3-8
  const std::vector<Bad_medit_case> cases = {
    {"truncated_eof.mesh", h + "Vertices\n3\n0 0 0 0\n1 0 0 0\n", 6, "end of file"},
    {"truncated_end.mesh", h + "Vertices\n3\n0 0 0 0\n1 0 0 0\nEnd\n", 7, "ends early"},
    {"truncated_tets.mesh", h + v4 + "Tetrahedra\n2\n1 2 3 4 1\n1 2 3\n", 12, "end of file"},
    {"index_high.mesh", h + v4 + "Tetrahedra\n1\n1 2 3 9 1\nEnd\n", 11, "out of range"},
    {"index_zero.mesh", h + v4 + "Triangles\n1\n0 2 3 1\nEnd\n", 11, "out of range"},
    {"edge_index.mesh", h + v4 + "Edges 1\n1 5 0\nEnd\n", 10, "out of range"},
    {"corner_index.mesh", h + v4 + "Corners 1\n-1\nEnd\n", 10, "out of range"},
    {"dimension.mesh", "MeshVersionFormatted 2\n\nDimension 2\n", 3, "Dimension 2"},
    {"version.mesh", "MeshVersionFormatted 3\nDimension 3\n", 1, "MeshVersionFormatted 3"},
    {"garbage_coordinate.mesh", h + "Vertices\n1\n0 0.5x 0 0\n", 5, "0.5x"},
    {"garbage_ref.mesh", h + "Vertices\n1\n0 0 0 1.5\n", 5, "1.5"},
    {"garbage_top.mesh", h + v4 + "@@@\nEnd\n", 9, "@@@"},
    {"nan.mesh", h + "Vertices\n2\n0 0 0 0\n0 nan 0 0\n", 6, "not finite"},
    {"inf.mesh", h + "Vertices\n1\n0 0 1e999 0\n", 5, "1e999"},
    {"no_vertices.mesh", h + "\nEnd\n", 4, "no Vertices"},
    {"no_dimension.mesh", "MeshVersionFormatted 2\nVertices\n0\n", 2, "before Dimension"},
    {"not_medit.off", "OFF\n4 4 0\n", 1, "MeshVersionFormatted"},
    {"empty.mesh", "", 1, "empty"},
    {"tets_first.mesh", h + "Tetrahedra\n0\n" + v4, 3, "before the Vertices"},
    {"twice.mesh", h + v4 + v4, 9, "second Vertices"},
    {"extra_numbers.mesh", h + v4 + "Tetrahedra\n1\n1 2 3 4 1\n2 3 4 1 1\nEnd\n", 12, "unexpected number"},
    {"negative_count.mesh", h + "Vertices\n-2\n", 4, "invalid number of entries"},
    {"huge_count.mesh", h + "Vertices\n2000000000\n0 0 0 0\n", 4, "too short"},
  };
  for(const Bad_medit_case& c : cases) {
    SCOPED_TRACE(c.file);
    const std::string path = scratch(c.file);
    write_text(path, c.text);
    expect_error<BM::Invalid_file>([&] { BM::IO::read_medit(path); },
                                   {path + ":" + std::to_string(c.line) + ":", c.needle});
  }
}

TEST(Medit, MissingFileIsNamed)
{
  const std::string path = scratch("does_not_exist.mesh");
  expect_error<BM::Invalid_file>([&] { BM::IO::read_medit(path); }, {path, "cannot open"});
}

TEST(Medit, FailedWriteLeavesNoPartialFile)
{
  const std::string path = scratch("keep.mesh");
  write_text(path, "previous content");
  BM::Indexed_tet_mesh_3 bad = cube_mesh(1);
  bad.tets[3][2] = 8; // out of range
  expect_error<BM::Invalid_input>([&] { BM::IO::write_medit(path, bad); }, {"tetrahedron 3", "out of range"});
  bad = cube_mesh(1);
  bad.tet_refs.pop_back();
  expect_error<BM::Invalid_input>([&] { BM::IO::write_medit(path, bad); }, {"reference array"});
  bad = cube_mesh(1);
  bad.points[2][1] = std::numeric_limits<double>::quiet_NaN();
  expect_error<BM::Invalid_input>([&] { BM::IO::write_medit(path, bad); }, {"vertex 2"});
  EXPECT_EQ(read_text(path), "previous content");
  EXPECT_EQ(files_starting_with("keep.mesh"), std::vector<std::string>{"keep.mesh"});

  const std::string unwritable = scratch("no_such_directory/out.mesh");
  expect_error<BM::Invalid_file>([&] { BM::IO::write_medit(unwritable, cube_mesh(1)); }, {unwritable});
  EXPECT_FALSE(fs::exists(unwritable));
}

TEST(Medit, ReadsLargeFile)
{
  // 20^3 cubes = 48000 tets: exercises the buffered reader and writer
  const BM::Indexed_tet_mesh_3 m = cube_mesh(20, 3.0);
  const std::string path = scratch("large.mesh");
  BM::IO::write_medit(path, m);
  expect_same_mesh(BM::IO::read_medit(path), m);
}

// ---------------------------------------------------------------- MEDIT .sol

TEST(Sol, RoundTripIsExact)
{
  std::mt19937 gen(12345);
  std::vector<Metric> metrics;
  for(int i = 0; i < 200; ++i)
    metrics.push_back(random_metric(gen));
  metrics.push_back(Metric::isotropic(1e-5));
  const std::string path = scratch("roundtrip.sol");
  BM::IO::write_sol(path, metrics);
  const std::vector<Metric> r = BM::IO::read_sol(path, metrics.size());
  ASSERT_EQ(r.size(), metrics.size());
  for(std::size_t i = 0; i < r.size(); ++i)
    EXPECT_TRUE(same_bits(r[i], metrics[i])) << "metric " << i;
  EXPECT_EQ(files_starting_with("roundtrip.sol"), std::vector<std::string>{"roundtrip.sol"});
  // 0 = no count check
  EXPECT_EQ(BM::IO::read_sol(path).size(), metrics.size());
}

TEST(Sol, WritesLowerTriangleRowByRow)
{
  const Metric m = Metric::from_entries(4, 0.1, 0.2, 5, 0.3, 6); // m11 m12 m13 m22 m23 m33
  std::stringstream ss;
  BM::IO::write_sol(ss, {m});
  std::string word;
  std::vector<std::string> words;
  while(ss >> word)
    words.push_back(word);
  // MeshVersionFormatted 2 Dimension 3 SolAtVertices 1 1 3 <6 values> End
  ASSERT_EQ(words.size(), 15u);
  EXPECT_EQ(words[4], "SolAtVertices");
  EXPECT_EQ(words[5], "1");
  EXPECT_EQ(words[6], "1");
  EXPECT_EQ(words[7], "3");
  EXPECT_EQ((std::vector<std::string>(words.begin() + 8, words.begin() + 14)),
            (std::vector<std::string>{"4", "0.1", "5", "0.2", "0.3", "6"}));
}

TEST(Sol, ReadsMeditOrderAndScalarSizes)
{
  const std::string path = scratch("order.sol");
  write_text(path, "MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n2\n1 3\n"
                   "4 0.1 5 0.2 0.3 6\n1 0 1 0 0 1\nEnd\n");
  const std::vector<Metric> r = BM::IO::read_sol(path, 2);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_TRUE(r[0] == Metric::from_entries(4, 0.1, 0.2, 5, 0.3, 6));
  EXPECT_EQ(r[0](1, 0), 0.1);
  EXPECT_EQ(r[0](2, 0), 0.2);
  EXPECT_EQ(r[0](2, 1), 0.3);
  EXPECT_TRUE(r[1] == Metric());

  const std::string scalar = scratch("scalar.sol");
  write_text(scalar, "MeshVersionFormatted 1\nDimension 3\nSolAtVertices 3 1 1\n0.5\n2\n1\nEnd\n");
  const std::vector<Metric> s = BM::IO::read_sol(scalar, 3);
  ASSERT_EQ(s.size(), 3u);
  EXPECT_TRUE(s[0] == Metric(4 * Metric::Matrix::Identity()));
  EXPECT_TRUE(s[1] == Metric(0.25 * Metric::Matrix::Identity()));
  EXPECT_TRUE(s[2] == Metric());
}

TEST(Sol, InvalidMetricsNameFileLineAndVertex)
{
  const std::string head = "MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n3\n1 3\n"; // lines 1-5
  const std::string ok = "1 0 1 0 0 1\n";
  struct Case {
    const char* file;
    std::string text;
    std::string needle;
  };
  const std::vector<Case> cases = {
    {"not_spd.sol", head + ok + "1 2 1 0 0 1\n" + ok, "positive definite"},
    {"negative.sol", head + ok + ok + "1 0 1 0 0 -1\n", "positive definite"},
    {"nan.sol", head + ok + "1 0 nan 0 0 1\n" + ok, "NaN"},
    {"zero.sol", head + ok + "0 0 0 0 0 0\n" + ok, "zero"},
    {"scalar_negative.sol", "MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n3\n1 1\n1\n-2\n1\n", "positive"},
  };
  const int expected_vertex[] = {2, 3, 2, 2, 2};
  const int expected_line[] = {7, 8, 7, 7, 7};
  for(std::size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE(cases[i].file);
    const std::string path = scratch(cases[i].file);
    write_text(path, cases[i].text);
    expect_error<BM::Invalid_metric>(
      [&] { BM::IO::read_sol(path, 3); },
      {path + ":" + std::to_string(expected_line[i]) + ": vertex " + std::to_string(expected_vertex[i]) + ":",
       cases[i].needle});
  }
}

// a .sol file that must be refused: its text, the vertex count expected, the
// line and a phrase the message must name
struct Sol_error_case {
  const char* file;
  std::string text;
  std::size_t expected;
  int line;
  std::string needle;
};

TEST(Sol, FormatErrorsAreRefused)
{
  const std::string head = "MeshVersionFormatted 2\nDimension 3\n"; // lines 1-2
  const std::vector<Sol_error_case> cases = {
    {"count.sol", head + "SolAtVertices\n3\n1 3\n1 0 1 0 0 1\n1 0 1 0 0 1\n1 0 1 0 0 1\n", 4, 4,
     "3 entries but the mesh has 4 vertices"},
    {"type.sol", head + "SolAtVertices\n1\n1 2\n1 0 0\n", 1, 5, "type 2"},
    {"fields.sol", head + "SolAtVertices\n1\n2 1 3\n1 1 0 1 0 0 1\n", 1, 5, "2 fields"},
    {"truncated.sol", head + "SolAtVertices\n2\n1 3\n1 0 1 0 0 1\n1 0 1\n", 2, 7, "end of file"},
    {"missing.sol", head + "End\n", 0, 3, "no SolAtVertices"},
    {"dimension.sol", "MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n1\n1 3\n1 0 1\n", 0, 2, "Dimension 2"},
    {"garbage.sol", head + "SolAtVertices\n1\n1 3\n1 0 1 0 x 1\n", 1, 6, "'x'"},
  };
  for(const Sol_error_case& c : cases) {
    SCOPED_TRACE(c.file);
    const std::string path = scratch(c.file);
    write_text(path, c.text);
    expect_error<BM::Invalid_file>([&] { BM::IO::read_sol(path, c.expected); },
                                   {path + ":" + std::to_string(c.line) + ":", c.needle});
  }
  const std::string missing = scratch("missing_file.sol");
  expect_error<BM::Invalid_file>([&] { BM::IO::read_sol(missing, 0); }, {missing});
}

TEST(Sol, ScalarSolutionsRoundTripAndRefuseOtherLayouts)
{
  std::vector<double> values = {0.0, -1.5, 1e-300, 3.141592653589793, -2.5e17, 0.1};
  const std::string path = scratch("scalar_roundtrip.sol");
  BM::IO::write_scalar_sol(path, values);
  EXPECT_EQ(BM::IO::read_scalar_sol(path, values.size()), values); // bitwise
  EXPECT_EQ(BM::IO::read_scalar_sol(path).size(), values.size());
  const std::string head = "MeshVersionFormatted 2\nDimension 3\n"; // lines 1-2
  const std::vector<Sol_error_case> cases = {
    {"scalar_count.sol", head + "SolAtVertices\n2\n1 1\n1\n2\n", 3, 4, "2 entries but the mesh has 3 vertices"},
    {"scalar_metric.sol", head + "SolAtVertices\n1\n1 3\n1 0 1 0 0 1\n", 1, 5, "exactly one scalar field"},
    {"scalar_two.sol", head + "SolAtVertices\n1\n2 1 1\n1 2\n", 1, 5, "exactly one scalar field"},
    {"scalar_nan.sol", head + "SolAtVertices\n2\n1 1\n1\nnan\n", 2, 7, "vertex 2: the value is not a finite number"},
    {"scalar_fields.sol", head + "SolAtVertices\n2\n0\n1\n2\n", 2, 5, "invalid number of fields 0"},
  };
  for(const Sol_error_case& c : cases) {
    SCOPED_TRACE(c.file);
    const std::string f = scratch(c.file);
    write_text(f, c.text);
    expect_error<BM::Invalid_file>([&] { BM::IO::read_scalar_sol(f, c.expected); },
                                   {f + ":" + std::to_string(c.line) + ":", c.needle});
  }
}

// ---------------------------------------------------------------- VTU

// A tiny XML reader, enough for the files we write: checks that tags are
// balanced and gives attributes and element texts.
struct Xml_element {
  std::string name;
  std::string attributes;
  std::string text;
};

std::vector<Xml_element> parse_xml(const std::string& xml)
{
  std::vector<Xml_element> elements;
  std::vector<std::size_t> open;
  std::size_t pos = 0;
  EXPECT_EQ(xml.rfind("<?xml", 0), 0u);
  while((pos = xml.find('<', pos)) != std::string::npos) {
    const std::size_t close = xml.find('>', pos);
    if(close == std::string::npos) {
      ADD_FAILURE() << "unterminated tag";
      break;
    }
    std::string tag = xml.substr(pos + 1, close - pos - 1);
    if(tag[0] == '?') {
      // prolog
    } else if(tag[0] == '/') {
      if(open.empty() || elements[open.back()].name != tag.substr(1)) {
        ADD_FAILURE() << "unbalanced closing tag " << tag;
        break;
      }
      open.pop_back();
    } else {
      const bool self_closing = tag.back() == '/';
      if(self_closing)
        tag.pop_back();
      const std::size_t space = tag.find(' ');
      Xml_element e;
      e.name = tag.substr(0, space);
      e.attributes = space == std::string::npos ? std::string() : tag.substr(space);
      elements.push_back(e);
      if(!self_closing)
        open.push_back(elements.size() - 1);
    }
    // text up to the next tag belongs to the innermost open element
    const std::size_t next = xml.find('<', close);
    if(!open.empty() && next != std::string::npos)
      elements[open.back()].text += xml.substr(close + 1, next - close - 1);
    pos = close + 1;
  }
  EXPECT_TRUE(open.empty()) << "unclosed tags";
  return elements;
}

std::string attribute(const Xml_element& e, const std::string& name)
{
  const std::string key = " " + name + "=\"";
  const std::size_t p = e.attributes.find(key);
  if(p == std::string::npos)
    return "<none>";
  const std::size_t b = p + key.size();
  return e.attributes.substr(b, e.attributes.find('"', b) - b);
}

template <typename T>
std::vector<T> numbers(const std::string& text)
{
  std::istringstream is(text);
  std::vector<T> r;
  T x;
  while(is >> x)
    r.push_back(x);
  EXPECT_TRUE(is.eof()) << "non-numeric data in a DataArray";
  return r;
}

const Xml_element& data_array(const std::vector<Xml_element>& elements, const std::string& name)
{
  for(const Xml_element& e : elements)
    if(e.name == "DataArray" && attribute(e, "Name") == name)
      return e;
  static const Xml_element none;
  ADD_FAILURE() << "no DataArray named " << name;
  return none;
}

TEST(Vtu, TetMeshHasRightCountsAndArrays)
{
  const BM::Indexed_tet_mesh_3 m = cube_mesh(2);
  std::vector<double> dihedral(m.tets.size()), height(m.points.size());
  for(std::size_t i = 0; i < dihedral.size(); ++i)
    dihedral[i] = 0.1 * static_cast<double>(i) + 1.0 / 3.0;
  for(std::size_t i = 0; i < height.size(); ++i)
    height[i] = m.points[i][2];
  const std::string path = scratch("mesh.vtu");
  BM::IO::write_vtu(path, m, {{"min_dihedral", dihedral}}, {{"height", height}, {"a<b&\"c\"", height}});
  EXPECT_EQ(files_starting_with("mesh.vtu"), std::vector<std::string>{"mesh.vtu"});

  const std::vector<Xml_element> xml = parse_xml(read_text(path));
  ASSERT_FALSE(xml.empty());
  EXPECT_EQ(xml[0].name, "VTKFile");
  EXPECT_EQ(attribute(xml[0], "type"), "UnstructuredGrid");
  const auto piece = std::find_if(xml.begin(), xml.end(), [](const Xml_element& e) { return e.name == "Piece"; });
  ASSERT_NE(piece, xml.end());
  EXPECT_EQ(attribute(*piece, "NumberOfPoints"), std::to_string(m.points.size()));
  EXPECT_EQ(attribute(*piece, "NumberOfCells"), std::to_string(m.tets.size()));

  const std::vector<long long> connectivity = numbers<long long>(data_array(xml, "connectivity").text);
  ASSERT_EQ(connectivity.size(), 4 * m.tets.size());
  for(std::size_t i = 0; i < m.tets.size(); ++i)
    for(int k = 0; k < 4; ++k)
      EXPECT_EQ(connectivity[4 * i + k], m.tets[i][k]);
  const std::vector<long long> offsets = numbers<long long>(data_array(xml, "offsets").text);
  ASSERT_EQ(offsets.size(), m.tets.size());
  for(std::size_t i = 0; i < offsets.size(); ++i)
    EXPECT_EQ(offsets[i], static_cast<long long>(4 * (i + 1)));
  EXPECT_EQ(numbers<int>(data_array(xml, "types").text), std::vector<int>(m.tets.size(), 10));
  EXPECT_EQ(numbers<int>(data_array(xml, "subdomain").text), m.tet_refs);
  EXPECT_EQ(numbers<double>(data_array(xml, "min_dihedral").text), dihedral);
  EXPECT_EQ(numbers<double>(data_array(xml, "height").text), height);
  EXPECT_EQ(numbers<double>(data_array(xml, "a&lt;b&amp;&quot;c&quot;").text), height);

  const auto points = std::find_if(xml.begin(), xml.end(), [](const Xml_element& e) { return e.name == "Points"; });
  ASSERT_NE(points, xml.end());
  const Xml_element& coordinates = *(points + 1);
  EXPECT_EQ(attribute(coordinates, "NumberOfComponents"), "3");
  const std::vector<double> xyz = numbers<double>(coordinates.text);
  ASSERT_EQ(xyz.size(), 3 * m.points.size());
  for(std::size_t i = 0; i < m.points.size(); ++i)
    for(int k = 0; k < 3; ++k)
      EXPECT_EQ(xyz[3 * i + k], m.points[i][k]);
}

TEST(Vtu, PointSetUsesVertexCells)
{
  const std::vector<std::array<double, 3>> points = {{{0, 0, 0}}, {{1, 2, 3}}, {{-1, 0.5, 1e-3}}};
  std::stringstream ss;
  BM::IO::write_vtu_points(ss, points, {{"size", {1, 2, 3}}});
  const std::vector<Xml_element> xml = parse_xml(ss.str());
  const auto piece = std::find_if(xml.begin(), xml.end(), [](const Xml_element& e) { return e.name == "Piece"; });
  ASSERT_NE(piece, xml.end());
  EXPECT_EQ(attribute(*piece, "NumberOfPoints"), "3");
  EXPECT_EQ(attribute(*piece, "NumberOfCells"), "3");
  EXPECT_EQ(numbers<long long>(data_array(xml, "connectivity").text), (std::vector<long long>{0, 1, 2}));
  EXPECT_EQ(numbers<long long>(data_array(xml, "offsets").text), (std::vector<long long>{1, 2, 3}));
  EXPECT_EQ(numbers<int>(data_array(xml, "types").text), (std::vector<int>{1, 1, 1}));
  EXPECT_EQ(numbers<double>(data_array(xml, "size").text), (std::vector<double>{1, 2, 3}));

  const std::string path = scratch("points.vtu");
  BM::IO::write_vtu_points(path, points);
  EXPECT_EQ(read_text(path).find("NumberOfCells=\"3\"") != std::string::npos, true);
}

TEST(Vtu, BadArraysAreRefusedBeforeWriting)
{
  const BM::Indexed_tet_mesh_3 m = cube_mesh(1);
  const std::string path = scratch("bad.vtu");
  expect_error<BM::Invalid_input>([&] { BM::IO::write_vtu(path, m, {{"q", std::vector<double>(5)}}); },
                                  {"'q'", "5 values", "expected 6"});
  expect_error<BM::Invalid_input>([&] { BM::IO::write_vtu(path, m, {{"subdomain", std::vector<double>(6)}}); },
                                  {"subdomain"});
  expect_error<BM::Invalid_input>(
    [&] { BM::IO::write_vtu(path, m, {}, {{"h", std::vector<double>(8, std::nan(""))}}); }, {"'h'", "finite"});
  expect_error<BM::Invalid_input>(
    [&] { BM::IO::write_vtu_points(path, {{{0, std::nan(""), 0}}}); }, {"point 0"});
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(files_starting_with("bad.vtu").empty());
}

// ---------------------------------------------------------------- triangle surfaces

const std::string tetrahedron_off = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                                    "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";

TEST(Surface, ReadsClosedTriangleSurfaces)
{
  const std::string tet = scratch("tet.off");
  write_text(tet, tetrahedron_off);
  const CGAL::Surface_mesh<Point_3> t = BM::IO::read_triangle_surface<K>(tet);
  EXPECT_EQ(t.number_of_vertices(), 4u);
  EXPECT_EQ(t.number_of_faces(), 4u);
  EXPECT_TRUE(CGAL::is_closed(t));

  // cube: 8 vertices, 12 triangles, COFF header with per-vertex colours, upper-case extension
  const std::string cube = scratch("cube.OFF");
  write_text(cube, "COFF\n8 12 0\n"
                   "0 0 0 255 0 0 255\n1 0 0 255 0 0 255\n1 1 0 255 0 0 255\n0 1 0 255 0 0 255\n"
                   "0 0 1 255 0 0 255\n1 0 1 255 0 0 255\n1 1 1 255 0 0 255\n0 1 1 255 0 0 255\n"
                   "3 0 3 2\n3 0 2 1\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n"
                   "3 2 3 7\n3 2 7 6\n3 1 2 6\n3 1 6 5\n3 0 4 7\n3 0 7 3\n");
  const CGAL::Surface_mesh<Point_3> c = BM::IO::read_triangle_surface<K>(cube);
  EXPECT_EQ(c.number_of_vertices(), 8u);
  EXPECT_EQ(c.number_of_faces(), 12u);
  EXPECT_TRUE(CGAL::is_closed(c));

  // the same tetrahedron as OBJ and as ASCII STL (corners merged)
  const std::string obj = scratch("tet.obj");
  write_text(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n");
  EXPECT_EQ(BM::IO::read_triangle_surface<K>(obj).number_of_faces(), 4u);
  const std::string stl = scratch("tet.stl");
  std::string stl_text = "solid t\n";
  const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  const char* corners[4] = {"0 0 0", "1 0 0", "0 1 0", "0 0 1"};
  for(const auto& f : faces) {
    stl_text += "facet normal 0 0 0\nouter loop\n";
    for(int v : f)
      stl_text += std::string("vertex ") + corners[v] + "\n";
    stl_text += "endloop\nendfacet\n";
  }
  write_text(stl, stl_text + "endsolid t\n");
  const CGAL::Surface_mesh<Point_3> s = BM::IO::read_triangle_surface<K>(stl);
  EXPECT_EQ(s.number_of_vertices(), 4u);
  EXPECT_EQ(s.number_of_faces(), 4u);
}

TEST(Surface, InconsistentOrientationIsRepaired)
{
  const std::string path = scratch("flipped.off");
  // last face flipped with respect to tetrahedron_off
  write_text(path, "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 2 3\n");
  const CGAL::Surface_mesh<Point_3> t = BM::IO::read_triangle_surface<K>(path);
  EXPECT_EQ(t.number_of_faces(), 4u);
  EXPECT_TRUE(CGAL::is_closed(t));
  EXPECT_TRUE(CGAL::is_valid_polygon_mesh(t));
}

TEST(Surface, BadSurfacesAreRefusedWithTheReason)
{
  struct Case {
    const char* file;
    std::string text;
    std::vector<std::string> needles;
  };
  const std::string v4 = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  // two tetrahedra sharing only vertex 0 (pinched) / only edge 0-1
  const std::string two_tets_vertex = "OFF\n7 8 0\n" + v4 + "-1 0 0\n0 -1 0\n0 0 -1\n"
                                      "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n"
                                      "3 0 4 5\n3 0 6 4\n3 4 6 5\n3 0 5 6\n";
  const std::string two_tets_edge = "OFF\n6 8 0\n" + v4 + "0 -1 0\n0 0 -1\n"
                                    "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n"
                                    "3 0 1 4\n3 0 5 1\n3 1 5 4\n3 0 4 5\n";
  const std::vector<Case> cases = {
    {"open.off", "OFF\n4 3 0\n" + v4 + "3 0 2 1\n3 0 1 3\n3 1 2 3\n", {"not closed", "3 boundary edges"}},
    {"quads.off",
     "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
     "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 2 3 7 6\n4 1 2 6 5\n4 0 4 7 3\n",
     {"face 0", "4 vertices", "only triangle"}},
    {"mixed.off", "OFF\n5 2 0\n" + v4 + "1 1 1\n3 0 1 2\n5 0 1 2 3 4\n", {"face 1", "5 vertices"}},
    {"empty.off", "OFF\n0 0 0\n", {"no faces"}},
    {"degenerate.off", "OFF\n4 4 0\n" + v4 + "3 0 0 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n", {"face 0", "degenerate"}},
    {"edge_shared.off", two_tets_edge, {"non-manifold", "1 edges", "more than two faces"}},
    {"pinched.off", two_tets_vertex, {"non-manifold"}},
    {"garbage.off", "OFF\n4 4 0\n0 0 zero\n", {"cannot parse"}},
    {"tet.xyz", tetrahedron_off, {"unknown surface file extension 'xyz'"}},
    {"noextension", tetrahedron_off, {"unknown surface file extension"}},
  };
  for(const Case& c : cases) {
    SCOPED_TRACE(c.file);
    const std::string path = scratch(c.file);
    write_text(path, c.text);
    std::vector<std::string> needles = c.needles;
    needles.push_back(path + ":");
    expect_error<BM::Invalid_file>([&] { BM::IO::read_triangle_surface<K>(path); }, needles);
  }
  const std::string missing = scratch("missing.off");
  expect_error<BM::Invalid_file>([&] { BM::IO::read_triangle_surface<K>(missing); }, {missing, "cannot open"});
}

// The tetrahedron and the unit cube of the format tests, faces oriented outward.
const double tet_points[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
const int tet_faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
const double cube_points[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                  {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
const int cube_faces[12][3] = {{0, 3, 2}, {0, 2, 1}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                               {2, 3, 7}, {2, 7, 6}, {1, 2, 6}, {1, 6, 5}, {0, 4, 7}, {0, 7, 3}};

// Reads `path` and expects the tetrahedron (cube = false) or the cube: same
// points (as a set), same counts, outward, volume 1/6 or 1.
void expect_tet_or_cube(const std::string& path, bool cube)
{
  SCOPED_TRACE(path);
  BM::IO::Surface_check_report report;
  CGAL::Surface_mesh<Point_3> m;
  try {
    m = BM::IO::read_triangle_surface<K>(path, &report);
  } catch(const std::exception& e) {
    FAIL() << e.what();
  }
  const std::size_t nv = cube ? 8 : 4, nf = cube ? 12 : 4;
  EXPECT_EQ(m.number_of_vertices(), nv);
  EXPECT_EQ(m.number_of_faces(), nf);
  EXPECT_FALSE(report.reoriented_faces);
  EXPECT_EQ(report.reversed_components, 0u);
  EXPECT_NEAR(report.volume, cube ? 1.0 : 1.0 / 6, 1e-12);
  std::vector<std::array<double, 3>> got, expected;
  for(auto v : m.vertices())
    got.push_back({{m.point(v).x(), m.point(v).y(), m.point(v).z()}});
  for(std::size_t i = 0; i < nv; ++i) {
    const double* p = cube ? cube_points[i] : tet_points[i];
    expected.push_back({{p[0], p[1], p[2]}});
  }
  std::sort(got.begin(), got.end());
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(got, expected);
}

// Little- or big-endian bytes of a scalar.
template <typename T>
void put(std::string& s, T value, bool big_endian)
{
  typedef typename std::conditional<
      sizeof(T) == 1, std::uint8_t,
      typename std::conditional<sizeof(T) == 2, std::uint16_t,
                                typename std::conditional<sizeof(T) == 4, std::uint32_t, std::uint64_t>::type>::type>::type
      U;
  U u;
  std::memcpy(&u, &value, sizeof u);
  for(std::size_t i = 0; i < sizeof u; ++i)
    s += static_cast<char>((u >> (8 * (big_endian ? sizeof u - 1 - i : i))) & 0xff);
}

// An OFF file of the tetrahedron: `keyword`, then every vertex line gets
// `vertex_extra`, every face line `face_extra`; coordinates times `w` with
// `w` written as a fourth coordinate if `homogeneous`.
std::string tet_off(const std::string& keyword, const std::string& vertex_extra, const std::string& face_extra,
                    bool homogeneous = false, const std::string& eol = "\n")
{
  std::ostringstream o;
  o << keyword << eol << "4 4 0" << eol;
  for(const auto& p : tet_points) {
    const double w = homogeneous ? 2 : 1;
    o << p[0] * w << ' ' << p[1] * w << ' ' << p[2] * w << (homogeneous ? " 2" : "") << vertex_extra << eol;
  }
  for(const auto& f : tet_faces)
    o << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << face_extra << eol;
  return o.str();
}

std::string binary_stl(const double (*points)[3], const int (*faces)[3], std::size_t n, const std::string& header)
{
  std::string b = header;
  b.resize(80, ' ');
  put(b, std::uint32_t(n), false);
  for(std::size_t f = 0; f < n; ++f) {
    for(int k = 0; k < 3; ++k)
      put(b, 0.0f, false); // normal
    for(int k = 0; k < 3; ++k)
      for(int c = 0; c < 3; ++c)
        put(b, float(points[faces[f][k]][c]), false);
    put(b, std::uint16_t(0), false);
  }
  return b;
}

// A binary PLY cube with an element before the vertices, extra vertex and
// face properties, coordinates of three types and an element after the faces.
std::string binary_ply_cube(bool big_endian, const char* indices_name = "vertex_indices")
{
  std::string h = std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
                  " 1.0\ncomment written by test_io\nobj_info cube\n"
                  "element material 2\nproperty uchar red\nproperty list uchar float coefficients\n"
                  "element vertex 8\nproperty float x\nproperty uint8 confidence\nproperty double y\n"
                  "property short z\nproperty list int ushort neighbours\n"
                  "element face 12\nproperty int8 tag\nproperty list uchar uint " +
                  indices_name + "\nproperty float32 quality\nelement edge 1\nproperty int vertex1\nproperty int32 vertex2\n"
                                 "end_header\n";
  std::string b = h;
  for(int i = 0; i < 2; ++i) {
    put(b, std::uint8_t(200), big_endian);
    put(b, std::uint8_t(2), big_endian);
    put(b, 0.5f, big_endian);
    put(b, -1.5f, big_endian);
  }
  for(const auto& p : cube_points) {
    put(b, float(p[0]), big_endian);
    put(b, std::uint8_t(7), big_endian);
    put(b, double(p[1]), big_endian);
    put(b, std::int16_t(p[2]), big_endian);
    put(b, std::int32_t(1), big_endian);
    put(b, std::uint16_t(3), big_endian);
  }
  for(const auto& f : cube_faces) {
    put(b, std::int8_t(-1), big_endian);
    put(b, std::uint8_t(3), big_endian);
    for(int k = 0; k < 3; ++k)
      put(b, std::uint32_t(f[k]), big_endian);
    put(b, 0.25f, big_endian);
  }
  put(b, std::int32_t(0), big_endian);
  put(b, std::int32_t(1), big_endian);
  return b;
}

TEST(Surface, ReadsEveryFormatAndVariant)
{
  struct Case {
    const char* file;
    std::string text;
    bool cube;
  };
  std::vector<Case> cases = {
    {"plain.off", tetrahedron_off, false},
    {"comments_face_colours.off",
     "# written by hand\nOFF # keyword\n\n4 4 0 # vertices faces edges\n# the vertices\n" + [] {
       std::string v;
       for(const auto& p : tet_points)
         v += std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "   # a vertex\n";
       return v;
     }() + "3 0 2 1 255 0 0\n3 0 1 3 0.5 0.5 0.5 1\n\n# faces\n3 1 2 3 7\n3 0 3 2\n# end\n",
     false},
    {"colours.off", tet_off("COFF", " 255 0 0 255", ""), false},
    {"colour_index.off", tet_off("COFF", " 3", ""), false},
    {"normals.off", tet_off("NOFF", " 0 0 1", ""), false},
    {"normals_colours.off", tet_off("CNOFF", " 0 0 1 0.1 0.2 0.3 1", " 255 255 0"), false},
    {"texture.off", tet_off("STOFF", " 0.5 0.25", ""), false},
    {"homogeneous.off", tet_off("4OFF", "", "", true), false},
    {"dimension.off", tet_off("nOFF\n3", "", ""), false},
    {"crlf_counts_on_keyword_line.off", [] {
       std::string t = tet_off("OFF", "", "", false, "\r\n");
       return t.replace(t.find("\r\n"), 2, " "); // "OFF 4 4 0\r\n..."
     }(),
     false},
    {"no_keyword.off", tetrahedron_off.substr(4), false},
    {"slashes_negative.obj",
     "# tetrahedron\nmtllib t.mtl\no tet\ng all\nv 0 0 0\nv 1 0 0 1.0\nv 0 1 0\nv 0 0 1\n"
     "vt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\ns off\nusemtl red\n"
     "f 1/1/1 3/3/1 2/2/1\nf 1//1 2//1 4//1\nf -3/1 -2/2 -1/3\nf -4 -1 -2 # relative\n",
     false},
    {"binary.stl", binary_stl(tet_points, tet_faces, 4, "binary tetrahedron"), false},
    {"binary_header_solid.stl", binary_stl(tet_points, tet_faces, 4, "solid but binary"), false},
    {"binary_cube.stl", binary_stl(cube_points, cube_faces, 12, ""), true},
    {"upper_case_two_solids.stl", [] {
       std::string t = "SOLID cube\r\n";
       for(int f = 0; f < 12; ++f) {
         if(f == 6)
           t += "ENDSOLID cube\r\nsolid second half\r\n";
         t += "  FACET NORMAL 0 0 0\r\n    OUTER LOOP\r\n";
         for(int k = 0; k < 3; ++k) {
           const double* p = cube_points[cube_faces[f][k]];
           t += "      VERTEX " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) +
                "\r\n";
         }
         t += "    ENDLOOP\r\n  ENDFACET\r\n";
       }
       return t + "ENDSOLID\r\n";
     }(),
     true},
    {"ascii.ply",
     "ply\nformat ascii 1.0\ncomment extra properties and elements\nelement vertex 4\n"
     "property float x\nproperty float y\nproperty double z\nproperty uchar red\nproperty list uchar float extra\n"
     "element face 4\nproperty list uchar int vertex_indices\nproperty int flags\n"
     "element edge 2\nproperty int vertex1\nproperty int vertex2\nend_header\n"
     "0 0 0 255 0\n1 0 0 255 2 0.5 0.5\n0 1 0 0 1 7\n0 0 1 0 0\n"
     "3 0 2 1 0\n3 0 1 3 0\n3 1 2 3 1\n3 0 3 2 1\n0 1\n1 2\n",
     false},
    {"little_endian.ply", binary_ply_cube(false), true},
    {"big_endian.ply", binary_ply_cube(true, "vertex_index"), true},
  };
  for(const Case& c : cases) {
    const std::string path = scratch(c.file);
    write_text(path, c.text);
    expect_tet_or_cube(path, c.cube);
  }
  // the existing tetrahedron as ASCII STL with every corner written 3 times
  // gives 4 vertices: checked in ReadsClosedTriangleSurfaces
}

TEST(Surface, MalformedAndTruncatedFilesAreRefusedWithThePlace)
{
  struct Case {
    const char* file;
    std::string text;
    std::vector<std::string> needles;
  };
  const std::string v4 = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  const std::string f4 = "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";
  const std::string ascii_ply = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                                "property float z\nelement face 4\nproperty list uchar int vertex_indices\n"
                                "end_header\n" + v4 + f4;
  const std::string cube_le = binary_ply_cube(false);
  const std::string ascii_stl = [] {
    std::string t = "solid t\n";
    for(const auto& f : tet_faces) {
      t += "facet normal 0 0 0\nouter loop\n";
      for(int v : f)
        t += "vertex " + std::to_string(tet_points[v][0]) + " " + std::to_string(tet_points[v][1]) + " " +
             std::to_string(tet_points[v][2]) + "\n";
      t += "endloop\nendfacet\n";
    }
    return t + "endsolid t\n";
  }();
  // binary PLY whose only face announces 2^32 - 1 indices
  std::string huge_list = "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
                          "property float y\nproperty float z\nelement face 1\n"
                          "property list uint int vertex_indices\nend_header\n";
  for(int k = 0; k < 3; ++k)
    put(huge_list, 1.0f, false);
  put(huge_list, std::uint32_t(0xffffffffu), false);
  put(huge_list, std::int32_t(0), false);
  std::string negative_index = binary_ply_cube(false);
  {
    negative_index.replace(negative_index.find("uchar uint"), 10, "uchar int"); // signed indices
    // first index of the first face (after the header, 2 materials of 10
    // bytes, 8 vertices of 21 bytes, the tag and the count of face 0)
    const std::size_t at = negative_index.find("end_header\n") + 11 + 2 * 10 + 8 * 21 + 2;
    std::string minus_one;
    put(minus_one, std::int32_t(-1), false);
    negative_index.replace(at, 4, minus_one);
  }
  std::string nan_ply = binary_ply_cube(false);
  {
    std::string nan;
    put(nan, std::numeric_limits<float>::quiet_NaN(), false);
    nan_ply.replace(nan_ply.find("end_header\n") + 11 + 2 * 10 + 21, 4, nan); // x of vertex 1
  }
  const std::vector<Case> cases = {
    // the classes that crashed, hung or exhausted memory in CGAL 5.5's readers
    {"property_first.ply", "ply\nformat ascii 1.0\nproperty float x\nelement vertex 1\nend_header\n0\n",
     {"cannot parse as ply", "line 3", "'property' before any 'element'"}},
    {"colour_token.off", "COFF\n4 4 0\n0 0 0 abc\n1 0 0 1 0 0 1\n0 1 0 1 0 0 1\n0 0 1 1 0 0 1\n" + f4,
     {"cannot parse as off", "line 3", "unexpected 'abc' after the coordinates of vertex 0"}},
    {"colour_count.off", "COFF 5 4 1 5 4\n5 1 2 3 4 5\n1 2 3\n4 5 6\n7 8 9\n1 1 1\n",
     {"cannot parse as off", "line 1", "unexpected '5' after the counts"}},
    {"huge_list.ply", huge_list, {"cannot parse as ply", "binary_little_endian", "announces 4294967295 entries"}},
    {"truncated_header.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty float x\nprop",
     {"cannot parse as ply", "no 'end_header'"}},
    {"huge_counts.off", "OFF\n2000000000 2000000000 0\n0 0 0\n",
     {"cannot parse as off", "line 2", "announces 2000000000 vertices and 2000000000 faces, more than the"}},
    {"count_1e308.off", "OFF\n1e308 4 0\n" + v4 + f4, {"line 2", "expected the vertex count", "'1e308'"}},
    {"count_negative.off", "OFF\n4 -3 0\n" + v4 + f4, {"line 2", "expected the face count", "'-3'"}},
    {"face_size_negative.off", "OFF\n4 4 0\n" + v4 + "-3 0 1 2\n" + f4.substr(8),
     {"line 7", "expected the number of vertices of face 0", "'-3'"}},
    {"face_size_1e308.off", "OFF\n4 4 0\n" + v4 + "3 0 2 1\n1e308 0 1 3\n" + f4.substr(16),
     {"line 8", "vertices of face 1", "'1e308'"}},
    {"index_negative.off", "OFF\n4 4 0\n" + v4 + "3 0 -3 1\n" + f4.substr(8),
     {"line 7", "vertex indices for face 0", "'-3'"}},
    {"index_overflow.off", "OFF\n4 4 0\n" + v4 + "3 0 1 18446744073709551616\n" + f4.substr(8),
     {"line 7", "'18446744073709551616'"}},
    {"index_out_of_range.off", "OFF\n4 4 0\n" + v4 + "3 0 2 4\n" + f4.substr(8),
     {"line 7", "face 0 (0-based) has vertex index 4 out of range [0, 4)"}},
    {"face_too_long.off", "OFF\n4 4 0\n" + v4 + "4000000000 0 1 2\n" + f4.substr(8),
     {"line 7", "announces 4000000000 vertices, more than its line holds"}},
    {"binary.off", "OFF BINARY\n\x00\x00\x00\x04", {"cannot parse as off", "binary OFF is not supported"}},
    {"bad_keyword.off", "MESH\n4 4 0\n" + v4 + f4, {"line 1", "expected an OFF header keyword", "'MESH'"}},
    {"dimension_4.off", "nOFF 4\n4 4 0\n", {"line 1", "dimension 4 is not supported"}},
    {"w_zero.off", "4OFF\n4 4 0\n0 0 0 0\n" + v4 + f4, {"line 3", "homogeneous coordinate w = 0"}},
    {"infinite.off", "OFF\n4 4 0\n0 0 0\n1e999 0 0\n0 1 0\n0 0 1\n" + f4,
     {"line 4", "vertex 1 (0-based) has a non-finite coordinate '1e999'"}},
    {"extra_counts.off", "OFF\n4 4 0 9\n" + v4 + f4, {"line 2", "unexpected '9' after the counts"}},
    {"comments_only.off", "# nothing\n\n", {"cannot parse as off", "no OFF header"}},
    {"bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", {"cannot parse as obj", "line 4", "malformed face vertex 'x'"}},
    {"zero_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", {"line 4", "vertex index 0", "start at 1"}},
    {"relative_before_first.obj", "v 0 0 0\nv 1 0 0\nf 1 2 -3\n", {"line 3", "relative vertex index -3", "before the first"}},
    {"index_out_of_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n",
     {"face 0 (0-based) refers to vertex 4 (1-based), but the file defines 3 vertices"}},
    {"bad_coordinate.obj", "v 0 0 zero\n", {"line 1", "expected 3 coordinates for vertex 1", "'zero'"}},
    {"nan.obj", "v 0 nan 0\n", {"line 1", "non-finite coordinate 'nan'"}},
    {"no_solid.stl", "facet normal 0 0 0\n", {"cannot parse as stl", "does not start with 'solid'", "84-byte header"}},
    {"text_not_solid.stl", std::string(200, 'x'), {"does not start with 'solid'", "bytes, but the file has 200 bytes"}},
    {"bad_keyword.stl", "solid t\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendfacet\n",
     {"line 7", "expected 'endloop' in facet 0", "'endfacet'"}},
    {"bad_number.stl", "solid t\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 one 0\n",
     {"line 6", "expected a vertex coordinate in facet 0", "'one'"}},
    {"after_endsolid.stl", ascii_stl + "garbage\n", {"unexpected 'garbage' after 'endsolid'"}},
    {"unknown_type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty real x\nend_header\n",
     {"line 4", "unknown property type 'real'"}},
    {"no_format.ply", "ply\nelement vertex 0\nend_header\n", {"no 'format' line"}},
    {"no_y.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float z\nend_header\n0 0\n",
     {"line 3", "no property 'y'"}},
    {"no_indices.ply", "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
                       "element face 0\nproperty list uchar int vertex_list\nend_header\n",
     {"line 7", "no 'vertex_indices'"}},
    {"huge_element.ply", "ply\nformat binary_big_endian 1.0\nelement vertex 3000000000\nproperty float x\n"
                         "property float y\nproperty float z\nend_header\n" + std::string(24, '\0'),
     {"line 3", "element 'vertex' announces 3000000000 items of at least 12 bytes, more than the 24 bytes"}},
    {"negative_index.ply", negative_index, {"binary_little_endian", "face 0 (0-based) has a negative vertex index -1"}},
    {"bad_token.ply", ascii_ply.substr(0, ascii_ply.size() - 8) + "3 0 x 2\n",
     {"line 17", "expected a vertex index", "'x'"}},
    // caught after parsing, by read_triangle_surface() itself
    {"index_out_of_range.ply", ascii_ply.substr(0, ascii_ply.size() - 8) + "3 0 3 9\n",
     {"face 3 (0-based) has vertex index 9 out of range [0, 4)"}},
    {"nan_vertex.ply", nan_ply, {"vertex 1 (0-based) has a non-finite coordinate"}},
    // truncated files of every format
    {"no_faces.off", "OFF\n4 4 0\n" + v4 + f4.substr(0, 16), {"cannot parse as off", "unexpected end of file", "face 2"}},
    {"no_vertices.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n# the file was cut here\n", {"cannot parse as off", "unexpected end of file", "vertex 2"}},
    {"cut_counts.off", "OFF\n4", {"unexpected end of file", "counts line"}},
    {"cut.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0", {"cannot parse as obj", "line 4", "got only 2"}},
    {"cut_ascii.stl", ascii_stl.substr(0, ascii_stl.find("vertex", ascii_stl.find("facet", 200)) + 7),
     {"cannot parse as stl", "unexpected end of file", "in facet 2"}},
    {"cut_end.stl", ascii_stl.substr(0, ascii_stl.size() - 11), {"unexpected end of file", "'endsolid'"}},
    {"cut_binary.stl", binary_stl(tet_points, tet_faces, 4, "tet").substr(0, 84 + 50 * 3 + 20),
     {"cannot parse as stl", "announces 4 triangles", "84 + 50 x 4 = 284 bytes, but the file has 254 bytes"}},
    {"short_binary.stl", std::string(40, '\0'), {"40 bytes, shorter than the 84-byte header"}},
    {"cut_ascii.ply", ascii_ply.substr(0, ascii_ply.size() - 2),
     {"cannot parse as ply", "unexpected end of file in element 'face' item 3 (0-based) of 4"}},
    {"cut_list.ply", ascii_ply.substr(0, ascii_ply.size() - 5),
     {"line 17", "the list 'vertex_indices' of element 'face' item 3 (0-based) of 4 announces 3 entries, more than"}},
    {"cut_vertices.ply", ascii_ply.substr(0, ascii_ply.find("end_header\n") + 11 + 8),
     {"line 3", "element 'vertex' announces 4 items of at least 6 bytes, more than the 8 bytes of data hold"}},
    {"cut_binary.ply", cube_le.substr(0, cube_le.size() - 2),
     {"cannot parse as ply", "binary_little_endian data: the file ends inside element 'edge' item 0 (0-based) of 1",
      "property 'vertex2'"}},
    {"cut_binary_faces.ply", cube_le.substr(0, cube_le.find("end_header\n") + 11 + 2 * 10 + 8 * 21 + 16),
     {"line 14", "element 'face' announces 12 items of at least 6 bytes", "after the elements before it"}},
    {"cut_header.ply", cube_le.substr(0, cube_le.find("end_header")), {"cannot parse as ply", "no 'end_header'"}},
    {"empty.ply", "", {"cannot parse as ply", "empty file"}},
    {"empty.stl", "", {"cannot parse as stl", "empty file"}},
    {"empty.obj", "", {"the surface has no faces"}},
  };
  for(const Case& c : cases) {
    SCOPED_TRACE(c.file);
    const std::string path = scratch(c.file);
    write_text(path, c.text);
    std::vector<std::string> needles = c.needles;
    needles.push_back(path + ":");
    const std::string what =
        expect_error<BM::Invalid_file>([&] { BM::IO::read_triangle_surface<K>(path); }, needles);
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  // a directory is not a file
  const std::string dir = scratch("directory.off");
  fs::create_directories(dir);
  expect_error<BM::Invalid_file>([&] { BM::IO::read_triangle_surface<K>(dir); }, {dir + ":", "cannot"});
}

TEST(Surface, ParsersAllocateNoMoreThanTheFileHolds)
{
  // the counts are checked against the bytes that follow before anything
  // is reserved: none of these may throw anything but Invalid_file
  using BM::IO::Surface_file_format;
  const std::vector<std::pair<Surface_file_format, std::string>> inputs = {
    {Surface_file_format::OFF, "OFF\n999999999999 999999999999 0\n"},
    {Surface_file_format::OFF, "OFF\n18446744073709551615 1 0\n"},
    {Surface_file_format::OFF, "OFF\n1 1 0\n0 0 0\n18446744073709551615 1 2 3\n"},
    {Surface_file_format::PLY, "ply\nformat ascii 1.0\nelement vertex 18446744073709551615\nproperty float x\n"
                               "property float y\nproperty float z\nend_header\n"},
    {Surface_file_format::PLY, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                               "property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n"
                               "0 0 0 4294967295 1 2 3\n"},
    {Surface_file_format::PLY, "ply\nformat binary_little_endian 1.0\nelement nothing 18446744073709551615\n"
                               "element vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n"},
  };
  for(const auto& in : inputs) {
    SCOPED_TRACE(in.second);
    try {
      BM::IO::parse_polygon_soup(in.second.data(), in.second.size(), in.first, "memory");
    } catch(const BM::Invalid_file&) {
    } catch(const std::exception& e) {
      ADD_FAILURE() << "unexpected exception: " << e.what();
    }
  }
}

// ---------------------------------------------------------------- Interpolated_metric_field_3

std::vector<Metric> random_metrics(std::size_t n, unsigned seed)
{
  std::mt19937 gen(seed);
  std::vector<Metric> r;
  for(std::size_t i = 0; i < n; ++i)
    r.push_back(random_metric(gen));
  return r;
}

Point_3 to_point(const std::array<double, 3>& p) { return Point_3(p[0], p[1], p[2]); }

std::vector<Point_3> random_points(std::size_t n, double lo, double hi, unsigned seed)
{
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<Point_3> r;
  for(std::size_t i = 0; i < n; ++i)
    r.emplace_back(u(gen), u(gen), u(gen));
  return r;
}

TEST(InterpolatedField, ExactAtVertices)
{
  const BM::Indexed_tet_mesh_3 m = cube_mesh(4);
  const std::vector<Metric> metrics = random_metrics(m.points.size(), 7);
  const Field field(m, metrics);
  EXPECT_EQ(field.number_of_vertices(), m.points.size());
  EXPECT_EQ(field.number_of_tets(), m.tets.size());
  for(std::size_t i = 0; i < m.points.size(); ++i) {
    const Metric value = field(to_point(m.points[i]));
    EXPECT_TRUE(same_bits(value, metrics[i])) << "vertex " << i;
  }
}

TEST(InterpolatedField, ReproducesLogLinearFieldInside)
{
  // log M(x) = A0 + x A1 + y A2 + z A3, all symmetric
  std::mt19937 gen(99);
  std::uniform_real_distribution<double> u(-1, 1);
  std::array<Metric::Matrix, 4> a;
  for(Metric::Matrix& s : a) {
    for(int i = 0; i < 3; ++i)
      for(int j = 0; j < 3; ++j)
        s(i, j) = u(gen);
    s = 0.5 * (s + s.transpose()).eval();
  }
  auto log_at = [&a](double x, double y, double z) { return Metric::Matrix(a[0] + x * a[1] + y * a[2] + z * a[3]); };
  const BM::Indexed_tet_mesh_3 m = cube_mesh(3, 2.0);
  std::vector<Metric> metrics;
  for(const auto& p : m.points)
    metrics.push_back(Metric::exp(log_at(p[0], p[1], p[2])));
  const Field field(m, metrics);
  double worst = 0;
  for(const Point_3& p : random_points(2000, 0, 2, 3)) {
    ASSERT_GE(field.locate(p), 0);
    const Metric::Matrix expected = Metric::exp(log_at(p.x(), p.y(), p.z())).matrix();
    worst = std::max(worst, relative_difference(field(p).matrix(), expected));
  }
  EXPECT_LT(worst, 1e-12);
  // the test can tell: a linear interpolation of the matrices is far off at a tet centroid
  const std::array<int, 4>& t = m.tets[0];
  Metric::Matrix linear = Metric::Matrix::Zero();
  std::array<double, 3> c = {{0, 0, 0}};
  for(int v : t) {
    linear += metrics[v].matrix() / 4;
    for(int k = 0; k < 3; ++k)
      c[k] += m.points[v][k] / 4;
  }
  const Metric::Matrix expected = Metric::exp(log_at(c[0], c[1], c[2])).matrix();
  EXPECT_GT(relative_difference(linear, expected), 1e-4);
  EXPECT_LT(relative_difference(field(to_point(c)).matrix(), expected), 1e-12);
}

TEST(InterpolatedField, ConstantFieldEverywhere)
{
  const BM::Indexed_tet_mesh_3 m = cube_mesh(3);
  std::mt19937 gen(5);
  const Metric c = random_metric(gen);
  const Field field(m, std::vector<Metric>(m.points.size(), c));
  for(const Point_3& p : random_points(500, 0, 1, 8))
    EXPECT_LT(relative_difference(field(p).matrix(), c.matrix()), 1e-12);
  for(const Point_3& p : random_points(100, 1.5, 3, 9))
    EXPECT_TRUE(same_bits(field(p), c));
}

TEST(InterpolatedField, NearestVertexValueOutside)
{
  const BM::Indexed_tet_mesh_3 m = cube_mesh(3);
  const std::vector<Metric> metrics = random_metrics(m.points.size(), 11);
  const Field field(m, metrics);
  for(const Point_3& p : random_points(300, -2, 3, 13)) {
    const bool inside = p.x() >= 0 && p.x() <= 1 && p.y() >= 0 && p.y() <= 1 && p.z() >= 0 && p.z() <= 1;
    EXPECT_EQ(field.locate(p) >= 0, inside);
    if(inside)
      continue;
    std::size_t nearest = 0;
    for(std::size_t i = 1; i < m.points.size(); ++i)
      if(CGAL::squared_distance(p, to_point(m.points[i])) < CGAL::squared_distance(p, to_point(m.points[nearest])))
        nearest = i;
    EXPECT_EQ(field.nearest_vertex(p), nearest);
    EXPECT_TRUE(same_bits(field(p), metrics[nearest]));
  }
  // just outside a face: nearest vertex, not the interpolation
  const Point_3 above(1.0 / 3.0 + 1e-3, 0.5, 1.0001);
  EXPECT_LT(field.locate(above), 0);
  EXPECT_TRUE(same_bits(field(above), metrics[field.nearest_vertex(above)]));
}

TEST(InterpolatedField, LocateFindsTheContainingTetInAnIrregularMesh)
{
  // jitter the interior vertices: tets of many shapes, none axis-aligned
  BM::Indexed_tet_mesh_3 m = cube_mesh(5);
  std::mt19937 gen(41);
  std::uniform_real_distribution<double> u(-0.06, 0.06);
  for(auto& p : m.points)
    if(p[0] > 0 && p[0] < 1 && p[1] > 0 && p[1] < 1 && p[2] > 0 && p[2] < 1)
      for(int k = 0; k < 3; ++k)
        p[k] += u(gen);
  auto P = [&m](int v) { return to_point(m.points[v]); };
  for(const auto& t : m.tets)
    ASSERT_EQ(CGAL::orientation(P(t[0]), P(t[1]), P(t[2]), P(t[3])), CGAL::POSITIVE);
  const Field field(m, random_metrics(m.points.size(), 43));
  for(const Point_3& p : random_points(3000, 0, 1, 47)) {
    const int t = field.locate(p);
    ASSERT_GE(t, 0) << p; // the mesh covers the unit cube
    ASSERT_LT(static_cast<std::size_t>(t), m.tets.size());
    const auto& tet = m.tets[static_cast<std::size_t>(t)];
    // p is in (the closure of) tet number t of the *input* mesh
    for(int f = 0; f < 4; ++f) {
      std::array<Point_3, 4> q = {{P(tet[0]), P(tet[1]), P(tet[2]), P(tet[3])}};
      q[f] = p;
      EXPECT_NE(CGAL::orientation(q[0], q[1], q[2], q[3]), CGAL::NEGATIVE) << "tet " << t << " face " << f;
    }
  }
  // the vertices too, with their exact metrics
  for(std::size_t i = 0; i < m.points.size(); ++i)
    EXPECT_TRUE(same_bits(field(P(static_cast<int>(i))), field.metric_at_vertex(i)));
}

TEST(InterpolatedField, InterpolatesOnFacesAndInNonConvexMesh)
{
  // an L-shaped mesh: the 3x3x1 block of cubes without the cubes with i,j >= 1
  BM::Indexed_tet_mesh_3 m = cube_mesh(3);
  BM::Indexed_tet_mesh_3 l = m;
  l.tets.clear();
  l.tet_refs.clear();
  for(std::size_t t = 0; t < m.tets.size(); ++t) {
    std::array<double, 3> c = {{0, 0, 0}};
    for(int v : m.tets[t])
      for(int k = 0; k < 3; ++k)
        c[k] += m.points[v][k] / 4;
    if(c[0] > 1.0 / 3.0 && c[1] > 1.0 / 3.0)
      continue;
    l.tets.push_back(m.tets[t]);
  }
  const std::vector<Metric> metrics = random_metrics(l.points.size(), 17);
  const Field field(l, metrics);
  EXPECT_LT(field.locate(Point_3(0.7, 0.7, 0.5)), 0); // in the notch
  EXPECT_TRUE(same_bits(field(Point_3(0.7, 0.7, 0.5)), metrics[field.nearest_vertex(Point_3(0.7, 0.7, 0.5))]));
  EXPECT_GE(field.locate(Point_3(0.2, 0.7, 0.5)), 0);
  // on a grid plane (shared faces): continuous, no fallback to the nearest vertex
  const Point_3 on_face(1.0 / 3.0, 0.1, 0.2);
  ASSERT_GE(field.locate(on_face), 0);
  const Metric a = field(on_face);
  const Metric b = field(Point_3(1.0 / 3.0 + 1e-12, 0.1, 0.2));
  EXPECT_LT(relative_difference(a.matrix(), b.matrix()), 1e-9);
}

TEST(InterpolatedField, ConcurrentQueriesMatchSerial)
{
  const BM::Indexed_tet_mesh_3 m = cube_mesh(6);
  const Field field(m, random_metrics(m.points.size(), 21));
  const std::vector<Point_3> points = random_points(4000, -0.2, 1.2, 23);
  std::vector<Metric> serial;
  for(const Point_3& p : points)
    serial.push_back(field(p));
  const int n_threads = 4;
  std::vector<std::vector<Metric>> parallel(n_threads);
  std::vector<std::thread> threads;
  const Field copy = field; // copies share the data
  for(int t = 0; t < n_threads; ++t)
    threads.emplace_back([&, t] {
      const Field& f = (t % 2 == 0) ? field : copy;
      for(int round = 0; round < 2; ++round) {
        parallel[t].clear();
        for(std::size_t i = 0; i < points.size(); ++i)
          parallel[t].push_back(f(points[(i + static_cast<std::size_t>(t) * 997) % points.size()]));
      }
    });
  for(std::thread& th : threads)
    th.join();
  for(int t = 0; t < n_threads; ++t)
    for(std::size_t i = 0; i < points.size(); ++i)
      ASSERT_TRUE(same_bits(parallel[t][i], serial[(i + static_cast<std::size_t>(t) * 997) % points.size()]))
        << "thread " << t << " query " << i;
}

TEST(InterpolatedField, InvalidInputsAreRefused)
{
  const BM::Indexed_tet_mesh_3 m = cube_mesh(1);
  const std::vector<Metric> metrics(m.points.size());

  expect_error<BM::Invalid_input>([&] { Field(m, std::vector<Metric>(7), "bg.mesh"); },
                                  {"bg.mesh", "7 metrics", "8 background vertices"});
  BM::Indexed_tet_mesh_3 bad = m;
  bad.tets[4][1] = 8;
  expect_error<BM::Invalid_input>([&] { Field(bad, metrics, "bg.mesh"); },
                                  {"bg.mesh", "tetrahedron 4", "5 in a MEDIT file", "out of range"});
  bad = m;
  bad.tets[2] = {{0, 1, 2, 3}}; // the 4 corners of the bottom face: coplanar
  expect_error<BM::Invalid_input>([&] { Field(bad, metrics, "bg.mesh"); }, {"tetrahedron 2", "zero volume"});
  bad = m;
  bad.tets[5] = {{0, 1, 1, 7}};
  expect_error<BM::Invalid_input>([&] { Field(bad, metrics, "bg.mesh"); }, {"tetrahedron 5", "zero volume"});
  bad = m;
  bad.tets.clear();
  expect_error<BM::Invalid_input>([&] { Field(bad, metrics, "bg.mesh"); }, {"bg.mesh", "no tetrahedra"});
  expect_error<BM::Invalid_input>([&] { Field(BM::Indexed_tet_mesh_3(), {}, "bg.mesh"); },
                                  {"bg.mesh", "no vertices"});
  bad = m;
  bad.points[3][0] = std::numeric_limits<double>::infinity();
  expect_error<BM::Invalid_input>([&] { Field(bad, metrics, "bg.mesh"); }, {"vertex 3", "non-finite"});

  const Field field(m, metrics);
  expect_error<BM::Invalid_input>([&] { field(Point_3(std::nan(""), 0, 0)); }, {"non-finite point"});
}

TEST(InterpolatedField, FromFiles)
{
  const BM::Indexed_tet_mesh_3 m = cube_mesh(2);
  const std::vector<Metric> metrics = random_metrics(m.points.size(), 31);
  const std::string mesh_path = scratch("bg.mesh"), sol_path = scratch("bg.sol");
  BM::IO::write_medit(mesh_path, m);
  BM::IO::write_sol(sol_path, metrics);
  const Field field = Field::from_files(mesh_path, sol_path);
  EXPECT_EQ(field.name(), mesh_path);
  for(std::size_t i = 0; i < m.points.size(); ++i)
    EXPECT_TRUE(same_bits(field(to_point(m.points[i])), metrics[i]));

  // count mismatch names the .sol file
  const std::string short_sol = scratch("short.sol");
  BM::IO::write_sol(short_sol, std::vector<Metric>(metrics.begin(), metrics.end() - 1));
  expect_error<BM::Invalid_file>([&] { Field::from_files(mesh_path, short_sol); },
                                 {short_sol + ":6:", "26 entries", "27 vertices"});
  // a degenerate tet in the file names the .mesh file and the tet as numbered in it
  BM::Indexed_tet_mesh_3 bad = m;
  bad.tets[10] = {{0, 1, 2, 2}};
  const std::string bad_path = scratch("degenerate.mesh");
  BM::IO::write_medit(bad_path, bad);
  expect_error<BM::Invalid_input>([&] { Field::from_files(bad_path, sol_path); },
                                  {bad_path, "11 in a MEDIT file", "zero volume"});
  expect_error<BM::Invalid_file>([&] { Field::from_files(scratch("none.mesh"), sol_path); }, {"none.mesh"});
}

} // namespace
