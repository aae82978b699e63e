// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Closest points on the input surface, per patch and per feature curve: what
// the improver's boundary vertices slide on (`Improvement_options::
// surface_projection` and `curve_projection`). A curve is a chain of input
// feature edges (feature_chains.h).
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_IMPROVE_INPUT_PROJECTIONS_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_IMPROVE_INPUT_PROJECTIONS_H

#include <CGAL/Bubble_mesh_3/internal/front/feature_chains.h>

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <array>
#include <map>
#include <memory>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {
namespace improve {

class Input_projections {
  typedef CGAL::Exact_predicates_inexact_constructions_kernel EK;
  typedef std::vector<EK::Triangle_3> Triangles;
  typedef std::vector<EK::Segment_3> Segments;
  typedef CGAL::AABB_tree<CGAL::AABB_traits<EK, CGAL::AABB_triangle_primitive<EK, Triangles::const_iterator>>>
      Patch_tree;
  typedef CGAL::AABB_tree<CGAL::AABB_traits<EK, CGAL::AABB_segment_primitive<EK, Segments::const_iterator>>>
      Curve_tree;

public:
  /// `chain_curves[c]`: the curve id of feature chain c (-1: none)
  Input_projections(const front::Boundary_surface& surface, const front::Feature_chains& chains,
                    const std::vector<int>& chain_curves)
  {
    for(std::size_t f = 0; f < surface.triangles.size(); ++f) {
      const auto& t = surface.triangles[f];
      patch_triangles_[surface.patches[f]].emplace_back(point(surface, t[0]), point(surface, t[1]),
                                                        point(surface, t[2]));
    }
    for(const auto& pt : patch_triangles_) {
      auto tree = std::make_unique<Patch_tree>(pt.second.begin(), pt.second.end());
      tree->accelerate_distance_queries();
      patch_trees_.emplace(pt.first, std::move(tree));
    }
    for(std::size_t c = 0; c < chains.chains.size(); ++c) {
      if(chain_curves[c] < 0)
        continue;
      Segments& segments = curve_segments_[chain_curves[c]];
      for(int e : chains.chains[c].edges)
        segments.emplace_back(point(surface, surface.feature_edges[std::size_t(e)][0]),
                              point(surface, surface.feature_edges[std::size_t(e)][1]));
    }
    for(const auto& cs : curve_segments_) {
      auto tree = std::make_unique<Curve_tree>(cs.second.begin(), cs.second.end());
      tree->accelerate_distance_queries();
      curve_trees_.emplace(cs.first, std::move(tree));
    }
  }

  /// closest point of patch `ref` to `p` (false: no such patch)
  bool surface(int ref, const std::array<double, 3>& p, std::array<double, 3>& q) const
  {
    const auto it = patch_trees_.find(ref);
    if(it == patch_trees_.end())
      return false;
    return closest(*it->second, p, q);
  }

  /// closest point of curve `ref` to `p` (false: no such curve)
  bool curve(int ref, const std::array<double, 3>& p, std::array<double, 3>& q) const
  {
    const auto it = curve_trees_.find(ref);
    if(it == curve_trees_.end())
      return false;
    return closest(*it->second, p, q);
  }

private:
  static EK::Point_3 point(const front::Boundary_surface& s, int v)
  {
    const auto& p = s.points[std::size_t(v)];
    return EK::Point_3(p[0], p[1], p[2]);
  }

  template <typename Tree>
  static bool closest(const Tree& tree, const std::array<double, 3>& p, std::array<double, 3>& q)
  {
    const EK::Point_3 c = tree.closest_point(EK::Point_3(p[0], p[1], p[2]));
    q = {{c.x(), c.y(), c.z()}};
    return true;
  }

  std::map<int, Triangles> patch_triangles_;
  std::map<int, Segments> curve_segments_;
  std::map<int, std::unique_ptr<Patch_tree>> patch_trees_;
  std::map<int, std::unique_ptr<Curve_tree>> curve_trees_;
};

} // namespace improve
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_IMPROVE_INPUT_PROJECTIONS_H
