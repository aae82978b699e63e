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
// domain's own intersection oracle (see `Surface_triangulator` below).
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

  /// `curve_samples`: samples per curve for the arc-length table (at least)
  Domain_oracle(const Mesh_domain& domain, std::size_t curve_samples, std::vector<std::pair<Surface_patch_index, std::vector<Triangle_3>>> patches)
      : domain_(domain)
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
    return std::make_pair(to_vec<K>(pp.first), l > 0 ? Vec3(n / l) : Vec3(0, 0, 1));
  }

  // ---- volume
  boost::optional<Subdomain_index> subdomain(const Vec3& p) const
  {
    return domain_.is_in_domain_object()(Point_3(p[0], p[1], p[2]));
  }
  bool is_inside(const Vec3& p) const { return bool(subdomain(p)); }
  bool has_distance() const { return !all_triangles_.empty(); }
  /// Euclidean distance to the boundary surface (0 when unknown)
  double distance_to_boundary(const Vec3& p) const
  {
    if(!has_distance())
      return 0;
    return std::sqrt(CGAL::to_double(all_tree_->squared_distance(Point_3(p[0], p[1], p[2]))));
  }

private:
  const Mesh_domain& domain_;
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

} // namespace packing
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_DOMAIN_ORACLE_H
