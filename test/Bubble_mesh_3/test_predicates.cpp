// Tests of the exact metric in-sphere predicate (filtered and symbolically
// perturbed) of Anisotropic_advancing_front_traits_3.
//
// The exact reference is independent of the implementation: it evaluates
// -sign det[x, y, z, x^T M x, 1] over the rows p, q, r, s, t (the 5x5 lifted
// form, not the 4x4 difference form of the predicate) in CGAL::Gmpq.
#include <CGAL/Bubble_mesh_3/Anisotropic_advancing_front_traits_3.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Gmpq.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/determinant.h>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <iostream>
#include <random>
#include <set>
#include <type_traits>
#include <vector>

namespace {

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_3 Point;
typedef CGAL::Bubble_mesh_3::Anisotropic_advancing_front_traits_3<K> Traits;
typedef CGAL::Bubble_mesh_3::Metric_3 Metric;
typedef Metric::Matrix Matrix;
typedef CGAL::Gmpq Rational;
typedef CGAL::Simple_cartesian<Rational> Exact_kernel;
typedef std::array<Point, 5> Five;
namespace bi = CGAL::Bubble_mesh_3::internal;
typedef bi::Metric_coefficients_3<double> Coefficients;
typedef bi::Side_of_oriented_metric_sphere_3_static_filter Static_filter;

const CGAL::Oriented_side POS = CGAL::ON_POSITIVE_SIDE;
const CGAL::Oriented_side NEG = CGAL::ON_NEGATIVE_SIDE;
const CGAL::Oriented_side ZERO_SIDE = CGAL::ON_ORIENTED_BOUNDARY;

// ---------------------------------------------------------------- helpers

Coefficients coefficients(const Metric& m) { return bi::metric_coefficients(m); }

Coefficients diagonal_coefficients(double a, double b, double c) { return Coefficients{a, 0, 0, b, 0, c}; }

bi::Coordinates_3<double> coordinates(const Point& p) { return bi::Coordinates_3<double>{p.x(), p.y(), p.z()}; }

CGAL::Oriented_side side(const Five& f, const Metric& m)
{
  return Traits().side_of_oriented_metric_sphere_3_object()(f[0], f[1], f[2], f[3], f[4], m);
}

// the internal entry point, for metrics outside the range Metric_3 accepts
CGAL::Oriented_side side(const Five& f, const Coefficients& m)
{
  return bi::side_of_oriented_metric_sphere_3(coordinates(f[0]), coordinates(f[1]), coordinates(f[2]),
                                              coordinates(f[3]), coordinates(f[4]), m);
}

CGAL::Oriented_side side_sos(const Five& f, const Metric& m, const std::array<std::size_t, 5>& id)
{
  return Traits().side_of_oriented_metric_sphere_SOS_3_object()(f[0], f[1], f[2], f[3], f[4], m, id[0], id[1],
                                                                 id[2], id[3], id[4]);
}

CGAL::Orientation orientation(const Point& p, const Point& q, const Point& r, const Point& s)
{
  return Traits().orientation_3_object()(p, q, r, s);
}

bool first_four_coplanar(const Five& f) { return orientation(f[0], f[1], f[2], f[3]) == CGAL::COPLANAR; }

// det[x, y, z, x^T M x + extra_i, 1] over the rows p, q, r, s, t, exactly.
Rational lifted_determinant_5(const Five& f, const Coefficients& m, const std::array<Rational, 5>* extra = nullptr)
{
  Rational a[5][5];
  const Rational m11(m.m11), m12(m.m12), m13(m.m13), m22(m.m22), m23(m.m23), m33(m.m33);
  for(int i = 0; i < 5; ++i) {
    const Rational x(f[i].x()), y(f[i].y()), z(f[i].z());
    a[i][0] = x;
    a[i][1] = y;
    a[i][2] = z;
    a[i][3] = m11 * x * x + m22 * y * y + m33 * z * z + 2 * (m12 * x * y + m13 * x * z + m23 * y * z);
    if(extra)
      a[i][3] += (*extra)[i];
    a[i][4] = 1;
  }
  return CGAL::determinant(a[0][0], a[0][1], a[0][2], a[0][3], a[0][4], a[1][0], a[1][1], a[1][2], a[1][3],
                           a[1][4], a[2][0], a[2][1], a[2][2], a[2][3], a[2][4], a[3][0], a[3][1], a[3][2],
                           a[3][3], a[3][4], a[4][0], a[4][1], a[4][2], a[4][3], a[4][4]);
}

CGAL::Oriented_side reference_side(const Five& f, const Coefficients& m)
{
  return -CGAL::sign(lifted_determinant_5(f, m));
}
CGAL::Oriented_side reference_side(const Five& f, const Metric& m) { return reference_side(f, coefficients(m)); }

// Reference for the SOS variant: the lifting of the point with the k-th
// largest id raised by eps^k, eps = 2^-200, evaluated exactly. Valid for the
// small dyadic inputs of the tests (consecutive terms differ by far more than
// the ratio of their coefficients).
CGAL::Oriented_side reference_side_sos(const Five& f, const Metric& m, const std::array<std::size_t, 5>& id)
{
  const Rational eps(std::ldexp(1.0, -200));
  std::array<Rational, 5> extra;
  for(int i = 0; i < 5; ++i) {
    int rank = 1;
    for(int j = 0; j < 5; ++j)
      if(id[j] > id[i])
        ++rank;
    Rational e = 1;
    for(int k = 0; k < rank; ++k)
      e *= eps;
    extra[i] = e;
  }
  return -CGAL::sign(lifted_determinant_5(f, coefficients(m), &extra));
}

// The plain double evaluation of the predicate's determinant (no filter).
double naive_determinant(const Five& f, const Coefficients& m)
{
  const Point* rows[4] = {&f[0], &f[2], &f[1], &f[3]};
  double d[4][3];
  for(int i = 0; i < 4; ++i) {
    d[i][0] = rows[i]->x() - f[4].x();
    d[i][1] = rows[i]->y() - f[4].y();
    d[i][2] = rows[i]->z() - f[4].z();
  }
  return bi::metric_lifted_determinant(d, m.m11, m.m22, m.m33, 2 * m.m12, 2 * m.m13, 2 * m.m23);
}
CGAL::Oriented_side naive_side(const Five& f, const Coefficients& m) { return CGAL::sign(naive_determinant(f, m)); }

bool static_evaluate(const Five& f, const Coefficients& m, double& det, double& eps)
{
  return Static_filter::evaluate(coordinates(f[0]), coordinates(f[1]), coordinates(f[2]), coordinates(f[3]),
                                 coordinates(f[4]), m, det, eps);
}

int permutation_sign(const std::array<int, 5>& perm)
{
  int inversions = 0;
  for(int i = 0; i < 5; ++i)
    for(int j = i + 1; j < 5; ++j)
      if(perm[i] > perm[j])
        ++inversions;
  return inversions % 2 == 0 ? 1 : -1;
}

Point random_point(std::mt19937_64& rng, double lo = -1, double hi = 1)
{
  std::uniform_real_distribution<double> u(lo, hi);
  const double x = u(rng);
  const double y = u(rng);
  const double z = u(rng);
  return Point(x, y, z);
}

// M = Q^T Q, Q upper triangular with a random positive diagonal.
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
      m(i, j) = m(j, i); // exactly symmetric
  return Metric(m);
}

