// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// The boundary front: the nodes that bubble packing left on the domain's
// boundary (corner, curve and patch nodes) connected into a closed, outward
// oriented triangle surface (paper, section 5.2: "we first mesh boundaries
// into a triangular mesh considering anisotropy" with a modified Delaunay
// criterion). The volume mesher advances from it.
//
// Why this construction. Triangulating the nodes directly (a surface
// Delaunay / ball pivoting / per-patch parametrisation) needs a parametrisation
// of each patch or a sampling condition, and patches may be closed (sphere),
// annuli (side of a cylinder) or curved and non-convex. Instead the input
// surface itself is used as the scaffold, which is already a valid closed
// manifold with the right topology, patches and feature curves:
//  1. the input triangles are copied into a small indexed mesh (per-vertex
//     face lists, a feature-edge table carrying the index of the input
//     feature edge each piece runs along, and for every face the input face it
//     comes from, whose normal is the "reference normal");
//  2. every node is inserted: a corner node takes the input vertex it
//     coincides with; a curve node splits the feature edge it lies on (the
//     nodes of one input edge sorted along it); a patch node is located (AABB
//     tree over its own patch) in an input face and inserted in the current
//     sub-triangulation of that face (face split, or edge split when it lies
//     on an edge), always at its exact position; the nodes of one input face
//     are inserted in Morton order, located by a walk (linear scan as the
//     fallback) and followed by Lawson metric Delaunay flips that stay inside
//     that input face (so each input face stays tiled by its own triangles);
//  3. the curves get the nodes their topology needs: a stretch of curve
//     from a node back to itself gets two nodes (at a third and two thirds
//     of its metric length), and of several stretches joining the same two
//     nodes all but the shortest get one (at the middle): else two of them
//     would collapse onto one edge. The nodes are new points splitting the
//     input feature edges (counted as added nodes). Then metric Delaunay
//     flips (below) clean the thin triangles of step 2;
//  4. every input vertex that is not a node is removed: by the edge collapse
//     into a neighbour that gives the best new triangles, subject to the link
//     condition (stays manifold), to "a curve vertex moves only along its own
//     curve, a corner never moves, no collapse across patches" and to "no new
//     triangle turns by more than max_normal_deviation from the triangle it
//     replaces nor by more than max_reference_deviation from the input face it
//     comes from" (no fold); when no collapse is valid the star is
//     re-triangulated in a local projection (ear clipping, per side of the
//     curve for a curve vertex); when that fails too, edges around the vertex
//     are flipped and the vertex is retried later; a vertex that still cannot
//     be removed is collapsed into a node closer than half a metric unit
//     with a looser tilt bound, or else the surface needs a node there (a
//     tip, a thin part): it is kept as an added node;
//  5. metric Delaunay flips: an edge ab with opposite vertices c, d (same
//     patch, not a feature edge, cd not an edge yet) is flipped when the
//     angles at c and d, measured after mapping by Q of the metric at the
//     centroid of abcd, sum to more than the angles at a and b (for a planar
//     convex quad: more than pi); the flip must not fold nor make a crease
//     sharper than max(current, max_flip_dihedral). Bounded passes.
//  6. the result is checked (closed, edge- and vertex-manifold, oriented,
//     positive volume, no degenerate triangle, feature edges are mesh edges,
//     no self-intersection via PMP::self_intersections).
//  7. repair: where step 6 finds a problem (two chords of a thin part that
//     cross, a degenerate or non-manifold spot), the input vertices of the
//     input faces under the offending triangles (and, round after round, a
//     growing ring of input vertices around them) are kept as added nodes and
//     the front is rebuilt. The last round keeps every input vertex and flips
//     only inside input faces: the front is then the input surface itself,
//     refined by the nodes, which is valid for any valid input. So a valid
//     closed surface always gives a front; Meshing_failure is raised only if
//     even that last round fails its checks.
// Node positions never change: collapses always remove a non-node vertex.
// Added nodes (new points on feature curves, kept input vertices) follow
// the given nodes in the numbering.
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_FRONT_BOUNDARY_FRONT_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_FRONT_BOUNDARY_FRONT_H

#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {
namespace front {

/// The input surface: closed, manifold, outward oriented triangles.
struct Boundary_surface {
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<int, 3>> triangles;
  /// patch id of each triangle
  std::vector<int> patches;
  /// sharp edges (vertex pairs); must include every edge between two patches
  std::vector<std::array<int, 2>> feature_edges;
};

/// A node left by bubble packing on the boundary.
struct Boundary_node {
  std::array<double, 3> point;
  /// 0: corner (an input vertex up to rounding), 1: on a feature edge,
  /// 2: on a face of patch `patch`
  int dimension;
  /// for dimension 2: the patch id; otherwise ignored
  int patch;
};

struct Boundary_front_options {
  /// a node farther than this from the surface (resp. its feature edge, its
  /// patch, its vertex) is invalid input; relative to the bounding box diagonal
  double surface_tolerance = 1e-5;
  /// a patch node closer than this to an edge (vertex) of the current mesh is
  /// inserted on that edge (is that vertex); relative to the bbox diagonal
  double snap_tolerance = 1e-9;
  /// a collapse/flip/re-triangulation may not turn a triangle by more than
  /// this from the triangles it replaces (for a flip: from the mean normal of
  /// the two triangles) (degrees)
  double max_normal_deviation = 60;
  /// nor by more than this from the input face it lies on (degrees)
  double max_reference_deviation = 80;
  /// a Delaunay flip may not make the crease between its two triangles
  /// sharper than max(current crease, this) (degrees)
  double max_flip_dihedral = 30;
  /// bound on the passes of metric Delaunay flips (each pass visits all edges)
  int max_flip_passes = 60;
  /// rounds without progress (after flips around stuck vertices) before
  /// giving up on removing the input vertices that are not nodes
  int max_stuck_rounds = 10;
  /// then a vertex closer than this (metric length) to a neighbour is
  /// collapsed into it with the looser bound below; any other is kept as a node
  double short_collapse_length = 0.5;
  /// (degrees) bound on the turn of each triangle in such a collapse, from
  /// the triangle it replaces and from its input face
  double max_short_collapse_deviation = 85;
  /// check the result for self-intersections (PMP::self_intersections)
  bool check_self_intersection = true;
  /// rebuilds with more kept input vertices before the last one, which keeps
  /// every input vertex (step 7)
  int max_repair_rounds = 6;
};

struct Boundary_front {
  /// nodes the front added where the given nodes could not represent the
  /// surface (input vertices it kept, points at the middle of a stretch of
  /// feature curve); node i >= nodes.size() is added_nodes[i - nodes.size()]
  /// (dimension 1: on a feature curve, 2: inside patch `patch`; 0 only if a
  /// surface corner had no node, which the packer never leaves)
  std::vector<Boundary_node> added_nodes;
  /// node indices (the given nodes, then the added ones), outward oriented
  std::vector<std::array<int, 3>> triangles;
  /// patch id of each triangle
  std::vector<int> patches;
  /// node pairs: the edges lying on feature curves
  std::vector<std::array<int, 2>> feature_edges;
  /// for each feature edge: index in surface.feature_edges of an input
  /// feature edge it runs along
  std::vector<int> feature_edge_sources;

