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

/// Whether triangles `t` and `g` (vertex ids into `pts`) meet anywhere but in
/// the vertices and the edge they share. Two triangles with the same vertex
/// set are not tested here (the caller decides by orientation).
/// Shared edge uv: only coplanar triangles on the same side of uv overlap.
/// Shared vertex v: the triangles meet beyond v iff the edge of one opposite
/// v meets the other triangle (the contact set is a segment from v; its far
/// end lies on one of these two edges, whatever the configuration).
template <typename Traits>
bool triangles_meet_beyond_shared(const Tri& t, const Tri& g, const std::vector<typename Traits::Point_3>& pts,
                                  const Traits& traits)
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
  if(shared == 0)
    return do_intersect(Triangle_3(pts[t[0]], pts[t[1]], pts[t[2]]), Triangle_3(pts[g[0]], pts[g[1]], pts[g[2]]));
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
