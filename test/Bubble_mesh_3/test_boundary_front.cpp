// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Tests of the boundary front (internal/front/boundary_front.h). The nodes
// are generated here (grids, jittered grids, dart throwing on the input
// triangles, arc-length sampling of the feature curves), independently of
// the bubble packer. Every front is checked by `check_front`, which
// recomputes each requirement from scratch.
#include <CGAL/Bubble_mesh_3/internal/front/boundary_front.h>

#include <CGAL/Constant_metric_field_3.h>
#include <CGAL/Function_metric_field_3.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_polyhedron_3.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>
#include <CGAL/boost/graph/generators.h>
#include <CGAL/convex_hull_3.h>

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <random>
#include <set>
#include <unordered_map>
#include <vector>

namespace {

using namespace CGAL::Bubble_mesh_3::internal::front;
using CGAL::Bubble_mesh_3::Invalid_input;
using CGAL::Bubble_mesh_3::Meshing_failure;
using CGAL::Bubble_mesh_3::Metric_3;

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Constant_metric_field_3<K> Constant_field;
typedef Eigen::Vector3d V3;
typedef Eigen::Matrix3d M3;

const double pi = 3.14159265358979323846;

V3 vec(const std::array<double, 3>& p) { return V3(p[0], p[1], p[2]); }
std::array<double, 3> arr(const V3& p) { return {{p[0], p[1], p[2]}}; }

// ------------------------------------------------------------------ surfaces

// every edge between two patches becomes a feature edge
void add_patch_features(Boundary_surface& s)
{
  std::map<std::pair<int, int>, int> face_of;
  for(std::size_t f = 0; f < s.triangles.size(); ++f)
    for(int k = 0; k < 3; ++k)
      face_of[{s.triangles[f][k], s.triangles[f][(k + 1) % 3]}] = int(f);
  for(const auto& e : face_of)
    if(e.first.first < e.first.second) {
      const int g = face_of.at({e.first.second, e.first.first});
      if(s.patches[e.second] != s.patches[g])
        s.feature_edges.push_back({{e.first.first, e.first.second}});
    }
}

// Union of filled cells of a grid of spacing h; one patch per (normal, plane).
Boundary_surface voxel_surface(int nx, int ny, int nz, double h, const std::function<bool(int, int, int)>& filled)
{
  const int n[3] = {nx, ny, nz};
  auto inside = [&](int i, int j, int k) {
    return i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz && filled(i, j, k);
  };
  std::map<std::array<int, 3>, int> index;
  Boundary_surface s;
  auto vertex = [&](std::array<int, 3> g) {
    auto it = index.find(g);
    if(it != index.end())
      return it->second;
    const int id = int(s.points.size());
    index[g] = id;
    s.points.push_back({{g[0] * h, g[1] * h, g[2] * h}});
    return id;
  };
  for(int i = 0; i < nx; ++i)
    for(int j = 0; j < ny; ++j)
      for(int k = 0; k < nz; ++k) {
        if(!inside(i, j, k))
          continue;
        const int c[3] = {i, j, k};
        for(int a = 0; a < 3; ++a)
          for(int sign = -1; sign <= 1; sign += 2) {
            int d[3] = {c[0], c[1], c[2]};
            d[a] += sign;
            if(inside(d[0], d[1], d[2]))
              continue;
            const int u = (a + 1) % 3, w = (a + 2) % 3;
            std::array<int, 3> base{{c[0], c[1], c[2]}};
            if(sign > 0)
              base[a] += 1;
            std::array<std::array<int, 3>, 4> q;
            const int du[4] = {0, 1, 1, 0}, dw[4] = {0, 0, 1, 1};
            for(int m = 0; m < 4; ++m) {
              q[m] = base;
              q[m][u] += du[m];
              q[m][w] += dw[m];
            }
            if(sign < 0)
              std::swap(q[1], q[3]);
            const int v0 = vertex(q[0]), v1 = vertex(q[1]), v2 = vertex(q[2]), v3 = vertex(q[3]);
            const int patch = (a * 2 + (sign > 0)) * 1000 + base[a];
            s.triangles.push_back({{v0, v1, v2}});
            s.triangles.push_back({{v0, v2, v3}});
            s.patches.push_back(patch);
            s.patches.push_back(patch);
          }
      }
  (void)n;
  add_patch_features(s);
  return s;
}

Boundary_surface cube_surface(int m)
{
  return voxel_surface(m, m, m, 1.0 / m, [](int, int, int) { return true; });
}

// L-shaped prism: ([0,2]x[0,1] U [0,1]x[0,2]) x [0,1], cells of size 1/m
Boundary_surface l_prism_surface(int m)
{
  return voxel_surface(2 * m, 2 * m, m, 1.0 / m, [m](int i, int j, int) { return i < m || j < m; });
}

Boundary_surface icosphere(int subdivisions)
{
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<V3> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                       {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> f = {{{0, 11, 5}}, {{0, 5, 1}},  {{0, 1, 7}},   {{0, 7, 10}}, {{0, 10, 11}},
                                       {{1, 5, 9}},  {{5, 11, 4}}, {{11, 10, 2}}, {{10, 7, 6}}, {{7, 1, 8}},
                                       {{3, 9, 4}},  {{3, 4, 2}},  {{3, 2, 6}},   {{3, 6, 8}},  {{3, 8, 9}},
                                       {{4, 9, 5}},  {{2, 4, 11}}, {{6, 2, 10}},  {{8, 6, 7}},  {{9, 8, 1}}};
  for(auto& q : p)
    q.normalize();
  for(int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> mid;
    auto middle = [&](int a, int b) {
      auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = mid.find(key);
      if(it != mid.end())
        return it->second;
      p.push_back((p[a] + p[b]).normalized());
      return mid[key] = int(p.size()) - 1;
    };
    std::vector<std::array<int, 3>> g;
    for(const auto& t3 : f) {
      const int a = middle(t3[0], t3[1]), b = middle(t3[1], t3[2]), c = middle(t3[2], t3[0]);
      g.push_back({{t3[0], a, c}});
      g.push_back({{t3[1], b, a}});
      g.push_back({{t3[2], c, b}});
      g.push_back({{a, b, c}});
    }
    f.swap(g);
  }
  Boundary_surface s;
  for(const auto& q : p)
    s.points.push_back(arr(q));
  s.triangles = f;
  s.patches.assign(f.size(), 0);
  return s;
}

// radius 1, z in [-1,1], n segments; patches: side 0, top 1, bottom 2
Boundary_surface cylinder_surface(int n, int rings)
{
  Boundary_surface s;
  const double dz = 2 * pi / n;
  const int nz = std::max(1, int(std::lround(2 / dz)));
  auto ring_point = [&](int i, double r, double z) {
    const double a = 2 * pi * i / n;
    s.points.push_back({{r * std::cos(a), r * std::sin(a), z}});
    return int(s.points.size()) - 1;
  };
  std::vector<std::vector<int>> side(nz + 1);
  for(int k = 0; k <= nz; ++k)
    for(int i = 0; i < n; ++i)
      side[k].push_back(ring_point(i, 1, -1 + 2.0 * k / nz));
  for(int k = 0; k < nz; ++k)
    for(int i = 0; i < n; ++i) {
      const int a = side[k][i], b = side[k][(i + 1) % n], c = side[k + 1][(i + 1) % n], d = side[k + 1][i];
      s.triangles.push_back({{a, b, c}});
      s.triangles.push_back({{a, c, d}});
      s.patches.push_back(0);
      s.patches.push_back(0);
    }
  for(int cap = 0; cap < 2; ++cap) {
    const double z = cap == 0 ? 1 : -1;
    const int patch = cap == 0 ? 1 : 2;
    std::vector<std::vector<int>> ring(rings + 1);
    ring[rings] = cap == 0 ? side[nz] : side[0];
    for(int j = 1; j < rings; ++j)
      for(int i = 0; i < n; ++i)
        ring[j].push_back(ring_point(i, double(j) / rings, z));
    s.points.push_back({{0, 0, z}});
    const int centre = int(s.points.size()) - 1;
    auto add = [&](int a, int b, int c) {
      if(cap == 0)
        s.triangles.push_back({{a, b, c}});
      else
        s.triangles.push_back({{a, c, b}});
      s.patches.push_back(patch);
    };
    for(int i = 0; i < n; ++i)
      add(centre, ring[1][i], ring[1][(i + 1) % n]);
    for(int j = 1; j < rings; ++j)
      for(int i = 0; i < n; ++i) {
        const int a = ring[j][i], b = ring[j + 1][i], c = ring[j + 1][(i + 1) % n], d = ring[j][(i + 1) % n];
        add(a, b, c);
        add(a, c, d);
      }
  }
  add_patch_features(s);
  return s;
}

// torus (genus 1) around z: major radius R, minor radius r; one patch, no features
Boundary_surface torus_surface(double R, double r, int nu, int nv)
{
  Boundary_surface s;
  for(int i = 0; i < nu; ++i)
    for(int j = 0; j < nv; ++j) {
      const double u = 2 * pi * i / nu, v = 2 * pi * j / nv;
      s.points.push_back({{(R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u), r * std::sin(v)}});
    }
  auto id = [&](int i, int j) { return ((i + nu) % nu) * nv + (j + nv) % nv; };
  for(int i = 0; i < nu; ++i)
    for(int j = 0; j < nv; ++j) {
      s.triangles.push_back({{id(i, j), id(i + 1, j), id(i + 1, j + 1)}});
      s.triangles.push_back({{id(i, j), id(i + 1, j + 1), id(i, j + 1)}});
      s.patches.push_back(0);
      s.patches.push_back(0);
    }
  return s;
}

// A star-shaped surface: the vertices of `s` (a unit sphere) moved to radius
// r(direction). Never self-intersecting; spikes and bumps make tips and
// thin parts that coarse nodes cannot follow.
Boundary_surface radially_displaced(Boundary_surface s, const std::function<double(const V3&)>& r)
{
  for(auto& p : s.points) {
    const V3 d = vec(p).normalized();
    p = arr(r(d) * d);
  }
  return s;
}

Boundary_surface spiky_sphere()
{
  const double t = (1 + std::sqrt(5.0)) / 2;
  const std::vector<V3> tips = {{-1, t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, -t}, {t, 0, -1}, {-t, 0, 1}};
  return radially_displaced(icosphere(4), [tips](const V3& d) {
    double r = 1;
    for(const V3& a : tips)
      r += 0.6 * std::pow(std::max(0.0, d.dot(a.normalized())), 40);
    return r;
  });
}

Boundary_surface bumpy_sphere()
{
  return radially_displaced(icosphere(4), [](const V3& d) {
    return 1 + 0.15 * std::sin(6 * d[0]) * std::sin(6 * d[1]) * std::sin(6 * d[2]);
  });
}

double surface_volume(const Boundary_surface& s)
{
  double v = 0;
  for(const auto& t : s.triangles)
    v += vec(s.points[t[0]]).dot(vec(s.points[t[1]]).cross(vec(s.points[t[2]]))) / 6;
  return v;
}

// ------------------------------------------------------------------ nodes

struct Feature_graph {
  std::vector<std::vector<std::pair<int, int>>> adj; // (neighbour, feature edge index)
  explicit Feature_graph(const Boundary_surface& s) : adj(s.points.size())
  {
    for(std::size_t e = 0; e < s.feature_edges.size(); ++e) {
      adj[s.feature_edges[e][0]].emplace_back(s.feature_edges[e][1], int(e));
      adj[s.feature_edges[e][1]].emplace_back(s.feature_edges[e][0], int(e));
    }
  }
  bool corner(int v) const { return !adj[v].empty() && adj[v].size() != 2; }
};

// The feature curves as vertex chains (closed chains repeat their first vertex).
std::vector<std::vector<int>> feature_chains(const Boundary_surface& s)
{
  Feature_graph g(s);
  std::vector<char> used(s.feature_edges.size(), 0);
  std::vector<std::vector<int>> chains;
  auto walk = [&](int start, int first_edge) {
    std::vector<int> chain{start};
    int v = start, e = first_edge;
    while(true) {
      used[e] = 1;
      const int w = s.feature_edges[e][0] == v ? s.feature_edges[e][1] : s.feature_edges[e][0];
      chain.push_back(w);
      if(g.corner(w) || w == start)
        break;
      int next = -1;
      for(const auto& ne : g.adj[w])
        if(!used[ne.second])
          next = ne.second;
      if(next < 0)
        break;
      v = w;
      e = next;
    }
    chains.push_back(chain);
  };
  for(std::size_t v = 0; v < s.points.size(); ++v)
    if(g.corner(int(v)))
      for(const auto& ne : g.adj[v])
        if(!used[ne.second])
          walk(int(v), ne.second);
  for(std::size_t e = 0; e < s.feature_edges.size(); ++e)
    if(!used[e])
      walk(s.feature_edges[e][0], int(e));
  return chains;
}

// Corner nodes, then curve nodes at (metric, through Q) arc-length spacing h.
std::vector<Boundary_node> curve_nodes(const Boundary_surface& s, double h, const M3& q = M3::Identity(),
                                       double jitter = 0, unsigned seed = 1)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Boundary_node> nodes;
  Feature_graph g(s);
  for(std::size_t v = 0; v < s.points.size(); ++v)
    if(g.corner(int(v)))
      nodes.push_back({s.points[v], 0, -1});
  for(const auto& chain : feature_chains(s)) {
    const bool closed = chain.front() == chain.back();
    std::vector<double> acc{0};
    for(std::size_t i = 1; i < chain.size(); ++i)
      acc.push_back(acc.back() + (q * (vec(s.points[chain[i]]) - vec(s.points[chain[i - 1]]))).norm());
    const double len = acc.back();
    int k = std::max(1, int(std::lround(len / h)));
    if(closed)
      k = std::max(k, 3);
    for(int j = closed ? 0 : 1; j < k; ++j) {
      double a = len * (j + (closed ? 0.25 : 0) + jitter * u(rng) * 0.3) / k;
      a = std::clamp(a, 0.0, len);
      std::size_t i = std::upper_bound(acc.begin(), acc.end(), a) - acc.begin();
      i = std::min(std::max<std::size_t>(i, 1), acc.size() - 1);
      const double t = (a - acc[i - 1]) / (acc[i] - acc[i - 1]);
      const V3 p = (1 - t) * vec(s.points[chain[i - 1]]) + t * vec(s.points[chain[i]]);
      nodes.push_back({arr(p), 1, -1});
    }
  }
  return nodes;
}

double segment_distance(const V3& p, const V3& a, const V3& b)
{
  const V3 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

// Dart throwing on the input triangles: a patch node at (Q-)distance >= r
// from every node, and >= 0.45 r from the feature curves.
void add_patch_darts(const Boundary_surface& s, std::vector<Boundary_node>& nodes, double r,
                     const M3& q = M3::Identity(), unsigned seed = 7)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> cumulative;
  double total = 0;
  for(const auto& t : s.triangles) {
    const V3 a = q * vec(s.points[t[0]]), b = q * vec(s.points[t[1]]), c = q * vec(s.points[t[2]]);
    total += (b - a).cross(c - a).norm() / 2;
    cumulative.push_back(total);
  }
  std::unordered_map<long long, std::vector<V3>> grid; // mapped points hashed by cells of size r
  auto cell = [&](const V3& m, int dx, int dy, int dz) {
    const long long i = (long long)std::floor(m[0] / r) + dx, j = (long long)std::floor(m[1] / r) + dy,
                    k = (long long)std::floor(m[2] / r) + dz;
    return (i * 73856093LL) ^ (j * 19349663LL) ^ (k * 83492791LL);
  };
  auto far_enough = [&](const V3& m) {
    for(int dx = -1; dx <= 1; ++dx)
      for(int dy = -1; dy <= 1; ++dy)
        for(int dz = -1; dz <= 1; ++dz) {
          auto it = grid.find(cell(m, dx, dy, dz));
          if(it != grid.end())
            for(const V3& o : it->second)
              if((o - m).norm() < r)
                return false;
        }
    return true;
  };
  for(const auto& n : nodes)
    grid[cell(q * vec(n.point), 0, 0, 0)].push_back(q * vec(n.point));
  const int tries = int(60 * total / (r * r)) + 100;
  for(int i = 0; i < tries; ++i) {
    const std::size_t f = std::lower_bound(cumulative.begin(), cumulative.end(), u(rng) * total) - cumulative.begin();
    if(f >= s.triangles.size())
      continue;
    double b1 = u(rng), b2 = u(rng);
    if(b1 + b2 > 1) {
      b1 = 1 - b1;
      b2 = 1 - b2;
    }
    const auto& t = s.triangles[f];
    const V3 p = vec(s.points[t[0]]) + b1 * (vec(s.points[t[1]]) - vec(s.points[t[0]])) +
                 b2 * (vec(s.points[t[2]]) - vec(s.points[t[0]]));
    const V3 m = q * p;
    if(!far_enough(m))
      continue;
    bool near_curve = false;
    for(const auto& e : s.feature_edges)
      if(segment_distance(m, q * vec(s.points[e[0]]), q * vec(s.points[e[1]])) < 0.45 * r) {
        near_curve = true;
        break;
      }
    if(near_curve)
      continue;
    nodes.push_back({arr(p), 2, s.patches[f]});
    grid[cell(m, 0, 0, 0)].push_back(m);
  }
}

// patch of the input triangle closest to p
int patch_at(const Boundary_surface& s, const V3& p)
{
  double best = 1e300;
  int patch = -1;
  const K::Point_3 q(p[0], p[1], p[2]);
  for(std::size_t f = 0; f < s.triangles.size(); ++f) {
    auto P = [&](int v) { return K::Point_3(s.points[v][0], s.points[v][1], s.points[v][2]); };
    const K::Triangle_3 t(P(s.triangles[f][0]), P(s.triangles[f][1]), P(s.triangles[f][2]));
    const double d = CGAL::to_double(CGAL::squared_distance(q, t));
    if(d < best) {
      best = d;
      patch = s.patches[f];
    }
  }
  return patch;
}

// Nodes on the unit cube [0,1]^3 on an n x n grid per face (jittered).
std::vector<Boundary_node> cube_grid_nodes(const Boundary_surface& s, int n, double jitter, unsigned seed = 3)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Boundary_node> nodes = curve_nodes(s, 1.0 / n, M3::Identity(), jitter, seed);
  for(int a = 0; a < 3; ++a)
    for(int side = 0; side < 2; ++side)
      for(int i = 1; i < n; ++i)
        for(int j = 1; j < n; ++j) {
          V3 p;
          p[a] = side;
          p[(a + 1) % 3] = (i + jitter * 0.3 * u(rng)) / n;
          p[(a + 2) % 3] = (j + jitter * 0.3 * u(rng)) / n;
          nodes.push_back({arr(p), 2, patch_at(s, p)});
        }
  return nodes;
}

