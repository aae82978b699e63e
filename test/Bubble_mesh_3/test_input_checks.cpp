// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// The API rows of doc/Bubble_mesh_3/input_checks.md: every class of bad input
// gets its exception type and message (or its repair), the node-count guard
// refuses before any packing, and a run can be stopped (should_stop,
// time_limit) with Interrupted / Time_limit_exceeded.

#include <CGAL/make_anisotropic_mesh_3.h>

#include <CGAL/Bubble_mesh_3/IO/read_triangle_surface.h>
#include <CGAL/Bubble_mesh_3/IO/sol.h>
#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Constant_metric_field_3.h>
#include <CGAL/Function_metric_field_3.h>
#include <CGAL/Interpolated_metric_field_3.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>
#include <CGAL/boost/graph/copy_face_graph.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace {

typedef CGAL::Epick K;
typedef CGAL::Polyhedral_mesh_domain_with_features_3<K> Domain;
typedef CGAL::Surface_mesh<K::Point_3> Surface;
typedef CGAL::Bubble_mesh_3::Metric_3 Metric;
namespace BM = CGAL::Bubble_mesh_3;

const std::string bad = std::string(BUBBLE_MESH_3_TEST_DATA) + "/bad/";

// The exception's message, or "" when `f` does not throw E.
template <typename E, typename F>
std::string message_of(F&& f)
{
  try {
    f();
  } catch(const E& e) {
    return e.what();
  }
  return std::string();
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A domain from a surface file read without the reader's checks (CGAL's own
// OFF reader), as an API user would build it.
// (Domains cannot be copied.)
std::unique_ptr<Domain> domain_from_off(const std::string& path)
{
  Domain::Polyhedron poly;
  std::ifstream in(path);
  in >> poly;
  EXPECT_GT(poly.size_of_facets(), 0u) << path;
  auto d = std::make_unique<Domain>(poly);
  d->detect_features(60);
  return d;
}

// ---------------------------------------------------------------- surfaces

struct Refusal {
  const char* file;
  const char* message;
};

TEST(InputChecks, BadSurfacesAreRefusedWithTheFileAndTheProblem)
{
  const Refusal cases[] = {
    {"missing.off", "cannot open file"},
    {"empty.off", "cannot parse as off"},
    {"truncated.off", "cannot parse as off"},
    {"nan_vertex.off", "cannot parse as off"},
    {"quads.off", "face 0 (0-based) has 4 vertices; only triangle surfaces"},
    {"non_manifold_edge.off", "edges are shared by more than two faces"},
    {"non_manifold_vertex.off", "vertex copies needed to make it a manifold"},
    {"degenerate_face.off", "face 5 (0-based) has zero area"},
    {"flat.off", "the surface encloses no volume"},
    {"self_intersecting.off", "the surface intersects itself"},
  };
  for(const Refusal& c : cases) {
    const std::string path = bad + c.file;
    const std::string m = message_of<BM::Invalid_file>([&] { BM::IO::read_triangle_surface<K>(path); });
    EXPECT_TRUE(contains(m, path + ": ")) << c.file << ": " << m;
    EXPECT_TRUE(contains(m, c.message)) << c.file << ": " << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << "one line: " << m;
  }
}

TEST(InputChecks, OpenSurfaceIsRefused)
{
  // the unit cube without its last face
  const std::string path = ::testing::TempDir() + "open_cube.off";
  {
    std::ifstream in(bad + "inward_cube.off");
    std::ofstream out(path);
    std::string line;
    int n = 0;
    while(std::getline(in, line)) {
      if(line == "8 12 0")
        line = "8 11 0";
      if(++n <= 22) // header (3 lines), 8 vertices, 11 of the 12 faces
        out << line << '\n';
    }
  }
  const std::string m = message_of<BM::Invalid_file>([&] { BM::IO::read_triangle_surface<K>(path); });
  EXPECT_TRUE(contains(m, "the surface is not closed: 3 boundary edges")) << m;
}

TEST(InputChecks, OrientationIsRepairedAndReported)
{
  BM::IO::Surface_check_report r;
  Surface s = BM::IO::read_triangle_surface<K>(bad + "inward_cube.off", &r);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.reversed_components, 1u);
  EXPECT_FALSE(r.reoriented_faces);
  EXPECT_NEAR(r.volume, 1.0, 1e-12);
  EXPECT_TRUE(CGAL::Polygon_mesh_processing::is_outward_oriented(s));

  s = BM::IO::read_triangle_surface<K>(bad + "inconsistent_orientation.off", &r);
  EXPECT_TRUE(r.reoriented_faces);
  EXPECT_NEAR(r.volume, 1.0, 1e-12);
  EXPECT_TRUE(CGAL::Polygon_mesh_processing::does_bound_a_volume(s));
}

