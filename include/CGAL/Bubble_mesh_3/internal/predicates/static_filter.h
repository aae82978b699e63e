// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Error-bound arithmetic used to derive the constants of semi-static filters.
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PREDICATES_STATIC_FILTER_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PREDICATES_STATIC_FILTER_H

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

// A number type that runs a polynomial expression on *bounds* instead of
// values, to derive the error constant of a semi-static filter.
//
// Each variable x stands for a double x' computed by the same expression in
// round-to-nearest arithmetic, measured in a unit U that the filter fixes at
// run time (e.g. the largest |coordinate difference|):
//   bound():  |x'| <= bound() * U
//   error():  |x' - x| <= error() * U,   x the value in exact arithmetic.
// The rules only use the standard model |fl(a op b) - (a op b)| <= u |a op b|,
// u = 2^-53, which holds at every scale as long as nothing overflows and
// nothing underflows (the filter checks ranges for that), so the constant is
// valid for any unit, not only powers of two. With a' and b' the computed
// operands:
//   a + b:  |a'+b'| <= Ba + Bb,  rounding <= u (Ba + Bb),  E = Ea + Eb + u (Ba + Bb)
//   a * b:  |a' b' - a b| <= Ba Eb + Bb Ea + Ea Eb,          E += u Ba Bb
// The computed magnitude is bounded with (1 + 2u) >= (1 + u), as 1 + u is not
// a double. The bound arithmetic itself runs in round-to-nearest; every
// result is inflated by (1 + 4u), which keeps it an upper bound (a rounded
// nonnegative result is at most a factor (1 - u) too small). No rounding-mode switch is needed, so
// constant folding by the compiler cannot break it.
class Static_error_bound {
public:
  static constexpr double unit_roundoff() { return 1.0 / 9007199254740992.0; } // 2^-53

  Static_error_bound() : bound_(0), error_(0) {}
  // a variable with |x'| <= bound and |x' - x| <= error (in units of U)
  Static_error_bound(double bound, double error = 0) : bound_(bound), error_(error) {}

  double bound() const { return bound_; }
  double error() const { return error_; }

  friend Static_error_bound operator+(const Static_error_bound& a, const Static_error_bound& b)
  {
    const double s = up(a.bound_ + b.bound_);
    return Static_error_bound(up(s * (1 + 2 * unit_roundoff())),
                              up(up(a.error_ + b.error_) + up(unit_roundoff() * s)));
  }
  // |a - b| obeys the same bounds as |a + b|
  friend Static_error_bound operator-(const Static_error_bound& a, const Static_error_bound& b)
  {
    return a + b;
  }
  friend Static_error_bound operator-(const Static_error_bound& a) { return a; }
  friend Static_error_bound operator*(const Static_error_bound& a, const Static_error_bound& b)
  {
    const double p = up(a.bound_ * b.bound_);
    const double propagated =
        up(up(up(a.bound_ * b.error_) + up(b.bound_ * a.error_)) + up(a.error_ * b.error_));
    return Static_error_bound(up(p * (1 + 2 * unit_roundoff())),
                              up(propagated + up(unit_roundoff() * p)));
  }

  // Inflate a nonnegative double computed with one rounding to nearest so that
  // it bounds the exact value from above.
  static double up(double x) { return x * (1 + 4 * unit_roundoff()); }

private:
  double bound_;
  double error_;
};

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PREDICATES_STATIC_FILTER_H