// ------------------------------------------------------------------ checks

struct Report {
  std::size_t nodes = 0, triangles = 0;
  double worst_metric_angle = 0, mean_metric_angle = 0; // minimum angle after mapping by Q, degrees
  double worst_angle = 0;                               // Euclidean
  double volume = 0;
  std::size_t non_delaunay = 0; // flippable-looking edges left that fail the metric Delaunay criterion
};

double min_mapped_angle(const Metric_3& m, const V3& a, const V3& b, const V3& c)
{
  const V3 p[3] = {m.map(a), m.map(b), m.map(c)};
  double best = 180;
  for(int k = 0; k < 3; ++k) {
    const V3 u = p[(k + 1) % 3] - p[k], v = p[(k + 2) % 3] - p[k];
    best = std::min(best, std::atan2(u.cross(v).norm(), u.dot(v)) * 180 / pi);
  }
  return best;
}

template <class Field>
double metric_angle(const Field& field, const V3& a, const V3& b, const V3& c)
{
  const V3 g = (a + b + c) / 3;
  return min_mapped_angle(Metric_3(field(K::Point_3(g[0], g[1], g[2]))), a, b, c);
}

typedef CGAL::AABB_triangle_primitive<K, std::vector<K::Triangle_3>::const_iterator> Tri_primitive;
typedef CGAL::AABB_tree<CGAL::AABB_traits<K, Tri_primitive>> Tri_tree;

