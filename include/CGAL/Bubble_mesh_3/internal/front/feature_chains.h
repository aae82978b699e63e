// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// The feature curves of the input surface as chains of its feature edges:
// a chain runs between two corners (input vertices that are not on exactly
// two feature edges, or that the caller marks: the domain's corners), or
// around a closed loop. With the domain's corners marked, a chain is one of
// the domain's curves (every curve of a CGAL mesh domain ends at corners;
// CGAL also puts corners where a loop needs two ends, or where the pair of
// patches along a curve changes, which the feature graph alone does not show).
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_FRONT_FEATURE_CHAINS_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_FRONT_FEATURE_CHAINS_H

#include <CGAL/Bubble_mesh_3/internal/front/boundary_front.h>

#include <array>
#include <cmath>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {
namespace front {

struct Feature_chain {
  std::vector<int> edges; ///< indices in `Boundary_surface::feature_edges`, in order along the chain
  std::array<int, 2> ends{{-1, -1}}; ///< the end vertices (equal for a closed loop)
  double length = 0;
};

struct Feature_chains {
  std::vector<Feature_chain> chains;
  std::vector<int> chain_of_edge; ///< for each input feature edge
};

/// `is_corner[v]`: input vertex v ends the chains through it (may be empty)
inline Feature_chains feature_chains(const Boundary_surface& s, const std::vector<char>& is_corner)
{
  auto passes = [&](int v, std::size_t degree) {
    return degree == 2 && !(std::size_t(v) < is_corner.size() && is_corner[std::size_t(v)]);
  };
  Feature_chains out;
  const auto& edges = s.feature_edges;
  std::vector<std::vector<int>> edges_at(s.points.size());
  for(std::size_t e = 0; e < edges.size(); ++e)
    for(int v : edges[e])
      edges_at[std::size_t(v)].push_back(int(e));
  out.chain_of_edge.assign(edges.size(), -1);
  auto length = [&](int e) {
    const auto &a = s.points[std::size_t(edges[std::size_t(e)][0])], &b = s.points[std::size_t(edges[std::size_t(e)][1])];
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
  };
  for(std::size_t start = 0; start < edges.size(); ++start) {
    if(out.chain_of_edge[start] >= 0)
      continue;
    const int id = int(out.chains.size());
    out.chains.emplace_back();
    Feature_chain& c = out.chains.back();
    out.chain_of_edge[start] = id;
    std::vector<int> sides[2];
    for(int side = 0; side < 2; ++side) {
      int e = int(start), v = edges[start][side];
      while(passes(v, edges_at[std::size_t(v)].size())) {
        const auto& at = edges_at[std::size_t(v)];
        const int next = at[0] == e ? at[1] : at[0];
        if(out.chain_of_edge[std::size_t(next)] >= 0)
          break; // around a closed loop
        out.chain_of_edge[std::size_t(next)] = id;
        sides[side].push_back(next);
        e = next;
        v = edges[std::size_t(e)][0] == v ? edges[std::size_t(e)][1] : edges[std::size_t(e)][0];
      }
      c.ends[std::size_t(side)] = v;
    }
    c.edges.assign(sides[0].rbegin(), sides[0].rend());
    c.edges.push_back(int(start));
    c.edges.insert(c.edges.end(), sides[1].begin(), sides[1].end());
    for(int e : c.edges)
      c.length += length(e);
  }
  return out;
}

} // namespace front
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_FRONT_FEATURE_CHAINS_H