TEST(InputChecks, SeveralComponentsDisjointOrNestedAreAccepted)
{
  BM::IO::Surface_check_report r;
  BM::IO::read_triangle_surface<K>(bad + "two_cubes.off", &r);
  EXPECT_EQ(r.components, 2u);
  EXPECT_EQ(r.cavities, 0u);
  EXPECT_EQ(r.reversed_components, 0u);
  EXPECT_NEAR(r.volume, 2.0, 1e-12);

  // both cubes face out in the file: the inner one is reversed, a cavity
  BM::IO::read_triangle_surface<K>(bad + "nested_cubes.off", &r);
  EXPECT_EQ(r.components, 2u);
  EXPECT_EQ(r.cavities, 1u);
  EXPECT_EQ(r.reversed_components, 1u);
  EXPECT_NEAR(r.volume, 26.0, 1e-12);
}

TEST(InputChecks, CheckWithoutRepairRefusesOrientationAgainstNesting)
{
  // nested cubes as given (both outward): refused without repair
  Surface s;
  {
    std::ifstream in(bad + "nested_cubes.off");
    ASSERT_TRUE(CGAL::IO::read_OFF(in, s));
  }
  const std::string m = BM::IO::check_triangle_surface(s, false);
  EXPECT_TRUE(contains(m, "not oriented consistently with their nesting (1 of 2")) << m;
  // every component reversed (inward throughout) is accepted: the mesher turns it around
  Surface inward;
  {
    std::ifstream in(bad + "inward_cube.off");
    ASSERT_TRUE(CGAL::IO::read_OFF(in, inward));
  }
  EXPECT_EQ(BM::IO::check_triangle_surface(inward, false), "");
  // repaired, it passes
  EXPECT_EQ(BM::IO::check_triangle_surface(s, true), "");
  EXPECT_EQ(BM::IO::check_triangle_surface(s, false), "");
}

TEST(InputChecks, DomainSurfaceIsCheckedBeforeAnyPacking)
{
  const CGAL::Constant_metric_field_3<K> field(Metric::isotropic(0.2));
  const Refusal cases[] = {
    {"self_intersecting.off", "domain: the surface intersects itself"},
    {"degenerate_face.off", "domain: face 5 (0-based) has zero area"},
    {"flat.off", "domain: the surface encloses no volume"},
    {"nested_cubes.off", "domain: the components are not oriented consistently"},
  };
  for(const Refusal& c : cases) {
    const auto domain = domain_from_off(bad + c.file);
    BM::Meshing_report report;
    const std::string m = message_of<BM::Invalid_input>([&] {
      BM::make_indexed_anisotropic_mesh_3(*domain, field, BM::parameters::meshing_report(&report));
    });
    EXPECT_TRUE(contains(m, c.message)) << c.file << ": " << m;
    EXPECT_EQ(report.estimated_nodes, 0.0) << c.file << ": refused before the estimate";
  }
}

TEST(InputChecks, SeveralComponentsAreMeshedAsOneSubdomain)
{
  // two disjoint cubes: one valid mesh of volume 2
  const auto domain = domain_from_off(bad + "two_cubes.off");
  const CGAL::Constant_metric_field_3<K> field(Metric::isotropic(0.3));
  const BM::Indexed_tet_mesh_3 mesh =
      BM::make_indexed_anisotropic_mesh_3(*domain, field, BM::parameters::mesh_improvement(false));
  double volume = 0;
  for(const auto& t : mesh.tets) {
    const auto& a = mesh.points[t[0]];
    Eigen::Matrix3d m;
    for(int k = 0; k < 3; ++k)
      for(int i = 0; i < 3; ++i)
        m(i, k) = mesh.points[t[k + 1]][i] - a[i];
    volume += m.determinant() / 6;
  }
  EXPECT_NEAR(volume, 2.0, 1e-9);
  for(int ref : mesh.tet_refs)
    EXPECT_EQ(ref, mesh.tet_refs.front());
}

