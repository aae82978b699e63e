// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_BOUNDARY_STAGE_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_BOUNDARY_STAGE_H

// Stage 2 of the pipeline (paper, section 3.1): the packed corner, curve and
// patch nodes triangulated into a closed boundary front that honours the
// metric, with the feature edges labelled by the domain's curves. The stage
// chooses the nodes it uses (patch nodes on or next to a feature curve would
// make slivers) and adds those the surface needs (counted by the front).

#include <CGAL/Bubble_mesh_3/Meshing_report.h>
#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/internal/front/boundary_front.h>
#include <CGAL/Bubble_mesh_3/internal/front/feature_chains.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/domain_mesh.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/run_control.h>

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <chrono>
#include <limits>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

/// The input surface as the later stages use it: its triangles, patches and
/// feature edges, the chains of feature edges between corners, and the
/// domain's curve id of each chain (-1: not used by the front).
struct Domain_boundary {
  front::Boundary_surface surface;
  front::Feature_chains chains;
  std::vector<int> chain_curves;
};

/// Which patch nodes the boundary front takes: not those on, or within metric
/// distance 0.1 of, a feature curve bounding their patch. The surface packer
/// keeps a bubble on its patch by a wall at the patch boundary, but a step
/// that overshoots the wall by less than its rounding allowance ends on the
/// curve itself (a 1:100 metric oblique to the faces of a cube did it): the
/// front would refuse it. Closer than 0.1 it would only make a sliver
/// triangle against the curve, whose own nodes stand.
class Patch_node_filter {
  typedef CGAL::Exact_predicates_inexact_constructions_kernel EK;
  typedef CGAL::AABB_segment_primitive<EK, typename std::vector<EK::Segment_3>::const_iterator> Primitive;

public:
  explicit Patch_node_filter(const front::Boundary_surface& surface)
  {
    std::map<std::pair<int, int>, std::array<int, 2>> sides;
    for(const auto& e : surface.feature_edges)
      sides.emplace(std::minmax(e[0], e[1]), std::array<int, 2>{{-1, -1}});
    for(std::size_t f = 0; f < surface.triangles.size(); ++f)
      for(int k = 0; k < 3; ++k) {
        auto it = sides.find(std::minmax(surface.triangles[f][k], surface.triangles[f][(k + 1) % 3]));
        if(it != sides.end())
          it->second[it->second[0] < 0 ? 0 : 1] = surface.patches[f];
      }
    for(const auto& e : sides) {
      const auto &a = surface.points[std::size_t(e.first.first)], &b = surface.points[std::size_t(e.first.second)];
      segments_.emplace_back(EK::Point_3(a[0], a[1], a[2]), EK::Point_3(b[0], b[1], b[2]));
      patches_.push_back(e.second);
    }
    if(!segments_.empty()) {
      tree_.insert(segments_.begin(), segments_.end());
      tree_.accelerate_distance_queries();
    }
  }

  /// whether a node of `patch` at `x` is too close to a curve bounding it
  template <typename MetricField>
  bool rejects(const std::array<double, 3>& x, int patch, const MetricField& field) const
  {
    if(segments_.empty())
      return false;
    const EK::Point_3 q(x[0], x[1], x[2]);
    const auto cp = tree_.closest_point_and_primitive(q);
    const std::size_t si = static_cast<std::size_t>(cp.second - segments_.begin());
    if(patches_[si][0] != patch && patches_[si][1] != patch)
      return false;
    // the distance in the node's metric to that segment (closest point in the metric)
    typedef typename MetricField::Kernel::Point_3 Point;
    const Metric_3 mq = Metric_3(field(Point(x[0], x[1], x[2])));
    const EK::Segment_3& sg = segments_[si];
    const Eigen::Vector3d a(sg.source().x(), sg.source().y(), sg.source().z());
    const Eigen::Vector3d ab = Eigen::Vector3d(sg.target().x(), sg.target().y(), sg.target().z()) - a;
    const Eigen::Vector3d p(x[0], x[1], x[2]);
    const double l2 = mq.squared_length(ab);
    const double t = l2 > 0 ? std::clamp((p - a).dot(mq.matrix() * ab) / l2, 0.0, 1.0) : 0.0;
    return mq.length(a + t * ab - p) < 0.1;
  }

private:
  std::vector<EK::Segment_3> segments_;
  std::vector<std::array<int, 2>> patches_; // the patches on both sides of each segment
  CGAL::AABB_tree<CGAL::AABB_traits<EK, Primitive>> tree_;
};

