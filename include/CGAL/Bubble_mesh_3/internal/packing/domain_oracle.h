// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Contract: what the packer asks a domain, behind one interface.
//  - corners (position, Corner_index);
//  - curves, each sampled once by arc length through
//    `construct_point_on_curve` into a table (positions and unit tangents for
//    the 1D dynamics); exact positions are taken from the domain at the end;
//  - surface patches as triangle sets with one AABB tree each, for projection
//    restricted to one patch (a bubble never leaves its patch);
//  - the inside test (`is_in_domain_object`) and, when the surface is known as
//    triangles, the distance to the boundary (one AABB tree over all patches),
//    which lets volume bubbles skip the inside test while they are far from it.
// Domains whose patches are given as triangles: Polyhedral_mesh_domain_with_features_3
// (patch ids from detect_features). Other domains (implicit, Labeled_mesh_domain_3
// with polyline features) give their patches as a triangle soup built from the
// domain's own inside test and surface-patch oracle (`Surface_triangulator`
// below); the soup is then only a guide (projection, seeding, distance less a
// margin) and surface nodes are put on the exact surface at the end of the
// stage (`exact_surface_point`, bisection with the inside test).
// Every query is const and thread-safe once the constructor returned.
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_DOMAIN_ORACLE_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_DOMAIN_ORACLE_H

#include <CGAL/Bubble_mesh_3/internal/packing/bubble.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/properties.h>

