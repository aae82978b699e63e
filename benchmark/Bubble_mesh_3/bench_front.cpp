// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Anisotropic_advancing_front_3::run (connection of packed nodes into tets)
// against CGAL::Delaunay_triangulation_3 built from the same points (range
// constructor: spatial sort + insertion), at about 10k, 100k (and 1M) nodes:
//   identity   the unit cube, constant isotropic metric of size h
//   stretched  the box [0,5] x [0,1] x [0,1], constant metric with sizes
//              (5 g, g, g): elements stretched 1:5 along x
// Each case: pack the nodes (Bubble_packer_3), build the boundary front
// (internal::front::build_boundary_front), run the front (timed), build the
// Delaunay triangulation of the same points (timed), check the front's mesh
// with check_validity (require_outward_triangles, expected volume).
// One table row per case. Target: front time within 10x the Delaunay time.
//
//   bench_front                   10k and 100k, both metrics (default)
//   bench_front 1000000           adds the given size (e.g. 1M)
//   bench_front --only 20000      that size alone
//   bench_front --identity | --stretched   one metric only
//   (--threads t: packing threads, 0 = all (default); the front is serial)
#include <CGAL/Anisotropic_advancing_front_3.h>
#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/boundary_stage.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/volume_stage.h>
#include <CGAL/Bubble_mesh_3/validity.h>
#include <CGAL/Bubble_packer_3.h>
#include <CGAL/Constant_metric_field_3.h>

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_polyhedron_3.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>

#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <sstream>
#include <string>
#include <vector>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Mesh_polyhedron_3<K>::type Polyhedron;
typedef CGAL::Polyhedral_mesh_domain_with_features_3<K> Domain;
typedef CGAL::Bubble_mesh_3::Metric_3 Metric;
typedef CGAL::Constant_metric_field_3<K> Field;
typedef CGAL::Anisotropic_advancing_front_3<Field> Front;
typedef CGAL::Delaunay_triangulation_3<K> Delaunay;
namespace BMI = CGAL::Bubble_mesh_3::internal;

// the box [0, a] x [0, 1] x [0, 1]
static Polyhedron box(double a)
{
  std::stringstream off;
  off << "OFF\n8 12 0\n0 0 0\n" << a << " 0 0\n" << a << " 1 0\n0 1 0\n0 0 1\n" << a << " 0 1\n" << a
      << " 1 1\n0 1 1\n"
      << "3 0 3 2\n3 0 2 1\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n3 1 2 6\n3 1 6 5\n"
      << "3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n";
  Polyhedron p;
  off >> p;
  return p;
}

