// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Contract: `for_each_block(n, f)` calls `f(begin, end)` on the fixed blocks
// [k*B, min(n,(k+1)*B)) of [0, n). The partition depends only on `n`, never on
// the number of threads, so any per-block output is identical for every thread
// count. With TBB (CGAL_LINKED_WITH_TBB) the blocks run in parallel inside a
// task arena of `threads` workers (0 = TBB's default); otherwise serially.
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_PARALLEL_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_PARALLEL_H

#include <cstddef>

#ifdef CGAL_LINKED_WITH_TBB
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <memory>
#endif

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {
namespace packing {

class Parallel_executor {
public:
  static constexpr std::size_t block_size = 256;

  explicit Parallel_executor(int threads = 0) : threads_(threads)
  {
#ifdef CGAL_LINKED_WITH_TBB
    if(threads_ != 1)
      arena_ = threads_ > 0 ? std::make_unique<tbb::task_arena>(threads_) : std::make_unique<tbb::task_arena>();
#endif
  }

  /// number of threads asked for (0: all)
  int threads() const { return threads_; }

  static std::size_t number_of_blocks(std::size_t n) { return (n + block_size - 1) / block_size; }

  /// calls f(block, begin, end) for every fixed block
  template <typename F>
  void for_each_block(std::size_t n, const F& f) const
  {
    const std::size_t nb = number_of_blocks(n);
#ifdef CGAL_LINKED_WITH_TBB
    if(arena_ && nb > 1) {
      arena_->execute([&] {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nb, 1), [&](const tbb::blocked_range<std::size_t>& r) {
          for(std::size_t b = r.begin(); b != r.end(); ++b)
            f(b, b * block_size, (b + 1) * block_size < n ? (b + 1) * block_size : n);
        });
      });
      return;
    }
#endif
    for(std::size_t b = 0; b < nb; ++b)
      f(b, b * block_size, (b + 1) * block_size < n ? (b + 1) * block_size : n);
  }

  /// calls f(i) for every i in [0, n)
  template <typename F>
  void for_each(std::size_t n, const F& f) const
  {
    for_each_block(n, [&](std::size_t, std::size_t b, std::size_t e) {
      for(std::size_t i = b; i < e; ++i)
        f(i);
    });
  }

private:
  int threads_;
#ifdef CGAL_LINKED_WITH_TBB
  std::unique_ptr<tbb::task_arena> arena_;
#endif
};

} // namespace packing
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PACKING_PARALLEL_H