#include <boost/optional.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <map>
#include <memory>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {
namespace packing {

template <typename K>
inline Vec3 to_vec(const typename K::Point_3& p)
{
  return Vec3(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
}

// Detects Polyhedral_mesh_domain_with_features_3-like domains (polyhedra()).
template <typename D, typename = void>
struct Has_polyhedra : std::false_type {};
template <typename D>
struct Has_polyhedra<D, std::void_t<decltype(std::declval<const D&>().polyhedra())>> : std::true_type {};

/// A triangle of a surface patch (double precision).
struct Patch_triangle {
  Vec3 a, b, c;
};

template <typename MeshDomain>
class Domain_oracle {
public:
  typedef MeshDomain Mesh_domain;
  typedef typename Mesh_domain::R K;
  typedef typename K::Point_3 Point_3;
  typedef typename K::Triangle_3 Triangle_3;
  typedef typename Mesh_domain::Corner_index Corner_index;
  typedef typename Mesh_domain::Curve_index Curve_index;
  typedef typename Mesh_domain::Surface_patch_index Surface_patch_index;
  typedef typename Mesh_domain::Subdomain_index Subdomain_index;
  typedef typename Mesh_domain::Index Index;

  typedef typename std::vector<Triangle_3>::const_iterator Triangle_iterator;
  typedef CGAL::AABB_triangle_primitive<K, Triangle_iterator> Primitive;
  typedef CGAL::AABB_traits<K, Primitive> Tree_traits;
  typedef CGAL::AABB_tree<Tree_traits> Tree;

  struct Corner {
    Corner_index index;
    Point_3 point;
  };
  struct Curve {
    Curve_index index;
    Point_3 start;
    double length = 0;
    bool loop = false;
    std::vector<double> s;  // arc length of the samples
    std::vector<Vec3> p;    // sample positions
  };
  struct Patch {
    Surface_patch_index index;
    std::vector<Triangle_3> triangles;
    std::unique_ptr<Tree> tree;
  };

  /// `curve_samples`: samples per curve for the arc-length table (at least);
  /// `patches`: the triangles of every surface patch; `surface_tolerance`: how
  /// far these triangles may be from the domain's surface (0: they are the
  /// surface; else distances are reduced by it and surface nodes are moved
  /// onto the exact surface by `exact_surface_point`)
  Domain_oracle(const Mesh_domain& domain, std::size_t curve_samples,
                std::vector<std::pair<Surface_patch_index, std::vector<Triangle_3>>> patches,
                double surface_tolerance = 0)
      : domain_(domain), tolerance_(surface_tolerance)
  {
    std::vector<std::pair<Corner_index, Point_3>> corners;
    domain.get_corners(std::back_inserter(corners));
    for(const auto& c : corners)
      corners_.push_back(Corner{c.first, c.second});

    typedef std::tuple<Curve_index, std::pair<Point_3, Index>, std::pair<Point_3, Index>> Curve_tuple;
    std::vector<Curve_tuple> curves;
    domain.get_curves(std::back_inserter(curves));
    for(const auto& t : curves) {
      Curve c;
      c.index = std::get<0>(t);
      c.start = std::get<1>(t).first;
      c.length = CGAL::to_double(domain.curve_length(c.index));
      c.loop = domain.is_loop(c.index);
      const std::size_t n = std::max<std::size_t>(2, curve_samples);
      for(std::size_t k = 0; k <= n; ++k) {
        const double s = c.length * double(k) / double(n);
        c.s.push_back(s);
        if(k == 0)
          c.p.push_back(to_vec<K>(c.start));
        else if(k == n && !c.loop)
          c.p.push_back(to_vec<K>(std::get<2>(t).first));
        else if(k == n)
          c.p.push_back(c.p.front());
        else
          c.p.push_back(to_vec<K>(domain.construct_point_on_curve(c.start, c.index, s)));
      }
      curves_.push_back(std::move(c));
    }

    for(auto& pt : patches) {
      Patch patch;
      patch.index = pt.first;
      patch.triangles = std::move(pt.second);
      patches_.push_back(std::move(patch));
    }
    for(Patch& patch : patches_) {
      patch.tree = std::make_unique<Tree>(patch.triangles.begin(), patch.triangles.end());
      patch.tree->accelerate_distance_queries();
      if(!patch.triangles.empty())
        patch.tree->closest_point(patch.triangles.front().vertex(0));
      all_triangles_.insert(all_triangles_.end(), patch.triangles.begin(), patch.triangles.end());
    }
    all_tree_ = std::make_unique<Tree>(all_triangles_.begin(), all_triangles_.end());
    all_tree_->accelerate_distance_queries();
    if(!all_triangles_.empty())
      all_tree_->closest_point(all_triangles_.front().vertex(0));
    // warm up the domain's own lazily built structures before threads use them
    const CGAL::Bbox_3 bb = domain.bbox();
    is_inside(Vec3(bb.xmin(), bb.ymin(), bb.zmin()));
  }

  const Mesh_domain& domain() const { return domain_; }
  const std::vector<Corner>& corners() const { return corners_; }
  const std::vector<Curve>& curves() const { return curves_; }
  const std::vector<Patch>& patches() const { return patches_; }

  // ---- curves
  /// index of the table segment holding arc length s
  std::size_t curve_segment(int c, double s) const
  {
    const Curve& cv = curves_[c];
    std::size_t k = std::upper_bound(cv.s.begin(), cv.s.end(), s) - cv.s.begin();
    k = std::min(std::max<std::size_t>(k, 1), cv.s.size() - 1);
    return k - 1;
  }
  /// wraps (loops) or clamps (open curves, strictly inside) an arc length
  double normalize_arc_length(int c, double s) const
  {
    const Curve& cv = curves_[c];
    if(cv.loop) {
      s = std::fmod(s, cv.length);
      if(s < 0)
        s += cv.length;
      return s;
    }
    const double eps = 1e-9 * cv.length;
    return std::min(std::max(s, eps), cv.length - eps);
  }
  Vec3 curve_point(int c, double s) const
  {
    const Curve& cv = curves_[c];
    const std::size_t k = curve_segment(c, s);
    const double ds = cv.s[k + 1] - cv.s[k];
    const double t = ds > 0 ? (s - cv.s[k]) / ds : 0;
    return (1 - t) * cv.p[k] + t * cv.p[k + 1];
  }
  Vec3 curve_tangent(int c, double s) const
  {
    const Curve& cv = curves_[c];
    const std::size_t k = curve_segment(c, s);
    Vec3 t = cv.p[k + 1] - cv.p[k];
    const double l = t.norm();
    return l > 0 ? Vec3(t / l) : Vec3(1, 0, 0);
  }
  /// exact point of the domain's curve at arc length s from the start
  Point_3 exact_curve_point(int c, double s) const
  {
    return domain_.construct_point_on_curve(curves_[c].start, curves_[c].index, s);
  }

  // ---- patches
  /// closest point of patch `k` to p, and the unit normal of its triangle
  std::pair<Vec3, Vec3> project_on_patch(int k, const Vec3& p) const
  {
    const auto pp = patches_[k].tree->closest_point_and_primitive(Point_3(p[0], p[1], p[2]));
    const Triangle_3& t = *pp.second;
    const Vec3 a = to_vec<K>(t.vertex(0)), b = to_vec<K>(t.vertex(1)), c = to_vec<K>(t.vertex(2));
    Vec3 n = (b - a).cross(c - a);
    const double l = n.norm();
    // A coordinate the triangle's corners share (a face of a box, a symmetry
    // plane) is kept exactly: the rounded projection leaves residuals like
    // 1e-120 there, which make coplanar nodes slightly non-coplanar, so the
    // front may build faces at a zero angle to the boundary (unfillable
    // wedges) and TetGen's inexact checks see intersecting facets.
    Vec3 x = to_vec<K>(pp.first);
    for(int d = 0; d < 3; ++d)
      if(a[d] == b[d] && b[d] == c[d])
        x[d] = a[d];
    return std::make_pair(x, l > 0 ? Vec3(n / l) : Vec3(0, 0, 1));
  }

  // ---- volume
  boost::optional<Subdomain_index> subdomain(const Vec3& p) const
  {
    return domain_.is_in_domain_object()(Point_3(p[0], p[1], p[2]));
  }
  bool is_inside(const Vec3& p) const { return bool(subdomain(p)); }
  bool has_distance() const { return !all_triangles_.empty(); }
  /// Euclidean distance to the boundary surface, a lower bound (0 when unknown)
  double distance_to_boundary(const Vec3& p) const
  {
    if(!has_distance())
      return 0;
    const double d = std::sqrt(CGAL::to_double(all_tree_->squared_distance(Point_3(p[0], p[1], p[2]))));
    return std::max(0.0, d - tolerance_);
  }

  /// the surface point of the domain on the line through p along n (unit),
  /// within `tolerance_` of p (then 2x, 4x); p itself when the triangles are
  /// the surface or when no crossing is found there
  Vec3 exact_surface_point(const Vec3& p, const Vec3& n) const
  {
    if(!(tolerance_ > 0))
      return p;
    for(double r = tolerance_; r <= 4 * tolerance_; r *= 2) {
      Vec3 a = p - r * n, b = p + r * n;
      const auto la = subdomain(a);
      if(la == subdomain(b))
        continue;
      // bisection on the inside test, to about 1e-12 of the search length
      for(int k = 0; k < 42; ++k) {
        const Vec3 m = 0.5 * (a + b);
        if(subdomain(m) == la)
          a = m;
        else
          b = m;
      }
      return 0.5 * (a + b);
    }
    return p;
  }
  double surface_tolerance() const { return tolerance_; }

private:
  const Mesh_domain& domain_;
  double tolerance_ = 0;
  std::vector<Corner> corners_;
  std::vector<Curve> curves_;
  std::vector<Patch> patches_;
  std::vector<Triangle_3> all_triangles_;
  std::unique_ptr<Tree> all_tree_;
};

/// The patches of a polyhedral domain with features (after detect_features):
/// faces grouped by patch_id, in increasing id order.
template <typename MeshDomain>
std::vector<std::pair<typename MeshDomain::Surface_patch_index, std::vector<typename MeshDomain::R::Triangle_3>>>
patches_of_polyhedral_domain(const MeshDomain& domain)
{
  typedef typename MeshDomain::R K;
  typedef typename MeshDomain::Surface_patch_index Surface_patch_index;
  typedef typename MeshDomain::Polyhedron Polyhedron;
  std::map<Surface_patch_index, std::vector<typename K::Triangle_3>> by_id;
  for(const Polyhedron& poly : domain.polyhedra()) {
    auto vpm = get(CGAL::vertex_point, poly);
    for(auto f : faces(poly)) {
      auto h = halfedge(f, poly);
      const auto& a = get(vpm, source(h, poly));
      const auto& b = get(vpm, target(h, poly));
      const auto& c = get(vpm, target(next(h, poly), poly));
      by_id[Surface_patch_index(f->patch_id())].emplace_back(a, b, c);
    }
  }
  return std::vector<std::pair<Surface_patch_index, std::vector<typename K::Triangle_3>>>(by_id.begin(), by_id.end());
}

/// Triangle soup of the surface patches of a domain known only through its
/// inside test (`is_in_domain_object`, which labels points by subdomain) and
/// `do_intersect_surface_object` (the patch of a crossing segment): marching
/// tetrahedra on a regular grid over the bounding box (each cube cut into the
/// six tetrahedra around its main diagonal, so neighbouring cubes match), a
/// surface point on every grid edge whose end labels differ (bisection), one
/// or two triangles per tetrahedron whose corners carry two labels, filed
/// under the patch of that tetrahedron. Tetrahedra with three labels (where
/// three subdomains meet) are left out: the soup only guides the packing.
/// The soup is within about one cell of the surface (less on smooth parts).
template <typename MeshDomain>
class Surface_triangulator {
public:
  typedef typename MeshDomain::R K;
  typedef typename K::Point_3 Point_3;
  typedef typename K::Segment_3 Segment_3;
  typedef typename K::Triangle_3 Triangle_3;
  typedef typename MeshDomain::Surface_patch_index Surface_patch_index;
  typedef typename MeshDomain::Subdomain_index Subdomain_index;
  typedef std::vector<std::pair<Surface_patch_index, std::vector<Triangle_3>>> Result;

  /// `resolution`: grid cells along the longest side of the bounding box
  Surface_triangulator(const MeshDomain& domain, int resolution) : d_(domain)
  {
    const CGAL::Bbox_3 bb = domain.bbox();
    Vec3 lo(bb.xmin(), bb.ymin(), bb.zmin()), hi(bb.xmax(), bb.ymax(), bb.zmax());
    const double longest = (hi - lo).maxCoeff();
    // a margin so that the grid's outer vertices are off a surface that touches the box
    const double step = longest / std::max(4, resolution);
    lo -= Vec3::Constant(0.5 * step);
    hi += Vec3::Constant(0.5 * step);
    for(int k = 0; k < 3; ++k) {
      n_[k] = std::max(1, int(std::ceil((hi[k] - lo[k]) / step)));
      h_[k] = (hi[k] - lo[k]) / n_[k];
    }
    lo_ = lo;
  }

  /// the length of a cell's diagonal
  double cell_diagonal() const { return h_.norm(); }

  Result run()
  {
    const std::size_t nv = std::size_t(n_[0] + 1) * (n_[1] + 1) * (n_[2] + 1);
    label_.assign(nv, -1);
    for(int i = 0; i <= n_[0]; ++i)
      for(int j = 0; j <= n_[1]; ++j)
        for(int k = 0; k <= n_[2]; ++k)
          label_[vid(i, j, k)] = label_of(vertex(i, j, k));
    std::map<Surface_patch_index, std::vector<Triangle_3>> by_patch;
    // the six tetrahedra of a cube: paths from corner 0 to corner 7 along the axes
    static const int perm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for(int i = 0; i < n_[0]; ++i)
      for(int j = 0; j < n_[1]; ++j)
        for(int k = 0; k < n_[2]; ++k) {
          const std::size_t c0 = vid(i, j, k);
          bool uniform = true;
          for(int c = 1; c < 8 && uniform; ++c)
            uniform = label_[vid(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1))] == label_[c0];
          if(uniform)
            continue;
          for(const auto& pm : perm) {
            std::array<int, 3> g = {i, j, k};
            std::array<std::size_t, 4> t;
            t[0] = vid(g[0], g[1], g[2]);
            for(int s = 0; s < 3; ++s) {
              ++g[pm[s]];
              t[s + 1] = vid(g[0], g[1], g[2]);
            }
            tetrahedron(t, by_patch);
          }
        }
    return Result(by_patch.begin(), by_patch.end());
  }

private:
  std::size_t vid(int i, int j, int k) const { return (std::size_t(i) * (n_[1] + 1) + j) * (n_[2] + 1) + k; }
  Vec3 vertex(int i, int j, int k) const { return lo_ + Vec3(i * h_[0], j * h_[1], k * h_[2]); }
  Vec3 vertex(std::size_t v) const
  {
    const int k = int(v % (n_[2] + 1));
    const int j = int((v / (n_[2] + 1)) % (n_[1] + 1));
    const int i = int(v / (std::size_t(n_[2] + 1) * (n_[1] + 1)));
    return vertex(i, j, k);
  }
  boost::optional<Subdomain_index> subdomain(const Vec3& p) const
  {
    return d_.is_in_domain_object()(Point_3(p[0], p[1], p[2]));
  }
  // -1 outside, else the position of the subdomain in `subdomains_`
  int label_of(const Vec3& p)
  {
    const auto s = subdomain(p);
    if(!s)
      return -1;
    for(std::size_t q = 0; q < subdomains_.size(); ++q)
      if(subdomains_[q] == *s)
        return int(q);
    subdomains_.push_back(*s);
    return int(subdomains_.size()) - 1;
  }

  // the surface point on grid edge (a, b), whose labels differ (cached)
  Vec3 crossing(std::size_t a, std::size_t b)
  {
    if(b < a)
      std::swap(a, b);
    const auto key = std::make_pair(a, b);
    const auto it = crossings_.find(key);
    if(it != crossings_.end())
      return it->second;
    Vec3 p = vertex(a), q = vertex(b);
    const int la = label_[a];
    for(int k = 0; k < 40; ++k) {
      const Vec3 m = 0.5 * (p + q);
      if(label_of(m) == la)
        p = m;
      else
        q = m;
    }
    const Vec3 x = 0.5 * (p + q);
    crossings_.emplace(key, x);
    return x;
  }

  void tetrahedron(const std::array<std::size_t, 4>& t, std::map<Surface_patch_index, std::vector<Triangle_3>>& out)
  {
    const int l0 = label_[t[0]];
    int other = l0;
    std::array<int, 4> side; // 1: label l0
    int count0 = 0;
    for(int c = 0; c < 4; ++c) {
      const int l = label_[t[c]];
      if(l != l0) {
        if(other != l0 && l != other)
          return; // three labels
        other = l;
      }
      side[c] = (l == l0) ? 1 : 0;
      count0 += side[c];
    }
    if(other == l0)
      return;
    // the patch of this label pair, from the domain (a segment from an l0 corner to an `other` corner)
    int a = -1, b = -1;
    for(int c = 0; c < 4; ++c)
      (side[c] ? a : b) = c;
    const Vec3 pa = vertex(t[a]), pb = vertex(t[b]);
    const auto patch = d_.do_intersect_surface_object()(Segment_3(Point_3(pa[0], pa[1], pa[2]), Point_3(pb[0], pb[1], pb[2])));
    if(!patch)
      return;
    std::vector<Triangle_3>& tri = out[*patch];
    // every triangle's normal points towards the side of the larger label,
    // so the normals of a patch are consistent (the packing compares the
    // normals of bubbles: see on_opposite_sides)
    const Vec3 towards = (other > l0) ? Vec3(pb - pa) : Vec3(pa - pb);
    auto add = [&](const Vec3& x, const Vec3& y, const Vec3& z) {
      const Vec3 n = (y - x).cross(z - x);
      if(!(n.squaredNorm() > 1e-24 * h_.squaredNorm() * h_.squaredNorm()))
        return;
      if(n.dot(towards) >= 0)
        tri.emplace_back(Point_3(x[0], x[1], x[2]), Point_3(y[0], y[1], y[2]), Point_3(z[0], z[1], z[2]));
      else
        tri.emplace_back(Point_3(x[0], x[1], x[2]), Point_3(z[0], z[1], z[2]), Point_3(y[0], y[1], y[2]));
    };
    if(count0 == 1 || count0 == 3) {
      // one corner alone on its side: one triangle
      const int lone_side = count0 == 1 ? 1 : 0;
      int lone = 0;
      for(int c = 0; c < 4; ++c)
        if(side[c] == lone_side)
          lone = c;
      std::array<Vec3, 3> p;
      int m = 0;
      for(int c = 0; c < 4; ++c)
        if(c != lone)
          p[m++] = crossing(t[lone], t[c]);
      add(p[0], p[1], p[2]);
    } else {
      // two and two: a quadrilateral (u0 v0, u0 v1, u1 v1, u1 v0), split in two
      std::array<int, 2> u, v;
      int nu = 0, nv = 0;
      for(int c = 0; c < 4; ++c)
        (side[c] ? u[nu++] : v[nv++]) = c;
      const Vec3 q0 = crossing(t[u[0]], t[v[0]]), q1 = crossing(t[u[0]], t[v[1]]),
                 q2 = crossing(t[u[1]], t[v[1]]), q3 = crossing(t[u[1]], t[v[0]]);
      add(q0, q1, q2);
      add(q0, q2, q3);
    }
  }

  const MeshDomain& d_;
  Vec3 lo_, h_;
  std::array<int, 3> n_;
  std::vector<int> label_;
  std::vector<Subdomain_index> subdomains_;
  std::map<std::pair<std::size_t, std::size_t>, Vec3> crossings_;
};

/// The patches of any domain as triangles and how far they may be from the
/// surface: the polyhedral domain's own faces (exact), else the marching
/// tetrahedra soup of `Surface_triangulator` at `resolution` cells along the
/// longest side of the bounding box.
template <typename MeshDomain>
std::pair<std::vector<std::pair<typename MeshDomain::Surface_patch_index, std::vector<typename MeshDomain::R::Triangle_3>>>,
          double>
patches_of_domain(const MeshDomain& domain, int resolution)
{
  if constexpr(Has_polyhedra<MeshDomain>::value) {
    return std::make_pair(patches_of_polyhedral_domain(domain), 0.0);
  } else {
    Surface_triangulator<MeshDomain> tri(domain, resolution);
    auto patches = tri.run();
    return std::make_pair(std::move(patches), tri.cell_diagonal());
  }
}

} // namespace packing
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_DOMAIN_ORACLE_H