TEST(InputChecks, HollowShellGivesAC3t3WithTheShellOnly)
{
  typedef CGAL::Anisotropic_mesh_triangulation_3<Domain>::type Tr;
  typedef CGAL::Mesh_complex_3_in_triangulation_3<Tr, Domain::Corner_index, Domain::Curve_index> C3t3;
  // the reader reverses the inner cube; the domain is built from its result
  const Surface s = BM::IO::read_triangle_surface<K>(bad + "nested_cubes.off");
  Domain::Polyhedron poly;
  CGAL::copy_face_graph(s, poly);
  Domain domain(poly);
  domain.detect_features(60);
  const CGAL::Constant_metric_field_3<K> field(Metric::isotropic(0.5));
  if(!BM::internal::has_exterior_padding) {
    EXPECT_FALSE(message_of<BM::Meshing_failure>([&] { CGAL::make_anisotropic_mesh_3<C3t3>(domain, field); }).empty());
    return;
  }
  const C3t3 c3t3 = CGAL::make_anisotropic_mesh_3<C3t3>(domain, field, BM::parameters::mesh_improvement(false));
  double inside = 0;
  for(auto c = c3t3.cells_in_complex_begin(); c != c3t3.cells_in_complex_end(); ++c)
    inside += CGAL::to_double(c3t3.triangulation().tetrahedron(c).volume());
  EXPECT_NEAR(inside, 26.0, 1e-9);
  // the cavity's centre is in a padding cell (subdomain 0), not in the complex
  const auto cell = c3t3.triangulation().locate(Tr::Point(K::Point_3(1.5, 1.5, 1.5)));
  EXPECT_FALSE(c3t3.is_in_complex(cell));
}

// ------------------------------------------------------------------ metrics

TEST(InputChecks, BadMetricValuesThrowInvalidMetric)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  Metric::Matrix m = Metric::Matrix::Identity();
  m(1, 1) = nan;
  EXPECT_TRUE(contains(message_of<BM::Invalid_metric>([&] { Metric x(m, "here"); }), "here: metric has a NaN or infinite"));
  m(1, 1) = inf;
  EXPECT_TRUE(contains(message_of<BM::Invalid_metric>([&] { Metric x(m); }), "NaN or infinite"));
  m = Metric::Matrix::Identity();
  m(0, 1) = 0.5;
  EXPECT_TRUE(contains(message_of<BM::Invalid_metric>([&] { Metric x(m); }), "not symmetric"));
  EXPECT_TRUE(contains(message_of<BM::Invalid_metric>([&] { Metric::from_entries(1, 2, 0, 1, 0, 1); }),
                       "not positive definite"));
  EXPECT_TRUE(contains(message_of<BM::Invalid_metric>([&] { Metric::from_entries(-1, 0, 0, -1, 0, -1); }),
                       "not positive definite"));
  // the anisotropy bound: eigenvalue ratio 1e12, a size ratio of 1e6
  EXPECT_EQ(Metric::maximum_eigenvalue_ratio(), 1e12);
  EXPECT_EQ(message_of<BM::Invalid_metric>([&] { Metric::from_entries(1, 0, 0, 1, 0, 0.99e12); }), "");
  EXPECT_TRUE(contains(message_of<BM::Invalid_metric>([&] { Metric::from_entries(1, 0, 0, 1, 0, 1.01e12); }),
                       "too anisotropic"));
}

TEST(InputChecks, BadMetricFromAUserFunctorStopsTheRun)
{
  const auto domain = domain_from_off(bad + "inward_cube.off");
  // NaN everywhere above z = 0.5, found by the estimate (before any packing)
  auto field = CGAL::make_function_metric_field_3<K>([](const K::Point_3& p) {
    const double h = p.z() > 0.5 ? std::numeric_limits<double>::quiet_NaN() : 0.2;
    return Metric::from_entries(1 / (h * h), 0, 0, 1 / (h * h), 0, 1 / (h * h));
  });
  for(int threads : {1, 2}) {
    const std::string m = message_of<BM::Invalid_metric>([&] {
      BM::make_indexed_anisotropic_mesh_3(*domain, field, BM::parameters::number_of_threads(threads));
    });
    EXPECT_TRUE(contains(m, "NaN or infinite")) << m;
  }
}

