// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Cost of one metric evaluation for the three MetricField_3 models, at random
// points inside [0,1]^3. The interpolated field uses a structured background
// mesh of 26^3 cubes x 6 tets = 105456 tets (17576 cubes, 19683 vertices).
//
//   build/bin/bench_metric_field --benchmark_min_time=1

#include <CGAL/Constant_metric_field_3.h>
#include <CGAL/Function_metric_field_3.h>
#include <CGAL/Interpolated_metric_field_3.h>

#include <CGAL/Simple_cartesian.h>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <tuple>
#include <vector>

namespace {

typedef CGAL::Simple_cartesian<double> K;
typedef K::Point_3 Point_3;
typedef CGAL::Bubble_mesh_3::Metric_3 Metric;

// Graded anisotropic metric: size 0.005 across the plane x = 0.5, growing
// linearly away from it, 0.05 and 0.1 in the other directions, rotated by
// an angle that depends on z.
Metric::Matrix graded_metric(const Point_3& p)
{
  const double hx = 0.005 + 0.2 * std::abs(p.x() - 0.5);
  const double hy = 0.05, hz = 0.1;
  const double a = 0.5 * p.z();
  Metric::Matrix r;
  r << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
  const Metric::Vector lambda(1 / (hx * hx), 1 / (hy * hy), 1 / (hz * hz));
  return r * lambda.asDiagonal() * r.transpose();
}

CGAL::Bubble_mesh_3::Indexed_tet_mesh_3 cube_mesh(int n)
{
  CGAL::Bubble_mesh_3::Indexed_tet_mesh_3 m;
  auto id = [n](int i, int j, int k) { return (k * (n + 1) + j) * (n + 1) + i; };
  for(int k = 0; k <= n; ++k)
    for(int j = 0; j <= n; ++j)
      for(int i = 0; i <= n; ++i)
        m.points.push_back({{double(i) / n, double(j) / n, double(k) / n}});
  const int permutations[6][3] = {{1, 2, 4}, {1, 4, 2}, {2, 1, 4}, {2, 4, 1}, {4, 1, 2}, {4, 2, 1}};
  for(int k = 0; k < n; ++k)
    for(int j = 0; j < n; ++j)
      for(int i = 0; i < n; ++i) {
        auto corner = [&](int b) { return id(i + (b & 1), j + ((b >> 1) & 1), k + ((b >> 2) & 1)); };
        for(const auto& p : permutations)
          m.tets.push_back({{corner(0), corner(p[0]), corner(p[0] | p[1]), corner(7)}});
      }
  m.tet_refs.assign(m.tets.size(), 1);
  return m;
}

const std::vector<Point_3>& query_points(double lo, double hi)
{
  static std::vector<Point_3> inside, outside;
  std::vector<Point_3>& r = lo >= 0 ? inside : outside;
  if(r.empty()) {
    std::mt19937 gen(42);
    std::uniform_real_distribution<double> u(lo, hi);
    for(int i = 0; i < (1 << 16); ++i)
      r.emplace_back(u(gen), u(gen), u(gen));
  }
  return r;
}

const CGAL::Interpolated_metric_field_3<K>& interpolated_field()
{
  static const CGAL::Interpolated_metric_field_3<K> field = [] {
    const CGAL::Bubble_mesh_3::Indexed_tet_mesh_3 m = cube_mesh(26);
    std::vector<Metric> metrics;
    for(const auto& p : m.points)
      metrics.emplace_back(graded_metric(Point_3(p[0], p[1], p[2])));
    return CGAL::Interpolated_metric_field_3<K>(m, std::move(metrics));
  }();
  return field;
}

template <typename Field>
void run(benchmark::State& state, const Field& field, const std::vector<Point_3>& points)
{
  std::size_t i = 0;
  for(auto _ : state) {
    auto m = field(points[i]);
    benchmark::DoNotOptimize(m);
    i = (i + 1) & (points.size() - 1);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_constant_field(benchmark::State& state)
{
  const CGAL::Constant_metric_field_3<K> field(Metric(graded_metric(Point_3(0.3, 0.2, 0.1))));
  run(state, field, query_points(0, 1));
}
BENCHMARK(BM_constant_field);

void BM_function_field(benchmark::State& state)
{
  const auto field = CGAL::make_function_metric_field_3<K>([](const Point_3& p) { return graded_metric(p); });
  run(state, field, query_points(0, 1));
}
BENCHMARK(BM_function_field);

void BM_interpolated_field_inside(benchmark::State& state)
{
  const auto& field = interpolated_field();
  state.counters["tets"] = static_cast<double>(field.number_of_tets());
  run(state, field, query_points(0, 1));
}
BENCHMARK(BM_interpolated_field_inside);

// Spatially coherent queries (points sorted along x-rows of small blocks, as
// when a packer moves neighbouring bubbles): caches are warm, unlike above.
void BM_interpolated_field_inside_coherent(benchmark::State& state)
{
  std::vector<Point_3> points = query_points(0, 1);
  auto key = [](const Point_3& p) {
    return std::make_tuple(int(p.z() * 32), int(p.y() * 32), int(p.x() * 32), p.x());
  };
  std::sort(points.begin(), points.end(), [&](const Point_3& a, const Point_3& b) { return key(a) < key(b); });
  run(state, interpolated_field(), points);
}
BENCHMARK(BM_interpolated_field_inside_coherent);

// Location only (grid + barycentric tests), without the log-Euclidean mean.
void BM_interpolated_field_locate(benchmark::State& state)
{
  const auto& field = interpolated_field();
  const std::vector<Point_3>& points = query_points(0, 1);
  std::size_t i = 0;
  for(auto _ : state) {
    benchmark::DoNotOptimize(field.locate(points[i]));
    i = (i + 1) & (points.size() - 1);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_interpolated_field_locate);

// Queries outside the background mesh: nearest-vertex value (Kd-tree).
void BM_interpolated_field_outside(benchmark::State& state)
{
  std::vector<Point_3> points;
  for(const Point_3& p : query_points(-1, 2))
    if(p.x() < 0 || p.x() > 1 || p.y() < 0 || p.y() > 1 || p.z() < 0 || p.z() > 1)
      points.push_back(p);
  points.resize(std::size_t(1) << 15);
  run(state, interpolated_field(), points);
}
BENCHMARK(BM_interpolated_field_outside);

// Construction: validation, log M per vertex, grid and Kd-tree.
void BM_interpolated_field_construction(benchmark::State& state)
{
  const CGAL::Bubble_mesh_3::Indexed_tet_mesh_3 m = cube_mesh(26);
  std::vector<Metric> metrics;
  for(const auto& p : m.points)
    metrics.emplace_back(graded_metric(Point_3(p[0], p[1], p[2])));
  for(auto _ : state) {
    CGAL::Interpolated_metric_field_3<K> field(m, metrics);
    benchmark::DoNotOptimize(&field);
  }
}
BENCHMARK(BM_interpolated_field_construction)->Unit(benchmark::kMillisecond);

} // namespace

BENCHMARK_MAIN();