// Expected feature chains between consecutive nodes, computed independently:
// pair of nodes -> the input feature edges between them.
std::map<std::pair<int, int>, std::set<int>> expected_feature_chains(const Boundary_surface& s,
                                                                     const std::vector<Boundary_node>& nodes,
                                                                     double eps)
{
  const int nv = int(s.points.size());
  std::vector<int> station_of_vertex(nv);
  for(int v = 0; v < nv; ++v)
    station_of_vertex[v] = v;
  std::vector<std::vector<std::pair<double, int>>> on_edge(s.feature_edges.size());
  for(std::size_t i = 0; i < nodes.size(); ++i) {
    if(nodes[i].dimension == 2)
      continue;
    const V3 p = vec(nodes[i].point);
    bool placed = false;
    for(int v = 0; v < nv && !placed; ++v)
      if((vec(s.points[v]) - p).norm() < eps) {
        station_of_vertex[v] = nv + int(i);
        placed = true;
      }
    for(std::size_t e = 0; e < s.feature_edges.size() && !placed; ++e) {
      const V3 a = vec(s.points[s.feature_edges[e][0]]), b = vec(s.points[s.feature_edges[e][1]]);
      if(segment_distance(p, a, b) < eps) {
        on_edge[e].emplace_back((p - a).norm() / (b - a).norm(), nv + int(i));
        placed = true;
      }
    }
    EXPECT_TRUE(placed) << "test generator: node " << i << " is not on a feature";
  }
  std::map<int, std::vector<std::pair<int, int>>> adj; // station -> (station, input edge)
  for(std::size_t e = 0; e < s.feature_edges.size(); ++e) {
    std::sort(on_edge[e].begin(), on_edge[e].end());
    std::vector<int> seq{station_of_vertex[s.feature_edges[e][0]]};
    for(const auto& x : on_edge[e])
      seq.push_back(x.second);
    seq.push_back(station_of_vertex[s.feature_edges[e][1]]);
    for(std::size_t i = 0; i + 1 < seq.size(); ++i) {
      adj[seq[i]].emplace_back(seq[i + 1], int(e));
      adj[seq[i + 1]].emplace_back(seq[i], int(e));
    }
  }
  std::map<std::pair<int, int>, std::set<int>> result;
  for(const auto& st : adj) {
    if(st.first < nv)
      continue;
    for(const auto& first : st.second) {
      std::set<int> edges{first.second};
      int prev = st.first, cur = first.first, via = first.second;
      while(cur < nv) {
        const auto& nb = adj[cur];
        EXPECT_EQ(nb.size(), 2u) << "test generator: a surface corner without node";
        if(nb.size() != 2)
          break;
        const auto& nx = (nb[0].second == via && nb[0].first == prev) ? nb[1] : nb[0];
        prev = cur;
        cur = nx.first;
        via = nx.second;
        edges.insert(via);
      }
      const int a = st.first - nv, b = cur - nv;
      result[{std::min(a, b), std::max(a, b)}].insert(edges.begin(), edges.end());
    }
  }
  return result;
}

