// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Contract: the 1D stage. `seed_curves` places, on every feature curve, the
// number of bubbles its metric length asks for, evenly in metric arc length
// (the 1D packing is then already nearly at rest); `Curve_constraint` moves a
// bubble along its curve (arc length parameter, ends fixed, loops wrap).
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_CURVE_PACKING_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_CURVE_PACKING_H

#include <CGAL/Bubble_mesh_3/internal/packing/bubble.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {
namespace packing {

template <typename Oracle>
class Curve_constraint {
public:
  explicit Curve_constraint(const Oracle& oracle) : o_(oracle) {}

  void move(Bubble_record& b, const Vec3& delta) const
  {
    // the projection on the tangent orthogonal in the metric (as on patches:
    // the step M^-1 g of an equilibrium, g normal to the curve, gives 0)
    const Vec3 t = o_.curve_tangent(b.entity, b.s);
    const double tmt = b.m.squared_length(t);
    const double along = tmt > 0 ? t.dot(b.m * delta) / tmt : t.dot(delta);
    b.s = o_.normalize_arc_length(b.entity, b.s + along);
    b.x = o_.curve_point(b.entity, b.s);
  }

  int probe_directions(const Bubble_record& b, Vec3* out) const
  {
    Vec3 t = o_.curve_tangent(b.entity, b.s);
    t /= b.m.length(t);
    out[0] = t;
    out[1] = -t;
    return 2;
  }

  bool place(Bubble_record& b, const Vec3& p) const
  {
    const Vec3 t = o_.curve_tangent(b.entity, b.s);
    const double s = b.s + t.dot(p - b.x);
    if(!o_.curves()[b.entity].loop && (s <= 0 || s >= o_.curves()[b.entity].length))
      return false;
    b.s = o_.normalize_arc_length(b.entity, s);
    b.x = o_.curve_point(b.entity, b.s);
    return true;
  }

private:
  const Oracle& o_;
};

/// the sum over the curves of their metric lengths (the expected number of
/// curve bubbles; the packer's up-front estimate)
template <typename Oracle, typename Refresh>
double curve_metric_length(const Oracle& o, const Refresh& refresh)
{
  double total = 0;
  for(const auto& cv : o.curves())
    for(std::size_t k = 0; k + 1 < cv.p.size(); ++k)
      total += refresh.at(0.5 * (cv.p[k] + cv.p[k + 1])).length(cv.p[k + 1] - cv.p[k]);
  return total;
}

/// Appends the curve bubbles (moving) to `bubbles`; returns the sum over the
/// curves of their metric lengths.
template <typename Oracle, typename Refresh>
double seed_curves(const Oracle& o, const Refresh& refresh, std::vector<Bubble_record>& bubbles)
{
  double total = 0;
  for(std::size_t c = 0; c < o.curves().size(); ++c) {
    const auto& cv = o.curves()[c];
    const std::size_t ns = cv.s.size();
    std::vector<double> lambda(ns, 0.0); // metric arc length at the samples
    for(std::size_t k = 0; k + 1 < ns; ++k) {
      const Sym3 m = refresh.at(0.5 * (cv.p[k] + cv.p[k + 1]));
      lambda[k + 1] = lambda[k] + m.length(cv.p[k + 1] - cv.p[k]);
    }
    const double lm = lambda.back();
    total += lm;
    const long segments = cv.loop ? std::max(3L, std::lround(lm)) : std::max(1L, std::lround(lm));
    const long first = cv.loop ? 0 : 1;
    for(long k = first; k < segments; ++k) {
      const double target = lm * double(k) / double(segments);
      std::size_t j = std::upper_bound(lambda.begin(), lambda.end(), target) - lambda.begin();
      j = std::min(std::max<std::size_t>(j, 1), ns - 1);
      const double dl = lambda[j] - lambda[j - 1];
      const double t = dl > 0 ? (target - lambda[j - 1]) / dl : 0;
      Bubble_record b;
      b.dimension = 1;
      b.entity = static_cast<int>(c);
      b.s = o.normalize_arc_length(static_cast<int>(c), cv.s[j - 1] + t * (cv.s[j] - cv.s[j - 1]));
      b.x = o.curve_point(static_cast<int>(c), b.s);
      refresh(b);
      bubbles.push_back(b);
    }
  }
  return total;
}

} // namespace packing
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_CURVE_PACKING_H