  // statistics
  std::size_t face_splits = 0;        ///< patch nodes inserted inside a face
  std::size_t edge_splits = 0;        ///< nodes inserted on an edge
  std::size_t removed_vertices = 0;   ///< input vertices that were not nodes
  std::size_t collapses = 0;          ///< removed by edge collapse
  std::size_t short_collapses = 0;    ///< removed by a collapse into a close node with the looser bound
  std::size_t fallback_retriangulations = 0; ///< removed by star re-triangulation
  std::size_t unstick_flips = 0;      ///< flips done to free stuck vertices
  std::size_t flips = 0;              ///< metric Delaunay flips (both passes)
  int flip_passes = 0;                ///< passes of the final flip loop
  bool input_reoriented = false;      ///< the input had negative volume: flipped
  int repair_rounds = 0;              ///< rebuilds with more kept input vertices (step 7)
  double seconds = 0;
};

namespace boundary_front_detail {

typedef Eigen::Vector3d Vec;
typedef Eigen::Vector2d Vec2;

inline Vec to_vec(const std::array<double, 3>& p) { return Vec(p[0], p[1], p[2]); }

inline std::uint64_t edge_key(int a, int b)
{
  if(a > b)
    std::swap(a, b);
  return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint64_t(std::uint32_t(b));
}

inline double angle_between(const Vec& u, const Vec& v) { return std::atan2(u.cross(v).norm(), u.dot(v)); }

inline std::string str(const Vec& p)
{
  std::ostringstream os;
  os.precision(10);
  os << "(" << p[0] << " " << p[1] << " " << p[2] << ")";
  return os.str();
}

inline double cross2(const Vec2& a, const Vec2& b) { return a[0] * b[1] - a[1] * b[0]; }

// 2 * area / (longest edge)^2 <= eps: a needle or a cap of zero area
inline bool degenerate(const Vec& a, const Vec& b, const Vec& c, double eps = 1e-10)
{
  const double n = (b - a).cross(c - a).norm();
  const double m = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  return !(m > 0) || !(n > eps * m);
}

// 1 for equilateral, 0 for degenerate
inline double shape_quality(const Vec& a, const Vec& b, const Vec& c)
{
  const double n = (b - a).cross(c - a).norm();
  const double s = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
  return s > 0 ? 2 * std::sqrt(3.0) * n / s : 0;
}

// Squared distance from p to segment [a,b], and the parameter of the closest point.
inline double segment_distance2(const Vec& p, const Vec& a, const Vec& b, double& t)
{
  const Vec ab = b - a;
  const double l2 = ab.squaredNorm();
  t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).squaredNorm();
}

template <class MetricField>
class Front_builder {
  typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
  typedef std::vector<K::Triangle_3>::const_iterator Triangle_iterator;
  typedef CGAL::AABB_triangle_primitive<K, Triangle_iterator> Primitive;
  typedef CGAL::AABB_traits<K, Primitive> Traits;
  typedef CGAL::AABB_tree<Traits> Tree;

public:
  /// `keep`: input vertices to keep as nodes from the start (one flag per
  /// input vertex, or empty); `input_faces_only`: flips never cross input
  /// faces (the front stays on the input surface).
  Front_builder(const Boundary_surface& s, const std::vector<Boundary_node>& nodes, const MetricField& field,
                const Boundary_front_options& o, const std::vector<char>& keep, bool input_faces_only,
                Boundary_front& out)
      : s_(s), nodes_(nodes), field_(field), o_(o), keep_(keep), input_faces_only_(input_faces_only), out_(out)
  {}

  /// Builds the front into `out`; returns the input faces under the
  /// triangles that fail the final checks (empty: the front is valid), and
  /// the first problem in `problem`.
  std::vector<int> run(std::string& problem)
  {
    setup_surface();
    insert_nodes();
    check_corners();
    for(std::size_t v = 0; v < keep_.size() && v < s_.points.size(); ++v)
      if(keep_[v] && vnode_[v] < 0)
        add_node_at(int(v));
    add_curve_nodes_the_topology_needs();
    flip_passes();
    remove_non_nodes();
    out_.flip_passes = flip_passes();
    extract();
    return validate(problem);
  }

private:
  // ---------------------------------------------------------------- mesh
  int new_vertex(const Vec& p, int node)
  {
    pos_.push_back(p);
    vnode_.push_back(node);
    vdead_.push_back(0);
    vfaces_.emplace_back();
    fnbrs_.emplace_back();
    return int(pos_.size()) - 1;
  }

  int add_face(int a, int b, int c, int patch, int origin)
  {
    const int f = int(tri_.size());
    tri_.push_back({{a, b, c}});
    fpatch_.push_back(patch);
    forigin_.push_back(origin);
    falive_.push_back(1);
    fversion_.push_back(0);
    refused_.push_back({});
    vfaces_[a].push_back(f);
    vfaces_[b].push_back(f);
    vfaces_[c].push_back(f);
    by_origin_[origin].push_back(f);
    return f;
  }

  void kill_face(int f)
  {
    falive_[f] = 0;
    for(int v : tri_[f]) {
      auto& l = vfaces_[v];
      l.erase(std::remove(l.begin(), l.end(), f), l.end());
    }
  }

  bool is_feature(int a, int b) const { return feature_.count(edge_key(a, b)) != 0; }

  void add_feature(int a, int b, int source)
  {
    feature_[edge_key(a, b)] = source;
    fnbrs_[a].push_back(b);
    fnbrs_[b].push_back(a);
  }

  int remove_feature(int a, int b)
  {
    auto it = feature_.find(edge_key(a, b));
    const int src = it->second;
    feature_.erase(it);
    fnbrs_[a].erase(std::remove(fnbrs_[a].begin(), fnbrs_[a].end(), b), fnbrs_[a].end());
    fnbrs_[b].erase(std::remove(fnbrs_[b].begin(), fnbrs_[b].end(), a), fnbrs_[b].end());
    return src;
  }

  static bool contains(const std::array<int, 3>& t, int v) { return t[0] == v || t[1] == v || t[2] == v; }

  // the face with the directed edge a->b, or -1
  int face_of_directed(int a, int b) const
  {
    for(int f : vfaces_[a]) {
      const auto& t = tri_[f];
      for(int k = 0; k < 3; ++k)
        if(t[k] == a && t[(k + 1) % 3] == b)
          return f;
    }
    return -1;
  }

  int third(int f, int a, int b) const
  {
    for(int v : tri_[f])
      if(v != a && v != b)
        return v;
    return -1;
  }

  bool has_edge(int a, int b) const
  {
    for(int f : vfaces_[a])
      if(contains(tri_[f], b))
        return true;
    return false;
  }

  void neighbours(int v, std::vector<int>& out) const
  {
    out.clear();
    for(int f : vfaces_[v])
      for(int x : tri_[f])
        if(x != v && std::find(out.begin(), out.end(), x) == out.end())
          out.push_back(x);
  }

  Vec normal(int a, int b, int c) const { return (pos_[b] - pos_[a]).cross(pos_[c] - pos_[a]); }
  Vec unit_normal(int f) const
  {
    Vec n = normal(tri_[f][0], tri_[f][1], tri_[f][2]);
    const double l = n.norm();
    return l > 0 ? Vec(n / l) : Vec::Zero();
  }

  Metric_3 metric_at(const Vec& p) const
  {
    typedef typename MetricField::Point_3 Point;
    return Metric_3(field_(Point(p[0], p[1], p[2])));
  }