// Edges inside a patch whose opposite angles (after mapping by Q at the quad
// centroid) sum to more than those of the flipped edge: not metric-Delaunay.
template <class Field>
std::size_t non_delaunay_edges(const std::vector<Boundary_node>& nodes, const Boundary_front& f, const Field& field)
{
  std::map<std::pair<int, int>, int> directed;
  for(std::size_t i = 0; i < f.triangles.size(); ++i)
    for(int k = 0; k < 3; ++k)
      directed[{f.triangles[i][k], f.triangles[i][(k + 1) % 3]}] = int(i);
  std::set<std::pair<int, int>> features;
  for(const auto& e : f.feature_edges)
    features.insert({std::min(e[0], e[1]), std::max(e[0], e[1])});
  std::size_t bad = 0;
  for(const auto& e : directed) {
    const int a = e.first.first, b = e.first.second;
    if(a > b || features.count({a, b}))
      continue;
    const auto rev = directed.find({b, a});
    if(rev == directed.end())
      continue; // not closed: reported by check_front
    const int f1 = e.second, f2 = rev->second;
    if(f.patches[f1] != f.patches[f2])
      continue;
    auto third = [&](int t) {
      for(int v : f.triangles[t])
        if(v != a && v != b)
          return v;
      return -1;
    };
    const V3 pa = vec(nodes[a].point), pb = vec(nodes[b].point), pc = vec(nodes[third(f1)].point),
             pd = vec(nodes[third(f2)].point);
    const V3 g = (pa + pb + pc + pd) / 4;
    const Metric_3 m(field(K::Point_3(g[0], g[1], g[2])));
    auto ang = [&](const V3& o, const V3& x, const V3& y) {
      const V3 u = m.map(x - o), v = m.map(y - o);
      return std::atan2(u.cross(v).norm(), u.dot(v));
    };
    if(ang(pc, pa, pb) + ang(pd, pa, pb) > ang(pa, pc, pd) + ang(pb, pc, pd) + 1e-6)
      ++bad;
  }
  return bad;
}

