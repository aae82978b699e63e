// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// The oriented boundary of a set of tets, as a chain: each face of each tet
// counts +1 in its outward orientation and -1 in the opposite one, so the
// faces two tets share with opposite orientations cancel. This is how a
// third-party tetrahedralization (TetGen) is checked before it is used: a set
// of positively oriented tets whose chain is exactly a closed surface S (each
// triangle once, outward) covers every point inside S exactly once (the
// number of tets over a point is the winding number of S around it), i.e.
// it tiles the volume S bounds, with no hole, overlap or stray tet.
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_TET_BOUNDARY_CHAIN_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_TET_BOUNDARY_CHAIN_H

#include <algorithm>
#include <array>
#include <map>
#include <utility>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

namespace chain_detail {

// the triangle rotated to start at its smallest id, and +1 if the other two
// then increase (the orientation of the sorted triangle), -1 otherwise
inline std::pair<std::array<int, 3>, int> canonical(const std::array<int, 3>& t)
{
  int r = 0;
  if(t[1] < t[r])
    r = 1;
  if(t[2] < t[r])
    r = 2;
  const int a = t[r], b = t[(r + 1) % 3], c = t[(r + 2) % 3];
  return b < c ? std::make_pair(std::array<int, 3>{{a, b, c}}, 1) : std::make_pair(std::array<int, 3>{{a, c, b}}, -1);
}

} // namespace chain_detail

/// The boundary chain of `tets` (each given positively oriented): the faces
/// whose counts do not cancel, in their outward orientation. Returns false if
/// some face counts more than once in one orientation (stacked or
/// overlapping tets), which no tiling has.
inline bool boundary_chain(const std::vector<std::array<int, 4>>& tets, std::vector<std::array<int, 3>>& faces)
{
  std::map<std::array<int, 3>, int> count;
  for(const std::array<int, 4>& t : tets) {
    const std::array<std::array<int, 3>, 4> outward{{{{t[1], t[2], t[3]}},
                                                     {{t[0], t[3], t[2]}},
                                                     {{t[0], t[1], t[3]}},
                                                     {{t[0], t[2], t[1]}}}};
    for(const auto& f : outward) {
      const auto c = chain_detail::canonical(f);
      count[c.first] += c.second;
    }
  }
  faces.clear();
  for(const auto& kv : count) {
    if(kv.second > 1 || kv.second < -1)
      return false;
    if(kv.second == 1)
      faces.push_back(kv.first);
    else if(kv.second == -1)
      faces.push_back({{kv.first[0], kv.first[2], kv.first[1]}});
  }
  return true;
}

/// Whether `tets` (each given positively oriented) have exactly `surface`
/// (each triangle once, oriented outward from the tets) as their boundary
/// chain, i.e. tile the volume it bounds (see the file comment).
inline bool tets_tile_surface(const std::vector<std::array<int, 4>>& tets,
                              const std::vector<std::array<int, 3>>& surface)
{
  std::vector<std::array<int, 3>> chain;
  if(!boundary_chain(tets, chain) || chain.size() != surface.size())
    return false;
  std::vector<std::pair<std::array<int, 3>, int>> a, b;
  for(const auto& f : chain)
    a.push_back(chain_detail::canonical(f));
  for(const auto& f : surface)
    b.push_back(chain_detail::canonical(f));
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  return a == b;
}

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_TET_BOUNDARY_CHAIN_H
