// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_IMPROVE_MUTABLE_TET_MESH_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_IMPROVE_MUTABLE_TET_MESH_H

#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

// The editable tet mesh the improver works on: tets in slots (a removed tet
// frees its slot, new tets reuse freed slots, last freed first), the tets
// around each vertex, and the protected entities that no operation may
// change: boundary and interface faces, their edges, feature edges, and the
// vertices that must not move. Everything here is deterministic: the order
// of the vertex-to-tet lists only depends on the sequence of operations.

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {
namespace improve {

typedef CGAL::Exact_predicates_inexact_constructions_kernel::Point_3 Exact_point;

/// exact orientation of four points given by double coordinates
inline CGAL::Orientation exact_orientation(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                                           const Eigen::Vector3d& p2, const Eigen::Vector3d& p3)
{
  return CGAL::orientation(Exact_point(p0[0], p0[1], p0[2]), Exact_point(p1[0], p1[1], p1[2]),
                           Exact_point(p2[0], p2[1], p2[2]), Exact_point(p3[0], p3[1], p3[2]));
}

/// parity (0 even, 1 odd) of the permutation that takes `tet` to `(a, b, c, d)`
/// (the four must be the tet's vertices)
inline int permutation_parity(const std::array<int, 4>& tet, int a, int b, int c, int d)
{
  const int wanted[4] = {a, b, c, d};
  int position[4];
  for(int i = 0; i < 4; ++i)
    for(int j = 0; j < 4; ++j)
      if(tet[j] == wanted[i])
        position[i] = j;
  int inversions = 0;
  for(int i = 0; i < 4; ++i)
    for(int j = i + 1; j < 4; ++j)
      if(position[i] > position[j])
        ++inversions;
  return inversions & 1;
}

inline std::uint64_t edge_key(int a, int b)
{
  if(a > b)
    std::swap(a, b);
  return (std::uint64_t(std::uint32_t(a)) << 32) | std::uint32_t(b);
}

struct Face_key {
  std::array<int, 3> v;
  Face_key(int a, int b, int c) : v{{a, b, c}} { std::sort(v.begin(), v.end()); }
  bool operator==(const Face_key& o) const { return v == o.v; }
  bool operator<(const Face_key& o) const { return v < o.v; }
};

struct Face_key_hash {
  std::size_t operator()(const Face_key& f) const
  {
    std::uint64_t h = std::uint64_t(std::uint32_t(f.v[0])) * 0x9E3779B97F4A7C15ull;
    h ^= std::uint64_t(std::uint32_t(f.v[1])) + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2);
    h ^= std::uint64_t(std::uint32_t(f.v[2])) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    return std::size_t(h);
  }
};

struct Edge_key_hash {
  std::size_t operator()(std::uint64_t k) const { return std::size_t(k * 0x9E3779B97F4A7C15ull ^ (k >> 29)); }
};

/// The mesh being improved.
class Mutable_tet_mesh {
public:
  typedef std::array<int, 4> Tet;

  /// Copies `mesh` and classifies its entities. Protected faces: the listed
  /// triangles, the faces of a single tet (domain boundary, also when the
  /// mesh lists no triangles) and the faces between tets of different
  /// subdomains. Protected edges: the edges of protected faces and the
  /// feature edges. Fixed vertices: the vertices of protected faces and
  /// feature edges, and the corners.
  explicit Mutable_tet_mesh(const Indexed_tet_mesh_3& mesh)
  {
    const std::size_t np = mesh.points.size();
    points.resize(np);
    for(std::size_t i = 0; i < np; ++i)
      points[i] = Eigen::Vector3d(mesh.points[i][0], mesh.points[i][1], mesh.points[i][2]);
    if(!mesh.tet_refs.empty() && mesh.tet_refs.size() != mesh.tets.size())
      throw Invalid_input("improve_mesh: tet_refs is not parallel to tets");
    tets = mesh.tets;
    refs = mesh.tet_refs;
    refs.resize(tets.size(), 0);
    alive.assign(tets.size(), 1);
    stamp.assign(tets.size(), 0);
    vertex_tets.assign(np, {});
    for(std::size_t t = 0; t < tets.size(); ++t)
      for(int v : tets[t]) {
        if(v < 0 || std::size_t(v) >= np)
          throw Invalid_input("improve_mesh: tet " + std::to_string(t) + " references a missing point");
        vertex_tets[std::size_t(v)].push_back(int(t));
      }

    fixed.assign(np, 0);
    auto protect_face = [&](int a, int b, int c) {
      protected_faces.insert(Face_key(a, b, c));
      protected_edges.insert(edge_key(a, b));
      protected_edges.insert(edge_key(b, c));
      protected_edges.insert(edge_key(c, a));
      fixed[std::size_t(a)] = fixed[std::size_t(b)] = fixed[std::size_t(c)] = 1;
    };
    for(const auto& f : mesh.triangles) {
      for(int v : f)
        if(v < 0 || std::size_t(v) >= np)
          throw Invalid_input("improve_mesh: a triangle references a missing point");
      protect_face(f[0], f[1], f[2]);
    }
    // Faces of one tet, or of two tets of different subdomains.
    struct Entry {
      Face_key key;
      int tet;
      bool operator<(const Entry& o) const { return key < o.key || (key == o.key && tet < o.tet); }
    };
    std::vector<Entry> faces;
    faces.reserve(4 * tets.size());
    for(std::size_t t = 0; t < tets.size(); ++t) {
      const Tet& T = tets[t];
      faces.push_back({Face_key(T[1], T[2], T[3]), int(t)});
      faces.push_back({Face_key(T[0], T[2], T[3]), int(t)});
      faces.push_back({Face_key(T[0], T[1], T[3]), int(t)});
      faces.push_back({Face_key(T[0], T[1], T[2]), int(t)});
    }
    std::sort(faces.begin(), faces.end());
    for(std::size_t i = 0; i < faces.size();) {
      std::size_t j = i + 1;
      while(j < faces.size() && faces[j].key == faces[i].key)
        ++j;
      bool is_protected = (j - i != 2);
      if(!is_protected && refs[std::size_t(faces[i].tet)] != refs[std::size_t(faces[i + 1].tet)])
        is_protected = true;
      if(is_protected)
        protect_face(faces[i].key.v[0], faces[i].key.v[1], faces[i].key.v[2]);
      i = j;
    }
    for(const auto& e : mesh.edges) {
      if(e[0] < 0 || std::size_t(e[0]) >= np || e[1] < 0 || std::size_t(e[1]) >= np)
        throw Invalid_input("improve_mesh: a feature edge references a missing point");
      protected_edges.insert(edge_key(e[0], e[1]));
      fixed[std::size_t(e[0])] = fixed[std::size_t(e[1])] = 1;
    }
    for(int c : mesh.corners)
      if(c >= 0 && std::size_t(c) < np)
        fixed[std::size_t(c)] = 1;
  }

  /// writes the tets (in slot order) and the points back
  void write_back(Indexed_tet_mesh_3& mesh) const
  {
    for(std::size_t i = 0; i < points.size(); ++i)
      mesh.points[i] = {{points[i][0], points[i][1], points[i][2]}};
    const bool had_refs = !mesh.tet_refs.empty() || mesh.tets.empty();
    mesh.tets.clear();
    mesh.tet_refs.clear();
    for(std::size_t t = 0; t < tets.size(); ++t)
      if(alive[t]) {
        mesh.tets.push_back(tets[t]);
        mesh.tet_refs.push_back(refs[t]);
      }
    if(!had_refs)
      mesh.tet_refs.clear();
  }

  bool is_protected_face(int a, int b, int c) const { return protected_faces.count(Face_key(a, b, c)) != 0; }
  bool is_protected_edge(int a, int b) const { return protected_edges.count(edge_key(a, b)) != 0; }

  static bool has_vertex(const Tet& t, int v) { return t[0] == v || t[1] == v || t[2] == v || t[3] == v; }

  /// the tet other than `t` that has the face (a, b, c), or -1
  int opposite_tet(int t, int a, int b, int c) const
  {
    for(int s : vertex_tets[std::size_t(a)])
      if(s != t && has_vertex(tets[std::size_t(s)], b) && has_vertex(tets[std::size_t(s)], c))
        return s;
    return -1;
  }

  /// the vertex of tet `t` that is none of a, b, c
  int fourth_vertex(int t, int a, int b, int c) const
  {
    for(int v : tets[std::size_t(t)])
      if(v != a && v != b && v != c)
        return v;
    return -1;
  }

  /// true if some tet has both vertices
  bool are_connected(int a, int b) const
  {
    const std::vector<int>& list =
        vertex_tets[std::size_t(a)].size() <= vertex_tets[std::size_t(b)].size() ? vertex_tets[std::size_t(a)]
                                                                               : vertex_tets[std::size_t(b)];
    const int other = vertex_tets[std::size_t(a)].size() <= vertex_tets[std::size_t(b)].size() ? b : a;
    for(int s : list)
      if(has_vertex(tets[std::size_t(s)], other))
        return true;
    return false;
  }

  /// The ring of the edge (a, b): ring vertices p_0 .. p_{n-1} and the tets
  /// t_i = (a, b, p_i, p_{i+1}) (up to an even permutation), i.e. every
  /// `orientation(a, b, p_i, p_{i+1})` is positive. Returns false if the
  /// tets around the edge do not form one closed cycle (a boundary edge) or
  /// if there are more than `max_size` of them.
  bool edge_ring(int a, int b, std::size_t max_size, std::vector<int>& ring, std::vector<int>& ring_tets) const
  {
    ring.clear();
    ring_tets.clear();
    std::vector<std::array<int, 3>> links; // (x, y, tet) with (a, b, x, y) positive
    for(int s : vertex_tets[std::size_t(a)]) {
      const Tet& T = tets[std::size_t(s)];
      if(!has_vertex(T, b))
        continue;
      int x = -1, y = -1;
      for(int v : T)
        if(v != a && v != b) {
          if(x < 0)
            x = v;
          else
            y = v;
        }
      if(permutation_parity(T, a, b, x, y) != 0)
        std::swap(x, y);
      links.push_back({{x, y, s}});
      if(links.size() > max_size)
        return false;
    }
    const std::size_t n = links.size();
    if(n < 3)
      return false;
    // Follow x -> y from the first link (the vertex_tets order is deterministic).
    std::vector<char> used(n, 0);
    used[0] = 1;
    ring.push_back(links[0][0]);
    ring_tets.push_back(links[0][2]);
    int current = links[0][1];
    for(std::size_t k = 1; k < n; ++k) {
      std::size_t found = n;
      for(std::size_t i = 0; i < n; ++i)
        if(!used[i] && links[i][0] == current) {
          if(found != n)
            return false; // two successors: not a simple ring
          found = i;
        }
      if(found == n)
        return false;
      used[found] = 1;
      ring.push_back(current);
      ring_tets.push_back(links[found][2]);
      current = links[found][1];
    }
    return current == ring[0];
  }

  /// Removes the tets `old_tets` and adds `new_tets`, all with subdomain
  /// `ref`. Returns the slots of the new tets.
  std::vector<int> replace(const std::vector<int>& old_tets, const std::vector<Tet>& new_tets, int ref)
  {
    for(int t : old_tets) {
      for(int v : tets[std::size_t(t)]) {
        std::vector<int>& list = vertex_tets[std::size_t(v)];
        auto it = std::find(list.begin(), list.end(), t);
        CGAL_assertion(it != list.end());
        *it = list.back();
        list.pop_back();
      }
      alive[std::size_t(t)] = 0;
      free_slots.push_back(t);
    }
    std::vector<int> created;
    created.reserve(new_tets.size());
    for(const Tet& T : new_tets) {
      int slot;
      if(!free_slots.empty()) {
        slot = free_slots.back();
        free_slots.pop_back();
        tets[std::size_t(slot)] = T;
        refs[std::size_t(slot)] = ref;
        alive[std::size_t(slot)] = 1;
        ++stamp[std::size_t(slot)];
      } else {
        slot = int(tets.size());
        tets.push_back(T);
        refs.push_back(ref);
        alive.push_back(1);
        stamp.push_back(0);
      }
      for(int v : T)
        vertex_tets[std::size_t(v)].push_back(slot);
      created.push_back(slot);
    }
    return created;
  }

  std::size_t number_of_alive_tets() const
  {
    return std::size_t(std::count(alive.begin(), alive.end(), char(1)));
  }

  std::vector<Eigen::Vector3d> points;
  std::vector<Tet> tets;
  std::vector<int> refs;
  std::vector<char> alive;
  /// incremented each time a slot receives a new tet or its geometry changes
  std::vector<unsigned> stamp;
  std::vector<int> free_slots;
  std::vector<std::vector<int>> vertex_tets;
  std::unordered_set<Face_key, Face_key_hash> protected_faces;
  std::unordered_set<std::uint64_t, Edge_key_hash> protected_edges;
  std::vector<char> fixed;
};

} // namespace improve
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_IMPROVE_MUTABLE_TET_MESH_H