template <class Field>
Report check_front(const Boundary_surface& s, const std::vector<Boundary_node>& given, const Boundary_front& f,
                   const Field& field, int euler = 2, double volume_tolerance = 1e-9,
                   bool centroids_on_their_patch = true)
{
  Report r;
  // the front's nodes: the given ones, then the input vertices it kept
  std::vector<Boundary_node> nodes = given;
  nodes.insert(nodes.end(), f.added_nodes.begin(), f.added_nodes.end());
  for(const Boundary_node& a : f.added_nodes) {
    // a patch node: an input vertex; a curve node: on an input feature edge
    bool placed = false;
    if(a.dimension == 2)
      for(const auto& p : s.points)
        placed = placed || (vec(p) - vec(a.point)).norm() == 0;
    else
      for(const auto& e : s.feature_edges)
        placed = placed || segment_distance(vec(a.point), vec(s.points[e[0]]), vec(s.points[e[1]])) < 1e-12;
    EXPECT_TRUE(placed) << "an added node of dimension " << a.dimension << " is not where it belongs";
    EXPECT_TRUE(a.dimension == 1 || a.dimension == 2) << "an added node of dimension " << a.dimension;
  }
  const std::size_t n = nodes.size();
  r.nodes = n;
  r.triangles = f.triangles.size();
  EXPECT_EQ(f.triangles.size(), f.patches.size());
  EXPECT_EQ(f.feature_edges.size(), f.feature_edge_sources.size());

  V3 lo = V3::Constant(1e300), hi = -lo;
  for(const auto& p : s.points) {
    lo = lo.cwiseMin(vec(p));
    hi = hi.cwiseMax(vec(p));
  }
  const double L = (hi - lo).norm();

  // every node used, only nodes
  std::vector<int> used(n, 0);
  for(const auto& t : f.triangles)
    for(int v : t) {
      EXPECT_TRUE(v >= 0 && std::size_t(v) < n) << "index out of range";
      if(v < 0 || std::size_t(v) >= n)
        return r;
      used[v] = 1;
    }
  for(std::size_t i = 0; i < n; ++i)
    EXPECT_TRUE(used[i]) << "node " << i << " unused";

  // closed, oriented, edge-manifold
  std::map<std::pair<int, int>, int> directed;
  for(std::size_t i = 0; i < f.triangles.size(); ++i)
    for(int k = 0; k < 3; ++k) {
      const auto key = std::make_pair(f.triangles[i][k], f.triangles[i][(k + 1) % 3]);
      EXPECT_EQ(directed.count(key), 0u) << "directed edge used twice";
      directed[key] = int(i);
    }
  std::size_t undirected = 0;
  for(const auto& e : directed) {
    EXPECT_EQ(directed.count({e.first.second, e.first.first}), 1u) << "edge without its reverse: not closed";
    if(e.first.first < e.first.second)
      ++undirected;
  }
  // vertex-manifold: the triangles around each node form one cycle
  std::vector<std::map<int, int>> fan(n);
  for(const auto& t : f.triangles)
    for(int k = 0; k < 3; ++k)
      fan[t[k]][t[(k + 1) % 3]] = t[(k + 2) % 3];
  for(std::size_t v = 0; v < n; ++v) {
    if(fan[v].empty())
      continue;
    const int start = fan[v].begin()->first;
    int x = start;
    std::size_t len = 0;
    do {
      auto it = fan[v].find(x);
      if(it == fan[v].end())
        break;
      x = it->second;
      ++len;
    } while(x != start && len <= fan[v].size());
    EXPECT_EQ(len, fan[v].size()) << "node " << v << " is not vertex-manifold";
  }
  EXPECT_EQ(int(n) - int(undirected) + int(f.triangles.size()), euler) << "Euler characteristic";

  // volume, degeneracy, angles
  double vol = 0;
  r.worst_metric_angle = 180;
  r.worst_angle = 180;
  double sum = 0;
  for(const auto& t : f.triangles) {
    const V3 a = vec(nodes[t[0]].point), b = vec(nodes[t[1]].point), c = vec(nodes[t[2]].point);
    vol += a.dot(b.cross(c)) / 6;
    const double area2 = (b - a).cross(c - a).norm();
    const double longest = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    EXPECT_GT(area2, 1e-8 * longest) << "degenerate triangle";
    const double ma = metric_angle(field, a, b, c);
    r.worst_metric_angle = std::min(r.worst_metric_angle, ma);
    r.worst_angle = std::min(r.worst_angle, min_mapped_angle(Metric_3(), a, b, c));
    sum += ma;
  }
  r.mean_metric_angle = f.triangles.empty() ? 0 : sum / f.triangles.size();
  r.volume = vol;
  EXPECT_GT(vol, 0);
  const double input_volume = surface_volume(s);
  EXPECT_NEAR(vol, input_volume, volume_tolerance * std::abs(input_volume));

  // patches: dimension-2 vertices agree, the centroid is closest to a face of that patch
  std::vector<K::Triangle_3> tris;
  for(const auto& t : s.triangles) {
    auto P = [&](int v) { return K::Point_3(s.points[v][0], s.points[v][1], s.points[v][2]); };
    tris.emplace_back(P(t[0]), P(t[1]), P(t[2]));
  }
  Tri_tree tree(tris.begin(), tris.end());
  tree.accelerate_distance_queries();
  for(std::size_t i = 0; i < f.triangles.size(); ++i) {
    const auto& t = f.triangles[i];
    for(int v : t) {
      if(nodes[v].dimension == 2) {
        EXPECT_EQ(nodes[v].patch, f.patches[i]) << "triangle tagged with another patch than its node";
      }
    }
    const V3 g = (vec(nodes[t[0]].point) + vec(nodes[t[1]].point) + vec(nodes[t[2]].point)) / 3;
    const auto cp = tree.closest_point_and_primitive(K::Point_3(g[0], g[1], g[2]));
    if(centroids_on_their_patch) {
      EXPECT_EQ(s.patches[cp.second - tris.begin()], f.patches[i]) << "triangle centroid is on another patch";
    }
  }

  // feature curves: exactly the chains between consecutive curve/corner nodes
  const auto expected = expected_feature_chains(s, nodes, 1e-9 * std::max(L, 1.0));
  std::set<std::pair<int, int>> got;
  for(std::size_t i = 0; i < f.feature_edges.size(); ++i) {
    const auto e = std::make_pair(std::min(f.feature_edges[i][0], f.feature_edges[i][1]),
                                  std::max(f.feature_edges[i][0], f.feature_edges[i][1]));
    got.insert(e);
    auto it = expected.find(e);
    EXPECT_TRUE(it != expected.end()) << "feature edge " << e.first << "-" << e.second << " is not a curve chain";
    if(it != expected.end()) {
      EXPECT_EQ(it->second.count(f.feature_edge_sources[i]), 1u) << "feature edge source is not on its chain";
    }
    EXPECT_EQ(directed.count(e), 1u) << "feature edge is not a mesh edge";
  }
  EXPECT_EQ(got.size(), f.feature_edges.size()) << "duplicate feature edges";
  EXPECT_EQ(got.size(), expected.size()) << "some curve chains are missing";
  // no triangle crosses a feature: edges between two patches are feature edges
  for(const auto& e : directed)
    if(e.first.first < e.first.second) {
      auto o = directed.find({e.first.second, e.first.first});
      if(o != directed.end() && f.patches[e.second] != f.patches[o->second]) {
        EXPECT_EQ(got.count(e.first), 1u) << "an edge between two patches is not a feature edge";
      }
    }

  // no self-intersection
  CGAL::Surface_mesh<K::Point_3> sm;
  std::vector<CGAL::Surface_mesh<K::Point_3>::Vertex_index> vs;
  for(const auto& p : nodes)
    vs.push_back(sm.add_vertex(K::Point_3(p.point[0], p.point[1], p.point[2])));
  for(const auto& t : f.triangles)
    sm.add_face(vs[t[0]], vs[t[1]], vs[t[2]]);
  EXPECT_EQ(sm.number_of_faces(), f.triangles.size());
  EXPECT_FALSE(CGAL::Polygon_mesh_processing::does_self_intersect(sm)) << "self-intersection";
  r.non_delaunay = non_delaunay_edges(nodes, f, field);
  return r;
}

void print(const char* name, const Boundary_surface& s, const Report& r, const Boundary_front& f)
{
  std::printf("[front] %-34s input %zu v / %zu t, nodes %zu, triangles %zu, %.3f s, worst/mean metric angle "
              "%.1f/%.1f deg, worst angle %.1f, non-Delaunay %zu, collapses %zu, fallbacks %zu, unstick %zu, flips "
              "%zu, added nodes %zu, short collapses %zu, repair rounds %d\n",
              name, s.points.size(), s.triangles.size(), r.nodes, r.triangles, f.seconds, r.worst_metric_angle,
              r.mean_metric_angle, r.worst_angle, r.non_delaunay, f.collapses, f.fallback_retriangulations,
              f.unstick_flips, f.flips, f.added_nodes.size(), f.short_collapses, f.repair_rounds);
}

// ------------------------------------------------------------------ tests

TEST(BoundaryFront, CubeCoarseInputRegularGrid)
{
  const Boundary_surface s = cube_surface(1); // 12 triangles: many nodes per input face
  const auto nodes = cube_grid_nodes(s, 6, 0);
  const Constant_field field;
  const Boundary_front f = build_boundary_front(s, nodes, field);
  const Report r = check_front(s, nodes, f, field);
  print("cube, coarse input, grid 6", s, r, f);
  EXPECT_EQ(r.nodes, 8u + 12u * 5 + 6u * 25);
  EXPECT_EQ(f.feature_edges.size(), 12u * 6);
  EXPECT_GE(r.worst_angle, 44.9); // a square grid: right isosceles triangles
  EXPECT_EQ(f.removed_vertices, 0u);
}

TEST(BoundaryFront, CubeJitteredStretchedMetric)
{
  const Boundary_surface s = cube_surface(3);
  const auto nodes = cube_grid_nodes(s, 8, 1.0);
  const Constant_field field(Metric_3::from_directions_and_sizes(M3::Identity(), V3(0.2, 0.05, 0.2)));
  const Boundary_front f = build_boundary_front(s, nodes, field);
  const Report r = check_front(s, nodes, f, field);
  print("cube, jittered grid, metric 1:4", s, r, f);
  EXPECT_GT(f.removed_vertices, 0u);
  EXPECT_GT(r.worst_metric_angle, 1.0);
}

// mean minimum angle, after mapping by Q of `m`, of the triangles of one patch
double mean_patch_metric_angle(const std::vector<Boundary_node>& nodes, const Boundary_front& f, int patch,
                               const Metric_3& m, std::size_t& count)
{
  double sum = 0;
  count = 0;
  for(std::size_t i = 0; i < f.triangles.size(); ++i)
    if(f.patches[i] == patch) {
      const auto& t = f.triangles[i];
      sum += min_mapped_angle(m, vec(nodes[t[0]].point), vec(nodes[t[1]].point), vec(nodes[t[2]].point));
      ++count;
    }
  return count ? sum / count : 0;
}

