// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Exact tests of a candidate tet against the advancing front: triangles that
// may share vertices (sharing is allowed, any other contact is not) and the
// closed point-in-tet test. Everything is decided by the traits' exact
// predicates (orientation, coplanar orientation, do_intersect).
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_FRONT_FRONT_GEOMETRY_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_FRONT_FRONT_GEOMETRY_H

#include <CGAL/enum.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {
namespace front {

typedef std::array<int, 3> Tri;
typedef std::array<int, 4> Tet;

inline Tri sorted(Tri t)
{
  std::sort(t.begin(), t.end());
  return t;
}

/// true if the two triangles with the same vertex set have the same cyclic order
inline bool same_orientation(const Tri& a, const Tri& b)
{
  for(int k = 0; k < 3; ++k)
    if(a[0] == b[k])
      return a[1] == b[(k + 1) % 3];
  return false;
}

/// The side of the plane through a, b, c on which points lie, decided in
/// double precision when the rounding error bound allows (Shewchuk's
/// orient3d bound with a safety factor, from differences to `a` and the
/// precomputed cofactors), `COPLANAR` meaning "undecided: ask the exact
/// predicate". Saves the repeated set-up when many points are tested
/// against one plane.
class Plane_side_filter {
public:
  template <typename Point>
  Plane_side_filter(const Point& a, const Point& b, const Point& c)
      : ax_(a.x()), ay_(a.y()), az_(a.z())
  {
    const double bx = b.x() - ax_, by = b.y() - ay_, bz = b.z() - az_;
    const double cx = c.x() - ax_, cy = c.y() - ay_, cz = c.z() - az_;
    nx_ = by * cz - bz * cy;
    ny_ = bz * cx - bx * cz;
    nz_ = bx * cy - by * cx;
    px_ = std::abs(by * cz) + std::abs(bz * cy);
    py_ = std::abs(bz * cx) + std::abs(bx * cz);
    pz_ = std::abs(bx * cy) + std::abs(by * cx);
  }
  template <typename Point>
  CGAL::Orientation operator()(const Point& q) const
  {
    const double qx = q.x() - ax_, qy = q.y() - ay_, qz = q.z() - az_;
    const double det = qx * nx_ + qy * ny_ + qz * nz_;
    const double permanent = std::abs(qx) * px_ + std::abs(qy) * py_ + std::abs(qz) * pz_;
    // (7 + 56 eps) eps is the bound; 4x that, and no decision near underflow
    constexpr double eps = 1.1102230246251565e-16;
    const double bound = 4 * (7 + 56 * eps) * eps * permanent;
    if(!(permanent > 1e-250) || !(permanent < 1e250))
      return CGAL::COPLANAR;
    if(det > bound)
      return CGAL::POSITIVE;
    if(det < -bound)
      return CGAL::NEGATIVE;
    return CGAL::COPLANAR;
  }

private:
  double ax_, ay_, az_, nx_, ny_, nz_, px_, py_, pz_;
};

/// Whether triangles `t` and `g` (vertex ids into `pts`) meet anywhere but in
/// the vertices and the edge they share. Two triangles with the same vertex
/// set are not tested here (the caller decides by orientation).
/// Shared edge uv: only coplanar triangles on the same side of uv overlap.
/// Shared vertex v: the triangles meet beyond v iff the edge of one opposite
/// v meets the other triangle (the contact set is a segment from v; its far
/// end lies on one of these two edges, whatever the configuration).
/// `t_plane`, if given, is the `Plane_side_filter` of t's vertices in t's
/// order; it only saves time.
template <typename Traits>
bool triangles_meet_beyond_shared(const Tri& t, const Tri& g, const std::vector<typename Traits::Point_3>& pts,
                                  const Traits& traits, const Plane_side_filter* t_plane = nullptr)
{
  typedef typename Traits::Segment_3 Segment_3;
  typedef typename Traits::Triangle_3 Triangle_3;
  int shared = 0;
  std::array<bool, 3> t_shared{{false, false, false}}, g_shared{{false, false, false}};
  for(int i = 0; i < 3; ++i)
    for(int j = 0; j < 3; ++j)
      if(t[i] == g[j]) {
        ++shared;
        t_shared[i] = true;
        g_shared[j] = true;
      }
  auto do_intersect = traits.do_intersect_3_object();
  if(shared == 0) {
    // separated when one triangle lies strictly on one side of the other's
    // plane (filtered in double; undecided cases go to the exact test)
    auto strictly_one_side = [&](const Plane_side_filter& plane, const Tri& u) {
      const CGAL::Orientation o = plane(pts[u[0]]);
      return o != CGAL::COPLANAR && plane(pts[u[1]]) == o && plane(pts[u[2]]) == o;
    };
    if(t_plane != nullptr && strictly_one_side(*t_plane, g))
      return false;
    if(strictly_one_side(Plane_side_filter(pts[g[0]], pts[g[1]], pts[g[2]]), t))
      return false;
    return do_intersect(Triangle_3(pts[t[0]], pts[t[1]], pts[t[2]]), Triangle_3(pts[g[0]], pts[g[1]], pts[g[2]]));
  }
  if(shared == 3)
    return false;
  if(shared == 2) {
    int u = -1, v = -1, x = -1, y = -1;
    for(int i = 0; i < 3; ++i) {
      if(!t_shared[i])
        x = t[i];
      else if(u < 0)
        u = t[i];
      else
        v = t[i];
      if(!g_shared[i])
        y = g[i];
    }
    // only "coplanar or not" matters here, so t's plane in any vertex order will do
    if(t_plane != nullptr && (*t_plane)(pts[y]) != CGAL::COPLANAR)
      return false;
    if(traits.orientation_3_object()(pts[u], pts[v], pts[x], pts[y]) != CGAL::COPLANAR)
      return false;
    return traits.coplanar_orientation_3_object()(pts[u], pts[v], pts[x], pts[y]) != CGAL::NEGATIVE;
  }
  // one shared vertex
  int ti = 0, gi = 0;
  while(!t_shared[ti])
    ++ti;
  while(!g_shared[gi])
    ++gi;
  {
    // cheap separations first: if the far edge of one triangle lies strictly
    // on one side of the other's plane, they meet in the shared vertex only
    auto orientation = traits.orientation_3_object();
    const auto& v = pts[t[ti]];
    const auto& a = pts[t[(ti + 1) % 3]];
    const auto& b = pts[t[(ti + 2) % 3]];
    const auto& c = pts[g[(gi + 1) % 3]];
    const auto& d = pts[g[(gi + 2) % 3]];
    // (v, a, b) is a rotation of t: its plane filter gives the same signs
    auto side_of_t = [&](const typename Traits::Point_3& q) {
      const CGAL::Orientation quick = t_plane != nullptr ? (*t_plane)(q) : CGAL::COPLANAR;
      return quick != CGAL::COPLANAR ? quick : orientation(v, a, b, q);
    };
    const CGAL::Orientation oc = side_of_t(c);
    if(oc != CGAL::COPLANAR && oc == side_of_t(d))
      return false;
    // (v, c, d) is a rotation of g
    const Plane_side_filter g_plane(v, c, d);
    auto side_of_g = [&](const typename Traits::Point_3& q) {
      const CGAL::Orientation quick = g_plane(q);
      return quick != CGAL::COPLANAR ? quick : orientation(v, c, d, q);
    };
    const CGAL::Orientation oa = side_of_g(a);
    if(oa != CGAL::COPLANAR && oa == side_of_g(b))
      return false;
  }
  const Segment_3 t_opposite(pts[t[(ti + 1) % 3]], pts[t[(ti + 2) % 3]]);
  const Segment_3 g_opposite(pts[g[(gi + 1) % 3]], pts[g[(gi + 2) % 3]]);
  return do_intersect(t_opposite, Triangle_3(pts[g[0]], pts[g[1]], pts[g[2]])) ||
         do_intersect(g_opposite, Triangle_3(pts[t[0]], pts[t[1]], pts[t[2]]));
}

/// Whether `q` lies in the closed, positively oriented tet `t`.
template <typename Traits>
bool in_closed_tet(const typename Traits::Point_3& q, const Tet& t, const std::vector<typename Traits::Point_3>& pts,
                   const Traits& traits)
{
  auto orientation = traits.orientation_3_object();
  const auto& a = pts[t[0]];
  const auto& b = pts[t[1]];
  const auto& c = pts[t[2]];
  const auto& d = pts[t[3]];
  return orientation(q, b, c, d) != CGAL::NEGATIVE && orientation(a, q, c, d) != CGAL::NEGATIVE &&
         orientation(a, b, q, d) != CGAL::NEGATIVE && orientation(a, b, c, q) != CGAL::NEGATIVE;
}

/// The faces of the positive tet (a, b, c, p) other than (a, b, c), oriented
/// away from the tet (the unmeshed side is their positive side).
inline std::array<Tri, 3> new_faces(const Tri& f, int p)
{
  return {{Tri{{f[1], f[2], p}}, Tri{{f[0], p, f[2]}}, Tri{{f[0], f[1], p}}}};
}

/// The four faces of the positive tet `t`, oriented away from it.
inline std::array<Tri, 4> outward_faces(const Tet& t)
{
  return {{Tri{{t[1], t[2], t[3]}}, Tri{{t[0], t[3], t[2]}}, Tri{{t[0], t[1], t[3]}}, Tri{{t[0], t[2], t[1]}}}};
}

} // namespace front
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_FRONT_FRONT_GEOMETRY_H