  // ---------------------------------------------------------------- input
  void setup_surface()
  {
    const std::size_t nv = s_.points.size(), nf = s_.triangles.size();
    if(nf < 4)
      throw Invalid_input("boundary front: the surface has fewer than 4 triangles");
    if(s_.patches.size() != nf)
      throw Invalid_input("boundary front: the surface has " + std::to_string(nf) + " triangles but " +
                          std::to_string(s_.patches.size()) + " patch ids");
    Vec lo = Vec::Constant(std::numeric_limits<double>::max()), hi = -lo;
    for(const auto& p : s_.points) {
      const Vec q = to_vec(p);
      if(!q.allFinite())
        throw Invalid_input("boundary front: a surface point is not finite");
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    L_ = (hi - lo).norm();
    if(!(L_ > 0))
      throw Invalid_input("boundary front: the surface has an empty bounding box");
    tol_ = o_.surface_tolerance * L_;
    snap_ = o_.snap_tolerance * L_;
    const double degree = 3.14159265358979323846 / 180;
    cos_dev_ = std::cos(o_.max_normal_deviation * degree);
    cos_ref_ = std::cos(o_.max_reference_deviation * degree);
    max_dihedral_ = o_.max_flip_dihedral * degree;

    in_tri_ = s_.triangles;
    double volume = 0;
    for(const auto& t : in_tri_) {
      for(int k = 0; k < 3; ++k)
        if(t[k] < 0 || std::size_t(t[k]) >= nv)
          throw Invalid_input("boundary front: a surface triangle has a vertex index out of range");
      if(t[0] == t[1] || t[1] == t[2] || t[2] == t[0])
        throw Invalid_input("boundary front: a surface triangle repeats a vertex");
      // relative to a corner of the bounding box: far from the origin (1e6)
      // the terms a.(b x c) would cancel to noise
      const Vec a = to_vec(s_.points[t[0]]) - lo, b = to_vec(s_.points[t[1]]) - lo, c = to_vec(s_.points[t[2]]) - lo;
      volume += a.dot(b.cross(c)) / 6;
    }
    if(volume < 0) {
      out_.input_reoriented = true;
      for(auto& t : in_tri_)
        std::swap(t[1], t[2]);
    }
    // closed and edge-manifold: every directed edge once, with its reverse
    std::unordered_map<std::uint64_t, std::array<int, 2>> edge_faces; // key -> face with a<b direction, face with b<a
    for(std::size_t f = 0; f < nf; ++f)
      for(int k = 0; k < 3; ++k) {
        const int a = in_tri_[f][k], b = in_tri_[f][(k + 1) % 3];
        auto it = edge_faces.emplace(edge_key(a, b), std::array<int, 2>{{-1, -1}}).first;
        int& slot = it->second[a < b ? 0 : 1];
        if(slot != -1)
          throw Invalid_input("boundary front: the surface is not an oriented manifold (edge " + std::to_string(a) +
                              "-" + std::to_string(b) + " is used twice in the same direction)");
        slot = int(f);
      }
    for(const auto& e : edge_faces)
      if(e.second[0] < 0 || e.second[1] < 0)
        throw Invalid_input("boundary front: the surface is not closed (edge " + std::to_string(e.first >> 32) + "-" +
                            std::to_string(e.first & 0xffffffffu) + " has one triangle)");

    for(std::size_t v = 0; v < nv; ++v)
      new_vertex(to_vec(s_.points[v]), -1);
    by_origin_.resize(nf);
    list_live_.assign(nf, 1);
    ref_normal_.resize(nf);
    for(std::size_t f = 0; f < nf; ++f) {
      const auto& t = in_tri_[f];
      add_face(t[0], t[1], t[2], s_.patches[f], int(f));
      ref_normal_[f] = unit_normal(int(f));
    }
    for(std::size_t i = 0; i < s_.feature_edges.size(); ++i) {
      const int a = s_.feature_edges[i][0], b = s_.feature_edges[i][1];
      if(a < 0 || b < 0 || std::size_t(a) >= nv || std::size_t(b) >= nv || edge_faces.count(edge_key(a, b)) == 0)
        throw Invalid_input("boundary front: feature edge " + std::to_string(i) + " is not an edge of the surface");
      if(!is_feature(a, b))
        add_feature(a, b, int(i));
    }
    for(const auto& e : edge_faces) {
      const int p = s_.patches[e.second[0]], q = s_.patches[e.second[1]];
      if(p != q && feature_.count(e.first) == 0)
        throw Invalid_input("boundary front: the edge " + std::to_string(e.first >> 32) + "-" +
                            std::to_string(e.first & 0xffffffffu) + " between patches " + std::to_string(p) +
                            " and " + std::to_string(q) + " is not a feature edge");
    }
  }

  // ---------------------------------------------------------------- insertion
  void assign_node_to_vertex(int v, int node)
  {
    if(vnode_[v] >= 0)
      throw Invalid_input("boundary front: nodes " + std::to_string(vnode_[v]) + " and " + std::to_string(node) +
                          " are at the same place " + str(pos_[v]));
    vnode_[v] = node;
    pos_[v] = to_vec(nodes_[node].point);
    for(int f : vfaces_[v]) // their shapes changed
      ++fversion_[f];
  }

  void split_edge(int a, int b, int p)
  {
    const int f1 = face_of_directed(a, b), f2 = face_of_directed(b, a);
    const int c = third(f1, a, b), d = third(f2, b, a);
    kill_face(f1);
    kill_face(f2);
    add_face(a, p, c, fpatch_[f1], forigin_[f1]);
    add_face(p, b, c, fpatch_[f1], forigin_[f1]);
    add_face(b, p, d, fpatch_[f2], forigin_[f2]);
    add_face(p, a, d, fpatch_[f2], forigin_[f2]);
    if(is_feature(a, b)) {
      const int src = remove_feature(a, b);
      add_feature(a, p, src);
      add_feature(p, b, src);
    }
    ++out_.edge_splits;
  }

  void split_face(int f, int p)
  {
    const auto t = tri_[f];
    kill_face(f);
    add_face(t[0], t[1], p, fpatch_[f], forigin_[f]);
    add_face(t[1], t[2], p, fpatch_[f], forigin_[f]);
    add_face(t[2], t[0], p, fpatch_[f], forigin_[f]);
    ++out_.face_splits;
  }

  void insert_nodes()
  {
    const int nv = int(s_.points.size());
    std::vector<std::vector<std::pair<double, int>>> on_edge(s_.feature_edges.size());
    std::map<int, int> patch_index;
    for(std::size_t f = 0; f < in_tri_.size(); ++f)
      patch_index.emplace(s_.patches[f], int(patch_index.size()));

    for(std::size_t i = 0; i < nodes_.size(); ++i) {
      const Boundary_node& n = nodes_[i];
      const Vec p = to_vec(n.point);
      const std::string name = "boundary front: node " + std::to_string(i) + " " + str(p);
      if(!p.allFinite())
        throw Invalid_input(name + " is not finite");
      if(n.dimension == 0) {
        int best = -1;
        double d2 = std::numeric_limits<double>::max();
        for(int v = 0; v < nv; ++v) {
          const double e = (to_vec(s_.points[v]) - p).squaredNorm();
          if(e < d2) {
            d2 = e;
            best = v;
          }
        }
        if(std::sqrt(d2) > tol_)
          throw Invalid_input(name + " of dimension 0 is not at a vertex of the surface (distance " +
                              std::to_string(std::sqrt(d2)) + ")");
        assign_node_to_vertex(best, int(i));
      } else if(n.dimension == 1) {
        int best = -1;
        double d2 = std::numeric_limits<double>::max(), bt = 0;
        for(std::size_t e = 0; e < s_.feature_edges.size(); ++e) {
          double t;
          const double d = segment_distance2(p, to_vec(s_.points[s_.feature_edges[e][0]]),
                                             to_vec(s_.points[s_.feature_edges[e][1]]), t);
          if(d < d2) {
            d2 = d;
            best = int(e);
            bt = t;
          }
        }
        if(best < 0 || std::sqrt(d2) > tol_)
          throw Invalid_input(name + " of dimension 1 is not on a feature edge of the surface" +
                              (best < 0 ? std::string(" (there is none)")
                                        : " (distance " + std::to_string(std::sqrt(d2)) + ")"));
        on_edge[best].emplace_back(bt, int(i));
      } else if(n.dimension == 2) {
        if(patch_index.count(n.patch) == 0)
          throw Invalid_input(name + " is on patch " + std::to_string(n.patch) + ", which the surface does not have");
      } else
        throw Invalid_input(name + " has dimension " + std::to_string(n.dimension) + " (must be 0, 1 or 2)");
    }

    // curve nodes: split each input feature edge in order along it
    for(std::size_t e = 0; e < on_edge.size(); ++e) {
      auto& list = on_edge[e];
      if(list.empty())
        continue;
      std::sort(list.begin(), list.end());
      const int a = s_.feature_edges[e][0], b = s_.feature_edges[e][1];
      int cur = a;
      for(const auto& tn : list) {
        const Vec p = to_vec(nodes_[tn.second].point);
        if((p - pos_[a]).norm() <= tol_ && cur == a && vnode_[a] != tn.second) {
          assign_node_to_vertex(a, tn.second);
          continue;
        }
        if((p - pos_[b]).norm() <= tol_) {
          assign_node_to_vertex(b, tn.second);
          continue;
        }
        if((p - pos_[cur]).norm() <= snap_)
          throw Invalid_input("boundary front: node " + std::to_string(tn.second) + " " + str(p) +
                              " coincides with another node or vertex");
        const int v = new_vertex(p, tn.second);
        split_edge(cur, b, v);
        cur = v;
      }
    }

    // patch nodes: locate in the input face of their patch, then in its sub-triangulation
    std::vector<std::vector<K::Triangle_3>> patch_triangles(patch_index.size());
    std::vector<std::vector<int>> patch_faces(patch_index.size());
    for(std::size_t f = 0; f < in_tri_.size(); ++f) {
      const int k = patch_index[s_.patches[f]];
      const auto& t = in_tri_[f];
      auto P = [&](int v) { return K::Point_3(s_.points[v][0], s_.points[v][1], s_.points[v][2]); };
      patch_triangles[k].emplace_back(P(t[0]), P(t[1]), P(t[2]));
      patch_faces[k].push_back(int(f));
    }
    std::vector<std::unique_ptr<Tree>> trees(patch_index.size());
    std::vector<std::vector<int>> in_face(in_tri_.size());
    for(std::size_t i = 0; i < nodes_.size(); ++i) {
      if(nodes_[i].dimension != 2)
        continue;
      const int k = patch_index[nodes_[i].patch];
      if(!trees[k]) {
        trees[k].reset(new Tree(patch_triangles[k].begin(), patch_triangles[k].end()));
        trees[k]->accelerate_distance_queries();
      }
      const Vec p = to_vec(nodes_[i].point);
      const K::Point_3 q(p[0], p[1], p[2]);
      const auto cp = trees[k]->closest_point_and_primitive(q);
      const double d = std::sqrt(CGAL::to_double(CGAL::squared_distance(q, cp.first)));
      if(d > tol_)
        throw Invalid_input("boundary front: node " + std::to_string(i) + " " + str(p) + " is not on patch " +
                            std::to_string(nodes_[i].patch) + " (distance " + std::to_string(d) + ")");
      in_face[patch_faces[k][cp.second - patch_triangles[k].begin()]].push_back(int(i));
    }
    for(std::size_t f = 0; f < in_face.size(); ++f) {
      if(in_face[f].empty())
        continue;
      // spatial (Morton) order so that each location walk starts near its target
      const auto& t = in_tri_[f];
      const Vec o = to_vec(s_.points[t[0]]);
      const Vec u = to_vec(s_.points[t[1]]) - o, w = to_vec(s_.points[t[2]]) - o;
      std::vector<std::pair<std::uint64_t, int>> order;
      for(int node : in_face[f]) {
        const Vec d = to_vec(nodes_[node].point) - o;
        const double bu = std::clamp(d.dot(u) / u.squaredNorm(), 0.0, 1.0);
        const double bw = std::clamp(d.dot(w) / w.squaredNorm(), 0.0, 1.0);
        const auto qu = std::uint32_t(bu * 65535), qw = std::uint32_t(bw * 65535);
        std::uint64_t code = 0;
        for(int bit = 0; bit < 16; ++bit)
          code |= (std::uint64_t((qu >> bit) & 1u) << (2 * bit)) | (std::uint64_t((qw >> bit) & 1u) << (2 * bit + 1));
        order.emplace_back(code, node);
      }
      std::sort(order.begin(), order.end());
      for(const auto& cn : order)
        insert_patch_node(int(f), cn.second);
    }
  }

  // After inserting p: metric Delaunay flips of the edges opposite to p
  // (Lawson), inside input face `origin` only.
  void legalize_around(int p, int origin)
  {
    std::vector<std::pair<int, int>> stack;
    for(int f : vfaces_[p]) {
      const auto& t = tri_[f];
      int k = 0;
      while(t[k] != p)
        ++k;
      stack.emplace_back(t[(k + 1) % 3], t[(k + 2) % 3]);
    }
    std::size_t budget = 64 * (stack.size() + 4);
    while(!stack.empty() && budget-- > 0) {
      const auto e = stack.back();
      stack.pop_back();
      const int g = face_of_directed(e.second, e.first);
      if(g < 0 || face_of_directed(e.first, e.second) < 0 || !contains(tri_[face_of_directed(e.first, e.second)], p))
        continue;
      const int d = third(g, e.second, e.first);
      if(try_flip(e.first, e.second, true, origin)) {
        ++out_.flips;
        stack.emplace_back(e.first, d);
        stack.emplace_back(d, e.second);
      }
    }
  }

  // Walks from the last face created in input face f towards q (2D, in the
  // frame of f); -1 when the walk leaves f or does not converge.
  template <class Flat>
  int walk(int f, const Vec2& q, const Flat& flat)
  {
    int g = last_face_.count(f) ? last_face_[f] : -1;
    if(g < 0 || !falive_[g] || forigin_[g] != f)
      return -1;
    for(std::size_t step = 0; step < by_origin_[f].size() + 8; ++step) {
      int worst = -1;
      double worst_d = -snap_;
      for(int k = 0; k < 3; ++k) {
        const Vec2 a = flat(pos_[tri_[g][k]]), b = flat(pos_[tri_[g][(k + 1) % 3]]);
        const double l = (b - a).norm();
        const double d = l > 0 ? cross2(b - a, q - a) / l : 0;
        if(d < worst_d) {
          worst_d = d;
          worst = k;
        }
      }
      if(worst < 0)
        return g;
      const int h = face_of_directed(tri_[g][(worst + 1) % 3], tri_[g][worst]);
      if(h < 0 || forigin_[h] != f)
        return -1;
      g = h;
    }
    return -1;
  }

  void insert_patch_node(int f, int node)
  {
    const Vec p = to_vec(nodes_[node].point);
    const std::string name = "boundary front: node " + std::to_string(node) + " " + str(p);
    // a 2D frame in the plane of input face f
    const auto& t = in_tri_[f];
    const Vec o = to_vec(s_.points[t[0]]);
    const Vec n = ref_normal_[f];
    Vec e1 = to_vec(s_.points[t[1]]) - o;
    e1.normalize();
    const Vec e2 = n.cross(e1);
    auto flat = [&](const Vec& x) { return Vec2((x - o).dot(e1), (x - o).dot(e2)); };
    const Vec2 q = flat(p);

    auto& list = by_origin_[f];
    if(list.size() > 2 * (list_live_[f] + 8)) { // drop dead faces now and then
      list.erase(std::remove_if(list.begin(), list.end(), [&](int g) { return !falive_[g]; }), list.end());
      list_live_[f] = list.size();
    }
    int best = -1;
    double best_min = -std::numeric_limits<double>::max();
    std::array<double, 3> best_d{};
    const int walked = walk(f, q, flat);
    for(int g : list) {
      if(!falive_[g] || (walked >= 0 && g != walked))
        continue;
      std::array<double, 3> d;
      for(int k = 0; k < 3; ++k) {
        const Vec2 a = flat(pos_[tri_[g][k]]), b = flat(pos_[tri_[g][(k + 1) % 3]]);
        const double l = (b - a).norm();
        d[k] = l > 0 ? cross2(b - a, q - a) / l : -std::numeric_limits<double>::max();
      }
      const double m = std::min({d[0], d[1], d[2]});
      if(m > best_min) {
        best_min = m;
        best = g;
        best_d = d;
      }
    }
    if(best < 0)
      throw Meshing_failure(name + ": lost the sub-triangulation of its input face");
    const auto tg = tri_[best];
    for(int v : tg)
      if((pos_[v] - p).norm() <= snap_) {
        if(!fnbrs_[v].empty())
          throw Invalid_input(name + " of dimension 2 lies on a feature curve");
        assign_node_to_vertex(v, node);
        return;
      }
    int on = -1, count = 0;
    for(int k = 0; k < 3; ++k)
      if(best_d[k] <= snap_) {
        on = k;
        ++count;
      }
    if(count >= 2) { // near a vertex without being within snap of it: treat as the closest edge
      on = int(std::min_element(best_d.begin(), best_d.end()) - best_d.begin());
      count = 1;
    }
    if(count == 1) {
      const int a = tg[on], b = tg[(on + 1) % 3];
      if(!is_feature(a, b)) {
        const int v = new_vertex(p, node);
        split_edge(a, b, v);
        after_insertion(f, v);
        return;
      }
      if(best_d[on] <= 0)
        throw Invalid_input(name + " of dimension 2 lies on a feature curve");
    }
    const int v = new_vertex(p, node);
    split_face(best, v);
    after_insertion(f, v);
  }

  void after_insertion(int f, int v)
  {
    legalize_around(v, f);
    for(int g : vfaces_[v])
      if(forigin_[g] == f) {
        last_face_[f] = g;
        break;
      }
    list_live_[f] += 2;
  }

  void check_corners()
  {
    for(std::size_t v = 0; v < s_.points.size(); ++v)
      if(vnode_[v] < 0 && !fnbrs_[v].empty() && fnbrs_[v].size() != 2)
        throw Invalid_input("boundary front: the surface corner " + std::to_string(v) + " " + str(pos_[v]) +
                            " (on " + std::to_string(fnbrs_[v].size()) + " feature edges) has no node");
  }

  // ---------------------------------------------------------------- curve topology (step 3)
  struct Stretch {
    std::vector<int> path; // node vertex, non-node curve vertices, node vertex
  };

  // The stretches of feature curve between consecutive nodes. Before any
  // removal every feature edge is a piece of an input feature edge, so a
  // stretch follows the input curve exactly.
  std::vector<Stretch> curve_stretches() const
  {
    std::vector<Stretch> out;
    std::set<std::uint64_t> seen; // first edge of each stretch
    for(std::size_t u = 0; u < pos_.size(); ++u) {
      if(vdead_[u] || vnode_[u] < 0)
        continue;
      for(int first : fnbrs_[u]) {
        if(!seen.insert(edge_key(int(u), first)).second)
          continue;
        Stretch st;
        st.path = {int(u)};
        int prev = int(u), cur = first;
        while(vnode_[cur] < 0 && fnbrs_[cur].size() == 2) {
          st.path.push_back(cur);
          const int next = fnbrs_[cur][0] == prev ? fnbrs_[cur][1] : fnbrs_[cur][0];
          prev = cur;
          cur = next;
        }
        st.path.push_back(cur);
        seen.insert(edge_key(prev, cur)); // the same stretch from its other end
        out.push_back(std::move(st));
      }
    }
    return out;
  }

  // A node at metric arc-length fraction `f` of the stretch (a new vertex
  // splitting the edge there, on the input curve, which joins `st.path`).
  void add_node_along(Stretch& st, double f)
  {
    std::vector<double> at{0};
    for(std::size_t i = 0; i + 1 < st.path.size(); ++i) {
      const Vec d = pos_[st.path[i + 1]] - pos_[st.path[i]];
      at.push_back(at.back() + metric_at(0.5 * (pos_[st.path[i]] + pos_[st.path[i + 1]])).length(d));
    }
    const double target = f * at.back();
    std::size_t i = 0;
    while(i + 2 < st.path.size() && at[i + 1] < target)
      ++i;
    const double t = at[i + 1] > at[i] ? std::clamp((target - at[i]) / (at[i + 1] - at[i]), 0.05, 0.95) : 0.5;
    const int a = st.path[i], b = st.path[i + 1];
    // an existing vertex of the stretch within a tenth of the stretch of the target: keep it instead
    for(std::size_t k = 1; k + 1 < st.path.size(); ++k)
      if(std::abs(at[k] - target) <= 0.1 * at.back() && vnode_[st.path[k]] < 0) {
        add_node_at(st.path[k]);
        return;
      }
    const int p = new_vertex(pos_[a] + t * (pos_[b] - pos_[a]), -1);
    split_edge(a, b, p);
    add_node_at(p);
    st.path.insert(st.path.begin() + std::ptrdiff_t(i + 1), p);
  }

  void add_curve_nodes_the_topology_needs()
  {
    // a closed curve without any node (the packer leaves none, but a caller may)
    for(std::size_t u = 0; u < pos_.size(); ++u)
      if(!vdead_[u] && vnode_[u] < 0 && fnbrs_[u].size() == 2) {
        int prev = int(u), cur = fnbrs_[u][0];
        while(cur != int(u) && vnode_[cur] < 0 && fnbrs_[cur].size() == 2) {
          const int next = fnbrs_[cur][0] == prev ? fnbrs_[cur][1] : fnbrs_[cur][0];
          prev = cur;
          cur = next;
        }
        if(cur == int(u))
          add_node_at(int(u));
      }
    std::map<std::pair<int, int>, std::vector<Stretch>> by_ends;
    for(Stretch& st : curve_stretches())
      by_ends[std::minmax(st.path.front(), st.path.back())].push_back(std::move(st));
    for(auto& group : by_ends) {
      auto& list = group.second;
      if(group.first.first == group.first.second) { // from a node back to itself
        for(Stretch& st : list) {
          add_node_along(st, 2.0 / 3);
          add_node_along(st, 1.0 / 3);
        }
        continue;
      }
      if(list.size() < 2)
        continue;
      auto length = [&](const Stretch& st) {
        double l = 0;
        for(std::size_t i = 0; i + 1 < st.path.size(); ++i)
          l += (pos_[st.path[i + 1]] - pos_[st.path[i]]).norm();
        return l;
      };
      std::sort(list.begin(), list.end(),
                [&](const Stretch& x, const Stretch& y) { return length(x) < length(y); });
      for(std::size_t k = 1; k < list.size(); ++k)
        add_node_along(list[k], 0.5);
    }
  }

  // ---------------------------------------------------------------- flips
  // Flips edge ab (faces abc, bad) into cd. `delaunay`: only if the metric
  // criterion asks for it.
  // `only_origin` >= 0: both triangles must come from that input face (keeps
  // the input faces tiled by their own triangles while nodes are inserted).
  bool try_flip(int a, int b, bool delaunay, int only_origin = -1)
  {
    const int f1 = face_of_directed(a, b), f2 = face_of_directed(b, a);
    if(f1 < 0 || f2 < 0 || fpatch_[f1] != fpatch_[f2] || is_feature(a, b))
      return false;
    if(only_origin >= 0 && (forigin_[f1] != only_origin || forigin_[f2] != only_origin))
      return false;
    const int c = third(f1, a, b), d = third(f2, b, a);
    if(c == d || has_edge(c, d))
      return false;
    const Vec &pa = pos_[a], &pb = pos_[b], &pc = pos_[c], &pd = pos_[d];
    if(degenerate(pa, pd, pc) || degenerate(pd, pb, pc))
      return false;
    // What follows depends only on the two faces as they are (corners,
    // positions, input faces): a Delaunay flip refused for the pair is
    // refused again without evaluating the metric while neither face changed
    // (the passes over all edges cost 38 s of the bunny's 1:4 boundary layer
    // in metric evaluations). Per direction: the other one sums the same
    // points in another order, which can tip a near tie.
    std::size_t k1 = 0;
    while(tri_[f1][k1] != a)
      ++k1;
    Refusal& memo = refused_[std::size_t(f1)][k1];
    if(delaunay && memo.across == f2 && memo.version == fversion_[f1] && memo.across_version == fversion_[f2])
      return false;
    auto refuse = [&]() {
      if(delaunay)
        memo = Refusal{f2, fversion_[f1], fversion_[f2]};
      return false;
    };
    if(delaunay) {
      const Metric_3 m = metric_at((pa + pb + pc + pd) / 4);
      auto ang = [&](const Vec& apex, const Vec& x, const Vec& y) {
        return angle_between(m.map(x - apex), m.map(y - apex));
      };
      const double old_sum = ang(pc, pa, pb) + ang(pd, pa, pb);
      const double new_sum = ang(pa, pc, pd) + ang(pb, pc, pd);
      if(!(old_sum > new_sum + 1e-9))
        return refuse();
    }
    // No fold: both new triangles turn by less than max_normal_deviation from
    // the area-weighted normal of the quad (a sliver's own normal is not
    // trusted: flipping it away is the point) and stay close to the input.
    const Vec n1 = unit_normal(f1), n2 = unit_normal(f2);
    const Vec navg = (normal(a, b, c) + normal(b, a, d)).normalized();
    const Vec m1 = normal(a, d, c).normalized(), m2 = normal(d, b, c).normalized();
    for(const Vec* m : {&m1, &m2})
      if(!(m->dot(navg) >= cos_dev_) || m->dot(ref_normal_[forigin_[f1]]) < cos_ref_ ||
         m->dot(ref_normal_[forigin_[f2]]) < cos_ref_)
        return refuse();
    if(angle_between(m1, m2) > std::max(angle_between(n1, n2), max_dihedral_))
      return refuse();
    const int patch = fpatch_[f1], o1 = forigin_[f1], o2 = forigin_[f2];
    kill_face(f1);
    kill_face(f2);
    add_face(a, d, c, patch, o1);
    add_face(d, b, c, patch, o2);
    return true;
  }

  // metric Delaunay flips until none applies or the pass bound; returns passes
  int flip_passes()
  {
    int pass = 0;
    for(; pass < o_.max_flip_passes; ++pass) {
      std::size_t count = 0;
      const std::size_t n = tri_.size();
      for(std::size_t f = 0; f < n; ++f)
        for(int k = 0; k < 3 && falive_[f]; ++k) {
          const int a = tri_[f][k], b = tri_[f][(k + 1) % 3];
          if(a < b && try_flip(a, b, true, input_faces_only_ ? forigin_[f] : -1))
            ++count;
        }
      out_.flips += count;
      if(count == 0)
        break;
    }
    return pass + 1;
  }

  // ---------------------------------------------------------------- removal
  // quality of the worst new triangle of the collapse v -> w, -1 if invalid
  double collapse_score(int v, int w) { return collapse_score(v, w, cos_dev_, cos_ref_); }

  double collapse_score(int v, int w, double cos_dev, double cos_ref)
  {
    const auto& fn = fnbrs_[v];
    int other = -1;
    if(!fn.empty()) {
      if(fn.size() != 2 || (fn[0] != w && fn[1] != w))
        return -1;
      other = fn[0] == w ? fn[1] : fn[0];
      if(is_feature(w, other))
        return -1;
    }
    int shared = 0;
    std::array<int, 2> opp{{-1, -1}};
    for(int f : vfaces_[v])
      if(contains(tri_[f], w)) {
        if(shared < 2)
          opp[shared] = third(f, v, w);
        ++shared;
      }
    if(shared != 2 || opp[0] == opp[1])
      return -1;
    neighbours(v, nv_);
    neighbours(w, nw_);
    for(int x : nv_)
      if(x != w && x != opp[0] && x != opp[1] && std::find(nw_.begin(), nw_.end(), x) != nw_.end())
        return -1;
    double q = 1;
    for(int f : vfaces_[v]) {
      auto t = tri_[f];
      if(contains(t, w))
        continue;
      for(int& x : t)
        if(x == v)
          x = w;
      if(degenerate(pos_[t[0]], pos_[t[1]], pos_[t[2]]))
        return -1;
      // a needle's own normal is noise (collapsing it away is the point):
      // only its input face's normal bounds the new triangle then
      const Vec m = normal(t[0], t[1], t[2]).normalized();
      const auto& old = tri_[f];
      const bool needle = shape_quality(pos_[old[0]], pos_[old[1]], pos_[old[2]]) < 0.05;
      if((!needle && m.dot(unit_normal(f)) < cos_dev) || m.dot(ref_normal_[forigin_[f]]) < cos_ref)
        return -1;
      q = std::min(q, shape_quality(pos_[t[0]], pos_[t[1]], pos_[t[2]]));
    }
    return q;
  }

  void collapse(int v, int w)
  {
    int other = -1, src = -1;
    for(int x : std::vector<int>(fnbrs_[v])) {
      const int s = remove_feature(v, x);
      if(x != w) {
        other = x;
        src = s;
      }
    }
    for(int f : std::vector<int>(vfaces_[v])) {
      if(contains(tri_[f], w))
        kill_face(f);
      else {
        for(int& x : tri_[f])
          if(x == v)
            x = w;
        ++fversion_[f]; // another shape
        vfaces_[w].push_back(f);
      }
    }
    vfaces_[v].clear();
    vdead_[v] = 1;
    if(other >= 0 && !is_feature(w, other))
      add_feature(w, other, src);
  }

  // Ear clipping of polygon `poly` (counter-clockwise seen from `n`) into triangles.
  bool triangulate_polygon(std::vector<int> poly, const Vec& n, int origin, std::vector<std::array<int, 3>>& out)
  {
    Vec e1 = n.unitOrthogonal();
    const Vec e2 = n.cross(e1);
    auto flat = [&](int v) { return Vec2(pos_[v].dot(e1), pos_[v].dot(e2)); };
    while(poly.size() >= 3) {
      const std::size_t m = poly.size();
      int best = -1;
      double best_q = -1;
      for(std::size_t i = 0; i < m; ++i) {
        const int a = poly[(i + m - 1) % m], b = poly[i], c = poly[(i + 1) % m];
        const Vec2 A = flat(a), B = flat(b), C = flat(c);
        const double area2 = cross2(B - A, C - A);
        const double scale = std::max({(B - A).squaredNorm(), (C - B).squaredNorm(), (A - C).squaredNorm()});
        if(!(area2 > 1e-10 * scale))
          continue;
        if(m > 3 && has_edge(a, c))
          continue;
        bool empty = true;
        for(std::size_t j = 0; j < m && empty && m > 3; ++j) {
          const int x = poly[j];
          if(x == a || x == b || x == c)
            continue;
          const Vec2 X = flat(x);
          if(cross2(B - A, X - A) >= 0 && cross2(C - B, X - B) >= 0 && cross2(A - C, X - C) >= 0)
            empty = false;
        }
        if(!empty || degenerate(pos_[a], pos_[b], pos_[c]))
          continue;
        const Vec nn = normal(a, b, c).normalized();
        if(nn.dot(n) < cos_dev_ || nn.dot(ref_normal_[origin]) < cos_ref_)
          continue;
        const double q = shape_quality(pos_[a], pos_[b], pos_[c]);
        if(q > best_q) {
          best_q = q;
          best = int(i);
        }
      }
      if(best < 0)
        return false;
      out.push_back({{poly[(best + m - 1) % m], poly[best], poly[(best + 1) % m]}});
      poly.erase(poly.begin() + best);
      if(poly.size() == 2)
        break;
    }
    return true;
  }

  // Removes v by re-triangulating its star (each side of its curve apart).
  bool remove_by_retriangulation(int v)
  {
    const auto& fn = fnbrs_[v];
    if(!fn.empty() && fn.size() != 2)
      return false;
    std::unordered_map<int, int> next, face_of;
    for(int f : vfaces_[v]) {
      const auto& t = tri_[f];
      int k = 0;
      while(t[k] != v)
        ++k;
      const int x = t[(k + 1) % 3], y = t[(k + 2) % 3];
      if(!next.emplace(x, y).second)
        return false;
      face_of[x] = f;
    }
    std::vector<int> ring;
    int x = next.begin()->first;
    do {
      ring.push_back(x);
      auto it = next.find(x);
      if(it == next.end() || ring.size() > next.size())
        return false;
      x = it->second;
    } while(x != ring.front());
    if(ring.size() != next.size())
      return false;
    std::vector<std::vector<int>> polys;
    if(fn.empty())
      polys.push_back(ring);
    else {
      const int a = fn[0], b = fn[1];
      if(has_edge(a, b))
        return false;
      const std::size_t m = ring.size();
      const std::size_t ia = std::find(ring.begin(), ring.end(), a) - ring.begin();
      const std::size_t ib = std::find(ring.begin(), ring.end(), b) - ring.begin();
      if(ia == m || ib == m)
        return false;
      for(std::size_t start : {ia, ib}) {
        std::vector<int> chain;
        const int stop = start == ia ? b : a;
        for(std::size_t i = start;; i = (i + 1) % m) {
          chain.push_back(ring[i]);
          if(ring[i] == stop)
            break;
        }
        if(chain.size() < 3)
          return false;
        polys.push_back(chain);
      }
    }
    std::vector<std::array<int, 3>> tris;
    std::vector<int> tri_patch, tri_origin;
    for(const auto& poly : polys) {
      Vec n = Vec::Zero();
      int patch = fpatch_[face_of[poly[0]]], origin = forigin_[face_of[poly[0]]];
      for(std::size_t i = 0; i + 1 < poly.size() || (fn.empty() && i < poly.size()); ++i) {
        const int f = face_of[poly[i]];
        if(fpatch_[f] != patch)
          return false;
        n += normal(tri_[f][0], tri_[f][1], tri_[f][2]);
      }
      if(!(n.norm() > 0))
        return false;
      n.normalize();
      const std::size_t before = tris.size();
      if(!triangulate_polygon(poly, n, origin, tris))
        return false;
      for(std::size_t i = before; i < tris.size(); ++i) {
        tri_patch.push_back(patch);
        tri_origin.push_back(origin);
      }
    }
    // the diagonals must be new edges, and distinct from each other
    std::vector<std::uint64_t> diagonals;
    for(const auto& t : tris)
      for(int k = 0; k < 3; ++k) {
        const int p = t[k], q = t[(k + 1) % 3];
        if(next.count(p) && next[p] == q)
          continue; // a ring edge
        diagonals.push_back(edge_key(p, q));
      }
    std::sort(diagonals.begin(), diagonals.end());
    // every interior diagonal appears twice (once per side), the curve edge ab once per side as well
    for(std::size_t i = 0; i < diagonals.size(); i += 2)
      if(i + 1 >= diagonals.size() || diagonals[i] != diagonals[i + 1] ||
         (i + 2 < diagonals.size() && diagonals[i + 2] == diagonals[i]))
        return false;
    int src = -1, a = -1, b = -1;
    if(!fn.empty()) {
      a = fn[0];
      b = fn[1];
      remove_feature(v, b);
      src = remove_feature(v, a);
    }
    for(int f : std::vector<int>(vfaces_[v]))
      kill_face(f);
    vdead_[v] = 1;
    for(std::size_t i = 0; i < tris.size(); ++i)
      add_face(tris[i][0], tris[i][1], tris[i][2], tri_patch[i], tri_origin[i]);
    if(a >= 0)
      add_feature(a, b, src);
    return true;
  }

  bool try_remove(int v)
  {
    std::vector<int> candidates;
    if(fnbrs_[v].empty())
      neighbours(v, candidates);
    else
      candidates = fnbrs_[v];
    int best = -1;
    double best_q = -1;
    for(int w : candidates) {
      const double q = collapse_score(v, w);
      if(q > best_q) {
        best_q = q;
        best = w;
      }
    }
    if(best >= 0) {
      collapse(v, best);
      ++out_.collapses;
      return true;
    }
    if(remove_by_retriangulation(v)) {
      ++out_.fallback_retriangulations;
      return true;
    }
    return false;
  }

  // the input face a flip of ab must stay in (-1: any)
  int flip_origin(int a, int b) const
  {
    if(!input_faces_only_)
      return -1;
    const int f = face_of_directed(a, b);
    return f < 0 ? -1 : forigin_[f];
  }

  // Keeps input vertex v as a node of the front (an added node).
  void add_node_at(int v)
  {
    Boundary_node n;
    n.point = {{pos_[v][0], pos_[v][1], pos_[v][2]}};
    n.dimension = fnbrs_[v].empty() ? 2 : fnbrs_[v].size() == 2 ? 1 : 0;
    n.patch = vfaces_[v].empty() ? -1 : fpatch_[vfaces_[v].front()];
    vnode_[v] = int(nodes_.size() + out_.added_nodes.size());
    out_.added_nodes.push_back(n);
  }

  // The collapse of v into its closest neighbour within metric distance
  // short_collapse_length, with the looser deviation bound.
  bool short_collapse(int v)
  {
    std::vector<int> candidates;
    if(fnbrs_[v].empty())
      neighbours(v, candidates);
    else
      candidates = fnbrs_[v];
    const Metric_3 m = metric_at(pos_[v]);
    const double degree = 3.14159265358979323846 / 180;
    const double c = std::cos(o_.max_short_collapse_deviation * degree);
    int best = -1;
    double best_length = o_.short_collapse_length;
    for(int w : candidates) {
      const double l = m.length(pos_[w] - pos_[v]);
      if(l < best_length && collapse_score(v, w, c, c) > 0) {
        best_length = l;
        best = w;
      }
    }
    if(best < 0)
      return false;
    collapse(v, best);
    return true;
  }

  bool unstick(int v)
  {
    std::vector<int> nb;
    neighbours(v, nb);
    for(int x : nb)
      if(!is_feature(v, x) && (try_flip(v, x, false, flip_origin(v, x)) || try_flip(x, v, false, flip_origin(x, v)))) {
        ++out_.unstick_flips;
        return true;
      }
    return false;
  }

  void remove_non_nodes()
  {
    std::vector<int> todo;
    for(std::size_t v = 0; v < pos_.size(); ++v)
      if(vnode_[v] < 0 && !vdead_[v])
        todo.push_back(int(v));
    int stuck_rounds = 0;
    while(!todo.empty()) {
      std::vector<int> left;
      for(int v : todo)
        if(try_remove(v))
          ++out_.removed_vertices;
        else
          left.push_back(v);
      if(left.size() == todo.size()) {
        bool any = false;
        for(int v : left)
          any = unstick(v) || any;
        if(!any || ++stuck_rounds > o_.max_stuck_rounds) {
          // No collapse, re-triangulation or flip frees them. A vertex next
          // to a node (metric distance < short_collapse_length) is collapsed
          // into it if that only tilts triangles (by less than
          // max_short_collapse_deviation, never flipping one): the geometric
          // error is below that short distance, while a node kept there
          // would make a needle. Any other one is a place where the surface
          // needs a node (a tip, a short closed curve): it is kept.
          std::vector<int> kept;
          for(int v : left)
            if(!short_collapse(v))
              kept.push_back(v);
            else
              ++out_.removed_vertices, ++out_.short_collapses;
          for(int v : kept)
            if(!vdead_[v])
              add_node_at(v);
          left.clear();
        }
      }
      todo.swap(left);
    }
  }

  // ---------------------------------------------------------------- output
  void extract()
  {
    for(std::size_t f = 0; f < tri_.size(); ++f) {
      if(!falive_[f])
        continue;
      std::array<int, 3> t;
      for(int k = 0; k < 3; ++k) {
        t[k] = vnode_[tri_[f][k]];
        if(t[k] < 0)
          throw Meshing_failure("boundary front: internal error, a surface vertex is left");
      }
      out_.triangles.push_back(t);
      out_.patches.push_back(fpatch_[f]);
      out_origin_.push_back(forigin_[f]);
    }
    std::vector<std::pair<std::array<int, 2>, int>> fe;
    for(const auto& e : feature_) {
      std::array<int, 2> p{{vnode_[int(e.first >> 32)], vnode_[int(e.first & 0xffffffffu)]}};
      if(p[0] > p[1])
        std::swap(p[0], p[1]);
      fe.emplace_back(p, e.second);
    }
    std::sort(fe.begin(), fe.end());
    for(const auto& e : fe) {
      out_.feature_edges.push_back(e.first);
      out_.feature_edge_sources.push_back(e.second);
    }
  }

  Vec node_point(int i) const
  {
    const std::size_t n = nodes_.size();
    return to_vec(std::size_t(i) < n ? nodes_[i].point : out_.added_nodes[std::size_t(i) - n].point);
  }

  // The final checks. Returns the input faces under the offending triangles
  // (every input face when the problem has no place) and the first problem.
  std::vector<int> validate(std::string& problem) const
  {
    const auto& T = out_.triangles;
    const std::size_t n = nodes_.size() + out_.added_nodes.size();
    std::vector<int> bad;
    auto fail = [&](const std::string& m, std::initializer_list<int> triangles) {
      if(problem.empty())
        problem = m;
      for(int t : triangles)
        bad.push_back(out_origin_[std::size_t(t)]);
    };
    auto fail_everywhere = [&](const std::string& m) {
      if(problem.empty())
        problem = m;
      for(std::size_t f = 0; f < in_tri_.size(); ++f)
        bad.push_back(int(f));
    };
    std::unordered_map<std::uint64_t, int> directed;
    std::vector<std::vector<int>> around(n);
    double volume = 0;
    const Vec o = n > 0 ? node_point(0) : Vec::Zero(); // volume relative to o (see setup_surface)
    for(std::size_t f = 0; f < T.size(); ++f) {
      const auto& t = T[f];
      const Vec a = node_point(t[0]), b = node_point(t[1]), c = node_point(t[2]);
      if(degenerate(a, b, c, 1e-12))
        fail("triangle " + str(a) + str(b) + str(c) + " is degenerate", {int(f)});
      volume += (a - o).dot((b - o).cross(c - o)) / 6;
      for(int k = 0; k < 3; ++k) {
        const int p = t[k], q = t[(k + 1) % 3];
        const std::uint64_t key = (std::uint64_t(std::uint32_t(p)) << 32) | std::uint32_t(q);
        auto it = directed.emplace(key, int(f));
        if(!it.second)
          fail("edge " + std::to_string(p) + "-" + std::to_string(q) + " is used twice in one direction",
               {int(f), it.first->second});
        around[p].push_back(int(f));
      }
    }
    for(const auto& e : directed) {
      const std::uint64_t rev = (e.first << 32) | (e.first >> 32);
      if(directed.count(rev) == 0)
        fail("the surface is not closed", {e.second});
    }
    for(std::size_t v = 0; v < n; ++v) {
      if(around[v].empty()) {
        fail_everywhere("node " + std::to_string(v) + " is not used");
        continue;
      }
      // the faces around v form a single cycle
      std::unordered_map<int, int> next;
      for(int f : around[v]) {
        const auto& t = T[f];
        int k = 0;
        while(t[k] != int(v))
          ++k;
        next[t[(k + 1) % 3]] = t[(k + 2) % 3];
      }
      std::size_t len = 0;
      const int start = next.begin()->first;
      int x = start;
      do {
        auto it = next.find(x);
        if(it == next.end())
          break;
        x = it->second;
        ++len;
      } while(x != start && len <= next.size());
      if(len != next.size()) {
        fail("node " + std::to_string(v) + " is not vertex-manifold", {});
        for(int f : around[v])
          bad.push_back(out_origin_[std::size_t(f)]);
      }
    }
    if(!(volume > 0))
      fail_everywhere("the surface has non-positive volume");
    for(const auto& e : out_.feature_edges)
      if(directed.count((std::uint64_t(std::uint32_t(e[0])) << 32) | std::uint32_t(e[1])) == 0)
        fail_everywhere("a feature edge is not a mesh edge");
    if(o_.check_self_intersection && bad.empty()) {
      typedef CGAL::Surface_mesh<K::Point_3> Mesh;
      Mesh sm;
      std::vector<Mesh::Vertex_index> vs;
      for(std::size_t i = 0; i < n; ++i) {
        const Vec p = node_point(int(i));
        vs.push_back(sm.add_vertex(K::Point_3(p[0], p[1], p[2])));
      }
      for(const auto& t : T)
        if(sm.add_face(vs[t[0]], vs[t[1]], vs[t[2]]) == Mesh::null_face()) {
          fail_everywhere("the surface cannot be built as a Surface_mesh");
          return bad;
        }
      std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
      CGAL::Polygon_mesh_processing::self_intersections(sm, std::back_inserter(pairs));
      if(!pairs.empty())
        problem = "the surface intersects itself (" + std::to_string(pairs.size()) + " pairs of triangles)";
      for(const auto& fp : pairs) {
        bad.push_back(out_origin_[std::size_t(fp.first)]);
        bad.push_back(out_origin_[std::size_t(fp.second)]);
      }
    }
    std::sort(bad.begin(), bad.end());
    bad.erase(std::unique(bad.begin(), bad.end()), bad.end());
    return bad;
  }

  const Boundary_surface& s_;
  const std::vector<Boundary_node>& nodes_;
  const MetricField& field_;
  const Boundary_front_options& o_;
  const std::vector<char>& keep_;
  const bool input_faces_only_;
  Boundary_front& out_;
  std::vector<int> out_origin_; // input face of each output triangle

  double L_ = 0, tol_ = 0, snap_ = 0, cos_dev_ = 0, cos_ref_ = 0, max_dihedral_ = 0;
  std::vector<std::array<int, 3>> in_tri_;
  std::vector<Vec> ref_normal_;

  std::vector<Vec> pos_;
  std::vector<int> vnode_;
  std::vector<char> vdead_;
  std::vector<std::vector<int>> vfaces_, fnbrs_;
  std::vector<std::array<int, 3>> tri_;
  std::vector<int> fpatch_, forigin_;
  std::vector<char> falive_;
  // a face's shape changes when a vertex is snapped to a node or renamed by
  // a collapse: fversion_ counts that
  std::vector<unsigned> fversion_;
  // per face and edge k (tri_[f][k] -> tri_[f][k + 1]): the face across it
  // when a Delaunay flip of that edge, in that direction, was refused, and
  // the two faces' versions then (try_flip())
  struct Refusal {
    int across = -1;
    unsigned version = 0, across_version = 0;
  };
  std::vector<std::array<Refusal, 3>> refused_;
  std::vector<std::vector<int>> by_origin_;
  std::vector<std::size_t> list_live_;     // live faces per input face (estimate)
  std::unordered_map<int, int> last_face_; // per input face: a face near the last insertion
  std::unordered_map<std::uint64_t, int> feature_;
  std::vector<int> nv_, nw_; // scratch
};

} // namespace boundary_front_detail

/// Connects the boundary nodes into a closed, outward oriented triangle
/// surface that follows the patches and feature curves of `surface`, with
/// triangles made Delaunay in the metric of `field` by edge flips. Throws
/// `Invalid_input` if a node is not on the surface or inconsistent with it,
/// `Meshing_failure` if the front cannot be built or fails its final checks.
template <class MetricField>
Boundary_front build_boundary_front(const Boundary_surface& surface, const std::vector<Boundary_node>& nodes,
                                    const MetricField& field, const Boundary_front_options& options = {})
{
  const auto start = std::chrono::steady_clock::now();
  // Step 7: rebuild with more kept input vertices until the checks pass; the
  // last round keeps them all and flips only inside input faces.
  const int last_round = std::max(1, options.max_repair_rounds);
  std::vector<char> keep;
  std::vector<std::vector<int>> faces_of_vertex; // of the input, built on the first repair
  Boundary_front out;
  for(int round = 0;; ++round) {
    out = Boundary_front();
    out.repair_rounds = round;
    const bool input_faces_only = round == last_round;
    if(input_faces_only)
      keep.assign(surface.points.size(), 1);
    boundary_front_detail::Front_builder<MetricField> builder(surface, nodes, field, options, keep, input_faces_only,
                                                              out);
    std::string problem;
    const std::vector<int> bad = builder.run(problem);
    if(bad.empty())
      break;
    if(input_faces_only)
      throw Meshing_failure("boundary front: " + problem +
                            ", even with every input vertex kept (the nodes do not fit the surface)");
    // keep the vertices of the offending input faces and `round` rings around them
    if(faces_of_vertex.empty()) {
      faces_of_vertex.resize(surface.points.size());
      for(std::size_t f = 0; f < surface.triangles.size(); ++f)
        for(int v : surface.triangles[f])
          if(v >= 0 && std::size_t(v) < surface.points.size())
            faces_of_vertex[std::size_t(v)].push_back(int(f));
    }
    keep.resize(surface.points.size(), 0);
    std::vector<int> ring;
    for(int f : bad)
      for(int v : surface.triangles[std::size_t(f)])
        if(!keep[std::size_t(v)]) {
          keep[std::size_t(v)] = 1;
          ring.push_back(v);
        }
    for(int r = 0; r < round; ++r) {
      std::vector<int> next;
      for(int v : ring)
        for(int f : faces_of_vertex[std::size_t(v)])
          for(int w : surface.triangles[std::size_t(f)])
            if(!keep[std::size_t(w)]) {
              keep[std::size_t(w)] = 1;
              next.push_back(w);
            }
      ring.swap(next);
    }
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

/// The surface of a `Polyhedral_mesh_domain_with_features_3` after
/// `detect_features()`: all its polyhedra, triangles with their `patch_id()`,
/// the halfedges marked `is_feature_edge()` plus every edge between two
/// patches. Oriented outward: if the enclosed signed volume is negative, every
/// triangle is flipped. Throws `Invalid_input` on a non-triangular face or an
/// open polyhedron.
template <class Domain>
Boundary_surface boundary_surface_from_polyhedral_domain(const Domain& domain)
{
  Boundary_surface s;
  for(const auto& poly : domain.polyhedra()) {
    std::map<const void*, int> index;
    for(auto v = poly.vertices_begin(); v != poly.vertices_end(); ++v) {
      index[&*v] = int(s.points.size());
      s.points.push_back({{CGAL::to_double(v->point().x()), CGAL::to_double(v->point().y()),
                           CGAL::to_double(v->point().z())}});
    }
    for(auto f = poly.facets_begin(); f != poly.facets_end(); ++f) {
      auto h = f->halfedge();
      std::array<int, 3> t;
      for(int k = 0; k < 3; ++k, h = h->next())
        t[k] = index[&*h->vertex()];
      if(h != f->halfedge())
        throw Invalid_input("boundary front: the domain's polyhedron has a face that is not a triangle");
      s.triangles.push_back(t);
      s.patches.push_back(static_cast<int>(f->patch_id()));
    }
    for(auto e = poly.edges_begin(); e != poly.edges_end(); ++e) {
      if(e->is_border_edge())
        throw Invalid_input("boundary front: the domain's polyhedron is not closed");
      const bool between = e->facet()->patch_id() != e->opposite()->facet()->patch_id();
      if(e->is_feature_edge() || e->opposite()->is_feature_edge() || between)
        s.feature_edges.push_back({{index[&*e->opposite()->vertex()], index[&*e->vertex()]}});
    }
  }
  double volume = 0;
  if(!s.points.empty()) {
    const std::array<double, 3> o = s.points[0]; // relative to o: exact cancellation far from the origin
    for(const auto& t : s.triangles) {
      std::array<std::array<double, 3>, 3> p;
      for(int k = 0; k < 3; ++k)
        for(int i = 0; i < 3; ++i)
          p[k][i] = s.points[t[k]][i] - o[i];
      const auto &a = p[0], &b = p[1], &c = p[2];
      volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                 a[2] * (b[0] * c[1] - b[1] * c[0])) / 6;
    }
  }
  if(volume < 0)
    for(auto& t : s.triangles)
      std::swap(t[1], t[2]);
  return s;
}

} // namespace front
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_FRONT_BOUNDARY_FRONT_H
