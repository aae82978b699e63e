// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// libFuzzer harness: the exact predicates of Anisotropic_advancing_front_traits_3
// (metric in-sphere, its SOS variant, Orientation_3) against a reference
// written here with CGAL::Exact_rational from first principles:
//
//   side_M(p,q,r,s,t) = -sign det [x  y  z  x^T M x  1]   (rows p,q,r,s,t)
//
// (absolute coordinates, a 5x5 determinant by rational elimination: a
// different formula from the library's 4x4 on differences), and the SOS
// answer as the first non-zero coefficient of the determinant perturbed by
// eps^rank(k) on the lifted entry of row k (rank 1 for the largest id), i.e.
// the cofactors of the lifted column. Any mismatch aborts.
//
// The fuzz bytes are decoded into five points and an SPD metric, biased
// towards the hard cases: points on one metric ellipsoid (exactly, from
// integer points of a sphere mapped by a dyadic shear), coplanar and
// collinear sets, duplicates, steps of a few ulps, huge and tiny magnitudes,
// and raw bit patterns.
#include <CGAL/Bubble_mesh_3/Anisotropic_advancing_front_traits_3.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>

#include "fuzz_common.h"

#include <fuzzer/FuzzedDataProvider.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <string>
#include <utility>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Bubble_mesh_3::Anisotropic_advancing_front_traits_3<K> Traits;
typedef CGAL::Bubble_mesh_3::Metric_3 Metric_3;
typedef K::Point_3 Point_3;
typedef CGAL::Exact_rational Q;

