// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Contract: the 3D stage. `Volume_seeder` applies the paper's estimate
// N = alpha V / V_b locally: an octree over the domain's bounding box is split
// until the metric is nearly constant on a cell and the cell holds at most a
// few hundred bubbles; each leaf is filled with the face-centred cubic lattice
// (nearest distance 1, the densest packing, sqrt(2) nodes per unit metric
// volume) of its centre metric, anchored at one fixed point so that cells of
// equal metric continue the same lattice. Seeds outside the domain, or closer
// to the boundary than half their smallest size, are dropped.
// `Volume_estimator` computes the expected interior count over the domain
// without making bubbles (the packer's up-front estimate).
// `Volume_constraint` moves a bubble and never lets it leave its subdomain: a
// bubble farther from the boundary than its step moves freely (the known
// clearance shrinks by the step); otherwise the step is tested with the
// domain's inside test and halved up to twice, else the bubble stays.
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_VOLUME_PACKING_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_VOLUME_PACKING_H

#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/internal/packing/bubble.h>
#include <CGAL/Bubble_mesh_3/internal/packing/metric_samples.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {
namespace packing {

/// the 26 directions of the cube's neighbours, unit length
inline const std::array<Vec3, 26>& probe_directions_26()
{
  static const std::array<Vec3, 26> dirs = [] {
    std::array<Vec3, 26> d;
    int k = 0;
    for(int x = -1; x <= 1; ++x)
      for(int y = -1; y <= 1; ++y)
        for(int z = -1; z <= 1; ++z)
          if(x || y || z)
            d[k++] = Vec3(x, y, z).normalized();
    return d;
  }();
  return dirs;
}

// Calls f(a, b) for the eight octant boxes of the box [lo, hi] split at c.
template <typename F>
void for_each_octant(const Vec3& lo, const Vec3& c, const Vec3& hi, F&& f)
{
  for(int k = 0; k < 8; ++k) {
    Vec3 a, b;
    for(int d = 0; d < 3; ++d) {
      const bool upper = (k >> d) & 1;
      a[d] = upper ? c[d] : lo[d];
      b[d] = upper ? hi[d] : c[d];
    }
    f(a, b);
  }
}

template <typename Oracle>
class Volume_constraint {
public:
  explicit Volume_constraint(const Oracle& oracle) : o_(oracle) {}

  void move(Bubble_record& b, Vec3 delta) const
  {
    const double len = delta.norm();
    if(len < b.clearance) {
      b.x += delta;
      b.clearance -= len;
      return;
    }
    for(int k = 0; k < 3; ++k, delta *= 0.5) {
      const Vec3 p = b.x + delta;
      const auto sub = o_.subdomain(p);
      if(sub && static_cast<int>(*sub) == b.entity) {
        b.x = p;
        b.clearance = o_.distance_to_boundary(p);
        return;
      }
    }
  }

  int probe_directions(const Bubble_record& b, Vec3* out) const
  {
    const Eigen::Matrix3d q = b.m.cholesky_upper();
    const auto& dirs = probe_directions_26();
    for(int k = 0; k < 26; ++k)
      out[k] = solve_upper(q, dirs[k]);
    return 26;
  }

  bool place(Bubble_record& b, const Vec3& p) const
  {
    const auto sub = o_.subdomain(p);
    if(!sub)
      return false;
    b.x = p;
    b.entity = static_cast<int>(*sub);
    b.clearance = o_.distance_to_boundary(p);
    return true;
  }

private:
  const Oracle& o_;
};

/// The expected number of interior bubbles sqrt(2) * int_domain sqrt(det M),
/// cheaply (no bubble is made): an octree over [lo, hi] split where the metric
/// varies; a cell whose centre is farther from the boundary than its half
/// diagonal is wholly inside or outside (one inside test); a cell crossing the
/// boundary is split a few times, then counted by the fraction of 8 sample
/// points inside. Stops as soon as the sum exceeds `stop` (the caller refuses).
template <typename Oracle, typename Refresh>
class Volume_estimator {
public:
  Volume_estimator(const Oracle& o, const Refresh& refresh, const Metric_samples& samples, double stop)
      : o_(o), refresh_(refresh), samples_(samples), stop_(stop)
  {}