TEST(BoundaryFront, StretchedMetricBeatsEuclideanDelaunay)
{
  const Boundary_surface s = cube_surface(2);
  const V3 sizes(0.2, 0.05, 0.2); // 1:4
  const Metric_3 metric = Metric_3::from_directions_and_sizes(M3::Identity(), sizes);
  const M3 q = metric.Q();
  auto nodes = curve_nodes(s, 1.0, q);
  add_patch_darts(s, nodes, 0.9, q);
  const Constant_field stretched(metric), identity;
  const Boundary_front fm = build_boundary_front(s, nodes, stretched);
  const Boundary_front fe = build_boundary_front(s, nodes, identity);
  const Report rm = check_front(s, nodes, fm, stretched);
  const Report re = check_front(s, nodes, fe, stretched);
  print("cube, metric nodes, metric Delaunay", s, rm, fm);
  print("cube, metric nodes, Euclidean Delaunay", s, re, fe);
  const int top = patch_at(s, V3(0.5, 0.5, 1));
  std::size_t cm, ce;
  const double mean_m = mean_patch_metric_angle(nodes, fm, top, metric, cm);
  const double mean_e = mean_patch_metric_angle(nodes, fe, top, metric, ce);
  std::printf("[front] top patch (z=1): %zu triangles, mean metric min angle %.2f (metric) vs %.2f (Euclidean)\n",
              cm, mean_m, mean_e);
  EXPECT_EQ(cm, ce); // same nodes, planar patch: same number of triangles
  EXPECT_GT(cm, 50u);
  EXPECT_GT(mean_m, mean_e + 5.0);
  EXPECT_GT(rm.mean_metric_angle, re.mean_metric_angle + 5.0);
}

TEST(BoundaryFront, SphereFineInputIsDelaunay)
{
  const Boundary_surface s = icosphere(4); // 2562 vertices, edges about 0.06
  std::vector<Boundary_node> nodes;
  add_patch_darts(s, nodes, 0.2);
  const Constant_field field;
  const Boundary_front f = build_boundary_front(s, nodes, field);
  const Report r = check_front(s, nodes, f, field, 2, 0.05);
  print("sphere, fine input, spacing 0.2", s, r, f);
  EXPECT_GT(f.removed_vertices, 2000u);
  // On a sphere the Delaunay triangulation is the convex hull of the nodes.
  std::vector<K::Point_3> pts;
  for(const auto& n : nodes)
    pts.emplace_back(n.point[0], n.point[1], n.point[2]);
  CGAL::Surface_mesh<K::Point_3> hull;
  CGAL::convex_hull_3(pts.begin(), pts.end(), hull);
  std::map<K::Point_3, int> id;
  for(std::size_t i = 0; i < pts.size(); ++i)
    id[pts[i]] = int(i);
  std::set<std::pair<int, int>> hull_edges, front_edges;
  for(auto e : hull.edges()) {
    const int a = id[hull.point(hull.vertex(e, 0))], b = id[hull.point(hull.vertex(e, 1))];
    hull_edges.insert({std::min(a, b), std::max(a, b)});
  }
  for(const auto& t : f.triangles)
    for(int k = 0; k < 3; ++k)
      front_edges.insert({std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])});
  std::size_t common = 0;
  for(const auto& e : front_edges)
    common += hull_edges.count(e);
  const double ratio = double(common) / front_edges.size();
  std::printf("[front] sphere: %zu of %zu edges are convex hull (Delaunay) edges (%.2f%%)\n", common,
              front_edges.size(), 100 * ratio);
  EXPECT_GT(ratio, 0.97);
  EXPECT_GT(r.worst_angle, 15.0);
}

TEST(BoundaryFront, SphereCoarseInput)
{
  const Boundary_surface s = icosphere(1); // 42 vertices: many nodes per input face
  std::vector<Boundary_node> nodes;
  add_patch_darts(s, nodes, 0.15, M3::Identity(), 11);
  const Constant_field field;
  const Boundary_front f = build_boundary_front(s, nodes, field);
  const Report r = check_front(s, nodes, f, field, 2, 0.05);
  print("icosahedron x4, coarse input", s, r, f);
  EXPECT_GT(r.nodes, 300u);
}

TEST(BoundaryFront, CylinderLoopsWithoutCorners)
{
  const Boundary_surface s = cylinder_surface(64, 6);
  auto nodes = curve_nodes(s, 0.35);
  add_patch_darts(s, nodes, 0.35);
  std::size_t corners = 0, curve = 0;
  for(const auto& n : nodes) {
    corners += n.dimension == 0;
    curve += n.dimension == 1;
  }
  EXPECT_EQ(corners, 0u);
  const Constant_field field;
  const Boundary_front f = build_boundary_front(s, nodes, field);
  const Report r = check_front(s, nodes, f, field, 2, 0.05);
  print("cylinder 64, loops without corners", s, r, f);
  EXPECT_EQ(f.feature_edges.size(), curve); // two closed chains: as many edges as nodes
  EXPECT_GT(f.removed_vertices, 100u);

  // the same with an anisotropic metric (long along the axis)
  const Constant_field axial(Metric_3::from_directions_and_sizes(M3::Identity(), V3(0.25, 0.25, 1.0)));
  const Boundary_front fa = build_boundary_front(s, nodes, axial);
  const Report ra = check_front(s, nodes, fa, axial, 2, 0.05);
  print("cylinder 64, axial metric 1:4", s, ra, fa);
}

TEST(BoundaryFront, LPrismFineInputNonConvex)
{
  const Boundary_surface s = l_prism_surface(10); // cells 0.1: many input vertices to remove
  auto nodes = curve_nodes(s, 0.3, M3::Identity(), 1.0);
  add_patch_darts(s, nodes, 0.3);
  const Constant_field field;
  const Boundary_front f = build_boundary_front(s, nodes, field);
  const Report r = check_front(s, nodes, f, field);
  print("L prism, fine input", s, r, f);
  EXPECT_NEAR(r.volume, 3.0, 1e-9);
  EXPECT_GT(f.removed_vertices, 500u);

  // a varying anisotropic metric: small near x = 0, large near x = 2, 1:3 between x and y
  auto size = [](const K::Point_3& p) {
    const double h = 0.1 + 0.2 * p.x();
    return Metric_3::from_directions_and_sizes(M3::Identity(), V3(h, 3 * h, h)).matrix();
  };
  const CGAL::Function_metric_field_3<K, decltype(size)> varying(size);
  const Boundary_front fv = build_boundary_front(s, nodes, varying);
  const Report rv = check_front(s, nodes, fv, varying);
  print("L prism, varying metric", s, rv, fv);
}

TEST(BoundaryFront, LPrismCoarseInputDenseNodes)
{
  const Boundary_surface s = l_prism_surface(1); // one cell per unit: large input triangles
  auto nodes = curve_nodes(s, 0.12, M3::Identity(), 1.0, 5);
  add_patch_darts(s, nodes, 0.12, M3::Identity(), 13);
  const Constant_field field;
  const Boundary_front f = build_boundary_front(s, nodes, field);
  const Report r = check_front(s, nodes, f, field);
  print("L prism, coarse input, dense nodes", s, r, f);
  EXPECT_GT(r.nodes, 500u);
}