namespace {

typedef std::array<double, 3> Coords;
typedef std::array<double, 6> Entries; // m11 m12 m13 m22 m23 m33

// ---------------------------------------------------------------- reference

template <std::size_t N>
int sign_of_determinant(std::array<std::array<Q, N>, N> a)
{
  int sign = 1;
  for(std::size_t c = 0; c < N; ++c) {
    std::size_t pivot = c;
    while(pivot < N && CGAL::is_zero(a[pivot][c]))
      ++pivot;
    if(pivot == N)
      return 0;
    if(pivot != c) {
      std::swap(a[pivot], a[c]);
      sign = -sign;
    }
    if(CGAL::is_negative(a[c][c]))
      sign = -sign;
    for(std::size_t r = c + 1; r < N; ++r) {
      if(CGAL::is_zero(a[r][c]))
        continue;
      const Q f = a[r][c] / a[c][c];
      for(std::size_t k = c; k < N; ++k)
        a[r][k] -= f * a[c][k];
    }
  }
  return sign;
}

// rows (x, y, z, x^T M x, 1), exact
std::array<std::array<Q, 5>, 5> lifted_matrix(const std::array<Coords, 5>& p, const Entries& m)
{
  std::array<std::array<Q, 5>, 5> a;
  for(int i = 0; i < 5; ++i) {
    const Q x(p[i][0]), y(p[i][1]), z(p[i][2]);
    const Q w = Q(m[0]) * x * x + Q(m[3]) * y * y + Q(m[5]) * z * z +
                Q(2) * (Q(m[1]) * x * y + Q(m[2]) * x * z + Q(m[4]) * y * z);
    a[i] = {x, y, z, w, Q(1)};
  }
  return a;
}

int reference_side(const std::array<Coords, 5>& p, const Entries& m)
{
  return -sign_of_determinant(lifted_matrix(p, m));
}

int reference_sos_side(const std::array<Coords, 5>& p, const Entries& m, const std::array<std::size_t, 5>& ids)
{
  const std::array<std::array<Q, 5>, 5> a = lifted_matrix(p, m);
  const int unperturbed = sign_of_determinant(a);
  if(unperturbed != 0)
    return -unperturbed;
  std::array<int, 5> order = {0, 1, 2, 3, 4};
  std::sort(order.begin(), order.end(), [&](int i, int j) { return ids[i] > ids[j]; });
  for(int k : order) {
    // cofactor of entry (k, 3)
    std::array<std::array<Q, 4>, 4> minor;
    for(int r = 0, i = 0; r < 5; ++r) {
      if(r == k)
        continue;
      minor[i] = {a[r][0], a[r][1], a[r][2], a[r][4]};
      ++i;
    }
    const int cofactor = ((k + 3) % 2 == 0 ? 1 : -1) * sign_of_determinant(minor);
    if(cofactor != 0)
      return -cofactor;
  }
  return 0;
}

int reference_orientation(const Coords& p, const Coords& q, const Coords& r, const Coords& s)
{
  std::array<std::array<Q, 3>, 3> a;
  const Coords* rows[3] = {&q, &r, &s};
  for(int i = 0; i < 3; ++i)
    for(int j = 0; j < 3; ++j)
      a[i][j] = Q((*rows[i])[j]) - Q(p[j]);
  return sign_of_determinant(a);
}

// ---------------------------------------------------------------- decoding

double pow2(int e) { return std::ldexp(1.0, e); }

double raw_double(FuzzedDataProvider& in)
{
  const std::uint64_t bits = in.ConsumeIntegral<std::uint64_t>();
  double x;
  std::memcpy(&x, &bits, sizeof x);
  return std::isfinite(x) ? x : 0.0;
}

// S unit upper triangular with small integer entries; its exact inverse.
struct Shear {
  int s12, s13, s23;
  Coords apply_inverse(const Coords& u) const
  {
    // S^-1 = [1 -s12 s12*s23-s13; 0 1 -s23; 0 0 1]
    return {u[0] - s12 * u[1] + (s12 * s23 - s13) * u[2], u[1] - s23 * u[2], u[2]};
  }
};

Shear consume_shear(FuzzedDataProvider& in)
{
  return Shear{in.ConsumeIntegralInRange(-3, 3), in.ConsumeIntegralInRange(-3, 3), in.ConsumeIntegralInRange(-3, 3)};
}

// M = S^T diag(g) S (exact for dyadic g and small shears)
Entries shear_metric(const Shear& s, const std::array<double, 3>& g)
{
  const double S[3][3] = {{1, double(s.s12), double(s.s13)}, {0, 1, double(s.s23)}, {0, 0, 1}};
  double M[3][3];
  for(int i = 0; i < 3; ++i)
    for(int j = 0; j < 3; ++j) {
      M[i][j] = 0;
      for(int k = 0; k < 3; ++k)
        M[i][j] += S[k][i] * g[k] * S[k][j];
    }
  return {M[0][0], M[0][1], M[0][2], M[1][1], M[1][2], M[2][2]};
}

struct Configuration {
  std::array<Coords, 5> points;
  Entries metric = {1, 0, 0, 1, 0, 1};
  bool has_metric = false;
};

// Five points on the M-ellipsoid |A(x - c)| = |y| with A = D S: the y are
// signed permutations of one integer vector, D = diag(2^d).
void cospherical(FuzzedDataProvider& in, Configuration& c)
{
  const Coords base = {double(in.ConsumeIntegralInRange(0, 6)), double(in.ConsumeIntegralInRange(0, 6)),
                       double(in.ConsumeIntegralInRange(0, 6))};
  const Shear shear = consume_shear(in);
  const int d[3] = {in.ConsumeIntegralInRange(-8, 8), in.ConsumeIntegralInRange(-8, 8),
                    in.ConsumeIntegralInRange(-8, 8)};
  const int ec = in.ConsumeIntegralInRange(-4, 4);
  const Coords centre = {in.ConsumeIntegralInRange(-8, 8) * pow2(ec), in.ConsumeIntegralInRange(-8, 8) * pow2(ec),
                         in.ConsumeIntegralInRange(-8, 8) * pow2(ec)};
  static const int permutations[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for(Coords& p : c.points) {
    const std::uint8_t choice = in.ConsumeIntegral<std::uint8_t>();
    const int* perm = permutations[choice % 6];
    const int signs = choice / 6;
    Coords u;
    for(int k = 0; k < 3; ++k)
      u[k] = ((signs >> k) & 1 ? -1 : 1) * base[perm[k]] * pow2(-d[k]);
    const Coords x = shear.apply_inverse(u);
    for(int k = 0; k < 3; ++k)
      p[k] = x[k] + centre[k];
  }
  c.metric = shear_metric(shear, {pow2(2 * d[0]), pow2(2 * d[1]), pow2(2 * d[2])});
  c.has_metric = true;
}

void grid(FuzzedDataProvider& in, Configuration& c)
{
  const double scale = pow2(in.ConsumeIntegralInRange(-60, 60));
  for(Coords& p : c.points)
    for(double& x : p)
      x = in.ConsumeIntegralInRange(-4, 4) * scale;
}

// all five on the plane z = k1 x + k2 y + k0, axes then permuted
void coplanar(FuzzedDataProvider& in, Configuration& c)
{
  const int k0 = in.ConsumeIntegralInRange(-3, 3), k1 = in.ConsumeIntegralInRange(-3, 3),
            k2 = in.ConsumeIntegralInRange(-3, 3);
  const int axis = in.ConsumeIntegralInRange(0, 2);
  const double scale = pow2(in.ConsumeIntegralInRange(-30, 30));
  for(Coords& p : c.points) {
    const int x = in.ConsumeIntegralInRange(-8, 8), y = in.ConsumeIntegralInRange(-8, 8);
    const Coords q = {double(x), double(y), double(k1 * x + k2 * y + k0)};
    for(int k = 0; k < 3; ++k)
      p[(k + axis) % 3] = q[k] * scale;
  }
}

// grid points, then t derived from p, q, r: a midpoint (collinear with p, q)
// or p + q - r (coplanar with p, q, r)
void derived(FuzzedDataProvider& in, Configuration& c)
{
  grid(in, c);
  const bool midpoint = in.ConsumeBool();
  for(int k = 0; k < 3; ++k)
    c.points[4][k] = midpoint ? 0.5 * (c.points[0][k] + c.points[1][k])
                              : c.points[0][k] + c.points[1][k] - c.points[2][k];
}

void raw(FuzzedDataProvider& in, Configuration& c)
{
  for(Coords& p : c.points)
    for(double& x : p)
      x = raw_double(in);
}

Entries consume_metric(FuzzedDataProvider& in)
{
  switch(in.ConsumeIntegralInRange(0, 4)) {
  case 0:
    return {1, 0, 0, 1, 0, 1};
  case 1:
    return {pow2(in.ConsumeIntegralInRange(-20, 20)), 0, 0, pow2(in.ConsumeIntegralInRange(-20, 20)), 0,
            pow2(in.ConsumeIntegralInRange(-20, 20))};
  case 2: {
    const Shear s = consume_shear(in);
    return shear_metric(s, {pow2(in.ConsumeIntegralInRange(-12, 12)), pow2(in.ConsumeIntegralInRange(-12, 12)),
                            pow2(in.ConsumeIntegralInRange(-12, 12))});
  }
  case 3: {
    Entries m;
    for(double& x : m)
      x = raw_double(in);
    return m;
  }
  default: {
    // L L^T, L lower triangular with small integers and positive diagonal
    const double l11 = in.ConsumeIntegralInRange(1, 4), l22 = in.ConsumeIntegralInRange(1, 4),
                 l33 = in.ConsumeIntegralInRange(1, 4);
    const double l21 = in.ConsumeIntegralInRange(-4, 4), l31 = in.ConsumeIntegralInRange(-4, 4),
                 l32 = in.ConsumeIntegralInRange(-4, 4);
    return {l11 * l11, l11 * l21, l11 * l31, l21 * l21 + l22 * l22, l21 * l31 + l22 * l32,
            l31 * l31 + l32 * l32 + l33 * l33};
  }
  }
}

Configuration decode(FuzzedDataProvider& in)
{
  Configuration c;
  switch(in.ConsumeIntegralInRange(0, 4)) {
  case 0: cospherical(in, c); break;
  case 1: grid(in, c); break;
  case 2: coplanar(in, c); break;
  case 3: derived(in, c); break;
  default: raw(in, c); break;
  }
  if(!c.has_metric)
    c.metric = consume_metric(in);
  const std::uint8_t post = in.ConsumeIntegral<std::uint8_t>();
  if(post & 1) { // duplicate a point
    const int i = in.ConsumeIntegralInRange(0, 4), j = in.ConsumeIntegralInRange(0, 4);
    c.points[i] = c.points[j];
  }
  if(post & 2) { // a few ulps here and there
    const int n = in.ConsumeIntegralInRange(1, 4);
    for(int k = 0; k < n; ++k) {
      double& x = c.points[in.ConsumeIntegralInRange(0, 4)][in.ConsumeIntegralInRange(0, 2)];
      const int steps = in.ConsumeIntegralInRange(-3, 3);
      for(int s = 0; s < std::abs(steps); ++s)
        x = std::nextafter(x, steps > 0 ? HUGE_VAL : -HUGE_VAL);
    }
  }
  if(post & 4) { // huge or tiny magnitudes (exact unless it under/overflows)
    const double scale = pow2(in.ConsumeIntegralInRange(-1074, 1023));
    for(Coords& p : c.points)
      for(double& x : p)
        x *= scale;
  }
  if(post & 8) { // far from the origin: the coordinates round
    const double offset = in.ConsumeIntegralInRange(-1000, 1000) * pow2(in.ConsumeIntegralInRange(0, 60));
    for(Coords& p : c.points)
      p[in.ConsumeIntegralInRange(0, 2)] += offset;
  }
  if(post & 16) { // metric scale
    const double scale = pow2(in.ConsumeIntegralInRange(-400, 400));
    for(double& x : c.metric)
      x *= scale;
  }
  return c;
}

std::string describe(const Configuration& c, const std::array<std::size_t, 5>& ids)
{
  std::ostringstream os;
  char buffer[128];
  const char* names = "pqrst";
  for(int i = 0; i < 5; ++i) {
    std::snprintf(buffer, sizeof buffer, "\n  %c = (%a, %a, %a) id %zu", names[i], c.points[i][0], c.points[i][1],
                  c.points[i][2], ids[i]);
    os << buffer;
  }
  std::snprintf(buffer, sizeof buffer, "\n  M (m11 m12 m13 m22 m23 m33) = %a %a %a", c.metric[0], c.metric[1],
                c.metric[2]);
  os << buffer;
  std::snprintf(buffer, sizeof buffer, " %a %a %a", c.metric[3], c.metric[4], c.metric[5]);
  os << buffer;
  return os.str();
}

std::string mismatch(const char* what, int got, int expected, const Configuration& c,
                     const std::array<std::size_t, 5>& ids)
{
  return std::string(what) + ": got " + std::to_string(got) + ", exact reference " + std::to_string(expected) +
         describe(c, ids);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  using bubble_mesh_3_fuzz::check;
  FuzzedDataProvider in(data, size);
  Configuration c = decode(in);
  for(const Coords& p : c.points)
    for(double x : p)
      if(!std::isfinite(x))
        return 0; // overflowed while scaling: not a point

  // The predicate takes a validated Metric_3; metrics Metric_3 refuses are not inputs.
  Metric_3 metric;
  try {
    metric = Metric_3::from_entries(c.metric[0], c.metric[1], c.metric[2], c.metric[3], c.metric[4], c.metric[5]);
  } catch(const CGAL::Bubble_mesh_3::Invalid_metric&) {
    return 0;
  }
  // what the predicate reads is the stored matrix (symmetrised)
  const std::array<double, 6> stored = metric.entries();
  std::copy(stored.begin(), stored.end(), c.metric.begin());

  // five distinct ids, in an order chosen by the input
  std::array<std::size_t, 5> ids = {0, 1, 2, 3, 4};
  for(int i = 4; i > 0; --i)
    std::swap(ids[i], ids[in.ConsumeIntegralInRange(0, i)]);
  const std::size_t spacing = in.ConsumeIntegralInRange<std::size_t>(1, 1000);
  for(std::size_t& id : ids)
    id = id * spacing + 7;

  std::array<Point_3, 5> pts;
  for(int i = 0; i < 5; ++i)
    pts[i] = Point_3(c.points[i][0], c.points[i][1], c.points[i][2]);

  const Traits traits;
  const auto side = traits.side_of_oriented_metric_sphere_3_object();
  const auto sos = traits.side_of_oriented_metric_sphere_SOS_3_object();
  const auto orientation = traits.orientation_3_object();

  const int got = side(pts[0], pts[1], pts[2], pts[3], pts[4], metric);
  const int expected = reference_side(c.points, c.metric);
  if(got != expected)
    bubble_mesh_3_fuzz::fail(mismatch("Side_of_oriented_metric_sphere_3", got, expected, c, ids));

  const int got_sos = sos(pts[0], pts[1], pts[2], pts[3], pts[4], metric, ids[0], ids[1], ids[2], ids[3], ids[4]);
  const int expected_sos = reference_sos_side(c.points, c.metric, ids);
  if(got_sos != expected_sos)
    bubble_mesh_3_fuzz::fail(mismatch("Side_of_oriented_metric_sphere_SOS_3", got_sos, expected_sos, c, ids));

  const int got_orientation = orientation(pts[0], pts[1], pts[2], pts[3]);
  const int expected_orientation = reference_orientation(c.points[0], c.points[1], c.points[2], c.points[3]);
  if(got_orientation != expected_orientation)
    bubble_mesh_3_fuzz::fail(mismatch("Orientation_3(p, q, r, s)", got_orientation, expected_orientation, c, ids));

  // With M = I the metric test is the kernel's in-sphere test.
  if(metric.matrix() == Metric_3::Matrix::Identity()) {
    const int euclidean = K().side_of_oriented_sphere_3_object()(pts[0], pts[1], pts[2], pts[3], pts[4]);
    if(got != euclidean)
      bubble_mesh_3_fuzz::fail(mismatch("identity metric vs K::Side_of_oriented_sphere_3", got, euclidean, c, ids));
  }

  // Alternating: a transposition of two (point, id) pairs flips both answers.
  const int i = in.ConsumeIntegralInRange(0, 4);
  const int j = (i + in.ConsumeIntegralInRange(1, 4)) % 5;
  std::swap(pts[i], pts[j]);
  std::swap(ids[i], ids[j]);
  const int swapped = side(pts[0], pts[1], pts[2], pts[3], pts[4], metric);
  check(swapped == -got, "Side_of_oriented_metric_sphere_3 is not alternating under a transposition");
  const int swapped_sos =
      sos(pts[0], pts[1], pts[2], pts[3], pts[4], metric, ids[0], ids[1], ids[2], ids[3], ids[4]);
  check(swapped_sos == -got_sos, "Side_of_oriented_metric_sphere_SOS_3 is not alternating under a transposition");
  return 0;
}
