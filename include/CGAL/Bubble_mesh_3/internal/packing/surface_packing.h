// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Contract: the 2D stage. `seed_patches` puts on every patch the local
// estimate N = (2/sqrt 3) * metric area (hexagonal packing of unit spacing):
// triangles are split until the metric is nearly constant on them, then filled
// with a hexagonal lattice of the triangle's metric anchored at a fixed point
// (coplanar triangles with the same metric continue the same lattice), or, for
// triangles smaller than a couple of bubbles, by error diffusion of the
// expected count. `Surface_constraint` moves a bubble in its tangent plane and
// projects it back onto its own patch; the patch boundary is a wall along
// which the bubble slides (it never crosses a feature curve, nor settles on one).
// The seeder can also only count (the packer's up-front estimate).
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_SURFACE_PACKING_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_SURFACE_PACKING_H

#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/internal/packing/bubble.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {
namespace packing {

/// a Euclidean orthonormal basis (e1, e2) of the plane of normal n, e1 from a
/// fixed reference axis so that it is the same for parallel planes
inline void tangent_basis(const Vec3& n, Vec3& e1, Vec3& e2)
{
  Vec3 ref = std::abs(n[0]) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  e1 = ref - ref.dot(n) * n;
  e1.normalize();
  e2 = n.cross(e1);
}

/// Cholesky factor (upper, 2x2: l11 l12 / 0 l22) of the metric restricted to span(e1, e2)
struct Plane_metric {
  double l11, l12, l22;
  Plane_metric(const Sym3& m, const Vec3& e1, const Vec3& e2)
  {
    const double g11 = m.squared_length(e1), g22 = m.squared_length(e2), g12 = e1.dot(m * e2);
    l11 = std::sqrt(g11);
    l12 = g12 / l11;
    l22 = std::sqrt(std::max(g22 - l12 * l12, 1e-300 * g22));
  }
  /// tangent coordinates c with L c = y
  void solve(double y1, double y2, double& c1, double& c2) const
  {
    c2 = y2 / l22;
    c1 = (y1 - l12 * c2) / l11;
  }
  double determinant() const { return l11 * l22; }
};

template <typename Oracle>
class Surface_constraint {
public:
  explicit Surface_constraint(const Oracle& oracle) : o_(oracle) {}

  void move(Bubble_record& b, const Vec3& delta) const
  {
    // The step is M^-1 times the energy's gradient; at an equilibrium on the
    // patch that gradient is normal to it, so the step is along M^-1 n. It is
    // projected on the tangent plane along M^-1 n (the projection orthogonal
    // in the metric), which leaves nothing of it there. The Euclidean
    // projection would leave a tangential push wherever the metric is oblique
    // to the patch (a shock crossing a wall): the bubbles would drift to the
    // iteration cap instead of settling.
    const Vec3 mn = b.m.inverse() * b.n;
    const double nmn = b.n.dot(mn);
    const Vec3 d = nmn > 0 ? Vec3(delta - (delta.dot(b.n) / nmn) * mn) : Vec3(delta - delta.dot(b.n) * b.n);
    const Vec3 target = b.x + d;
    const auto pr = o_.project_on_patch(b.entity, target);
    if(stopped_by_boundary(target, pr, d.norm())) {
      // the patch's boundary (a feature curve) is a wall: the bubble slides
      // along it (the outward part of the step is dropped), never onto it
      Vec3 t = target - pr.first;
      t -= t.dot(pr.second) * pr.second;
      const double lt = t.norm();
      if(!(lt > 0))
        return;
      t /= lt;
      const Vec3 d2 = d - std::max(0.0, d.dot(t)) * t;
      const Vec3 target2 = b.x + d2;
      const auto pr2 = o_.project_on_patch(b.entity, target2);
      if(stopped_by_boundary(target2, pr2, d2.norm()))
        return;
      b.x = pr2.first;
      b.n = pr2.second;
      return;
    }
    b.x = pr.first;
    b.n = pr.second;
  }

  int probe_directions(const Bubble_record& b, Vec3* out) const
  {
    Vec3 e1, e2;
    tangent_basis(b.n, e1, e2);
    const Plane_metric pm(b.m, e1, e2);
    for(int k = 0; k < 24; ++k) {
      const double a = k * (3.14159265358979323846 / 12);
      double c1, c2;
      pm.solve(std::cos(a), std::sin(a), c1, c2);
      out[k] = c1 * e1 + c2 * e2;
    }
    return 24;
  }

  bool place(Bubble_record& b, const Vec3& p) const
  {
    const auto pr = o_.project_on_patch(b.entity, p);
    if(stopped_by_boundary(p, pr, (p - b.x).norm()))
      return false;
    b.x = pr.first;
    b.n = pr.second;
    return true;
  }

private:
  // The closest point of the patch is on its boundary when the residual has a
  // tangential part (inside a face, or across a smooth interior edge, the
  // residual is normal to the closest face); 2% of the step is left for
  // rounding and vertices of curved patches.
  static bool stopped_by_boundary(const Vec3& target, const std::pair<Vec3, Vec3>& pr, double step)
  {
    const Vec3 r = target - pr.first;
    const Vec3 t = r - r.dot(pr.second) * pr.second;
    return t.norm() > 0.02 * step + 1e-12 * (target.norm() + 1);
  }

  const Oracle& o_;
};

template <typename Oracle, typename Refresh>
class Patch_seeder {
public:
  /// `count_only`: only sums the expected number (nothing is appended to `out`)
  Patch_seeder(const Oracle& o, const Refresh& refresh, const Vec3& anchor, const Vec3& offset, double limit,
               std::vector<Bubble_record>& out, bool count_only = false)
      : o_(o), refresh_(refresh), anchor_(anchor), offset_(offset), limit_(limit), out_(out), count_only_(count_only)
  {}