TEST(BoundaryFront, TorusGenusOne)
{
  const Boundary_surface s = torus_surface(1, 0.4, 96, 32);
  std::vector<Boundary_node> nodes;
  add_patch_darts(s, nodes, 0.15);
  const Constant_field field;
  const Boundary_front f = build_boundary_front(s, nodes, field);
  const Report r = check_front(s, nodes, f, field, 0, 0.05);
  print("torus, fine input", s, r, f);
}

// Many random node sets (spacing, jitter, seeds, metrics) on every kind of
// surface. `angle_first`: the order of the draws for the metric's rotation
// (false: axis z, y, x then angle, as GCC evaluated the arguments of the
// original one-line expression; true: angle then x, y, z, as clang did).
void randomized_robustness(bool angle_first)
{
  struct Case {
    const char* name;
    Boundary_surface s;
    int euler;
    double volume_tolerance;
  };
  std::vector<Case> cases = {
      {"cube 3", cube_surface(3), 2, 1e-9},
      {"L prism 5", l_prism_surface(5), 2, 1e-9},
      {"thin slab", voxel_surface(10, 10, 1, 0.1, [](int, int, int) { return true; }), 2, 1e-9},
      {"cylinder 48", cylinder_surface(48, 4), 2, 0.1},
      {"sphere 3", icosphere(3), 2, 0.1},
      {"torus", torus_surface(1, 0.4, 48, 16), 0, 0.35}, // coarse nodes on a thin tube: chords lose volume
      // tips and thin parts the nodes are too coarse for: the front keeps input vertices there
      {"spiky sphere", spiky_sphere(), 2, 0.35},
      {"bumpy sphere", bumpy_sphere(), 2, 0.35},
      // 2 to 4 nodes around a tube of radius 0.12: the cross-section is a
      // triangle or a square (41 % to 64 % of the disk's area)
      {"thin torus", torus_surface(1, 0.12, 64, 12), 0, 0.75},
  };
  std::mt19937 rng(2026);
  std::uniform_real_distribution<double> u(0, 1);
  int runs = 0;
  double worst = 180;
  for(const Case& c : cases)
    for(int k = 0; k < 6; ++k) {
      const double h = 0.12 + 0.3 * u(rng);
      const double ratio = k % 2 ? 1.0 : 1 + 3 * u(rng); // 1:1 or up to 1:4
      // Explicit draw order: a call's arguments are evaluated in an
      // unspecified order (GCC and clang differ), and the cases must not
      // depend on the compiler.
      double angle = 0, axis_x = 0, axis_y = 0, axis_z = 0;
      if(angle_first) {
        angle = u(rng) * pi;
        axis_x = u(rng), axis_y = u(rng), axis_z = u(rng);
      } else {
        axis_z = u(rng), axis_y = u(rng), axis_x = u(rng);
        angle = u(rng) * pi;
      }
      const Metric_3 metric = Metric_3::from_directions_and_sizes(
          Eigen::AngleAxisd(angle, V3(axis_x, axis_y, axis_z).normalized()).toRotationMatrix(),
          V3(h, h / ratio, h));
      const M3 q = metric.Q();
      auto nodes = curve_nodes(c.s, 1.0, q, u(rng), unsigned(k + 1));
      add_patch_darts(c.s, nodes, 0.9, q, unsigned(100 + k));
      const Constant_field field(metric);
      SCOPED_TRACE(std::string(c.name) + " run " + std::to_string(k) + " h " + std::to_string(h) + " ratio " +
                   std::to_string(ratio));
      Boundary_front f;
      try {
        f = build_boundary_front(c.s, nodes, field);
      } catch(const std::exception& e) {
        ADD_FAILURE() << "threw: " << e.what();
        continue;
      }
      const Report r = check_front(c.s, nodes, f, field, c.euler, c.volume_tolerance);
      worst = std::min(worst, r.worst_metric_angle);
      std::printf("[front]   %s run %d: nodes %zu, worst metric angle %.1f, non-Delaunay %zu, fallbacks %zu, unstick %zu, "
                  "added %zu, repair rounds %d\n",
                  c.name, k, r.nodes, r.worst_metric_angle, r.non_delaunay, f.fallback_retriangulations, f.unstick_flips,
                  f.added_nodes.size(), f.repair_rounds);
      ++runs;
    }
  std::printf("[front] randomized: %d runs, worst metric angle %.1f deg\n", runs, worst);
}

TEST(BoundaryFront, RandomizedRobustness) { randomized_robustness(false); }

// Known failure, found when the suite was first built with clang: with the
// other draw order, "torus run 4" (h 0.406, ratio 1.35) throws "cannot
// remove 1 surface vertices that are not nodes without making the surface
// non-manifold or folding it" (vertex (0.991, -0.131, -0.4), inside a
// patch). A clear refusal, not a crash, but the input is valid: vertex
// removal needs another way out (e.g. an edge flip around the vertex first).
TEST(BoundaryFront, RandomizedRobustnessOtherDrawOrder) { randomized_robustness(true); }

// Larger inputs: a coarse input with ~20k nodes (point location and
// insertion), and a 40k-vertex input with ~5k nodes (vertex removal).
TEST(BoundaryFront, Scale)
{
  {
    const Boundary_surface s = cube_surface(1);
    const auto nodes = cube_grid_nodes(s, 60, 1.0);
    const Constant_field field;
    const Boundary_front f = build_boundary_front(s, nodes, field);
    const Report r = check_front(s, nodes, f, field);
    print("cube, coarse input, 20k nodes", s, r, f); // time is printed, not tested (benchmarks measure it)
  }
  {
    const Boundary_surface s = icosphere(6);
    std::vector<Boundary_node> nodes;
    add_patch_darts(s, nodes, 0.05);
    const Constant_field field;
    const Boundary_front f = build_boundary_front(s, nodes, field);
    const Report r = check_front(s, nodes, f, field, 2, 0.01);
    print("sphere, 40k-vertex input", s, r, f);
  }
}

TEST(BoundaryFront, PolyhedralDomainAdapter)
{
  typedef CGAL::Mesh_polyhedron_3<K>::type Polyhedron;
  typedef CGAL::Polyhedral_mesh_domain_with_features_3<K> Domain;
  for(int reversed = 0; reversed < 2; ++reversed) {
    Polyhedron poly;
    CGAL::make_hexahedron(K::Point_3(0, 0, 0), K::Point_3(1, 0, 0), K::Point_3(1, 1, 0), K::Point_3(0, 1, 0),
                          K::Point_3(0, 1, 1), K::Point_3(0, 0, 1), K::Point_3(1, 0, 1), K::Point_3(1, 1, 1), poly);
    CGAL::Polygon_mesh_processing::triangulate_faces(poly);
    if(reversed)
      CGAL::Polygon_mesh_processing::reverse_face_orientations(poly);
    Domain domain(poly);
    domain.detect_features(60);
    const Boundary_surface s = boundary_surface_from_polyhedral_domain(domain);
    EXPECT_EQ(s.points.size(), 8u);
    EXPECT_EQ(s.triangles.size(), 12u);
    EXPECT_EQ(s.feature_edges.size(), 12u);
    EXPECT_EQ(std::set<int>(s.patches.begin(), s.patches.end()).size(), 6u);
    EXPECT_NEAR(surface_volume(s), 1.0, 1e-12);
    auto nodes = curve_nodes(s, 0.25);
    add_patch_darts(s, nodes, 0.25);
    const Constant_field field;
    const Boundary_front f = build_boundary_front(s, nodes, field);
    const Report r = check_front(s, nodes, f, field);
    print(reversed ? "polyhedral domain (inward input)" : "polyhedral domain", s, r, f);
  }
}