// A point (rounded to double) on the M-circumsphere of p, q, r, s: the
// nearly degenerate input of the exact path.
Point point_near_metric_sphere(const Five& f, const Metric& metric, std::mt19937_64& rng)
{
  typedef Eigen::Vector3d V;
  const Matrix& m = metric.matrix();
  V p[4];
  for(int i = 0; i < 4; ++i)
    p[i] = V(f[i].x(), f[i].y(), f[i].z());
  Matrix a;
  V b;
  for(int i = 1; i < 4; ++i) {
    a.row(i - 1) = 2 * (p[i] - p[0]).transpose() * m;
    b(i - 1) = p[i].dot(m * p[i]) - p[0].dot(m * p[0]);
  }
  const V c = a.fullPivLu().solve(b);
  const double rho = std::sqrt((p[0] - c).dot(m * (p[0] - c)));
  std::normal_distribution<double> n(0, 1);
  V u(n(rng), n(rng), n(rng));
  u.normalize();
  const V x = c + rho * metric.Q_inverse() * u;
  return Point(x[0], x[1], x[2]);
}

// Integer points y with |y|^2 = n2.
std::vector<Eigen::Vector3i> sphere_points(int n2)
{
  std::vector<Eigen::Vector3i> out;
  const int r = static_cast<int>(std::sqrt(double(n2))) + 1;
  for(int x = -r; x <= r; ++x)
    for(int y = -r; y <= r; ++y)
      for(int z = -r; z <= r; ++z)
        if(x * x + y * y + z * z == n2)
          out.emplace_back(x, y, z);
  return out;
}

// An integer matrix A with det A = 1 and its integer inverse, from random
// elementary row operations.
struct Unimodular {
  Eigen::Matrix3i a = Eigen::Matrix3i::Identity();
  Eigen::Matrix3i inverse = Eigen::Matrix3i::Identity();
};

Unimodular random_unimodular(std::mt19937_64& rng, int steps, int max_entry = 4)
{
  Unimodular u;
  std::uniform_int_distribution<int> row(0, 2), coin(0, 1);
  for(int done = 0; done < steps;) {
    const int i = row(rng);
    const int j = row(rng);
    if(i == j)
      continue;
    const int k = coin(rng) ? 1 : -1;
    Unimodular v = u;
    v.a.row(i) += k * v.a.row(j);          // A <- (I + k e_i e_j^T) A
    v.inverse.col(j) -= k * v.inverse.col(i); // A^-1 <- A^-1 (I - k e_i e_j^T)
    if(v.a.cwiseAbs().maxCoeff() > max_entry || v.inverse.cwiseAbs().maxCoeff() > 4 * max_entry)
      continue;
    u = v;
    ++done;
  }
  EXPECT_EQ(u.a * u.inverse, Eigen::Matrix3i::Identity());
  return u;
}

// Exactly co-ellipsoidal points: Q = A D, D = diag(2^e), M = Q^T Q,
// x = 2^s D^-1 A^-1 (k y) + offset with |y|^2 = n2, so that
// (x - offset)^T M (x - offset) = 4^s k^2 n2 for every point. Every
// coordinate is checked to be exactly representable.
struct Co_ellipsoidal_set {
  Metric metric;
  std::vector<Point> points;
};

