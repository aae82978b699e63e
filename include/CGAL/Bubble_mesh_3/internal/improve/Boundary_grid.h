// Copyright (c) 2026 The Bubble_mesh_3 authors.
// SPDX-License-Identifier: LGPL-3.0-or-later OR LicenseRef-Commercial
//
// The boundary faces of the mesh being improved in a hash grid, so that an
// operation changing the boundary (a surface vertex move, a curved flip, a
// boundary split or collapse) can check that its new triangles meet no other
// boundary triangle except along the edges and vertices they share: each
// operation bounds how far its triangles turn, not how close they come to
// the opposite side of a thin part, which they could otherwise cross.
//
// Entries are never removed: a face that is no longer protected is skipped
// when met (the caller's set of protected faces is the authority), and a
// face whose vertex moved is inserted again in the cells of its new box
// (the old cells keep a stale entry, tested again, harmlessly).

#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_IMPROVE_BOUNDARY_GRID_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_IMPROVE_BOUNDARY_GRID_H

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {
namespace improve {

/// Whether the triangles (a0, a1, a2) and (b0, b1, b2), given with their
/// vertex ids (-1: a new vertex, shared with nothing), meet anywhere but in
/// the vertices and edges they share (exact predicates). Sharing an edge:
/// they overlap only if coplanar with the third vertices on one side of it;
/// sharing a vertex: if an edge of one away from it meets the other.
inline bool triangles_meet_improperly(const std::array<Eigen::Vector3d, 3>& a, const std::array<int, 3>& ia,
                                      const std::array<Eigen::Vector3d, 3>& b, const std::array<int, 3>& ib)
{
  typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
  auto point = [](const Eigen::Vector3d& x) { return K::Point_3(x[0], x[1], x[2]); };
  int shared_a[3], shared_b[3], shared = 0;
  for(int i = 0; i < 3; ++i)
    for(int j = 0; j < 3; ++j)
      if(ia[std::size_t(i)] >= 0 && ia[std::size_t(i)] == ib[std::size_t(j)]) {
        shared_a[shared] = i;
        shared_b[shared] = j;
        ++shared;
      }
  if(shared >= 3)
    return true; // the same face twice
  if(shared == 0)
    return CGAL::do_intersect(K::Triangle_3(point(a[0]), point(a[1]), point(a[2])),
                              K::Triangle_3(point(b[0]), point(b[1]), point(b[2])));
  if(shared == 2) {
    const int ca = 3 - shared_a[0] - shared_a[1], cb = 3 - shared_b[0] - shared_b[1];
    const K::Point_3 p = point(a[std::size_t(shared_a[0])]), q = point(a[std::size_t(shared_a[1])]);
    const K::Point_3 r = point(a[std::size_t(ca)]), s = point(b[std::size_t(cb)]);
    if(CGAL::orientation(p, q, r, s) != CGAL::COPLANAR)
      return false;
    // coplanar: on one side of the line pq (the same sign of the normals)
    const K::Vector_3 n1 = CGAL::cross_product(q - p, r - p), n2 = CGAL::cross_product(q - p, s - p);
    return n1 * n2 > 0;
  }
  // one shared vertex: the edge of each triangle opposite it against the other
  const int sa = shared_a[0], sb = shared_b[0];
  const K::Triangle_3 ta(point(a[0]), point(a[1]), point(a[2])), tb(point(b[0]), point(b[1]), point(b[2]));
  const K::Segment_3 ea(point(a[std::size_t((sa + 1) % 3)]), point(a[std::size_t((sa + 2) % 3)]));
  const K::Segment_3 eb(point(b[std::size_t((sb + 1) % 3)]), point(b[std::size_t((sb + 2) % 3)]));
  if(CGAL::do_intersect(ea, tb) || CGAL::do_intersect(eb, ta))
    return true;
  // coplanar triangles may also overlap in a wedge at the shared vertex
  const K::Point_3 s = point(a[std::size_t(sa)]);
  if(CGAL::orientation(s, ea.source(), ea.target(), eb.source()) == CGAL::COPLANAR &&
     CGAL::orientation(s, ea.source(), ea.target(), eb.target()) == CGAL::COPLANAR) {
    // an edge of b at s pointing into a (or of a into b)
    auto inside_wedge = [&](const K::Point_3& apex, const K::Point_3& u, const K::Point_3& w, const K::Point_3& x) {
      // x strictly inside the angle u-apex-w (coplanar)
      const K::Vector_3 n = CGAL::cross_product(u - apex, w - apex);
      return CGAL::cross_product(u - apex, x - apex) * n > 0 && CGAL::cross_product(x - apex, w - apex) * n > 0;
    };
    if(inside_wedge(s, ea.source(), ea.target(), eb.source()) || inside_wedge(s, ea.source(), ea.target(), eb.target()) ||
       inside_wedge(s, eb.source(), eb.target(), ea.source()) || inside_wedge(s, eb.source(), eb.target(), ea.target()))
      return true;
  }
  return false;
}

class Boundary_grid {
public:
  typedef std::array<int, 3> Face; // sorted vertex ids

  /// `cell` > 0: the cell size (about the boundary edges' length)
  explicit Boundary_grid(double cell = 1) : cell_(cell > 0 && std::isfinite(cell) ? cell : 1) {}

  void insert(const Face& f, const std::array<Eigen::Vector3d, 3>& x)
  {
    Cell lo, hi;
    box(x, lo, hi);
    const Entry e = entry(f, x);
    if(cells_in(lo, hi) > 64) { // a triangle much larger than the cells: met by every query
      large_.push_back(e);
      return;
    }
    for(long i = lo[0]; i <= hi[0]; ++i)
      for(long j = lo[1]; j <= hi[1]; ++j)
        for(long k = lo[2]; k <= hi[2]; ++k)
          cells_[Cell{{i, j, k}}].push_back(e);
  }

  /// Calls `visit(face)` once for each face indexed in a cell that the box of
  /// `x` overlaps, and for each face too large for the cells; stops and
  /// returns true when `visit` returns true.
  bool any_near(const std::array<Eigen::Vector3d, 3>& x, const std::function<bool(const Face&)>& visit) const
  {
    Cell lo, hi;
    box(x, lo, hi);
    const Entry query = entry(Face{{-1, -1, -1}}, x);
    seen_.clear();
    // only the entries whose box meets the query's (as indexed: a face
    // indexed again after a move is met through its new entry)
    auto visit_all = [&](const std::vector<Entry>& entries) {
      for(const Entry& e : entries) {
        bool overlap = true;
        for(int d = 0; d < 3 && overlap; ++d)
          overlap = e.lo[d] <= query.hi[d] && query.lo[d] <= e.hi[d];
        if(overlap && seen_.insert(e.face).second && visit(e.face))
          return true;
      }
      return false;
    };
    if(visit_all(large_))
      return true;
    if(cells_in(lo, hi) > double(cells_.size())) { // a large query: the non-empty cells in its box
      for(const auto& cell : cells_)
        if(cell.first[0] >= lo[0] && cell.first[0] <= hi[0] && cell.first[1] >= lo[1] && cell.first[1] <= hi[1] &&
           cell.first[2] >= lo[2] && cell.first[2] <= hi[2] && visit_all(cell.second))
          return true;
      return false;
    }
    for(long i = lo[0]; i <= hi[0]; ++i)
      for(long j = lo[1]; j <= hi[1]; ++j)
        for(long k = lo[2]; k <= hi[2]; ++k) {
          const auto it = cells_.find(Cell{{i, j, k}});
          if(it != cells_.end() && visit_all(it->second))
            return true;
        }
    return false;
  }

private:
  typedef std::array<long, 3> Cell;
  struct Entry {
    Face face;
    double lo[3], hi[3];
  };
  static Entry entry(const Face& f, const std::array<Eigen::Vector3d, 3>& x)
  {
    Entry e;
    e.face = f;
    for(int d = 0; d < 3; ++d) {
      e.lo[d] = std::min({x[0][d], x[1][d], x[2][d]});
      e.hi[d] = std::max({x[0][d], x[1][d], x[2][d]});
    }
    return e;
  }
  struct Cell_hash {
    std::size_t operator()(const Cell& c) const
    {
      return std::size_t((std::uint64_t(c[0]) * 0x9E3779B97F4A7C15ull) ^ (std::uint64_t(c[1]) * 0xC2B2AE3D27D4EB4Full) ^
                         (std::uint64_t(c[2]) * 0x165667B19E3779F9ull));
    }
  };
  struct Face_hash {
    std::size_t operator()(const Face& f) const
    {
      return std::size_t((std::uint64_t(std::uint32_t(f[0])) * 0x9E3779B97F4A7C15ull) ^
                         (std::uint64_t(std::uint32_t(f[1])) * 0xC2B2AE3D27D4EB4Full) ^ std::uint64_t(std::uint32_t(f[2])));
    }
  };

  void box(const std::array<Eigen::Vector3d, 3>& x, Cell& lo, Cell& hi) const
  {
    for(int d = 0; d < 3; ++d) {
      const double a = std::min({x[0][d], x[1][d], x[2][d]}), b = std::max({x[0][d], x[1][d], x[2][d]});
      lo[std::size_t(d)] = long(std::floor(a / cell_));
      hi[std::size_t(d)] = long(std::floor(b / cell_));
    }
  }
  static double cells_in(const Cell& lo, const Cell& hi)
  {
    return double(hi[0] - lo[0] + 1) * double(hi[1] - lo[1] + 1) * double(hi[2] - lo[2] + 1);
  }

  double cell_;
  std::unordered_map<Cell, std::vector<Entry>, Cell_hash> cells_;
  std::vector<Entry> large_;
  mutable std::unordered_set<Face, Face_hash> seen_;
};

} // namespace improve
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_IMPROVE_BOUNDARY_GRID_H