TEST(InputChecks, BadSolFilesAreRefused)
{
  auto sol = [](const std::string& body) {
    return "MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n" + body + "End\n";
  };
  auto read = [](const std::string& text, std::size_t n) {
    std::istringstream in(text);
    return BM::IO::read_sol(in, "bg.sol", n);
  };
  const std::string ok = sol("2\n1 3\n1 0 1 0 0 1\n1 0 1 0 0 1\n");
  EXPECT_EQ(read(ok, 2).size(), 2u);
  EXPECT_TRUE(contains(message_of<BM::Invalid_file>([&] { read(ok, 3); }), "SolAtVertices has 2 entries but the mesh has 3"));
  EXPECT_TRUE(contains(message_of<BM::Invalid_file>([&] { read(sol("2\n1 2\n1 0 0\n1 0 0\n"), 2); }),
                       "field of type 2 is not a metric"));
  EXPECT_TRUE(contains(message_of<BM::Invalid_file>([&] { read(sol("2\n2 3 1\n1 0 1 0 0 1 1\n1 0 1 0 0 1 1\n"), 2); }),
                       "exactly one metric field"));
  EXPECT_TRUE(contains(message_of<BM::Invalid_file>([&] { read(sol("2\n1 3\n1 0 1 0 0 1\n1 0 1\n"), 2); }), "bg.sol:"));
  EXPECT_TRUE(contains(message_of<BM::Invalid_metric>([&] { read(sol("2\n1 3\n1 0 1 0 0 1\n1 0 nan 0 0 1\n"), 2); }),
                       "vertex 2"));
  EXPECT_TRUE(contains(message_of<BM::Invalid_metric>([&] { read(sol("2\n1 3\n1 0 1 0 0 1\n1 0 -1 0 0 1\n"), 2); }),
                       "not positive definite"));
  EXPECT_TRUE(contains(message_of<BM::Invalid_metric>([&] { read(sol("2\n1 3\n1 0 1 0 0 1\n1 0 1 0 0 1e13\n"), 2); }),
                       "too anisotropic"));
  EXPECT_TRUE(contains(message_of<BM::Invalid_metric>([&] { read(sol("2\n1 1\n0.5\n-1\n"), 2); }), "vertex 2"));
}

TEST(InputChecks, BackgroundMeshNotCoveringTheDomainIsExtendedByNearestVertex)
{
  // one background tet in the corner of the unit cube
  BM::Indexed_tet_mesh_3 bg;
  bg.points = {{{0, 0, 0}}, {{0.5, 0, 0}}, {{0, 0.5, 0}}, {{0, 0, 0.5}}};
  bg.tets = {{{0, 1, 2, 3}}};
  bg.tet_refs = {1};
  std::vector<Metric> metrics = {Metric::isotropic(0.1), Metric::isotropic(0.2), Metric::isotropic(0.3),
                                 Metric::isotropic(0.4)};
  const CGAL::Interpolated_metric_field_3<K> field(bg, metrics, "bg.mesh");
  const Surface cube = BM::IO::read_triangle_surface<K>(bad + "inward_cube.off");
  // the origin is inside (a vertex), the other seven corners are not
  EXPECT_EQ(field.number_of_points_outside(cube.points()), 7u);
  EXPECT_EQ(field(K::Point_3(2, 0, 0)), metrics[1]); // nearest vertex (0.5, 0, 0)
  EXPECT_EQ(field(K::Point_3(0, 0, 1)), metrics[3]); // nearest vertex (0, 0, 0.5)
  const CGAL::Bbox_3 b = field.bbox();
  EXPECT_NEAR(b.xmax(), 0.5, 1e-9);
  EXPECT_NEAR(b.zmin(), 0.0, 1e-9);
}

// ------------------------------------------------------------ resource guard

