// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Contract: Verlet neighbour lists over a multi-level grid.
//
// Each bubble i has a metric reach r = w_cut + skin and, per axis k, a
// Euclidean extent e_i[k] = r sqrt((M_i^-1)_kk): the half-width of its
// ellipsoid {d : |d|_Mi <= r}. Two bubbles can interact (normalized distance
// w <= w_cut) only if min(|d|_Mi, |d|_Mj) <= w_cut (the harmonic mean of the
// two metric lengths is at least their minimum), hence only if
// |d_k| <= max(e_i[k], e_j[k]) on every axis. A pair is kept when
// min(|d|_Mi, |d|_Mj) <= r, so stretched bubbles keep short lists.
// The grid has per-axis cell sizes (a stretched packing gets stretched
// cells): level L has cells base[k] 2^L, and bubble i is stored at the
// smallest level whose cells are at least e_i[k] / 2 on every axis. It
// searches the 5^3 cells around it on levels > L_i and the half of them (62
// cells and its own) on L_i; pairs with a bubble of a finer level are found
// from that bubble's side. So the search is exact for any ratio of sizes, and
// costs 25 column look-ups (5 cells in z are consecutive) per non-empty level.
//
// `build` fills compressed rows: neighbours(i) lists every j with
// min(|d|_Mi, |d|_Mj) <= metric_reach, sorted by index, for each bubble with
// `wants_row(i)`. Pairs are produced per fixed block of bubbles and merged in
// block order, so the lists do not depend on the number of threads. Buffers are
// kept between builds (no allocation once sizes have settled).
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_NEIGHBOUR_SEARCH_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_NEIGHBOUR_SEARCH_H

#include <CGAL/Bubble_mesh_3/internal/packing/bubble.h>
#include <CGAL/Bubble_mesh_3/internal/packing/parallel.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {
namespace packing {

/// no pair is separated (the default of `Neighbour_lists::build`)
struct No_separation {
  bool operator()(int, int) const { return false; }
};

class Neighbour_lists {
public:
  /// Builds the lists of metric reach `metric_reach`. `has_row[i]` tells
  /// whether bubble i needs its own row (moving bubbles); pairs of two
  /// row-less bubbles are skipped, and so are the pairs (i, j) for which
  /// `separated(i, j)` is true. `Record` has the position `x` and the
  /// metric `m` of a bubble.
  template <typename Record, typename Separated = No_separation>
  void build(const std::vector<Record>& bubbles, const std::vector<char>& has_row, double metric_reach,
             const Parallel_executor& exec, const Separated& separated = Separated())
  {
    metric_reach2_ = metric_reach * metric_reach;
    const std::size_t n = bubbles.size();
    offsets_.assign(n + 1, 0);
    neighbours_.clear();
    if(n == 0)
      return;
    extent_.resize(n);
    exec.for_each(n, [&](std::size_t i) {
      const Sym3 inv = bubbles[i].m.inverse();
      // inflated by 0.1% against rounding (it only decides the search)
      extent_[i] = 1.001 * metric_reach * Vec3(std::sqrt(inv.a00), std::sqrt(inv.a11), std::sqrt(inv.a22));
    });
    setup_grid(bubbles);

    // Cell keys and the sorted (key, index) table.
    entries_.resize(n);
    exec.for_each(n, [&](std::size_t i) { entries_[i] = Entry{key(bubbles[i].x, level_[i]), static_cast<int>(i)}; });
    std::sort(entries_.begin(), entries_.end(), [](const Entry& a, const Entry& b) {
      return a.key < b.key || (a.key == b.key && a.index < b.index);
    });
    build_hash();

    // Candidate pairs per block.
    const std::size_t nb = Parallel_executor::number_of_blocks(n);
    if(block_pairs_.size() < nb)
      block_pairs_.resize(nb);
    exec.for_each_block(n, [&](std::size_t b, std::size_t begin, std::size_t end) {
      std::vector<std::pair<int, int>>& out = block_pairs_[b];
      out.clear();
      for(std::size_t i = begin; i < end; ++i)
        find_pairs(static_cast<int>(i), bubbles, has_row, separated, out);
    });

    // Compressed rows, in block order, then each row sorted by index.
    for(std::size_t b = 0; b < nb; ++b)
      for(const auto& p : block_pairs_[b]) {
        if(has_row[p.first])
          ++offsets_[p.first + 1];
        if(has_row[p.second])
          ++offsets_[p.second + 1];
      }
    for(std::size_t i = 0; i < n; ++i)
      offsets_[i + 1] += offsets_[i];
    neighbours_.resize(offsets_[n]);
    fill_.assign(offsets_.begin(), offsets_.end() - 1);
    for(std::size_t b = 0; b < nb; ++b)
      for(const auto& p : block_pairs_[b]) {
        if(has_row[p.first])
          neighbours_[fill_[p.first]++] = p.second;
        if(has_row[p.second])
          neighbours_[fill_[p.second]++] = p.first;
      }
    // rows by index: the force loops then read the bubbles in memory order
    exec.for_each(n, [&](std::size_t i) {
      std::sort(neighbours_.begin() + offsets_[i], neighbours_.begin() + offsets_[i + 1]);
    });
  }

