// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Hashed uniform grids for the advancing front: a static one over the nodes
// (candidate search, point-in-tet checks) and a dynamic one over the front
// triangles (intersection checks). Cells are keyed by their integer
// coordinates; boxes are clamped to a bounded number of cells per axis so a
// huge query degrades to a scan instead of exhausting memory.
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_FRONT_FRONT_GRID_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_FRONT_FRONT_GRID_H

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {
namespace front {

struct Box {
  std::array<double, 3> lo{{0, 0, 0}}, hi{{0, 0, 0}};
  bool contains(const Box& o) const
  {
    for(int k = 0; k < 3; ++k)
      if(o.lo[k] < lo[k] || o.hi[k] > hi[k])
        return false;
    return true;
  }
  void extend(const Box& o)
  {
    for(int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], o.lo[k]);
      hi[k] = std::max(hi[k], o.hi[k]);
    }
  }
  void inflate(double r)
  {
    for(int k = 0; k < 3; ++k) {
      lo[k] -= r;
      hi[k] += r;
    }
  }
};

class Grid_geometry {
public:
  Grid_geometry() = default;
  Grid_geometry(const std::array<double, 3>& origin, double cell) : origin_(origin), inv_(1.0 / cell) {}

  std::array<std::int64_t, 3> cell_of(const std::array<double, 3>& p) const
  {
    std::array<std::int64_t, 3> c;
    for(int k = 0; k < 3; ++k) {
      const double x = std::floor((p[k] - origin_[k]) * inv_);
      c[k] = static_cast<std::int64_t>(std::max(-1e6, std::min(1e6, x)));
    }
    return c;
  }
  static std::uint64_t key(std::int64_t i, std::int64_t j, std::int64_t k)
  {
    const std::uint64_t m = (std::uint64_t(1) << 21) - 1;
    return (std::uint64_t(i + (1 << 20)) & m) | ((std::uint64_t(j + (1 << 20)) & m) << 21) |
           ((std::uint64_t(k + (1 << 20)) & m) << 42);
  }
  /// calls f(key) for every cell of the box (false when the box spans more
  /// than `max_cells` cells: the caller then scans everything)
  template <typename F>
  bool for_cells(const Box& b, F f, std::int64_t max_cells = 1 << 16) const
  {
    const auto lo = cell_of(b.lo), hi = cell_of(b.hi);
    const std::int64_t n = (hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1);
    if(n > max_cells)
      return false;
    for(std::int64_t i = lo[0]; i <= hi[0]; ++i)
      for(std::int64_t j = lo[1]; j <= hi[1]; ++j)
        for(std::int64_t k = lo[2]; k <= hi[2]; ++k)
          f(key(i, j, k));
    return true;
  }

private:
  std::array<double, 3> origin_{{0, 0, 0}};
  double inv_ = 1;
};

/// Static grid over points; `query(box, f)` calls f(id) for every point in the box.
class Point_grid {
public:
  void build(const std::vector<std::array<double, 3>>& points, double cell)
  {
    points_ = &points;
    std::array<double, 3> lo{{0, 0, 0}};
    if(!points.empty())
      lo = points.front();
    for(const auto& p : points)
      for(int k = 0; k < 3; ++k)
        lo[k] = std::min(lo[k], p[k]);
    geo_ = Grid_geometry(lo, cell);
    cells_.clear();
    for(std::size_t i = 0; i < points.size(); ++i) {
      const auto c = geo_.cell_of(points[i]);
      cells_[Grid_geometry::key(c[0], c[1], c[2])].push_back(static_cast<int>(i));
    }
  }
  template <typename F>
  void query(const Box& b, F f) const
  {
    const auto& pts = *points_;
    auto in_box = [&](int i) {
      for(int k = 0; k < 3; ++k)
        if(pts[i][k] < b.lo[k] || pts[i][k] > b.hi[k])
          return false;
      return true;
    };
    const bool ok = geo_.for_cells(b, [&](std::uint64_t key) {
      auto it = cells_.find(key);
      if(it == cells_.end())
        return;
      for(int i : it->second)
        if(in_box(i))
          f(i);
    });
    if(!ok)
      for(int i = 0; i < static_cast<int>(pts.size()); ++i)
        if(in_box(i))
          f(i);
  }

private:
  const std::vector<std::array<double, 3>>* points_ = nullptr;
  Grid_geometry geo_;
  std::unordered_map<std::uint64_t, std::vector<int>> cells_;
};

/// Dynamic grid over items with boxes (front triangles).
class Box_grid {
public:
  void reset(const std::array<double, 3>& origin, double cell)
  {
    geo_ = Grid_geometry(origin, cell);
    cells_.clear();
    overflow_.clear();
  }
  void insert(int id, const Box& b)
  {
    if(!geo_.for_cells(b, [&](std::uint64_t key) { cells_[key].push_back(id); }, 4096))
      overflow_.push_back(id);
  }
  /// removes an item inserted with the same box
  void remove(int id, const Box& b)
  {
    auto drop = [id](std::vector<int>& v) {
      auto it = std::find(v.begin(), v.end(), id);
      if(it != v.end()) {
        *it = v.back();
        v.pop_back();
      }
    };
    if(!geo_.for_cells(b, [&](std::uint64_t key) {
         auto it = cells_.find(key);
         if(it != cells_.end())
           drop(it->second);
       }, 4096))
      drop(overflow_);
  }
  /// calls f(id) once per item whose cells meet the box
  template <typename F>
  void query(const Box& b, F f)
  {
    ++stamp_;
    auto visit = [&](int id) {
      if(id >= static_cast<int>(seen_.size()))
        seen_.resize(id + 1, 0);
      if(seen_[id] == stamp_)
        return;
      seen_[id] = stamp_;
      f(id);
    };
    const bool ok = geo_.for_cells(b, [&](std::uint64_t key) {
      auto it = cells_.find(key);
      if(it != cells_.end())
        for(int id : it->second)
          visit(id);
    });
    if(!ok)
      for(auto& c : cells_)
        for(int id : c.second)
          visit(id);
    for(int id : overflow_)
      visit(id);
  }
private:
  Grid_geometry geo_;
  std::unordered_map<std::uint64_t, std::vector<int>> cells_;
  std::vector<int> overflow_;
  std::vector<std::uint32_t> seen_;
  std::uint32_t stamp_ = 0;
};

} // namespace front
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_FRONT_FRONT_GRID_H
