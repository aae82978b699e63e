// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Uniform grids for the advancing front, flat arrays over the nodes' bounding
// box: a static one over the nodes (candidate search, point-in-tet checks)
// and a dynamic one over the front triangles (intersection checks). The cell
// count is bounded by about two per node whatever the requested cell size.
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_FRONT_FRONT_GRID_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_FRONT_FRONT_GRID_H

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
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
  /// closed boxes meet (exact: no arithmetic)
  bool meets(const Box& o) const
  {
    for(int k = 0; k < 3; ++k)
      if(o.hi[k] < lo[k] || o.lo[k] > hi[k])
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

/// the cell index of the scaled coordinate x in [0, n), NaN-safe
inline std::int64_t clamp_cell(double x, std::int64_t n)
{
  if(!(x > 0))
    return 0;
  if(x >= double(n - 1))
    return n - 1;
  return std::int64_t(x);
}

/// Static grid over points, flat (cells in one array, ids sorted by cell);
/// `query(box, f)` calls f(id) for every point in the box.
class Point_grid {
public:
  void build(const std::vector<std::array<double, 3>>& points, double cell)
  {
    points_ = &points;
    lo_ = hi_ = points.empty() ? std::array<double, 3>{{0, 0, 0}} : points.front();
    for(const auto& p : points)
      for(int k = 0; k < 3; ++k) {
        lo_[k] = std::min(lo_[k], p[k]);
        hi_[k] = std::max(hi_[k], p[k]);
      }
    // at most about 2 cells per point, whatever the requested cell size
    const double budget = 2.0 * double(points.size()) + 8;
    for(;;) {
      std::size_t cells = 1;
      for(int k = 0; k < 3; ++k) {
        n_[k] = std::max<std::int64_t>(1, std::int64_t((hi_[k] - lo_[k]) / cell) + 1);
        cells *= std::size_t(n_[k]);
      }
      if(double(cells) <= budget || !(cell > 0))
        break;
      cell *= 1.25;
    }
    inv_ = cell > 0 ? 1.0 / cell : 1.0;
    const std::size_t cells = std::size_t(n_[0] * n_[1] * n_[2]);
    start_.assign(cells + 1, 0);
    std::vector<std::size_t> cell_of_point(points.size());
    for(std::size_t i = 0; i < points.size(); ++i) {
      cell_of_point[i] = index(points[i]);
      ++start_[cell_of_point[i] + 1];
    }
    for(std::size_t c = 0; c < cells; ++c)
      start_[c + 1] += start_[c];
    ids_.assign(points.size(), 0);
    std::vector<std::size_t> fill(start_.begin(), start_.end() - 1);
    for(std::size_t i = 0; i < points.size(); ++i)
      ids_[fill[cell_of_point[i]]++] = static_cast<int>(i);
  }
  /// the point ids sorted by cell (ties by id)
  const std::vector<int>& ids_in_cell_order() const { return ids_; }

  template <typename F>
  void query(const Box& b, F f) const
  {
    const auto& pts = *points_;
    std::array<std::int64_t, 3> lo, hi;
    for(int k = 0; k < 3; ++k) {
      lo[k] = clamp(k, (b.lo[k] - lo_[k]) * inv_);
      hi[k] = clamp(k, (b.hi[k] - lo_[k]) * inv_);
      if(b.hi[k] < lo_[k] || b.lo[k] > hi_[k])
        return;
    }
    for(std::int64_t k = lo[2]; k <= hi[2]; ++k)
      for(std::int64_t j = lo[1]; j <= hi[1]; ++j)
        for(std::int64_t i = lo[0]; i <= hi[0]; ++i) {
          const std::size_t c = std::size_t(i + n_[0] * (j + n_[1] * k));
          for(std::size_t e = start_[c]; e < start_[c + 1]; ++e) {
            const int id = ids_[e];
            const auto& p = pts[id];
            if(p[0] >= b.lo[0] && p[0] <= b.hi[0] && p[1] >= b.lo[1] && p[1] <= b.hi[1] && p[2] >= b.lo[2] &&
               p[2] <= b.hi[2])
              f(id);
          }
        }
  }

private:
  std::int64_t clamp(int k, double x) const { return clamp_cell(x, n_[k]); }
  std::size_t index(const std::array<double, 3>& p) const
  {
    return std::size_t(clamp(0, (p[0] - lo_[0]) * inv_) +
                       n_[0] * (clamp(1, (p[1] - lo_[1]) * inv_) + n_[1] * clamp(2, (p[2] - lo_[2]) * inv_)));
  }
  const std::vector<std::array<double, 3>>* points_ = nullptr;
  std::array<double, 3> lo_{{0, 0, 0}}, hi_{{0, 0, 0}};
  std::array<std::int64_t, 3> n_{{1, 1, 1}};
  double inv_ = 1;
  std::vector<std::size_t> start_;
  std::vector<int> ids_;
};

/// Dynamic grid over items with boxes (front triangles), flat over a fixed
/// bounding box (the items' boxes are clamped into it).
class Box_grid {
public:
  void reset(const std::array<double, 3>& lo, const std::array<double, 3>& hi, double cell, std::size_t max_cells)
  {
    lo_ = lo;
    for(;;) {
      std::size_t cells = 1;
      for(int k = 0; k < 3; ++k) {
        n_[k] = std::max<std::int64_t>(1, std::int64_t((hi[k] - lo[k]) / cell) + 1);
        cells *= std::size_t(n_[k]);
      }
      if(cells <= max_cells || !(cell > 0))
        break;
      cell *= 1.25;
    }
    inv_ = cell > 0 ? 1.0 / cell : 1.0;
    cells_.assign(std::size_t(n_[0] * n_[1] * n_[2]), std::vector<int>());
  }
  /// removes every item
  void clear()
  {
    for(auto& c : cells_)
      c.clear();
  }
  void insert(int id, const Box& b)
  {
    for_cells(b, [&](std::vector<int>& c) { c.push_back(id); });
  }
  /// removes an item inserted with the same box
  void remove(int id, const Box& b)
  {
    for_cells(b, [&](std::vector<int>& v) {
      auto it = std::find(v.begin(), v.end(), id);
      if(it != v.end()) {
        *it = v.back();
        v.pop_back();
      }
    });
  }
  /// calls f(id) once per item whose cells meet the box
  template <typename F>
  void query(const Box& b, F f)
  {
    ++stamp_;
    for_cells(b, [&](std::vector<int>& v) {
      for(int id : v) {
        if(id >= static_cast<int>(seen_.size()))
          seen_.resize(std::size_t(id) + 1 + seen_.size() / 2, 0);
        if(seen_[id] == stamp_)
          continue;
        seen_[id] = stamp_;
        f(id);
      }
    });
  }

private:
  std::int64_t clamp(int k, double x) const { return clamp_cell(x, n_[k]); }
  template <typename F>
  void for_cells(const Box& b, F f)
  {
    std::array<std::int64_t, 3> lo, hi;
    for(int k = 0; k < 3; ++k) {
      lo[k] = clamp(k, (b.lo[k] - lo_[k]) * inv_);
      hi[k] = clamp(k, (b.hi[k] - lo_[k]) * inv_);
    }
    for(std::int64_t k = lo[2]; k <= hi[2]; ++k)
      for(std::int64_t j = lo[1]; j <= hi[1]; ++j)
        for(std::int64_t i = lo[0]; i <= hi[0]; ++i)
          f(cells_[std::size_t(i + n_[0] * (j + n_[1] * k))]);
  }
  std::array<double, 3> lo_{{0, 0, 0}};
  std::array<std::int64_t, 3> n_{{1, 1, 1}};
  double inv_ = 1;
  std::vector<std::vector<int>> cells_;
  std::vector<std::uint32_t> seen_;
  std::uint32_t stamp_ = 0;
};

} // namespace front
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_FRONT_FRONT_GRID_H