TEST(InputChecks, NodeEstimateAboveTheLimitIsRefusedBeforePacking)
{
  EXPECT_EQ(BM::internal::resolve_settings(CGAL::parameters::default_values()).maximum_bubbles,
            BM::default_maximum_number_of_nodes);
  const auto domain = domain_from_off(bad + "inward_cube.off");
  // h = 0.01 in the unit cube: about 1.4 million nodes, refused at a limit of 1e5
  const CGAL::Constant_metric_field_3<K> field(Metric::isotropic(0.01));
  BM::Meshing_report report;
  const auto t0 = std::chrono::steady_clock::now();
  double estimated = 0, limit = 0;
  const std::string m = message_of<BM::Invalid_input>([&] {
    try {
      BM::make_indexed_anisotropic_mesh_3(
          *domain, field, BM::parameters::maximum_number_of_bubbles(1e5).meshing_report(&report));
    } catch(const BM::Too_many_nodes& e) { // the refusal has its own type
      estimated = e.estimated();
      limit = e.limit();
      throw;
    }
  });
  EXPECT_TRUE(contains(m, "the metric asks for about")) << m;
  EXPECT_TRUE(contains(m, "more than the cap of 100000 (maximum_number_of_bubbles, --max-nodes")) << m;
  EXPECT_EQ(limit, 1e5);
  EXPECT_GT(estimated, 1e5);
  EXPECT_EQ(report.nodes[1] + report.nodes[2] + report.nodes[3], 0u) << "nothing packed";
  EXPECT_LT(BM::internal::seconds_since(t0), 30.0);
}

// ------------------------------------------------------ interruption, time

TEST(InputChecks, ShouldStopInterruptsAtTheFirstCheckPoint)
{
  const auto domain = domain_from_off(bad + "inward_cube.off");
  const CGAL::Constant_metric_field_3<K> field(Metric::isotropic(0.1));
  int calls = 0;
  const std::string m = message_of<BM::Interrupted>([&] {
    BM::make_indexed_anisotropic_mesh_3(*domain, field, BM::parameters::should_stop(std::function<bool()>([&] {
                                                          ++calls;
                                                          return true;
                                                        })));
  });
  EXPECT_EQ(m, "interrupted during the input checks");
  EXPECT_EQ(calls, 1);
}

TEST(InputChecks, ShouldStopInterruptsTheAdvancingFront)
{
  const auto domain = domain_from_off(bad + "inward_cube.off");
  const CGAL::Constant_metric_field_3<K> field(Metric::isotropic(0.12)); // about 1,700 nodes, 7,000 tets
  bool boundary_done = false;
  int calls_after = 0;
  std::function<bool()> stop = [&] { return boundary_done && ++calls_after > 1; };
  std::function<void(const std::string&)> progress = [&](const std::string& s) {
    if(s.rfind("boundary front:", 0) == 0)
      boundary_done = true;
  };
  BM::Meshing_report report;
  const std::string m = message_of<BM::Interrupted>([&] {
    BM::make_indexed_anisotropic_mesh_3(*domain, field,
                                        BM::parameters::should_stop(stop).progress_messages(progress).meshing_report(
                                            &report));
  });
  EXPECT_EQ(m, "interrupted during the advancing front");
  EXPECT_EQ(calls_after, 2); // the first check point of the front stopped it
  EXPECT_GT(report.nodes[3], 0u);
  EXPECT_EQ(report.tets, 0u) << "the front did not finish";
}

TEST(InputChecks, ShouldStopInterruptsThePacking)
{
  const auto domain = domain_from_off(bad + "inward_cube.off");
  const CGAL::Constant_metric_field_3<K> field(Metric::isotropic(0.05)); // about 20,000 nodes
  bool estimated = false;
  int polls_after = 0;
  std::function<bool()> stop = [&] { return estimated && ++polls_after > 3; };
  std::function<void(const std::string&)> progress = [&](const std::string& s) {
    if(s.rfind("estimated nodes:", 0) == 0)
      estimated = true;
  };
  BM::Meshing_report report;
  const std::string m = message_of<BM::Interrupted>([&] {
    BM::make_indexed_anisotropic_mesh_3(
        *domain, field, BM::parameters::should_stop(stop).progress_messages(progress).meshing_report(&report));
  });
  // polled inside the packer's iterations, not only between its stages
  EXPECT_EQ(m, "interrupted during the packing");
  EXPECT_EQ(polls_after, 4);
  EXPECT_EQ(report.nodes[3], 0u) << "the volume was not packed";
}