Co_ellipsoidal_set co_ellipsoidal_set(const Unimodular& u, int n2, std::array<int, 3> d_exponents = {{0, 0, 0}},
                                      int point_exponent = 0, std::array<double, 3> offset = {{0, 0, 0}},
                                      long scale_k = 1)
{
  Matrix q;
  for(int i = 0; i < 3; ++i)
    for(int j = 0; j < 3; ++j)
      q(i, j) = std::ldexp(double(u.a(i, j)), d_exponents[j]);
  Matrix m = q.transpose() * q; // small integers times powers of two: exact
  Co_ellipsoidal_set out{Metric(m), {}};
  EXPECT_TRUE(out.metric.matrix() == m);
  for(const Eigen::Vector3i& y : sphere_points(n2)) {
    double c[3];
    bool exact = true;
    for(int i = 0; i < 3; ++i) {
      long v = 0;
      for(int j = 0; j < 3; ++j)
        v += long(u.inverse(i, j)) * y[j] * scale_k;
      const double xi = std::ldexp(double(v), point_exponent - d_exponents[i]);
      c[i] = xi + offset[i];
      exact = exact && std::abs(v) < (1L << 53) && Rational(c[i]) == Rational(xi) + Rational(offset[i]);
    }
    EXPECT_TRUE(exact) << "construction lost exactness";
    out.points.push_back(Point(c[0], c[1], c[2]));
  }
  return out;
}

Five pick_five(const std::vector<Point>& pts, std::mt19937_64& rng)
{
  std::vector<int> idx(pts.size());
  for(std::size_t i = 0; i < idx.size(); ++i)
    idx[i] = int(i);
  std::shuffle(idx.begin(), idx.end(), rng);
  return Five{{pts[idx[0]], pts[idx[1]], pts[idx[2]], pts[idx[3]], pts[idx[4]]}};
}

Point ulp_perturbed(const Point& p, int coordinate, int ulps)
{
  double c[3] = {p.x(), p.y(), p.z()};
  for(int k = 0; k < std::abs(ulps); ++k)
    c[coordinate] = std::nextafter(c[coordinate], ulps > 0 ? HUGE_VAL : -HUGE_VAL);
  return Point(c[0], c[1], c[2]);
}

// ---------------------------------------------------------------- the traits

TEST(Predicates, TraitsTypes)
{
  static_assert(std::is_same<Traits::Metric_3, CGAL::Bubble_mesh_3::Metric_3>::value, "");
  static_assert(std::is_same<Traits::Orientation_3, K::Orientation_3>::value, "");
  static_assert(std::is_base_of<K, Traits>::value, "");
  static_assert(std::is_same<CGAL::Bubble_mesh_3::Anisotropic_advancing_front_traits_3<>, Traits>::value, "");
  const Traits traits;
  Traits::Side_of_oriented_metric_sphere_3 side = traits.side_of_oriented_metric_sphere_3_object();
  Traits::Side_of_oriented_metric_sphere_SOS_3 sos = traits.side_of_oriented_metric_sphere_SOS_3_object();
  const Point p(0, 0, 0), q(1, 0, 0), r(0, 1, 0), s(0, 0, 1);
  ASSERT_EQ(traits.orientation_3_object()(p, q, r, s), CGAL::POSITIVE);
  const Metric m = Metric::from_entries(1, 0, 0, 100, 0, 1);
  EXPECT_EQ(side(p, q, r, s, Point(0.25, 0.25, 0.25), m), POS); // inside, positive orientation
  EXPECT_EQ(side(p, q, r, s, Point(2, 2, 2), m), NEG);
  EXPECT_EQ(side(p, q, r, s, Point(1, 1, 1), m), ZERO_SIDE); // cube corner, centre (1/2,1/2,1/2)
  EXPECT_EQ(sos(p, q, r, s, Point(1, 1, 1), m, 0, 1, 2, 3, 4), NEG); // t has the largest id
}

// ---------------------------------------------------------------- (1)

