// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Bubble_packer_3 at about 10k, 100k and 1M interior bubbles, with the identity
// metric (scaled) on the unit cube and with a 1:10 graded anisotropic metric on
// a 10 x 1 x 1 box (so that most bubbles are interior), on 1 and 2 threads. Prints one table row per run: interior bubbles,
// iterations, time per iteration, interior-stage time, total wall time and
// process CPU time (all threads).
//
//   bench_packer            10k and 100k (default)
//   bench_packer 1000000    adds the given size (e.g. 1M)
//   bench_packer --only 20000 --threads 1 --identity   one size, one thread count, one metric
//   (--graded: the graded metric only; --skin s: Parameters::skin;
//    --no-population-control: Parameters::population_control = false;
//    --slabs: interior bubbles and their median nearest w per tenth of the box
//    along x, nearest-w percentiles; --grading G: g = g0 (1 + G x), default 0.9;
//    --tolerance t, --iterations n: Parameters::tolerance, maximum_iterations;
//    --frozen-metric: the force without the metric's gradient, as before)
#include <CGAL/Bubble_packer_3.h>
#include <CGAL/Constant_metric_field_3.h>
#include <CGAL/Function_metric_field_3.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_polyhedron_3.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Mesh_polyhedron_3<K>::type Polyhedron;
typedef CGAL::Polyhedral_mesh_domain_with_features_3<K> Domain;
typedef CGAL::Bubble_mesh_3::Metric_3 Metric;

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

static double bench_skin = -1; // -1: the default of Parameters
static bool bench_population = true;
static bool bench_slabs = false;
static double bench_tolerance = -1; // -1: the default of Parameters
static int bench_iterations = -1;
static double bench_grading = 0.9; // g = g0 (1 + grading x) in the graded case
static bool bench_frozen = false;  // Bubble_packer_traits_3::metric_gradient_force() == false

template <typename Field>
static void run(const char* name, const Domain& domain, const Field& field, double target, int threads)
{
  typedef CGAL::Bubble_packer_3<Domain, Field> Packer;
  typename Packer::Parameters prm;
  prm.number_of_threads = threads;
  if(bench_skin > 0)
    prm.skin = bench_skin;
  prm.population_control = bench_population;
  if(bench_tolerance > 0)
    prm.tolerance = bench_tolerance;
  if(bench_iterations > 0)
    prm.maximum_iterations = bench_iterations;
  typename Packer::Traits traits(1, 1, 2.5, 0.4, !bench_frozen);
  Packer packer(domain, field, prm, traits);
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  packer.run();
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // process CPU time of all threads: on a shared machine, wall time includes waiting
  const double cpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
  const auto& s3 = packer.statistics().stages[3];
  const auto& s2 = packer.statistics().stages[2];
  std::printf("%-9s %9.0f %2d | %9zu %5d %s %9.4f %8.2f | %8zu %5d %7.2f | %8.2f %8.2f | rebuilds %zu rounds %d | nn p05 %.3f p50 %.3f min %.3f\n", name,
              target, threads, s3.bubbles, s3.iterations, s3.converged ? "c" : "-",
              s3.seconds / std::max(1, s3.iterations), s3.seconds, s2.bubbles, s2.iterations, s2.seconds, total, cpu,
              s3.neighbour_rebuilds, s3.population_rounds,
              packer.statistics().nearest_p05, packer.statistics().nearest_p50, packer.statistics().nearest_min);
  std::fflush(stdout);
  std::printf("          estimate %.0f nodes, packed %zu (%.3f)\n", packer.estimated_number_of_bubbles(),
              packer.number_of_nodes(), double(packer.number_of_nodes()) / packer.estimated_number_of_bubbles());
  if(bench_slabs) { // interior bubbles per tenth of the box along x, against the volume estimate
    namespace P = CGAL::Bubble_mesh_3::internal::packing;
    const auto nodes = packer.nodes();
    std::vector<P::Bubble_record> recs(nodes.size());
    for(std::size_t i = 0; i < nodes.size(); ++i) {
      recs[i].x = P::Vec3(nodes[i].point.x(), nodes[i].point.y(), nodes[i].point.z());
      recs[i].m = P::Sym3(field(nodes[i].point));
    }
    P::Neighbour_lists lists;
    lists.build(recs, std::vector<char>(recs.size(), 1), 1.5, P::Parallel_executor(1));
    std::vector<std::vector<double>> near_slab(10), near_dim(4);
    std::vector<int> count(10, 0);
    for(std::size_t i = 0; i < nodes.size(); ++i) {
      double w = 1.5;
      for(const int* j = lists.begin(i); j != lists.end(i); ++j)
        w = std::min(w, P::normalized_distance_to(recs[i].x, recs[i].m, recs[*j]));
      near_dim[nodes[i].dimension].push_back(w);
      if(nodes[i].dimension == 3) {
        const int k = std::min(9, int(nodes[i].point.x() * 10 / domain.bbox().xmax()));
        count[k]++;
        near_slab[k].push_back(w);
      }
    }
    auto median = [](std::vector<double> v) {
      if(v.empty())
        return 0.0;
      std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
      return v[v.size() / 2];
    };
    std::printf("  nearest w median by dimension: 1 %.3f, 2 %.3f, 3 %.3f\n", median(near_dim[1]), median(near_dim[2]),
                median(near_dim[3]));
    {
      std::vector<double> v = near_dim[3];
      std::sort(v.begin(), v.end());
      if(!v.empty()) {
        std::printf("  interior nearest w percentiles:");
        for(double q : {0.01, 0.05, 0.1, 0.25, 0.5, 0.75, 0.9})
          std::printf(" p%g %.3f", q * 100, v[std::size_t(q * double(v.size() - 1))]);
        std::printf("\n");
      }
    }
    for(int k = 0; k < 10; ++k) {
      // expected: sqrt2 * int sqrt det M over the slab (bbox of the domain)
      double e = 0;
      const double L = domain.bbox().xmax();
      for(int q = 0; q < 100; ++q) {
        const double x = L * (k + (q + 0.5) / 100) / 10;
        e += std::sqrt(2.0) * std::sqrt(field(K::Point_3(x, 0.5, 0.5)).matrix().determinant()) * L / 1000 *
             (domain.bbox().ymax() * domain.bbox().zmax());
      }
      std::printf("  slab %d: %d interior, volume estimate %.0f, median nearest w %.3f\n", k, count[k], e,
                  median(near_slab[k]));
    }
  }
}