/// The input vertices that are corners: the one at each corner node's point
/// (the closest if a rounding moved it).
inline std::vector<char> input_corners(const front::Boundary_surface& surface, const Indexed_tet_mesh_3& m)
{
  std::vector<char> is_corner(surface.points.size(), 0);
  std::map<std::array<double, 3>, int> vertex_at;
  for(std::size_t v = 0; v < surface.points.size(); ++v)
    vertex_at.emplace(surface.points[v], int(v));
  for(int c : m.corners) {
    const auto& p = m.points[std::size_t(c)];
    const auto it = vertex_at.find(p);
    int v = it != vertex_at.end() ? it->second : -1;
    if(v < 0) {
      double best = std::numeric_limits<double>::max();
      for(std::size_t u = 0; u < surface.points.size(); ++u) {
        const auto& q = surface.points[u];
        const double d = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]);
        if(d < best) {
          best = d;
          v = int(u);
        }
      }
    }
    if(v >= 0)
      is_corner[std::size_t(v)] = 1;
  }
  return is_corner;
}

/// The domain's curve id of each feature chain of the input surface that the
/// front uses (-1 for the others): the domain's curve through the midpoints
/// of the chain's input edges (the domain's own segment tree of its curves).
/// Throws `Meshing_failure` if an edge lies on no curve of the domain, or a
/// chain's edges on two.
template <typename MeshDomain>
std::vector<int> curves_of_feature_chains(const MeshDomain& domain, const front::Boundary_surface& surface,
                                          const front::Feature_chains& chains, const front::Boundary_front& bf)
{
  std::vector<int> curve(chains.chains.size(), -1);
  std::vector<char> used(chains.chains.size(), 0);
  for(int source : bf.feature_edge_sources)
    used[std::size_t(chains.chain_of_edge[std::size_t(source)])] = 1;
  typedef typename std::decay_t<decltype(domain.curves_aabb_tree())>::Point Point;
  for(std::size_t c = 0; c < curve.size(); ++c) {
    if(!used[c])
      continue;
    for(int e : chains.chains[c].edges) {
      const auto& a = surface.points[std::size_t(surface.feature_edges[std::size_t(e)][0])];
      const auto& b = surface.points[std::size_t(surface.feature_edges[std::size_t(e)][1])];
      const Point mid((a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2);
      const auto hit = domain.curves_aabb_tree().closest_point_and_primitive(mid);
      const double squared_length = (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                                    (a[2] - b[2]) * (a[2] - b[2]);
      const int id = static_cast<int>(hit.second.first->first);
      if(CGAL::to_double(CGAL::squared_distance(hit.first, mid)) > 1e-12 * squared_length || (curve[c] >= 0 && curve[c] != id))
        throw Meshing_failure("boundary front: a feature curve of the surface is not a curve of the domain");
      curve[c] = id;
    }
  }
  return curve;
}

/// Stage 2: fills `out` with the boundary nodes (the packed corner, curve and
/// patch nodes it keeps, then the nodes the front added), the boundary
/// triangles with their patches, the feature edges with their curves and the
/// corners.
template <typename MeshDomain, typename MetricField, typename Node>
Domain_boundary boundary_stage(const MeshDomain& domain, const MetricField& field, const std::vector<Node>& nodes,
                               const Run_control& control, Meshing_report& rep, Domain_mesh& out)
{
  namespace F = front;
  control.advance(0.5);
  const auto t0 = std::chrono::steady_clock::now();
  Domain_boundary boundary;
  boundary.surface = F::boundary_surface_from_polyhedral_domain(domain);
  const F::Boundary_surface& surface = boundary.surface;
  Indexed_tet_mesh_3& m = out.mesh;

  // the packed boundary nodes the front takes (they come first in the point list)
  const Patch_node_filter filter(surface);
  std::vector<F::Boundary_node> bnodes;
  for(const auto& n : nodes) {
    if(n.dimension > 2)
      continue;
    int index = 0;
    if(n.dimension == 0)
      index = static_cast<int>(domain.corner_index(n.index));
    else if(n.dimension == 1)
      index = static_cast<int>(domain.curve_index(n.index));
    else
      index = static_cast<int>(domain.surface_patch_index(n.index));
    const std::array<double, 3> x{{CGAL::to_double(n.point.x()), CGAL::to_double(n.point.y()),
                                   CGAL::to_double(n.point.z())}};
    if(n.dimension == 2 && filter.rejects(x, index, field)) {
      ++rep.dropped_patch_nodes;
      continue;
    }
    bnodes.push_back(F::Boundary_node{x, n.dimension, n.dimension == 2 ? index : -1});
    out.add_point(x[0], x[1], x[2], n.dimension, index);
  }
  if(rep.dropped_patch_nodes > 0)
    control.say("dropped surface nodes: " + std::to_string(rep.dropped_patch_nodes) +
                " on or within 0.1 of a feature curve bounding their patch");

  // The nodes come from the packer, not from the user: a node the front
  // cannot place is a meshing failure (exit 3), not invalid input.
  F::Boundary_front bf;
  try {
    bf = F::build_boundary_front(surface, bnodes, field);
  } catch(const Invalid_metric&) {
    throw;
  } catch(const Invalid_input& e) {
    throw Meshing_failure(e.what());
  }
  rep.boundary_triangles = bf.triangles.size();
  rep.boundary_seconds = seconds_since(t0);
  control.say("boundary front: " + std::to_string(bf.triangles.size()) + " triangles, " +
              std::to_string(rep.boundary_seconds) + " s");
  control.check("the boundary front");

  // nodes the front added (it counts them); their curve ids follow
  for(const auto& a : bf.added_nodes)
    out.add_point(a.point[0], a.point[1], a.point[2], a.dimension, a.dimension == 2 ? a.patch : -1);
  rep.added_boundary_nodes = bf.added_nodes.size();
  rep.boundary_repair_rounds = bf.repair_rounds;
  if(!bf.added_nodes.empty())
    control.say("boundary front: added " + std::to_string(bf.added_nodes.size()) +
                " nodes where the packed nodes could not represent the surface");
  m.triangles = bf.triangles;
  m.triangle_refs = bf.patches;

  // feature edges: the curve of the input chain each one runs along
  boundary.chains = F::feature_chains(surface, input_corners(surface, m));
  boundary.chain_curves = curves_of_feature_chains(domain, surface, boundary.chains, bf);
  m.edges = bf.feature_edges;
  for(std::size_t i = 0; i < bf.feature_edges.size(); ++i) {
    const int chain = boundary.chains.chain_of_edge[std::size_t(bf.feature_edge_sources[i])];
    const int curve = boundary.chain_curves[std::size_t(chain)];
    m.edge_refs.push_back(curve);
    for(int v : bf.feature_edges[i])
      if(out.locations[std::size_t(v)].dimension == 1 && out.locations[std::size_t(v)].index < 0)
        out.locations[std::size_t(v)].index = m.point_refs[std::size_t(v)] = curve; // an added curve node
  }
  return boundary;
}

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_BOUNDARY_STAGE_H