// The checker itself: each kind of broken front must be reported.
TEST(BoundaryFront, CheckerDetectsBrokenFronts)
{
  const Boundary_surface s = cube_surface(2);
  const auto nodes = cube_grid_nodes(s, 4, 1.0);
  const Constant_field field;
  const Boundary_front good = build_boundary_front(s, nodes, field);
  auto failures = [&](const Boundary_front& f) {
    ::testing::TestPartResultArray results;
    {
      ::testing::ScopedFakeTestPartResultReporter reporter(
          ::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD, &results);
      check_front(s, nodes, f, field);
    }
    return results.size();
  };
  EXPECT_EQ(failures(good), 0);
  Boundary_front flipped = good; // one triangle inward
  std::swap(flipped.triangles[0][1], flipped.triangles[0][2]);
  EXPECT_GT(failures(flipped), 0);
  Boundary_front missing = good; // a hole
  missing.triangles.pop_back();
  missing.patches.pop_back();
  EXPECT_GT(failures(missing), 0);
  Boundary_front retagged = good; // a triangle on the wrong patch
  retagged.patches[0] = retagged.patches[0] == s.patches[0] ? s.patches.back() : s.patches[0];
  EXPECT_GT(failures(retagged), 0);
  Boundary_front no_feature = good; // a curve chain lost
  no_feature.feature_edges.pop_back();
  no_feature.feature_edge_sources.pop_back();
  EXPECT_GT(failures(no_feature), 0);
  Boundary_front wrong_source = good; // a feature edge attributed to another input edge
  wrong_source.feature_edge_sources[0] = (wrong_source.feature_edge_sources[0] + 5) % int(s.feature_edges.size());
  EXPECT_GT(failures(wrong_source), 0);
  Boundary_front not_delaunay = good; // flip one interior edge of a patch: metric quality checks see it
  {
    std::map<std::pair<int, int>, int> dir;
    for(std::size_t i = 0; i < good.triangles.size(); ++i)
      for(int k = 0; k < 3; ++k)
        dir[{good.triangles[i][k], good.triangles[i][(k + 1) % 3]}] = int(i);
    for(const auto& e : dir) {
      const int a = e.first.first, b = e.first.second, f1 = e.second, f2 = dir.at({b, a});
      if(good.patches[f1] != good.patches[f2] || nodes[a].dimension != 2 || nodes[b].dimension != 2)
        continue;
      int c = -1, d = -1;
      for(int v : good.triangles[f1])
        if(v != a && v != b)
          c = v;
      for(int v : good.triangles[f2])
        if(v != a && v != b)
          d = v;
      not_delaunay.triangles[f1] = {{a, d, c}};
      not_delaunay.triangles[f2] = {{d, b, c}};
      break;
    }
  }
  EXPECT_EQ(non_delaunay_edges(nodes, good, field), 0u);
  EXPECT_GT(non_delaunay_edges(nodes, not_delaunay, field), 0u);
}

TEST(BoundaryFront, InvalidInput)
{
  const Boundary_surface s = cube_surface(2);
  const auto good = cube_grid_nodes(s, 4, 0);
  const Constant_field field;
  ASSERT_NO_THROW(build_boundary_front(s, good, field));

  auto off = good;
  const int top = patch_at(s, V3(0.5, 0.5, 1)), left = patch_at(s, V3(0, 0.5, 0.5));
  ASSERT_NE(top, left);
  off.push_back({{{0.5, 0.5, 0.6}}, 2, top}); // inside the cube
  EXPECT_THROW(build_boundary_front(s, off, field), Invalid_input);

  auto wrong_patch = good;
  wrong_patch.push_back({{{0.4, 0.45, 1.0}}, 2, left}); // on z=1 but tagged x=0
  EXPECT_THROW(build_boundary_front(s, wrong_patch, field), Invalid_input);

  auto unknown_patch = good;
  unknown_patch.push_back({{{0.4, 0.45, 1.0}}, 2, 424242});
  EXPECT_THROW(build_boundary_front(s, unknown_patch, field), Invalid_input);

  auto not_on_curve = good;
  not_on_curve.push_back({{{0.4, 0.45, 1.0}}, 1, -1}); // a face point claimed on a curve
  EXPECT_THROW(build_boundary_front(s, not_on_curve, field), Invalid_input);

  auto not_a_corner = good;
  not_a_corner.push_back({{{0.4, 0.45, 1.0}}, 0, -1});
  EXPECT_THROW(build_boundary_front(s, not_a_corner, field), Invalid_input);

  std::vector<Boundary_node> missing_corner;
  for(const auto& n : good)
    if(!(n.dimension == 0 && n.point[0] == 0 && n.point[1] == 0 && n.point[2] == 0))
      missing_corner.push_back(n);
  ASSERT_EQ(missing_corner.size(), good.size() - 1);
  EXPECT_THROW(build_boundary_front(s, missing_corner, field), Invalid_input);

  auto duplicate = good;
  duplicate.push_back(good.back());
  EXPECT_THROW(build_boundary_front(s, duplicate, field), Invalid_input);

  auto bad_dimension = good;
  bad_dimension.back().dimension = 3;
  EXPECT_THROW(build_boundary_front(s, bad_dimension, field), Invalid_input);

  Boundary_surface open = s;
  open.triangles.pop_back();
  open.patches.pop_back();
  EXPECT_THROW(build_boundary_front(open, good, field), Invalid_input);
}

TEST(BoundaryFront, LoopWithTwoNodesGetsAddedNodes)
{
  // A closed curve needs at least 3 nodes: two nodes would need the same edge
  // twice. The front keeps an input vertex of each loop as a curve node.
  const Boundary_surface s = cylinder_surface(32, 3);
  std::vector<Boundary_node> nodes;
  for(const double z : {-1.0, 1.0})
    for(const double a : {0.1, 0.1 + pi})
      nodes.push_back({{{std::cos(a), std::sin(a), z}}, 1, -1});
  // Project onto the input polygon: the nodes must be on the feature edges.
  for(auto& n : nodes) {
    const double a = std::atan2(n.point[1], n.point[0]);
    const double step = 2 * pi / 32;
    const int i = int(std::floor(a / step));
    const double t = (a - i * step) / step;
    const V3 p0(std::cos(i * step), std::sin(i * step), n.point[2]),
        p1(std::cos((i + 1) * step), std::sin((i + 1) * step), n.point[2]);
    n.point = arr((1 - t) * p0 + t * p1);
  }
  add_patch_darts(s, nodes, 0.5);
  const Constant_field field;
  const Boundary_front f = build_boundary_front(s, nodes, field);
  // three nodes per loop: a prism, whose side triangles' centroids are closer
  // to the caps than to the side
  const Report r = check_front(s, nodes, f, field, 2, 0.7, false);
  print("cylinder, two nodes per closed curve", s, r, f);
  std::set<double> loops_with_added_node;
  for(const Boundary_node& a : f.added_nodes)
    if(a.dimension == 1)
      loops_with_added_node.insert(a.point[2]);
  EXPECT_EQ(loops_with_added_node.size(), 2u) << "each loop gets a curve node";
}

} // namespace