TEST(InputChecks, CallbackSeesTheAdvancementAndCanStop)
{
  const auto domain = domain_from_off(bad + "inward_cube.off");
  const CGAL::Constant_metric_field_3<K> field(Metric::isotropic(0.2));
  // CGAL's meaning: the advancement in [0, 1], false stops the run
  std::vector<double> seen;
  const BM::Indexed_tet_mesh_3 mesh = BM::make_indexed_anisotropic_mesh_3(
      *domain, field, BM::parameters::callback(std::function<bool(double)>([&](double a) {
        seen.push_back(a);
        return true;
      })));
  EXPECT_FALSE(mesh.tets.empty());
  ASSERT_GE(seen.size(), 8u); // input, packing stages, fronts, improvement, validation, end
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  EXPECT_GE(seen.front(), 0.0);
  EXPECT_EQ(seen.back(), 1.0);
  int calls = 0;
  const std::string m = message_of<BM::Interrupted>([&] {
    BM::make_indexed_anisotropic_mesh_3(*domain, field, BM::parameters::callback(std::function<bool(double)>([&](double a) {
                                                          ++calls;
                                                          return a < 0.1;
                                                        })));
  });
  EXPECT_TRUE(contains(m, "(the callback returned false)")) << m;
  EXPECT_TRUE(contains(m, "interrupted during the packing")) << m;
}

TEST(InputChecks, VerbosePrintsTheStagesAndTheSummary)
{
  const auto domain = domain_from_off(bad + "inward_cube.off");
  const CGAL::Constant_metric_field_3<K> field(Metric::isotropic(0.25));
  std::ostringstream captured;
  std::streambuf* old = std::cerr.rdbuf(captured.rdbuf());
  try {
    BM::make_indexed_anisotropic_mesh_3(*domain, field, BM::parameters::verbose(true));
  } catch(...) {
    std::cerr.rdbuf(old);
    throw;
  }
  std::cerr.rdbuf(old);
  const std::string text = captured.str();
  EXPECT_TRUE(contains(text, "packed volume:")) << text;
  EXPECT_TRUE(contains(text, "advancing front:")) << text;
  EXPECT_TRUE(contains(text, "nodes:    ")) << text; // the summary
  EXPECT_TRUE(contains(text, "total:    ")) << text;
  // quiet by default
  std::ostringstream none;
  old = std::cerr.rdbuf(none.rdbuf());
  BM::make_indexed_anisotropic_mesh_3(*domain, field);
  std::cerr.rdbuf(old);
  EXPECT_EQ(none.str(), "");
}

TEST(InputChecks, TimeLimitThrowsTimeLimitExceeded)
{
  const auto domain = domain_from_off(bad + "inward_cube.off");
  const CGAL::Constant_metric_field_3<K> field(Metric::isotropic(0.1));
  const std::string m = message_of<BM::Time_limit_exceeded>([&] {
    BM::make_indexed_anisotropic_mesh_3(*domain, field, BM::parameters::time_limit(1e-9));
  });
  EXPECT_EQ(m, "time limit of 1e-09 s reached during the input checks");
  // it is an Interrupted too
  EXPECT_FALSE(message_of<BM::Interrupted>([&] {
                 BM::make_indexed_anisotropic_mesh_3(*domain, field, BM::parameters::time_limit(1e-9));
               }).empty());
  // a generous limit changes nothing
  const CGAL::Constant_metric_field_3<K> coarse(Metric::isotropic(0.25));
  const BM::Indexed_tet_mesh_3 a = BM::make_indexed_anisotropic_mesh_3(
      *domain, coarse, BM::parameters::time_limit(1e6).mesh_improvement(false));
  const BM::Indexed_tet_mesh_3 b =
      BM::make_indexed_anisotropic_mesh_3(*domain, coarse, BM::parameters::mesh_improvement(false));
  EXPECT_EQ(a.tets, b.tets);
  EXPECT_FALSE(a.tets.empty());
}

// A NaN limit or bound is refused by name before any work (it would
// otherwise mean no limit, or an automatic one)
TEST(InputChecks, NotANumberParametersAreRefusedByName)
{
  const auto domain = domain_from_off(bad + "inward_cube.off");
  const CGAL::Constant_metric_field_3<K> field(Metric::isotropic(0.1));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(message_of<BM::Invalid_input>(
                [&] { BM::make_indexed_anisotropic_mesh_3(*domain, field, BM::parameters::time_limit(nan)); }),
            "time_limit: not a number");
  EXPECT_EQ(message_of<BM::Invalid_input>([&] {
              BM::make_indexed_anisotropic_mesh_3(*domain, field, BM::parameters::improvement_time_limit(nan));
            }),
            "improvement_time_limit: not a number");
  EXPECT_EQ(message_of<BM::Invalid_input>(
                [&] { BM::make_indexed_anisotropic_mesh_3(*domain, field, BM::parameters::surface_distance(nan)); }),
            "surface_distance: not a number");
}

} // namespace
