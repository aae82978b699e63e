// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Contract: Verlet neighbour lists over a multi-level grid.
//
// Each bubble i has a Euclidean reach R_i = (w_cut + skin) * h_max_i, where
// h_max_i is its largest principal size. Two bubbles can interact (normalized
// distance w <= w_cut) only if min(|d|_Mi, |d|_Mj) <= w_cut (the harmonic mean
// of the two metric lengths is at least their minimum), hence only if
// |x_i - x_j| <= max(R_i, R_j). The grid finds the pairs within that Euclidean
// distance; a pair is kept when min(|d|_Mi, |d|_Mj) <= `metric_reach` (= w_cut +
// skin), so stretched bubbles keep short lists. Bubble i is stored at
// the grid level L_i whose cell size s0 * 2^L_i is the smallest >= R_i, and
// searches the 27 cells around it on levels > L_i and the half shell (13 cells
// and its own) on L_i; pairs with a bubble of a finer level are found from that
// bubble's side. So the search is exact for
// any ratio of sizes, and costs 27 cell look-ups per non-empty level.
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
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {
namespace packing {

class Neighbour_lists {
public:
  /// Builds the lists. `reach[i]` is R_i; `has_row[i]` tells whether bubble i
  /// needs its own row (moving bubbles); pairs of two row-less bubbles are skipped.
  void build(const std::vector<Bubble_record>& bubbles, const std::vector<double>& reach,
             const std::vector<char>& has_row, double metric_reach, const Parallel_executor& exec)
  {
    metric_reach2_ = metric_reach * metric_reach;
    const std::size_t n = bubbles.size();
    offsets_.assign(n + 1, 0);
    neighbours_.clear();
    if(n == 0)
      return;
    setup_grid(bubbles, reach);

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
        find_pairs(static_cast<int>(i), bubbles, reach, has_row, out);
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

  static constexpr int coordinate_bits = 19;
  static constexpr std::int64_t coordinate_range = std::int64_t(1) << coordinate_bits;

  void setup_grid(const std::vector<Bubble_record>& bubbles, const std::vector<double>& reach)
  {
    const std::size_t n = bubbles.size();
    lo_ = bubbles[0].x;
    Vec3 hi = lo_;
    double rmin = reach[0], rmax = reach[0];
    for(std::size_t i = 0; i < n; ++i) {
      lo_ = lo_.cwiseMin(bubbles[i].x);
      hi = hi.cwiseMax(bubbles[i].x);
      rmin = std::min(rmin, reach[i]);
      rmax = std::max(rmax, reach[i]);
    }
    const double span = std::max((hi - lo_).maxCoeff(), rmax);
    // The finest cell: the smallest reach, unless the coordinates would overflow.
    base_ = std::max(rmin, 4 * span / double(coordinate_range));
    lo_ -= Vec3::Constant(base_);
    level_.resize(n);
    levels_ = 1;
    for(std::size_t i = 0; i < n; ++i) {
      int l = 0;
      double s = base_;
      while(s < reach[i]) {
        s *= 2;
        ++l;
      }
      level_[i] = l;
      levels_ = std::max(levels_, l + 1);
    }
    cell_size_.resize(levels_);
    inv_cell_size_.resize(levels_);
    for(int l = 0; l < levels_; ++l) {
      cell_size_[l] = std::ldexp(base_, l);
      inv_cell_size_[l] = 1 / cell_size_[l];
    }
    level_used_.assign(levels_, 0);
    for(std::size_t i = 0; i < n; ++i)
      level_used_[level_[i]] = 1;
  }

  std::int64_t coordinate(double x, int l) const { return static_cast<std::int64_t>(std::floor(x * inv_cell_size_[l])); }

  static std::uint64_t pack(int l, std::int64_t cx, std::int64_t cy, std::int64_t cz)
  {
    return (std::uint64_t(l) << (3 * coordinate_bits)) | (std::uint64_t(cx) << (2 * coordinate_bits)) |
           (std::uint64_t(cy) << coordinate_bits) | std::uint64_t(cz);
  }

  std::uint64_t key(const Vec3& x, int l) const
  {
    const Vec3 y = x - lo_;
    return pack(l, coordinate(y[0], l), coordinate(y[1], l), coordinate(y[2], l));
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

  void find_pairs(int i, const std::vector<Bubble_record>& bubbles, const std::vector<double>& reach,
                  const std::vector<char>& has_row, std::vector<std::pair<int, int>>& out) const
  {
    const Vec3& xi = bubbles[i].x;
    const Vec3 y = xi - lo_;
    const double ri = reach[i];
    const int li = level_[i];
    const Entry* const entries_end = entries_.data() + entries_.size();
    for(int l = li; l < levels_; ++l) {
      if(!level_used_[l])
        continue;
      const std::int64_t cx = coordinate(y[0], l), cy = coordinate(y[1], l), cz = coordinate(y[2], l);
      const bool own = (l == li);
      for(std::int64_t dx = -1; dx <= 1; ++dx)
        for(std::int64_t dy = -1; dy <= 1; ++dy) {
          // On its own level, a pair is found from the bubble whose cell is
          // lexicographically smaller (half shell), or, in one cell, from the
          // smaller index. The cells (ax, ay, z0..z1) are consecutive in the
          // sorted table: one look-up finds the first non-empty one.
          std::int64_t z0 = cz - 1;
          const std::int64_t z1 = cz + 1;
          if(own && (dx < 0 || (dx == 0 && dy < 0)))
            continue;
          if(own && dx == 0 && dy == 0)
            z0 = cz;
          const std::int64_t ax = cx + dx, ay = cy + dy;
          if(ax < 0 || ay < 0 || ax >= coordinate_range || ay >= coordinate_range)
            continue;
          z0 = std::max<std::int64_t>(z0, 0);
          const std::int64_t z1c = std::min<std::int64_t>(z1, coordinate_range - 1);
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
            const double r = std::max(ri, reach[j]);
            const Vec3 d = bubbles[j].x - xi;
            if(d.squaredNorm() > r * r)
              continue;
            // decided in the metric: min(|d|_Mi, |d|_Mj) <= metric reach
            if(bubbles[i].m.squared_length(d) <= metric_reach2_ || bubbles[j].m.squared_length(d) <= metric_reach2_)
              out.emplace_back(i, j);
          }
        }
    }
  }

  struct Slot {
    std::uint64_t key;
    std::uint32_t first, last;
  };
  static constexpr std::uint64_t empty_key = ~std::uint64_t(0);

  Vec3 lo_ = Vec3::Zero();
  double base_ = 1;
  double metric_reach2_ = 1;
  int levels_ = 1;
  std::vector<int> level_;
  std::vector<char> level_used_;
  std::vector<double> cell_size_, inv_cell_size_;
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