  /// seeds every patch; returns the expected number of surface bubbles
  double run()
  {
    for(std::size_t k = 0; k < o_.patches().size(); ++k)
      run(static_cast<int>(k));
    return expected_;
  }

  /// seeds patch k; returns its expected number of bubbles
  double run(int k)
  {
    const double before = expected_;
    accumulator_ = 0.5;
    for(const auto& t : o_.patches()[k].triangles) {
      typedef typename Oracle::K K;
      triangle(k, to_vec<K>(t.vertex(0)), to_vec<K>(t.vertex(1)), to_vec<K>(t.vertex(2)), 0);
    }
    return expected_ - before;
  }

private:
  void triangle(int patch, const Vec3& a, const Vec3& b, const Vec3& c, int depth)
  {
    Vec3 n = (b - a).cross(c - a);
    const double area = 0.5 * n.norm();
    if(!(area > 0))
      return;
    n.normalize();
    const Vec3 g = (a + b + c) / 3;
    const Sym3 m = refresh_.at(g);
    Vec3 e1, e2;
    tangent_basis(n, e1, e2);
    const Plane_metric pm(m, e1, e2);
    const double expected = (2 / std::sqrt(3.0)) * area * pm.determinant();
    if(depth < 10) {
      bool split = expected > 128;
      if(!split) {
        // Split where the metric varies, unless the triangle holds fewer than
        // 2 bubbles at its finest vertex too. (The count at the centroid alone
        // is not enough: with a strong grading, e.g. size 1e-3 at a corner and
        // 1 at the centroid, the triangle was never split, its corner region
        // got no seed and the surface no bubble at all.)
        const double d0 = m.sqrt_determinant();
        double finest = pm.determinant();
        bool varies = false;
        for(const Vec3* v : {&a, &b, &c}) {
          const Sym3 mv = refresh_.at(*v);
          const double dv = mv.sqrt_determinant();
          if(dv > 1.3 * d0 || d0 > 1.3 * dv)
            varies = true;
          finest = std::max(finest, Plane_metric(mv, e1, e2).determinant());
        }
        split = varies && (2 / std::sqrt(3.0)) * area * finest > 2;
      }
      if(split) {
        const Vec3 ab = 0.5 * (a + b), bc = 0.5 * (b + c), ca = 0.5 * (c + a);
        triangle(patch, a, ab, ca, depth + 1);
        triangle(patch, ab, b, bc, depth + 1);
        triangle(patch, ca, bc, c, depth + 1);
        triangle(patch, ab, bc, ca, depth + 1);
        return;
      }
    }
    expected_ += expected;
    if(expected_ > limit_)
      throw Too_many_nodes(expected_, limit_); // the packer adds the other stages' counts
    if(count_only_)
      return;
    if(expected < 2) {
      accumulator_ += expected;
      while(accumulator_ >= 1) {
        accumulator_ -= 1;
        push(patch, g, n);
      }
      return;
    }
    // hexagonal lattice in metric coordinates y = L (c1, c2) of the plane
    const Vec3 o = anchor_ - (anchor_ - a).dot(n) * n;
    auto to_y = [&](const Vec3& p, double& y1, double& y2) {
      const double c1 = (p - o).dot(e1), c2 = (p - o).dot(e2);
      y1 = pm.l11 * c1 + pm.l12 * c2;
      y2 = pm.l22 * c2;
    };
    double ya[2], yb[2], yc[2];
    to_y(a, ya[0], ya[1]);
    to_y(b, yb[0], yb[1]);
    to_y(c, yc[0], yc[1]);
    const double h = std::sqrt(3.0) / 2;
    const double lo2 = std::min({ya[1], yb[1], yc[1]}), hi2 = std::max({ya[1], yb[1], yc[1]});
    const double lo1 = std::min({ya[0], yb[0], yc[0]}), hi1 = std::max({ya[0], yb[0], yc[0]});
    const double det = (yb[0] - ya[0]) * (yc[1] - ya[1]) - (yc[0] - ya[0]) * (yb[1] - ya[1]);
    for(long j = long(std::floor((lo2 - offset_[1]) / h)); j <= long(std::ceil((hi2 - offset_[1]) / h)); ++j) {
      const double y2 = offset_[1] + j * h;
      const double shift = offset_[0] + 0.5 * double(j & 1);
      for(long i = long(std::floor(lo1 - shift)); i <= long(std::ceil(hi1 - shift)); ++i) {
        const double y1 = shift + double(i);
        // barycentric coordinates in the y plane
        const double u = ((y1 - ya[0]) * (yc[1] - ya[1]) - (yc[0] - ya[0]) * (y2 - ya[1])) / det;
        const double v = ((yb[0] - ya[0]) * (y2 - ya[1]) - (y1 - ya[0]) * (yb[1] - ya[1])) / det;
        if(u < 0 || v < 0 || u + v > 1)
          continue;
        push(patch, a + u * (b - a) + v * (c - a), n);
      }
    }
  }

  void push(int patch, const Vec3& p, const Vec3& n)
  {
    Bubble_record r;
    r.dimension = 2;
    r.entity = patch;
    r.x = p;
    r.n = n;
    refresh_(r);
    out_.push_back(r);
  }

  const Oracle& o_;
  const Refresh& refresh_;
  Vec3 anchor_, offset_;
  double limit_;
  std::vector<Bubble_record>& out_;
  bool count_only_;
  double accumulator_ = 0.5;
  double expected_ = 0;
};

} // namespace packing
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_SURFACE_PACKING_H