  double run(const Vec3& lo, const Vec3& hi)
  {
    cell(lo, hi, 0, samples_.all());
    return total_;
  }

private:
  void cell(const Vec3& lo, const Vec3& hi, int depth, const std::vector<int>& candidates)
  {
    if(total_ > stop_)
      return;
    const Vec3 c = 0.5 * (lo + hi);
    const Sym3 m = refresh_.at(c);
    const double d0 = m.sqrt_determinant();
    const double expected = std::sqrt(2.0) * d0 * (hi - lo).prod();
    // side: 1 inside, -1 outside, 0 crossing the boundary (or unknown)
    int side = 0;
    if(o_.has_distance() && o_.distance_to_boundary(c) > 0.5 * (hi - lo).norm())
      side = o_.is_inside(c) ? 1 : -1;
    if(side < 0)
      return;
    // split where the metric varies unless the cell holds fewer than 4
    // bubbles at its finest corner too (see Volume_seeder::cell)
    bool split = false;
    std::vector<int> inside;
    if(depth < 16) {
      double finest = d0;
      bool varies = false;
      for(int k = 0; k < 8; ++k) {
        const Vec3 v(k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]);
        const double dv = refresh_.at(v).sqrt_determinant();
        varies = varies || dv > 1.25 * d0 || d0 > 1.25 * dv;
        finest = std::max(finest, dv);
      }
      samples_.test_cell(candidates, lo, hi, d0, 1.25, finest, varies, inside);
      split = varies && std::sqrt(2.0) * finest * (hi - lo).prod() > 4;
    }
    if(side == 0 && depth < 4 && expected > 8)
      split = true;
    if(split) {
      for_each_octant(lo, c, hi, [&](const Vec3& a, const Vec3& b) { cell(a, b, depth + 1, inside); });
      return;
    }
    double fraction = 1;
    if(side == 0) {
      int inside = 0;
      for(int k = 0; k < 8; ++k) {
        const Vec3 v(k & 1 ? 0.75 : 0.25, k & 2 ? 0.75 : 0.25, k & 4 ? 0.75 : 0.25);
        inside += o_.is_inside(lo + v.cwiseProduct(hi - lo)) ? 1 : 0;
      }
      fraction = inside / 8.0;
    }
    total_ += fraction * expected;
  }

  const Oracle& o_;
  const Refresh& refresh_;
  const Metric_samples& samples_;
  double stop_;
  double total_ = 0;
};

template <typename Oracle, typename Refresh>
class Volume_seeder {
public:
  Volume_seeder(const Oracle& o, const Refresh& refresh, const Metric_samples& samples, const Vec3& anchor,
                const Vec3& offset, double limit, std::vector<Bubble_record>& out)
      : o_(o), refresh_(refresh), samples_(samples), anchor_(anchor), offset_(offset), limit_(limit), out_(out),
        first_(out.size())
  {}

