// Cost per call of the metric in-sphere predicate of
// Anisotropic_advancing_front_traits_3, against Epick's Euclidean
// side_of_oriented_sphere. Inputs are generated once; each benchmark cycles
// through 4096 of them.
//
//   bench_predicates --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <CGAL/Bubble_mesh_3/Anisotropic_advancing_front_traits_3.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <benchmark/benchmark.h>

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

namespace {

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_3 Point;
typedef CGAL::Bubble_mesh_3::Anisotropic_advancing_front_traits_3<K> Traits;
typedef CGAL::Bubble_mesh_3::Metric_3 Metric;
typedef Metric::Matrix Matrix;
namespace bi = CGAL::Bubble_mesh_3::internal;

const std::size_t N = 4096; // power of two

struct Input {
  std::array<Point, 5> p;
  Metric metric;
  std::array<std::size_t, 5> id;
};

Point random_point(std::mt19937_64& rng)
{
  std::uniform_real_distribution<double> u(-1, 1);
  const double x = u(rng);
  const double y = u(rng);
  const double z = u(rng);
  return Point(x, y, z);
}

Metric random_metric(std::mt19937_64& rng)
{
  std::uniform_real_distribution<double> logdiag(-2.3, 2.3), off(-3, 3);
  Matrix q = Matrix::Zero();
  for(int i = 0; i < 3; ++i) {
    q(i, i) = std::exp(logdiag(rng));
    for(int j = i + 1; j < 3; ++j)
      q(i, j) = off(rng) * q(i, i);
  }
  Matrix m = q.transpose() * q;
  for(int i = 0; i < 3; ++i)
    for(int j = 0; j < i; ++j)
      m(i, j) = m(j, i);
  return Metric(m);
}

// random points, a random anisotropic metric per input
const std::vector<Input>& random_inputs()
{
  static const std::vector<Input> inputs = [] {
    std::mt19937_64 rng(42);
    std::vector<Input> v(N);
    for(Input& in : v) {
      for(Point& p : in.p)
        p = random_point(rng);
      in.metric = random_metric(rng);
      in.id = {{0, 1, 2, 3, 4}};
    }
    return v;
  }();
  return inputs;
}

// t = a point of the M-circumsphere rounded to doubles: so close that
// neither the semi-static nor the interval stage can decide, the exact stage
// (Mpzf on full 53-bit mantissas) runs on almost every call
std::vector<Input> make_near_sphere_inputs(bool identity_metric)
{
    std::mt19937_64 rng(43);
    std::normal_distribution<double> n(0, 1);
    std::vector<Input> v(N);
    for(Input& in : v) {
      for(Point& p : in.p)
        p = random_point(rng);
      in.metric = identity_metric ? Metric() : random_metric(rng);
      in.id = {{0, 1, 2, 3, 4}};
      const Matrix& m = in.metric.matrix();
      Eigen::Vector3d x[4];
      for(int i = 0; i < 4; ++i)
        x[i] = Eigen::Vector3d(in.p[i].x(), in.p[i].y(), in.p[i].z());
      Matrix a;
      Eigen::Vector3d b;
      for(int i = 1; i < 4; ++i) {
        a.row(i - 1) = 2 * (x[i] - x[0]).transpose() * m;
        b(i - 1) = x[i].dot(m * x[i]) - x[0].dot(m * x[0]);
      }
      const Eigen::Vector3d c = a.fullPivLu().solve(b);
      const double rho = std::sqrt((x[0] - c).dot(m * (x[0] - c)));
      Eigen::Vector3d u(n(rng), n(rng), n(rng));
      const Eigen::Vector3d t = c + rho * in.metric.Q_inverse() * u.normalized();
      in.p[4] = Point(t[0], t[1], t[2]);
    }
    return v;
}

const std::vector<Input>& near_sphere_inputs()
{
  static const std::vector<Input> inputs = make_near_sphere_inputs(false);
  return inputs;
}

const std::vector<Input>& near_euclidean_sphere_inputs()
{
  static const std::vector<Input> inputs = make_near_sphere_inputs(true);
  return inputs;
}

// exactly co-ellipsoidal 5-tuples: M = A^T A with A unimodular,
// x = A^-1 (k y) + shift with |y|^2 = 50. With k = 1 and a small shift every
// interval operation is exact, so the interval stage decides the zero; with
// k = 99991 and a shift of 2^20 the intervals are too wide and the exact
// stage runs on every call.
std::vector<Input> make_co_ellipsoidal_inputs(long k, double shift)
{
    std::mt19937_64 rng(44);
    Eigen::Matrix3i a, a_inverse;
    a << 1, 1, 0, 0, 1, 1, 0, 0, 1;
    a_inverse << 1, -1, 1, 0, 1, -1, 0, 0, 1;
    Matrix m = (a.transpose() * a).cast<double>();
    const Metric metric(m);
    std::vector<Point> pts;
    for(int x = -8; x <= 8; ++x)
      for(int y = -8; y <= 8; ++y)
        for(int z = -8; z <= 8; ++z)
          if(x * x + y * y + z * z == 50) {
            const Eigen::Vector3i p = a_inverse * Eigen::Vector3i(x, y, z);
            pts.push_back(Point(double(p[0] * k) + shift, double(p[1] * k) - 77, double(p[2] * k) + 3));
          }
    const K::Orientation_3 orientation = K().orientation_3_object();
    std::uniform_int_distribution<std::size_t> pick(0, pts.size() - 1);
    std::vector<Input> v;
    while(v.size() < N) {
      Input in{{}, metric, {}};
      for(int k = 0; k < 5; ++k) {
        const std::size_t i = pick(rng);
        in.p[k] = pts[i];
        in.id[k] = i;
      }
      if(orientation(in.p[0], in.p[1], in.p[2], in.p[3]) == CGAL::COPLANAR)
        continue;
      if(in.id[4] == in.id[0] || in.id[4] == in.id[1] || in.id[4] == in.id[2] || in.id[4] == in.id[3])
        continue;
      v.push_back(in);
    }
    return v;
}

const std::vector<Input>& co_ellipsoidal_small_inputs()
{
  static const std::vector<Input> inputs = make_co_ellipsoidal_inputs(1, 1000);
  return inputs;
}

const std::vector<Input>& co_ellipsoidal_large_inputs()
{
  static const std::vector<Input> inputs = make_co_ellipsoidal_inputs(99991, 1048576);
  return inputs;
}

void run_metric(benchmark::State& state, const std::vector<Input>& inputs)
{
  const Traits::Side_of_oriented_metric_sphere_3 side = Traits().side_of_oriented_metric_sphere_3_object();
  std::size_t i = 0;
  for(auto _ : state) {
    const Input& in = inputs[i];
    benchmark::DoNotOptimize(side(in.p[0], in.p[1], in.p[2], in.p[3], in.p[4], in.metric));
    i = (i + 1) & (N - 1);
  }
  state.SetItemsProcessed(state.iterations());
}

// shares of the inputs decided by the semi-static, interval and exact stages
void count_stages(benchmark::State& state, const std::vector<Input>& inputs)
{
  std::size_t by_static = 0;
  std::size_t by_interval = 0;
  for(const Input& in : inputs) {
    bi::Coordinates_3<double> c[5];
    for(int k = 0; k < 5; ++k)
      c[k] = bi::Coordinates_3<double>{in.p[k].x(), in.p[k].y(), in.p[k].z()};
    const bi::Metric_coefficients_3<double> m = bi::metric_coefficients(in.metric);
    CGAL::Oriented_side s;
    if(bi::Side_of_oriented_metric_sphere_3_static_filter::certified_sign(c[0], c[1], c[2], c[3], c[4], m, s)) {
      ++by_static;
      continue;
    }
    CGAL::Protect_FPU_rounding<true> protection;
    const bi::To_metric_sphere_nt<CGAL::Interval_nt_advanced> to_interval;
    const CGAL::Uncertain<CGAL::Oriented_side> u = bi::Side_of_oriented_metric_sphere_3_nt<CGAL::Interval_nt_advanced>()(
        to_interval(c[0]), to_interval(c[1]), to_interval(c[2]), to_interval(c[3]), to_interval(c[4]), to_interval(m));
    if(CGAL::is_certain(u))
      ++by_interval;
  }
  const double n = double(inputs.size());
  state.counters["static"] = double(by_static) / n;
  state.counters["interval"] = double(by_interval) / n;
  state.counters["exact"] = double(inputs.size() - by_static - by_interval) / n;
}

void BM_metric_side_random(benchmark::State& state)
{
  run_metric(state, random_inputs());
  count_stages(state, random_inputs());
}

void BM_metric_side_random_identity_metric(benchmark::State& state)
{
  std::vector<Input> inputs = random_inputs();
  for(Input& in : inputs)
    in.metric = Metric();
  run_metric(state, inputs);
  count_stages(state, inputs);
}

void BM_metric_side_near_sphere(benchmark::State& state)
{
  run_metric(state, near_sphere_inputs());
  count_stages(state, near_sphere_inputs());
}

void BM_metric_side_co_ellipsoidal_interval(benchmark::State& state)
{
  run_metric(state, co_ellipsoidal_small_inputs());
  count_stages(state, co_ellipsoidal_small_inputs());
}

void BM_metric_side_co_ellipsoidal_exact(benchmark::State& state)
{
  run_metric(state, co_ellipsoidal_large_inputs());
  count_stages(state, co_ellipsoidal_large_inputs());
}

void run_sos(benchmark::State& state, const std::vector<Input>& inputs)
{
  const Traits::Side_of_oriented_metric_sphere_SOS_3 side = Traits().side_of_oriented_metric_sphere_SOS_3_object();
  std::size_t i = 0;
  for(auto _ : state) {
    const Input& in = inputs[i];
    benchmark::DoNotOptimize(side(in.p[0], in.p[1], in.p[2], in.p[3], in.p[4], in.metric, in.id[0], in.id[1],
                                  in.id[2], in.id[3], in.id[4]));
    i = (i + 1) & (N - 1);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_metric_side_SOS_random(benchmark::State& state) { run_sos(state, random_inputs()); }
void BM_metric_side_SOS_co_ellipsoidal_interval(benchmark::State& state) { run_sos(state, co_ellipsoidal_small_inputs()); }
void BM_metric_side_SOS_co_ellipsoidal_exact(benchmark::State& state) { run_sos(state, co_ellipsoidal_large_inputs()); }

void run_epick(benchmark::State& state, const std::vector<Input>& inputs)
{
  const K::Side_of_oriented_sphere_3 side = K().side_of_oriented_sphere_3_object();
  std::size_t i = 0;
  for(auto _ : state) {
    const Input& in = inputs[i];
    benchmark::DoNotOptimize(side(in.p[0], in.p[1], in.p[2], in.p[3], in.p[4]));
    i = (i + 1) & (N - 1);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_epick_side_of_oriented_sphere_random(benchmark::State& state) { run_epick(state, random_inputs()); }
void BM_epick_side_of_oriented_sphere_near_sphere(benchmark::State& state)
{
  run_epick(state, near_euclidean_sphere_inputs());
}

} // namespace

BENCHMARK(BM_epick_side_of_oriented_sphere_random);
BENCHMARK(BM_metric_side_random);
BENCHMARK(BM_metric_side_random_identity_metric);
BENCHMARK(BM_metric_side_SOS_random);
BENCHMARK(BM_epick_side_of_oriented_sphere_near_sphere);
BENCHMARK(BM_metric_side_near_sphere);
BENCHMARK(BM_metric_side_co_ellipsoidal_interval);
BENCHMARK(BM_metric_side_co_ellipsoidal_exact);
BENCHMARK(BM_metric_side_SOS_co_ellipsoidal_interval);
BENCHMARK(BM_metric_side_SOS_co_ellipsoidal_exact);

BENCHMARK_MAIN();