TEST(Predicates, IdentityMetricAgreesWithCgal)
{
  std::mt19937_64 rng(1);
  const Metric identity;
  K::Side_of_oriented_sphere_3 euclidean = K().side_of_oriented_sphere_3_object();
  int mismatches = 0;
  int positives = 0;
  const int n = 100000;
  for(int i = 0; i < n; ++i) {
    const Five f{{random_point(rng), random_point(rng), random_point(rng), random_point(rng), random_point(rng)}};
    const CGAL::Oriented_side expected = euclidean(f[0], f[1], f[2], f[3], f[4]);
    if(side(f, identity) != expected)
      ++mismatches;
    if(expected == POS)
      ++positives;
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(positives, n / 20); // both signs are exercised
  EXPECT_LT(positives, n - n / 20);

  // Small integer grid: many exactly cospherical 5-tuples.
  std::uniform_int_distribution<int> g(-2, 2);
  int zeros = 0;
  for(int i = 0; i < 20000; ++i) {
    Five f;
    for(Point& p : f)
      p = Point(g(rng), g(rng), g(rng));
    const CGAL::Oriented_side expected = euclidean(f[0], f[1], f[2], f[3], f[4]);
    if(side(f, identity) != expected)
      ++mismatches;
    if(expected == ZERO_SIDE)
      ++zeros;
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(zeros, 100);
}

// ---------------------------------------------------------------- (2)

TEST(Predicates, CoEllipsoidalIsBoundary)
{
  // A = [[1,1,0],[0,1,1],[0,0,1]], M = A^T A = [[1,1,0],[1,2,1],[0,1,2]]:
  // every non-coplanar 5-subset of the 30 points with |Ax|^2 = 25.
  Unimodular u;
  u.a << 1, 1, 0, 0, 1, 1, 0, 0, 1;
  u.inverse << 1, -1, 1, 0, 1, -1, 0, 0, 1;
  ASSERT_EQ(u.a * u.inverse, Eigen::Matrix3i::Identity());
  for(const std::array<double, 3>& offset :
      {std::array<double, 3>{{0, 0, 0}}, std::array<double, 3>{{1024, -77, 3}}}) {
    const Co_ellipsoidal_set set = co_ellipsoidal_set(u, 25, {{0, 0, 0}}, 0, offset);
    ASSERT_EQ(set.points.size(), 30u);
    EXPECT_EQ(set.metric.matrix(), (Matrix() << 1, 1, 0, 1, 2, 1, 0, 1, 2).finished());
    const std::vector<Point>& x = set.points;
    int tested = 0;
    int wrong = 0;
    const int n = int(x.size());
    for(int a = 0; a < n; ++a)
      for(int b = a + 1; b < n; ++b)
        for(int c = b + 1; c < n; ++c)
          for(int d = c + 1; d < n; ++d) {
            if(orientation(x[a], x[b], x[c], x[d]) == CGAL::COPLANAR)
              continue;
            for(int e = d + 1; e < n; ++e) {
              ++tested;
              if(side(Five{{x[a], x[b], x[c], x[d], x[e]}}, set.metric) != ZERO_SIDE)
                ++wrong;
            }
          }
    EXPECT_EQ(wrong, 0);
    EXPECT_GT(tested, 50000);
  }

  // Random unimodular A, integer translations, sampled subsets.
  std::mt19937_64 rng(2);
  std::uniform_int_distribution<int> shift(-1000, 1000);
  int tested = 0;
  int wrong = 0;
  for(int trial = 0; trial < 20; ++trial) {
    const Unimodular u2 = random_unimodular(rng, 6);
    const std::array<double, 3> offset{{double(shift(rng)), double(shift(rng)), double(shift(rng))}};
    const Co_ellipsoidal_set set = co_ellipsoidal_set(u2, 50, {{0, 0, 0}}, 0, offset);
    for(int i = 0; i < 200; ++i) {
      const Five f = pick_five(set.points, rng);
      if(first_four_coplanar(f))
        continue;
      ++tested;
      if(side(f, set.metric) != ZERO_SIDE)
        ++wrong;
    }
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(tested, 3000);

  // The 8 corners of the unit cube are co-ellipsoidal for M = diag(1, 100, 1).
  const Metric m = Metric::from_entries(1, 0, 0, 100, 0, 1);
  std::vector<Point> corners;
  for(int i = 0; i < 8; ++i)
    corners.push_back(Point(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  int cube_tested = 0;
  for(int a = 0; a < 8; ++a)
    for(int b = a + 1; b < 8; ++b)
      for(int c = b + 1; c < 8; ++c)
        for(int d = c + 1; d < 8; ++d)
          for(int e = d + 1; e < 8; ++e) {
            const Five f{{corners[a], corners[b], corners[c], corners[d], corners[e]}};
            if(first_four_coplanar(f))
              continue;
            ++cube_tested;
            EXPECT_EQ(side(f, m), ZERO_SIDE);
          }
  EXPECT_GT(cube_tested, 20);
  // ... and a point just off the ellipsoid is not.
  EXPECT_EQ(side(Five{{corners[0], corners[1], corners[2], corners[4], Point(1, 1, 0.999)}}, m),
            orientation(corners[0], corners[1], corners[2], corners[4]) * POS);
}

// ---------------------------------------------------------------- (3)

TEST(Predicates, NearDegenerateAgainstExactReference)
{
  std::mt19937_64 rng(3);
  // +-1..4 ulp perturbations of a co-ellipsoidal point, for several metrics
  // and offsets.
  int tested = 0;
  int wrong = 0;
  int nonzero = 0;
  for(int trial = 0; trial < 12; ++trial) {
    const Unimodular u = random_unimodular(rng, 5);
    const std::array<double, 3> offset{{trial % 3 == 0 ? 0.0 : 1e6 + trial, trial % 2 ? -1000003.0 : 3.0, 17.0}};
    const Co_ellipsoidal_set set = co_ellipsoidal_set(u, 50, {{0, 0, 0}}, 0, offset);
    for(int i = 0; i < 10; ++i) {
      Five f = pick_five(set.points, rng);
      if(first_four_coplanar(f))
        continue;
      const Point t = f[4];
      for(int coordinate = 0; coordinate < 3; ++coordinate)
        for(int ulps : {-4, -3, -2, -1, 1, 2, 3, 4}) {
          f[4] = ulp_perturbed(t, coordinate, ulps);
          const CGAL::Oriented_side expected = reference_side(f, set.metric);
          ++tested;
          if(expected != ZERO_SIDE)
            ++nonzero;
          if(side(f, set.metric) != expected)
            ++wrong;
        }
    }
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(nonzero, tested / 2);

  // Cases where the plain double evaluation gets the sign wrong: points on a
  // large M-sphere (|A x|^2 = 50 * 99991^2) far from the origin, t moved by a
  // few ulps. Keep the strict sign flips (naive = -exact, exact != 0) and the
  // false non-zeros.
  int flips = 0;
  int false_nonzeros = 0;
  int filter_certified_wrongly = 0;
  int searched = 0;
  for(int trial = 0; trial < 30 && flips < 40; ++trial) {
    const Unimodular u = random_unimodular(rng, 5);
    const std::array<double, 3> offset{{1048576.0 * (trial + 1), -3.0 * 1048576, 12345.0}};
    const Co_ellipsoidal_set set = co_ellipsoidal_set(u, 50, {{0, 0, 0}}, 0, offset, 99991);
    const Coefficients m = coefficients(set.metric);
    for(int i = 0; i < 200; ++i) {
      Five f = pick_five(set.points, rng);
      if(first_four_coplanar(f))
        continue;
      std::uniform_int_distribution<int> coordinate(0, 2), ulps(-4, 4);
      if(i % 2)
        f[4] = ulp_perturbed(f[4], coordinate(rng), ulps(rng));
      ++searched;
      const CGAL::Oriented_side expected = reference_side(f, m);
      const CGAL::Oriented_side naive = naive_side(f, m);
      if(naive == expected)
        continue;
      if(expected != ZERO_SIDE && naive == -expected)
        ++flips;
      if(expected == ZERO_SIDE)
        ++false_nonzeros;
      // the filtered predicate is right where the naive evaluation is not
      EXPECT_EQ(side(f, set.metric), expected);
      CGAL::Oriented_side certified;
      if(Static_filter::certified_sign(coordinates(f[0]), coordinates(f[1]), coordinates(f[2]), coordinates(f[3]),
                                       coordinates(f[4]), m, certified))
        ++filter_certified_wrongly;
    }
  }
  std::cout << "naive double evaluation: " << flips << " sign flips and " << false_nonzeros
            << " false non-zeros in " << searched << " near-degenerate inputs\n";
  EXPECT_GE(flips, 20);
  EXPECT_GE(false_nonzeros, 20);
  EXPECT_EQ(filter_certified_wrongly, 0);
}

// ---------------------------------------------------------------- (4)

TEST(Predicates, AgreesWithEuclideanTestOnExactlyMappedPoints)
{
  std::mt19937_64 rng(4);
  std::uniform_int_distribution<int> quarter(-8, 8), grid(-3, 3);
  int tested = 0;
  int wrong = 0;
  int zeros = 0;
  for(int trial = 0; trial < 40; ++trial) {
    // Q with entries in (1/4) Z, det Q > 0; M = Q^T Q is exact in doubles.
    Matrix q;
    do {
      for(int i = 0; i < 3; ++i)
        for(int j = 0; j < 3; ++j)
          q(i, j) = quarter(rng) / 4.0;
    } while(std::abs(q.determinant()) < 0.05);
    if(q.determinant() < 0)
      q = -q; // same M, det Q > 0
    Matrix m = q.transpose() * q;
    Metric metric;
    try {
      metric = Metric(m);
    } catch(const CGAL::Bubble_mesh_3::Invalid_metric&) {
      continue;
    }
    ASSERT_TRUE(metric.matrix() == m);
    auto map = [&q](const Point& p) {
      const Rational x(p.x()), y(p.y()), z(p.z());
      Rational c[3];
      for(int i = 0; i < 3; ++i)
        c[i] = Rational(q(i, 0)) * x + Rational(q(i, 1)) * y + Rational(q(i, 2)) * z;
      return Exact_kernel::Point_3(c[0], c[1], c[2]);
    };
    for(int i = 0; i < 1000; ++i) {
      Five f;
      for(Point& p : f)
        p = (i % 2) ? random_point(rng) : Point(grid(rng), grid(rng), grid(rng));
      const CGAL::Oriented_side expected =
          CGAL::side_of_oriented_sphere(map(f[0]), map(f[1]), map(f[2]), map(f[3]), map(f[4]));
      ++tested;
      if(expected == ZERO_SIDE)
        ++zeros;
      if(side(f, metric) != expected)
        ++wrong;
    }
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(tested, 30000);
  EXPECT_GT(zeros, 100);
}

// ---------------------------------------------------------------- (5)

TEST(Predicates, SwapsFlipTheSignAndKeepTheBoundedSide)
{
  std::mt19937_64 rng(5);
  int violations = 0;
  for(int i = 0; i < 10000; ++i) {
    const Metric m = random_metric(rng);
    Five f{{random_point(rng), random_point(rng), random_point(rng), random_point(rng), random_point(rng)}};
    if(i % 2)
      f[4] = point_near_metric_sphere(f, m, rng);
    const CGAL::Oriented_side s0 = side(f, m);
    const CGAL::Orientation o0 = orientation(f[0], f[1], f[2], f[3]);
    for(int a = 0; a < 4; ++a)
      for(int b = a + 1; b < 4; ++b) {
        Five g = f;
        std::swap(g[a], g[b]);
        const CGAL::Oriented_side s1 = side(g, m);
        if(s1 != -s0)
          ++violations;
        if(s1 * orientation(g[0], g[1], g[2], g[3]) != s0 * o0) // bounded side
          ++violations;
      }
    // the lifted determinant is alternating in all five points
    std::array<int, 5> perm{{0, 1, 2, 3, 4}};
    std::shuffle(perm.begin(), perm.end(), rng);
    Five g;
    for(int k = 0; k < 5; ++k)
      g[k] = f[perm[k]];
    if(side(g, m) != permutation_sign(perm) * s0)
      ++violations;
  }
  EXPECT_EQ(violations, 0);
}

// ---------------------------------------------------------------- (6)

TEST(Predicates, RandomMetricsAgainstExactReference)
{
  std::mt19937_64 rng(6);
  int wrong = 0;
  int near = 0;
  for(int i = 0; i < 20000; ++i) {
    const Metric m = random_metric(rng);
    Five f{{random_point(rng), random_point(rng), random_point(rng), random_point(rng), random_point(rng)}};
    if(i % 2) {
      f[4] = point_near_metric_sphere(f, m, rng);
      ++near;
    }
    if(side(f, m) != reference_side(f, m))
      ++wrong;
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(near, 10000);
}

// ---------------------------------------------------------------- (7)

TEST(Predicates, StaticFilterConstant)
{
  const double recomputed = Static_filter::compute_epsilon();
  std::cout.precision(17);
  std::cout << "semi-static filter constant: recomputed " << recomputed << ", hard-coded " << Static_filter::epsilon()
            << "\n";
  EXPECT_GE(Static_filter::epsilon(), recomputed);
  EXPECT_LE(Static_filter::epsilon(), recomputed * (1 + 1e-15));
  // sanity of the error-bound arithmetic on one product of two rounded
  // differences: |error| <= 3u + u^2 (plus the inflation)
  typedef bi::Static_error_bound F;
  const double u = F::unit_roundoff();
  const F product = F(1, u) * F(1, u);
  EXPECT_GE(product.error(), 3 * u + u * u);
  EXPECT_LE(product.error(), 3 * u * (1 + 1e-14));
}

TEST(Predicates, StaticFilterNeverCertifiesAWrongSign)
{
  // Adversarial inputs: co-ellipsoidal sets with large offsets and ulp
  // perturbations, points near random metric spheres, random points. On each
  // one the double determinant must be within eps of the exact one (the
  // derivation of the bound), and a certified sign must be right.
  std::mt19937_64 rng(7);
  int in_range = 0;
  int certified = 0;
  int bound_violations = 0;
  int wrong_certified = 0;
  double worst_ratio = 0;
  auto check = [&](const Five& f, const Coefficients& m) {
    double det;
    double eps;
    if(!static_evaluate(f, m, det, eps))
      return;
    ++in_range;
    // the predicate's 4x4 determinant equals minus the 5x5 lifted one
    const Rational exact = -lifted_determinant_5(f, m);
    const Rational error = CGAL::abs(Rational(det) - exact);
    if(error > Rational(eps))
      ++bound_violations;
    worst_ratio = (std::max)(worst_ratio, CGAL::to_double(error / Rational(eps)));
    CGAL::Oriented_side s;
    if(Static_filter::certified_sign(coordinates(f[0]), coordinates(f[1]), coordinates(f[2]), coordinates(f[3]),
                                     coordinates(f[4]), m, s)) {
      ++certified;
      if(s != CGAL::sign(exact))
        ++wrong_certified;
    }
  };
  for(int trial = 0; trial < 20; ++trial) {
    const Unimodular u = random_unimodular(rng, 6);
    const std::array<double, 3> offset{{1048576.0 * (trial + 1), -7.0 * 1048576, 99.0}};
    const Co_ellipsoidal_set set = co_ellipsoidal_set(u, 50, {{0, 0, 0}}, 0, offset, 99991);
    const Coefficients m = coefficients(set.metric);
    for(int i = 0; i < 300; ++i) {
      Five f = pick_five(set.points, rng);
      std::uniform_int_distribution<int> coordinate(0, 2), ulps(-64, 64);
      f[4] = ulp_perturbed(f[4], coordinate(rng), ulps(rng));
      check(f, m);
    }
  }
  for(int i = 0; i < 20000; ++i) {
    const Metric metric = random_metric(rng);
    Five f{{random_point(rng), random_point(rng), random_point(rng), random_point(rng), random_point(rng)}};
    if(i % 4 != 0)
      f[4] = point_near_metric_sphere(f, metric, rng);
    check(f, coefficients(metric));
  }
  std::cout << "static filter: " << in_range << " in range, " << certified << " certified, worst |error|/eps "
            << worst_ratio << "\n";
  EXPECT_EQ(bound_violations, 0);
  EXPECT_EQ(wrong_certified, 0);
  EXPECT_GT(certified, 4000);
  EXPECT_GT(worst_ratio, 0.0); // the inputs do produce rounding errors
}

// ---------------------------------------------------------------- (8)

TEST(Predicates, SymbolicPerturbation)
{
  std::mt19937_64 rng(8);
  std::uniform_int_distribution<std::size_t> id_dist(0, 1000000);
  auto random_ids = [&]() {
    std::array<std::size_t, 5> id;
    do {
      for(std::size_t& k : id)
        k = id_dist(rng);
    } while(std::set<std::size_t>(id.begin(), id.end()).size() != 5);
    return id;
  };

  int zeros = 0;
  int inconsistent = 0;
  int reference_mismatches = 0;
  int tested = 0;
  std::array<int, 5> identity{{0, 1, 2, 3, 4}};
  for(int trial = 0; trial < 10; ++trial) {
    const Unimodular u = random_unimodular(rng, 5);
    const Co_ellipsoidal_set set = co_ellipsoidal_set(u, 50, {{0, 0, 0}}, 0, {{double(trial), -3.0, 5.0}});
    for(int i = 0; i < 30; ++i) {
      const Five f = pick_five(set.points, rng);
      if(first_four_coplanar(f))
        continue;
      ASSERT_EQ(side(f, set.metric), ZERO_SIDE);
      const std::array<std::size_t, 5> id = random_ids();
      const CGAL::Oriented_side s0 = side_sos(f, set.metric, id);
      ++tested;
      if(s0 == ZERO_SIDE)
        ++zeros;
      if(s0 != reference_side_sos(f, set.metric, id))
        ++reference_mismatches;
      // all 120 permutations of the (point, id) pairs
      std::array<int, 5> perm = identity;
      do {
        Five g;
        std::array<std::size_t, 5> gid;
        for(int k = 0; k < 5; ++k) {
          g[k] = f[perm[k]];
          gid[k] = id[perm[k]];
        }
        if(side_sos(g, set.metric, gid) != permutation_sign(perm) * s0)
          ++inconsistent;
      } while(std::next_permutation(perm.begin(), perm.end()));
      // only the order of the ids matters
      std::array<std::size_t, 5> doubled;
      for(int k = 0; k < 5; ++k)
        doubled[k] = 2 * id[k] + 7;
      if(side_sos(f, set.metric, doubled) != s0)
        ++inconsistent;
    }
  }
  EXPECT_GT(tested, 200);
  EXPECT_EQ(zeros, 0);
  EXPECT_EQ(inconsistent, 0);
  EXPECT_EQ(reference_mismatches, 0);

  // cube corners, M = diag(1, 100, 1): every 5-subset, every id order
  const Metric m = Metric::from_entries(1, 0, 0, 100, 0, 1);
  std::vector<Point> corners;
  for(int i = 0; i < 8; ++i)
    corners.push_back(Point(i & 1, (i >> 1) & 1, (i >> 2) & 1));
  for(int a = 0; a < 8; ++a)
    for(int b = a + 1; b < 8; ++b)
      for(int c = b + 1; c < 8; ++c)
        for(int d = c + 1; d < 8; ++d)
          for(int e = d + 1; e < 8; ++e) {
            const Five f{{corners[a], corners[b], corners[c], corners[d], corners[e]}};
            if(first_four_coplanar(f))
              continue;
            std::array<int, 5> perm = identity;
            do {
              const std::array<std::size_t, 5> id{{std::size_t(perm[0]), std::size_t(perm[1]), std::size_t(perm[2]),
                                                   std::size_t(perm[3]), std::size_t(perm[4])}};
              const CGAL::Oriented_side s = side_sos(f, m, id);
              EXPECT_NE(s, ZERO_SIDE);
              EXPECT_EQ(s, reference_side_sos(f, m, id));
            } while(std::next_permutation(perm.begin(), perm.end()));
          }

  // equal to the unperturbed result whenever that is non-zero
  int differs = 0;
  for(int i = 0; i < 5000; ++i) {
    const Metric metric = random_metric(rng);
    Five f{{random_point(rng), random_point(rng), random_point(rng), random_point(rng), random_point(rng)}};
    if(i % 2)
      f[4] = point_near_metric_sphere(f, metric, rng);
    const CGAL::Oriented_side s = side(f, metric);
    ASSERT_NE(s, ZERO_SIDE);
    if(side_sos(f, metric, random_ids()) != s)
      ++differs;
  }
  EXPECT_EQ(differs, 0);

#if !defined(CGAL_NO_PRECONDITIONS) && !defined(CGAL_NDEBUG) && !defined(NDEBUG)
  EXPECT_THROW(side_sos(Five{{corners[0], corners[1], corners[2], corners[4], corners[7]}}, m, {{0, 1, 2, 3, 3}}),
               CGAL::Precondition_exception);
#endif
}

// ---------------------------------------------------------------- (9)

TEST(Predicates, ExtremeMagnitudesStayExact)
{
  std::mt19937_64 rng(9);
  // (D exponents, point exponent, offset): metric entries from ~1.5e-8
  // (2^-26) to ~1.3e8 (2^27) over the set of metrics, coordinates at the 1e-6
  // (2^-20) and 1e6 (2^20) scales, offsets near 1e6.
  struct Case {
    std::array<int, 3> d;
    int s;
    std::array<double, 3> offset;
  };
  const std::vector<Case> cases = {
      {{{-13, -13, -13}}, 0, {{0, 0, 0}}},          {{{13, 13, 13}}, 0, {{0, 0, 0}}},
      {{{-12, 0, 1}}, 0, {{1000003, -999999, 3}}},  {{{-1, 0, 12}}, 0, {{1000003, 5, -999999}}},
      {{{0, 0, 0}}, -20, {{0, 0, 0}}},              {{{0, 0, 0}}, 20, {{0, 0, 0}}},
      {{{0, 0, 0}}, -20, {{1000003, -999999, 7}}},  {{{-13, -13, -13}}, 20, {{1000003, -999999, 7}}},
      {{{13, 13, 13}}, -20, {{3, -5, 7}}}, {{{-10, 0, 6}}, -20, {{-1000003, 999999, 1}}},
  };
  double min_entry = HUGE_VAL;
  double max_entry = 0;
  int tested = 0;
  int wrong = 0;
  for(const Case& c : cases) {
    // retry the (rare) A for which D A^T A D exceeds Metric_3's anisotropy bound
    Co_ellipsoidal_set set;
    for(int attempt = 0;; ++attempt) {
      ASSERT_LT(attempt, 50);
      try {
        set = co_ellipsoidal_set(random_unimodular(rng, 4, 2), 50, c.d, c.s, c.offset);
        break;
      } catch(const CGAL::Bubble_mesh_3::Invalid_metric&) {
      }
    }
    for(double e : set.metric.entries())
      if(e != 0) {
        min_entry = (std::min)(min_entry, std::abs(e));
        max_entry = (std::max)(max_entry, std::abs(e));
      }
    for(int i = 0; i < 100; ++i) {
      Five f = pick_five(set.points, rng);
      if(first_four_coplanar(f))
        continue;
      if(i % 3 == 1) {
        std::uniform_int_distribution<int> coordinate(0, 2), ulps(-4, 4);
        f[4] = ulp_perturbed(f[4], coordinate(rng), ulps(rng));
      }
      const CGAL::Oriented_side expected = reference_side(f, set.metric);
      if(i % 3 == 0) {
        EXPECT_EQ(expected, ZERO_SIDE);
      }
      ++tested;
      if(side(f, set.metric) != expected)
        ++wrong;
    }
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(tested, 700);
  EXPECT_LT(min_entry, 2e-8);
  EXPECT_GT(max_entry, 1e8);

  // Metric entries 2^-27 .. 2^27 in one matrix (anisotropy 2^54, beyond what
  // Metric_3 accepts): the internal predicate on raw entries.
  {
    const Coefficients m = diagonal_coefficients(std::ldexp(1.0, -27), 1, std::ldexp(1.0, 27));
    // x = (2^13.5 X, Y, 2^-13.5 Z) is not dyadic; use M' with sqrt exponents
    // even: diag(2^-26, 1, 2^26) and x = (2^13 X, Y, 2^-13 Z), |(X,Y,Z)|^2 = 50
    const Coefficients m2 = diagonal_coefficients(std::ldexp(1.0, -26), 1, std::ldexp(1.0, 26));
    std::vector<Point> pts;
    for(const Eigen::Vector3i& y : sphere_points(50))
      pts.push_back(Point(std::ldexp(double(y[0]), 13) + 1000003, y[1] - 999999.0, std::ldexp(double(y[2]), -13)));
    for(int i = 0; i < 300; ++i) {
      Five f = pick_five(pts, rng);
      if(first_four_coplanar(f))
        continue;
      EXPECT_EQ(side(f, m2), ZERO_SIDE);
      EXPECT_EQ(side(f, m2), reference_side(f, m2));
      EXPECT_EQ(side(f, m), reference_side(f, m));
      std::uniform_int_distribution<int> coordinate(0, 2), ulps(-4, 4);
      f[4] = ulp_perturbed(f[4], coordinate(rng), ulps(rng));
      EXPECT_EQ(side(f, m2), reference_side(f, m2));
    }
  }

  // Far outside the range of the semi-static filter: it must abstain, and the
  // interval / exact stages must still be right (overflow, underflow,
  // subnormal differences).
  const std::vector<std::pair<double, double>> scales = {
      {1e-200, 1}, {1e200, 1}, {1, 1e-300}, {1, 1e300}, {1e-150, 1e-300}, {1e150, 1e100}, {1e-310, 1}, {1e-6, 1e-8}};
  int abstained = 0;
  for(const auto& sc : scales) {
    const double scale = sc.first;
    const Coefficients mc{sc.second * 2, sc.second * 0.5, 0, sc.second * 3, -sc.second, sc.second * 5};
    for(int i = 0; i < 200; ++i) {
      Five f;
      for(Point& p : f) {
        const Point r = random_point(rng);
        p = Point(r.x() * scale, r.y() * scale, r.z() * scale);
      }
      if(i % 2) { // exactly co-ellipsoidal: M = I scaled, integer sphere points scaled by a power of two
        const std::vector<Eigen::Vector3i> sp = sphere_points(50);
        const int e = std::ilogb(scale);
        for(Point& p : f) {
          const Eigen::Vector3i& y = sp[std::uniform_int_distribution<std::size_t>(0, sp.size() - 1)(rng)];
          p = Point(std::ldexp(double(y[0]), e), std::ldexp(double(y[1]), e), std::ldexp(double(y[2]), e));
        }
      }
      const Coefficients m = (i % 2) ? Coefficients{sc.second, 0, 0, sc.second, 0, sc.second} : mc;
      double det;
      double eps;
      if(!static_evaluate(f, m, det, eps))
        ++abstained;
      if(side(f, m) != reference_side(f, m))
        ++wrong;
    }
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(abstained, 1200);
}

} // namespace