  /// seeds the bounding box [lo, hi]; returns the expected count sqrt(2) * int sqrt(det M) over it
  double run(const Vec3& lo, const Vec3& hi)
  {
    cell(lo, hi, 0, samples_.all());
    return expected_;
  }

private:
  void cell(const Vec3& lo, const Vec3& hi, int depth, const std::vector<int>& candidates)
  {
    const Vec3 c = 0.5 * (lo + hi);
    const Vec3 size = hi - lo;
    const Sym3 m = refresh_.at(c);
    const double expected = std::sqrt(2.0) * m.sqrt_determinant() * size.prod();
    if(depth < 16) {
      bool split = expected > 512;
      std::vector<int> inside;
      if(!split) {
        // Split where the metric varies, unless the cell holds fewer than 4
        // bubbles at its finest corner too. (Testing the count at the centre
        // alone left a strongly graded region unseeded: size 1e-3 at a corner
        // of the unit cube and 1 at its centre gave no interior seed at all.)
        const double d0 = m.sqrt_determinant();
        double finest = d0;
        bool varies = false;
        for(int k = 0; k < 8; ++k) {
          const Vec3 v(k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]);
          const double dv = refresh_.at(v).sqrt_determinant();
          varies = varies || dv > 1.25 * d0 || d0 > 1.25 * dv;
          finest = std::max(finest, dv);
        }
        samples_.test_cell(candidates, lo, hi, d0, 1.25, finest, varies, inside);
        split = varies && std::sqrt(2.0) * finest * size.prod() > 4;
      } else
        samples_.select(candidates, lo, hi, inside);
      if(split) {
        for_each_octant(lo, c, hi, [&](const Vec3& a, const Vec3& b) { cell(a, b, depth + 1, inside); });
        return;
      }
    }
    expected_ += expected;
    leaf(lo, hi, m);
    // the packer refuses too large estimates before any work; this guards the
    // memory against an estimate that was far too low
    if(double(out_.size() - first_) > limit_)
      throw Too_many_nodes(double(out_.size() - first_), limit_); // the packer adds the other stages' counts
  }

  void leaf(const Vec3& lo, const Vec3& hi, const Sym3& m)
  {
    const Vec3 c = 0.5 * (lo + hi);
    const double half_diagonal = 0.5 * (hi - lo).norm();
    // classify the whole cell when it is far from the boundary
    int side = 0; // 1 all inside, -1 all outside, 0 test each point
    double dc = 0;
    if(o_.has_distance()) {
      dc = o_.distance_to_boundary(c);
      if(dc > half_diagonal)
        side = o_.is_inside(c) ? 1 : -1;
    }
    if(side < 0)
      return;
    const Eigen::Matrix3d q = m.cholesky_upper();
    const double h_min = smallest_principal_size(m);
    // FCC lattice y = (a/2)(i, j, k) + offset, i + j + k even, a = sqrt 2
    Vec3 ylo = Vec3::Constant(1e300), yhi = Vec3::Constant(-1e300);
    for(int k = 0; k < 8; ++k) {
      const Vec3 v(k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]);
      const Vec3 y = q.triangularView<Eigen::Upper>() * (v - anchor_);
      ylo = ylo.cwiseMin(y);
      yhi = yhi.cwiseMax(y);
    }
    const double step = std::sqrt(2.0) / 2;
    std::array<long, 3> i0, i1;
    for(int d = 0; d < 3; ++d) {
      i0[d] = long(std::floor((ylo[d] - offset_[d]) / step));
      i1[d] = long(std::ceil((yhi[d] - offset_[d]) / step));
    }
    for(long i = i0[0]; i <= i1[0]; ++i)
      for(long j = i0[1]; j <= i1[1]; ++j)
        for(long k = i0[2]; k <= i1[2]; ++k) {
          if((i + j + k) & 1)
            continue;
          const Vec3 y = offset_ + step * Vec3(double(i), double(j), double(k));
          const Vec3 x = anchor_ + solve_upper(q, y);
          if(x[0] < lo[0] || x[1] < lo[1] || x[2] < lo[2] || x[0] >= hi[0] || x[1] >= hi[1] || x[2] >= hi[2])
            continue;
          Bubble_record r;
          r.dimension = 3;
          r.x = x;
          if(side > 0) {
            r.clearance = dc - (x - c).norm();
            if(r.clearance < 0.5 * h_min)
              continue;
            r.entity = entity_of_inside(c);
          } else {
            const auto sub = o_.subdomain(x);
            if(!sub)
              continue;
            r.clearance = o_.distance_to_boundary(x);
            if(o_.has_distance() && r.clearance < 0.5 * h_min)
              continue;
            r.entity = static_cast<int>(*sub);
          }
          r.m = m;
          r.h_max = largest_principal_size(m);
          out_.push_back(r);
        }
  }

  int entity_of_inside(const Vec3& c)
  {
    if(!(c == last_center_)) {
      last_center_ = c;
      last_entity_ = static_cast<int>(*o_.subdomain(c));
    }
    return last_entity_;
  }

  const Oracle& o_;
  const Refresh& refresh_;
  const Metric_samples& samples_;
  Vec3 anchor_, offset_;
  double limit_;
  std::vector<Bubble_record>& out_;
  std::size_t first_;
  double expected_ = 0;
  Vec3 last_center_ = Vec3::Constant(1e300);
  int last_entity_ = 0;
};

} // namespace packing
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_VOLUME_PACKING_H