  const int* begin(std::size_t i) const { return neighbours_.data() + offsets_[i]; }
  const int* end(std::size_t i) const { return neighbours_.data() + offsets_[i + 1]; }
  std::size_t size(std::size_t i) const { return offsets_[i + 1] - offsets_[i]; }
  std::size_t number_of_entries() const { return neighbours_.size(); }
  int number_of_levels() const { return levels_; }

private:
  struct Entry {
    std::uint64_t key;
    int index;
  };

  // cells are 1/stencil of the extents: a (2 stencil + 1)^3 block of cells
  // holds fewer far candidates than 3^3 cells of the extents
  static constexpr std::int64_t stencil = 2;
  static constexpr int coordinate_bits = 19;
  static constexpr std::int64_t coordinate_range = std::int64_t(1) << coordinate_bits;

  template <typename Record>
  void setup_grid(const std::vector<Record>& bubbles)
  {
    const std::size_t n = bubbles.size();
    lo_ = bubbles[0].x;
    Vec3 hi = lo_;
    Vec3 emin = extent_[0], emax = extent_[0];
    for(std::size_t i = 0; i < n; ++i) {
      lo_ = lo_.cwiseMin(bubbles[i].x);
      hi = hi.cwiseMax(bubbles[i].x);
      emin = emin.cwiseMin(extent_[i]);
      emax = emax.cwiseMax(extent_[i]);
    }
    // The finest cells: the smallest extents over the stencil radius, unless
    // the coordinates would overflow.
    for(int k = 0; k < 3; ++k) {
      const double span = std::max(hi[k] - lo_[k], emax[k]);
      base_[k] = std::max(emin[k] / stencil, 8 * span / double(coordinate_range));
    }
    lo_ -= double(stencil) * base_;
    level_.resize(n);
    levels_ = 1;
    for(std::size_t i = 0; i < n; ++i) {
      int l = 0;
      double f = stencil;
      while(f * base_[0] < extent_[i][0] || f * base_[1] < extent_[i][1] || f * base_[2] < extent_[i][2]) {
        f *= 2;
        ++l;
      }
      level_[i] = l;
      levels_ = std::max(levels_, l + 1);
    }
    inv_cell_size_.resize(levels_);
    for(int l = 0; l < levels_; ++l)
      for(int k = 0; k < 3; ++k)
        inv_cell_size_[l][k] = 1 / std::ldexp(base_[k], l);
    level_used_.assign(levels_, 0);
    // per level, the box of the occupied cells: a search skips the levels and
    // columns it does not meet (the levels of a graded packing are far apart)
    level_box_.assign(levels_, Cell_box{{coordinate_range, coordinate_range, coordinate_range}, {-1, -1, -1}});
    for(std::size_t i = 0; i < n; ++i) {
      const int l = level_[i];
      level_used_[l] = 1;
      const Vec3 y = bubbles[i].x - lo_;
      for(int k = 0; k < 3; ++k) {
        const std::int64_t c = coordinate(y[k], l, k);
        level_box_[l].lo[k] = std::min(level_box_[l].lo[k], c);
        level_box_[l].hi[k] = std::max(level_box_[l].hi[k], c);
      }
    }
  }

  std::int64_t coordinate(double x, int l, int axis) const
  {
    return static_cast<std::int64_t>(std::floor(x * inv_cell_size_[l][axis]));
  }

  static std::uint64_t pack(int l, std::int64_t cx, std::int64_t cy, std::int64_t cz)
  {
    return (std::uint64_t(l) << (3 * coordinate_bits)) | (std::uint64_t(cx) << (2 * coordinate_bits)) |
           (std::uint64_t(cy) << coordinate_bits) | std::uint64_t(cz);
  }

  std::uint64_t key(const Vec3& x, int l) const
  {
    const Vec3 y = x - lo_;
    return pack(l, coordinate(y[0], l, 0), coordinate(y[1], l, 1), coordinate(y[2], l, 2));
  }

  static std::uint64_t hash(std::uint64_t k)
  {
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdULL;
    k ^= k >> 33;
    return k;
  }

  // Open addressing: key -> [first, last) in entries_.
  void build_hash()
  {
    std::size_t cells = 0;
    for(std::size_t i = 0; i < entries_.size(); ++i)
      if(i == 0 || entries_[i].key != entries_[i - 1].key)
        ++cells;
    std::size_t cap = 16;
    while(cap < 2 * cells)
      cap *= 2;
    mask_ = cap - 1;
    slots_.assign(cap, Slot{empty_key, 0, 0});
    for(std::size_t i = 0; i < entries_.size();) {
      std::size_t j = i + 1;
      while(j < entries_.size() && entries_[j].key == entries_[i].key)
        ++j;
      std::size_t h = hash(entries_[i].key) & mask_;
      while(slots_[h].key != empty_key)
        h = (h + 1) & mask_;
      slots_[h] = Slot{entries_[i].key, static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j)};
      i = j;
    }
  }