int main(int argc, char** argv)
{
  std::vector<double> sizes = {1e4, 1e5};
  std::vector<int> thread_counts = {1, 2};
  bool run_identity = true, run_graded = true;
  for(int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if(a == "--only" && i + 1 < argc) { // --only N: that size alone
      sizes = {std::atof(argv[++i])};
    } else if(a == "--threads" && i + 1 < argc) {
      thread_counts = {std::atoi(argv[++i])};
    } else if(a == "--skin" && i + 1 < argc) {
      bench_skin = std::atof(argv[++i]);
    } else if(a == "--tolerance" && i + 1 < argc) {
      bench_tolerance = std::atof(argv[++i]);
    } else if(a == "--iterations" && i + 1 < argc) {
      bench_iterations = std::atoi(argv[++i]);
    } else if(a == "--grading" && i + 1 < argc) {
      bench_grading = std::atof(argv[++i]);
    } else if(a == "--frozen-metric") {
      bench_frozen = true;
    } else if(a == "--slabs") {
      bench_slabs = true;
    } else if(a == "--no-population-control") {
      bench_population = false;
    } else if(a == "--identity") {
      run_graded = false;
    } else if(a == "--graded") {
      run_identity = false;
    } else {
      sizes.push_back(std::atof(argv[i]));
    }
  }
  Polyhedron p = box(1);
  Domain domain(p);
  domain.detect_features(60);
  // the graded metric is stretched 1:10 along x: its domain is 10 long in x,
  // so that most of its bubbles are interior (in the unit cube, a bubble at
  // the coarse end would be nearly as long as the cube)
  Polyhedron p10 = box(10);
  Domain domain10(p10);
  domain10.detect_features(60);
  std::printf("metric    target    thr | interior  iter   s/iter  stage3_s | surface  iter  stage2_s | total_s    cpu_s\n");
  for(double n : sizes) {
    // identity metric scaled so that sqrt(2)/h^3 = n
    const double h = std::cbrt(std::sqrt(2.0) / n);
    CGAL::Constant_metric_field_3<K> iso = CGAL::Constant_metric_field_3<K>::isotropic(h);
    // graded anisotropic on [0,10] x [0,1] x [0,1]: sizes (10 g, g, g) along
    // (x, y, z), g grows 1 -> 10 along x; scaled so that sqrt(2) int sqrt(det M)
    // = n (int_0^10 dx / (10 g(x)^3))
    const double G = bench_grading;
    const double integral = [G] {
      double s = 0;
      const int m = 10000;
      for(int i = 0; i < m; ++i) {
        const double x = 10 * (i + 0.5) / m, g = 1 + G * x;
        s += 10 / (10 * g * g * g) / m;
      }
      return s;
    }();
    const double g0 = std::cbrt(std::sqrt(2.0) * integral / n);
    auto graded = CGAL::make_function_metric_field_3<K>([g0, G](const K::Point_3& q) {
      const double g = g0 * (1 + G * q.x());
      return Metric::from_entries(1 / (100 * g * g), 0, 0, 1 / (g * g), 0, 1 / (g * g));
    });
    for(int threads : thread_counts) {
      if(run_identity)
        run("identity", domain, iso, n, threads);
      if(run_graded)
        run("graded", domain10, graded, n, threads);
    }
  }
  return 0;
}