static double seconds_since(std::chrono::steady_clock::time_point t0)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// CPU time of the calling thread: the front and the Delaunay triangulation
// are serial, and on a shared machine their CPU times compare more fairly
// than wall times (which include waiting for a core).
static double thread_cpu_seconds()
{
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

static int packing_threads = 0;

// the constant metric of sizes (stretch g, g, g) along (x, y, z)
static Field field_of(double g, double stretch)
{
  return Field(Metric::from_entries(1 / (stretch * stretch * g * g), 0, 0, 1 / (g * g), 0, 1 / (g * g)));
}

static void run_case(const char* name, const Domain& domain, double volume, double stretch, double target)
{
  typedef CGAL::Bubble_packer_3<Domain, Field> Packer;
  Packer::Parameters pp;
  pp.number_of_threads = packing_threads;

  // sizes: sqrt(2) V / (stretch g^3) nodes (volume estimate), then one
  // correction with the packer's own estimate (surface nodes included)
  double g = std::cbrt(std::sqrt(2.0) * volume / (stretch * target));
  double estimate = 0;
  for(int k = 0; k < 2; ++k) {
    Packer probe(domain, field_of(g, stretch), pp);
    estimate = probe.estimated_number_of_bubbles();
    if(k == 0)
      g *= std::cbrt(estimate / target);
  }
  const Field field = field_of(g, stretch);

  // 1. packing
  auto t0 = std::chrono::steady_clock::now();
  Packer packer(domain, field, pp);
  packer.run();
  const double pack_seconds = seconds_since(t0);
  const auto nodes = packer.nodes();

  // 2. the pipeline's boundary stage, then its choice of interior nodes
  t0 = std::chrono::steady_clock::now();
  const BMI::Meshing_settings settings;
  const BMI::Run_control control(settings);
  CGAL::Bubble_mesh_3::Meshing_report report;
  BMI::Domain_mesh dm;
  std::string failure;
  try {
    BMI::boundary_stage(domain, field, nodes, control, report, dm);
  } catch(const std::exception& e) {
    failure = std::string("boundary front: ") + e.what();
  }
  const double boundary_seconds = seconds_since(t0);
  const std::size_t boundary_nodes = dm.mesh.points.size();
  if(failure.empty())
    BMI::add_interior_nodes(domain, field, nodes, report, dm);
  std::vector<Front::Point_3> points;
  for(const auto& p : dm.mesh.points)
    points.emplace_back(p[0], p[1], p[2]);

  // BM3_FRONT_DUMP=FILE writes the front's input (points, boundary triangles)
  // to profile the front alone
  if(const char* dump = std::getenv("BM3_FRONT_DUMP")) {
    if(FILE* out = std::fopen(dump, "w")) {
      std::fprintf(out, "%zu\n", points.size());
      for(const auto& p : points)
        std::fprintf(out, "%.17g %.17g %.17g\n", p.x(), p.y(), p.z());
      std::fprintf(out, "%zu\n", dm.mesh.triangles.size());
      for(const auto& t : dm.mesh.triangles)
        std::fprintf(out, "%d %d %d\n", t[0], t[1], t[2]);
      std::fclose(out);
    }
  }

  // 3. the front (connection), timed
  Front::Result r;
  double front_seconds = 0, front_cpu = 0;
  if(failure.empty()) {
    t0 = std::chrono::steady_clock::now();
    const double c0 = thread_cpu_seconds();
    try {
      Front front(field);
      r = front.run(points, dm.mesh.triangles);
    } catch(const std::exception& e) {
      failure = std::string("front: ") + e.what();
    }
    front_seconds = seconds_since(t0);
    front_cpu = thread_cpu_seconds() - c0;
  }

  // 4. Delaunay of the same points, timed (range constructor: spatial sort)
  t0 = std::chrono::steady_clock::now();
  const double c1 = thread_cpu_seconds();
  std::size_t delaunay_tets = 0;
  {
    Delaunay dt(points.begin(), points.end());
    delaunay_tets = dt.number_of_finite_cells();
  }
  const double delaunay_seconds = seconds_since(t0);
  const double delaunay_cpu = thread_cpu_seconds() - c1;

  // 5. validity of the front's mesh
  std::string valid = "-";
  std::size_t problems = 0;
  std::string first_problem;
  double validity_seconds = 0;
  if(failure.empty()) {
    t0 = std::chrono::steady_clock::now();
    CGAL::Bubble_mesh_3::Indexed_tet_mesh_3 m = dm.mesh;
    for(std::size_t i = m.points.size(); i < r.points.size(); ++i) {
      m.points.push_back({{r.points[i].x(), r.points[i].y(), r.points[i].z()}});
      m.point_refs.push_back(1);
    }
    m.tets = r.tets;
    m.tet_refs.assign(m.tets.size(), 1);
    CGAL::Bubble_mesh_3::Validity_options vo;
    vo.require_outward_triangles = true;
    vo.expected_volume = volume;
    const CGAL::Bubble_mesh_3::Validity_report vr = CGAL::Bubble_mesh_3::check_validity(m, vo);
    validity_seconds = seconds_since(t0);
    valid = vr.is_valid() ? "yes" : "NO";
    problems = vr.number_of_problems;
    if(!vr.problems.empty())
      first_problem = vr.problems.front();
  } else {
    valid = "FAIL";
  }

  const auto& s = r.statistics;
  const std::size_t tets = r.tets.size();
  std::printf("%-9s %8.0f %8.0f %8zu %7zu | %7.1f %5.2f | %9zu %8.2f %9.0f | %8zu %7.2f %6.1f | %7.2f %7.2f %6.1f |"
              " %6zu %5zu %4zu %4zu | %-4s %5.2f\n",
              name, target, estimate, points.size(), boundary_nodes, pack_seconds, boundary_seconds, tets,
              front_seconds, front_seconds > 0 ? tets / front_seconds : 0.0, delaunay_tets, delaunay_seconds,
              delaunay_seconds > 0 ? front_seconds / delaunay_seconds : 0.0, front_cpu, delaunay_cpu,
              delaunay_cpu > 0 ? front_cpu / delaunay_cpu : 0.0, s.best_quality_tets, s.undo_rounds,
              s.cavities, s.steiner_points, valid.c_str(), validity_seconds);
  if(!failure.empty())
    std::printf("  failure: %s\n", failure.c_str());
  if(problems > 0)
    std::printf("  validity: %zu problems; first: %s\n", problems, first_problem.c_str());
  if(failure.empty())
    std::printf("  front detail: delaunay_tets %zu, undone_tets %zu, search_tets %zu, vertex_star %zu, "
                "steiner_star %zu, tetgen %zu, cavity_tets %zu, unused_nodes %zu\n",
                s.delaunay_tets, s.undone_tets, s.search_tets, s.vertex_star_fills, s.steiner_star_fills,
                s.tetgen_fills, s.cavity_tets, s.unused_nodes);
  std::fflush(stdout);
}

int main(int argc, char** argv)
{
  std::vector<double> sizes = {1e4, 1e5};
  bool run_identity = true, run_stretched = true;
  for(int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if(a == "--only" && i + 1 < argc) {
      sizes = {std::atof(argv[++i])};
    } else if(a == "--threads" && i + 1 < argc) {
      packing_threads = std::atoi(argv[++i]);
    } else if(a == "--identity") {
      run_stretched = false;
    } else if(a == "--stretched") {
      run_identity = false;
    } else if(!a.empty() && a[0] != '-') {
      sizes.push_back(std::atof(argv[i]));
    } else {
      std::fprintf(stderr, "usage: %s [N ...] [--only N] [--identity|--stretched] [--threads t]\n", argv[0]);
      return 1;
    }
  }
  Polyhedron p1 = box(1);
  Domain cube(p1);
  cube.detect_features(60);
  Polyhedron p5 = box(5);
  Domain box5(p5);
  box5.detect_features(60);
  std::printf("metric      target estimate    nodes  bnodes |  pack_s  bdry_s |      tets  front_s    tets/s |"
              "  DT_tets    DT_s  f/DT  | f_cpu_s DT_cpu_s cpu_f/DT | bestq  undo  cav stnr | valid val_s\n");
  std::fflush(stdout);
  for(double n : sizes) {
    if(run_identity)
      run_case("identity", cube, 1.0, 1.0, n);
    if(run_stretched)
      run_case("stretched", box5, 5.0, 5.0, n);
  }
  return 0;
}