  const Entry* find_cell(std::uint64_t k, const Entry*& last) const
  {
    std::size_t h = hash(k) & mask_;
    while(slots_[h].key != empty_key) {
      if(slots_[h].key == k) {
        last = entries_.data() + slots_[h].last;
        return entries_.data() + slots_[h].first;
      }
      h = (h + 1) & mask_;
    }
    last = nullptr;
    return nullptr;
  }

  template <typename Record, typename Separated>
  void find_pairs(int i, const std::vector<Record>& bubbles, const std::vector<char>& has_row,
                  const Separated& separated, std::vector<std::pair<int, int>>& out) const
  {
    const Vec3& xi = bubbles[i].x;
    const Vec3 y = xi - lo_;
    const Vec3& ei = extent_[i];
    const int li = level_[i];
    const Entry* const entries_end = entries_.data() + entries_.size();
    for(int l = li; l < levels_; ++l) {
      if(!level_used_[l])
        continue;
      const std::int64_t cx = coordinate(y[0], l, 0), cy = coordinate(y[1], l, 1), cz = coordinate(y[2], l, 2);
      const Cell_box& box = level_box_[l];
      if(cx + stencil < box.lo[0] || cx - stencil > box.hi[0] || cy + stencil < box.lo[1] ||
         cy - stencil > box.hi[1] || cz + stencil < box.lo[2] || cz - stencil > box.hi[2])
        continue;
      const bool own = (l == li);
      for(std::int64_t dx = -stencil; dx <= stencil; ++dx)
        for(std::int64_t dy = -stencil; dy <= stencil; ++dy) {
          // On its own level, a pair is found from the bubble whose cell is
          // lexicographically smaller (half shell), or, in one cell, from the
          // smaller index. The cells (ax, ay, z0..z1) are consecutive in the
          // sorted table: one look-up finds the first non-empty one.
          std::int64_t z0 = cz - stencil;
          const std::int64_t z1 = cz + stencil;
          if(own && (dx < 0 || (dx == 0 && dy < 0)))
            continue;
          if(own && dx == 0 && dy == 0)
            z0 = cz;
          const std::int64_t ax = cx + dx, ay = cy + dy;
          if(ax < box.lo[0] || ay < box.lo[1] || ax > box.hi[0] || ay > box.hi[1])
            continue;
          z0 = std::max<std::int64_t>(z0, box.lo[2]);
          const std::int64_t z1c = std::min<std::int64_t>(z1, box.hi[2]);
          const Entry* e = nullptr;
          for(std::int64_t z = z0; z <= z1c && e == nullptr; ++z) {
            const Entry* last;
            e = find_cell(pack(l, ax, ay, z), last);
          }
          if(e == nullptr)
            continue;
          const std::uint64_t last_key = pack(l, ax, ay, z1c);
          const std::uint64_t own_key = own ? pack(l, cx, cy, cz) : empty_key;
          for(; e != entries_end && e->key <= last_key; ++e) {
            const int j = e->index;
            if(e->key == own_key && j <= i)
              continue;
            if(!has_row[i] && !has_row[j])
              continue;
            const Vec3 d = bubbles[j].x - xi;
            const Vec3& ej = extent_[j];
            if(std::abs(d[0]) > std::max(ei[0], ej[0]) || std::abs(d[1]) > std::max(ei[1], ej[1]) ||
               std::abs(d[2]) > std::max(ei[2], ej[2]))
              continue;
            // decided in the metric: min(|d|_Mi, |d|_Mj) <= metric reach
            if((bubbles[i].m.squared_length(d) <= metric_reach2_ || bubbles[j].m.squared_length(d) <= metric_reach2_) &&
               !separated(i, j))
              out.emplace_back(i, j);
          }
        }
    }
  }

  struct Cell_box {
    std::array<std::int64_t, 3> lo, hi;
  };

  struct Slot {
    std::uint64_t key;
    std::uint32_t first, last;
  };
  static constexpr std::uint64_t empty_key = ~std::uint64_t(0);

  Vec3 lo_ = Vec3::Zero();
  Vec3 base_ = Vec3::Ones();
  std::vector<Vec3> extent_;
  double metric_reach2_ = 1;
  int levels_ = 1;
  std::vector<int> level_;
  std::vector<char> level_used_;
  std::vector<Cell_box> level_box_;
  std::vector<std::array<double, 3>> inv_cell_size_;
  std::vector<Entry> entries_;
  std::vector<Slot> slots_;
  std::size_t mask_ = 0;
  std::vector<std::vector<std::pair<int, int>>> block_pairs_;
  std::vector<std::size_t> offsets_, fill_;
  std::vector<int> neighbours_;
};

} // namespace packing
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_NEIGHBOUR_SEARCH_H
