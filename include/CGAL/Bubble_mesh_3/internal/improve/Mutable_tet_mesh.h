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
#include <functional>
#include <limits>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

// The editable tet mesh the improver works on: tets in slots (a removed tet
// frees its slot, new tets reuse freed slots, last freed first), the tets
// around each vertex, and the protected entities that no operation may
// change: boundary and interface faces, their edges, feature edges, and the
// vertices that must not move or may only slide in a plane or along a line
// (`Vertex_constraint`). Everything here is deterministic: the order of the
// vertex-to-tet lists only depends on the sequence of operations.

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

/// How a vertex may move. `plane`: every protected face around it lies
/// exactly in one plane (exact coplanarity of the input doubles), all of one
/// patch, forming one closed fan, and no feature edge or corner touches it:
/// it may slide in that plane. `line`: it is on exactly two feature edges,
/// exactly collinear, and every protected face around it lies in a plane
/// through that line: it may slide along the line, between its two feature
/// neighbours. Either way the union of the protected faces (the boundary and
/// the interfaces as point sets) is unchanged by a move that keeps every tet
/// positively oriented, up to the rounding of the projected coordinates
/// (none when the plane or line is axis-parallel: the constant coordinates
/// are copied).
///
/// (3) *surface*: like (1) but the fan is not planar (a curved patch), and a
/// surface projection was given: the vertex slides in the tangent plane of
/// its fan, every candidate projected onto the true surface of its patch.
/// The boundary then changes (the triangles stay chords of the surface).
///
/// (4) *curve*: the vertex has two feature neighbours on the same curve (edge
/// ref) but is not on a straight line through them (a curved feature curve),
/// and a curve projection was given: it slides along the chord direction of
/// its neighbours, every candidate projected onto the true curve, strictly
/// between its two neighbours.
struct Vertex_constraint {
  enum Kind { free, plane, line, fixed, surface, curve };
  Kind kind = free;
  /// surface: the patch (triangle ref) of the fan; curve: the curve (edge ref)
  int patch = 0;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  /// plane: unit normal; line: unit direction
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();
  /// plane: an orthonormal basis of the plane; line: `tangent[0] == axis`
  Eigen::Vector3d tangent[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  /// plane: the coordinate held constant if the plane is axis-parallel, else
  /// -1; line: the coordinate that varies if the line is axis-parallel, else -1
  int exact_axis = -1;
  /// line: the two feature neighbours (the move stays strictly between them)
  int ends[2] = {-1, -1};
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
  /// If `ref_0_is_exterior`, tets of ref 0 are *passive*: padding outside
  /// the domain (a C3T3's cells outside the complex), kept positively
  /// oriented by every move but never flipped or measured.
  /// closest point of patch `ref` to a point (false: unknown, no move)
  typedef std::function<bool(int ref, const std::array<double, 3>& p, std::array<double, 3>& closest)>
      Surface_projection;

  /// With a `projection`, vertices inside one curved patch get the
  /// `surface` constraint instead of staying fixed; with a
  /// `curve_projection` (same signature, the ref is an edge ref), vertices
  /// inside a curved feature curve get the `curve` constraint.
  explicit Mutable_tet_mesh(const Indexed_tet_mesh_3& mesh, bool ref_0_is_exterior = false,
                            Surface_projection projection = {}, Surface_projection curve_projection = {})
    : exterior_ref_0(ref_0_is_exterior), surface_projection(std::move(projection)),
      curve_projection(std::move(curve_projection))
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
    removed.assign(np, 0);
    for(std::size_t t = 0; t < tets.size(); ++t)
      for(int v : tets[t]) {
        if(v < 0 || std::size_t(v) >= np)
          throw Invalid_input("improve_mesh: tet " + std::to_string(t) + " references a missing point");
        vertex_tets[std::size_t(v)].push_back(int(t));
      }

    fixed.assign(np, 0);
    // protected faces with their patch (the triangle ref, or `unlisted`)
    std::vector<std::pair<Face_key, int>> face_patches;
    const int unlisted = std::numeric_limits<int>::min();
    int current_patch = unlisted;
    auto protect_face = [&](int a, int b, int c) {
      if(protected_faces.insert(Face_key(a, b, c)).second)
        face_patches.push_back({Face_key(a, b, c), current_patch});
      protected_edges.insert(edge_key(a, b));
      protected_edges.insert(edge_key(b, c));
      protected_edges.insert(edge_key(c, a));
      fixed[std::size_t(a)] = fixed[std::size_t(b)] = fixed[std::size_t(c)] = 1;
    };
    for(std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      const auto& f = mesh.triangles[i];
      for(int v : f)
        if(v < 0 || std::size_t(v) >= np)
          throw Invalid_input("improve_mesh: a triangle references a missing point");
      current_patch = i < mesh.triangle_refs.size() ? mesh.triangle_refs[i] : 0;
      protect_face(f[0], f[1], f[2]);
      listed_index.emplace(Face_key(f[0], f[1], f[2]), i);
    }
    current_patch = unlisted;
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
    feature_edge_list = mesh.edges;
    feature_edge_list_refs = mesh.edge_refs;
    feature_edge_list_refs.resize(feature_edge_list.size(), 0);
    for(std::size_t i = 0; i < mesh.edges.size(); ++i)
      feature_edge_ref.emplace(edge_key(mesh.edges[i][0], mesh.edges[i][1]), feature_edge_list_refs[i]);
    for(const auto& e : mesh.edges) {
      if(e[0] < 0 || std::size_t(e[0]) >= np || e[1] < 0 || std::size_t(e[1]) >= np)
        throw Invalid_input("improve_mesh: a feature edge references a missing point");
      protected_edges.insert(edge_key(e[0], e[1]));
      feature_edges.insert(edge_key(e[0], e[1]));
      fixed[std::size_t(e[0])] = fixed[std::size_t(e[1])] = 1;
    }
    for(int c : mesh.corners)
      if(c >= 0 && std::size_t(c) < np)
        fixed[std::size_t(c)] = 1;
    classify_boundary_vertices(mesh, face_patches);
    listed = mesh.triangles;
    has_duplicate_triangles = listed_index.size() != listed.size();
    listed_refs = mesh.triangle_refs;
    listed_refs.resize(listed.size(), 0);
  }

  bool is_passive(int t) const { return exterior_ref_0 && refs[std::size_t(t)] == 0; }

  /// The outward normal of the boundary at `v`: the sum of the area vectors
  /// of the protected faces at `v`, each taken outward from its active tet
  /// (zero where the faces are interfaces between active tets).
  Eigen::Vector3d boundary_normal(int v) const
  {
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    for(int t : vertex_tets[std::size_t(v)]) {
      if(is_passive(t))
        continue;
      const Tet& T = tets[std::size_t(t)];
      for(int k = 0; k < 4; ++k) {
        if(T[std::size_t(k)] == v)
          continue;
        // the face opposite T[k] contains v
        int f[3];
        int j = 0;
        for(int i = 0; i < 4; ++i)
          if(i != k)
            f[j++] = T[std::size_t(i)];
        if(!protected_faces.count(Face_key(f[0], f[1], f[2])))
          continue;
        const Eigen::Vector3d& a = points[std::size_t(f[0])];
        Eigen::Vector3d area = 0.5 * (points[std::size_t(f[1])] - a).cross(points[std::size_t(f[2])] - a);
        if(area.dot(points[std::size_t(T[std::size_t(k)])] - a) > 0)
          area = -area;
        n += area;
      }
    }
    return n;
  }

  /// `x` moved onto the plane or line of the constraint of `v` (unchanged
  /// for a free vertex); a line point is clamped strictly between the line's
  /// current end vertices
  Eigen::Vector3d project(int v, const Eigen::Vector3d& x) const
  {
    const Vertex_constraint& c = constraint[std::size_t(v)];
    if(c.kind == Vertex_constraint::curve) {
      std::array<double, 3> closest;
      if(!curve_projection || !curve_projection(c.patch, {{x[0], x[1], x[2]}}, closest))
        return points[std::size_t(v)];
      const Eigen::Vector3d y(closest[0], closest[1], closest[2]);
      // strictly between the neighbours along their chord
      const Eigen::Vector3d a = points[std::size_t(c.ends[0])], b = points[std::size_t(c.ends[1])];
      const double t = (y - a).dot(b - a) / (b - a).squaredNorm();
      return t > 0.01 && t < 0.99 ? y : points[std::size_t(v)];
    }
    if(c.kind == Vertex_constraint::surface) {
      std::array<double, 3> closest;
      if(!surface_projection || !surface_projection(c.patch, {{x[0], x[1], x[2]}}, closest))
        return points[std::size_t(v)];
      return Eigen::Vector3d(closest[0], closest[1], closest[2]);
    }
    if(c.kind == Vertex_constraint::plane) {
      Eigen::Vector3d y = x - c.axis * c.axis.dot(x - c.origin);
      if(c.exact_axis >= 0) {
        y[c.exact_axis] = c.origin[c.exact_axis];
      } else {
        // solve the plane equation for the dominant coordinate: the closest
        // double to the plane along that axis
        int k = 0;
        c.axis.cwiseAbs().maxCoeff(&k);
        double sum = 0;
        for(int j = 0; j < 3; ++j)
          if(j != k)
            sum += c.axis[j] * (y[j] - c.origin[j]);
        y[k] = c.origin[k] - sum / c.axis[k];
      }
      return y;
    }
    if(c.kind == Vertex_constraint::line) {
      double t = c.axis.dot(x - c.origin);
      double t0 = c.axis.dot(points[std::size_t(c.ends[0])] - c.origin);
      double t1 = c.axis.dot(points[std::size_t(c.ends[1])] - c.origin);
      if(t0 > t1)
        std::swap(t0, t1);
      const double margin = 0.01 * (t1 - t0);
      t = std::min(std::max(t, t0 + margin), t1 - margin);
      Eigen::Vector3d y = c.origin + t * c.axis;
      if(c.exact_axis >= 0) {
        const double moving = y[c.exact_axis];
        y = c.origin;
        y[c.exact_axis] = moving;
      }
      return y;
    }
    return x;
  }

  /// writes the tets (in slot order) and the points back; vertices added by
  /// edge splits are appended with their refs (`added_point_refs`); vertices
  /// removed by edge collapses are dropped and every index renumbered.
  /// Returns, if a vertex was removed, the new index of each old one (-1:
  /// removed), else an empty vector.
  std::vector<int> write_back(Indexed_tet_mesh_3& mesh) const
  {
    const std::size_t original = mesh.points.size();
    const bool had_point_refs = mesh.point_refs.size() == original && original > 0;
    std::vector<int> point_refs;
    if(had_point_refs) {
      point_refs = mesh.point_refs;
      for(std::size_t i = original; i < points.size(); ++i)
        point_refs.push_back(added_point_refs[i - original]);
    }
    std::vector<int> new_index;
    if(std::find(removed.begin(), removed.end(), char(1)) != removed.end()) {
      new_index.assign(points.size(), -1);
      int next = 0;
      for(std::size_t i = 0; i < points.size(); ++i)
        if(!removed[i])
          new_index[i] = next++;
    }
    auto index = [&new_index](int v) { return new_index.empty() ? v : new_index[std::size_t(v)]; };
    mesh.points.clear();
    mesh.point_refs.clear();
    for(std::size_t i = 0; i < points.size(); ++i)
      if(!removed[i]) {
        mesh.points.push_back({{points[i][0], points[i][1], points[i][2]}});
        if(had_point_refs)
          mesh.point_refs.push_back(point_refs[i]);
      }
    const bool had_refs = !mesh.tet_refs.empty() || mesh.tets.empty();
    mesh.tets.clear();
    mesh.tet_refs.clear();
    for(std::size_t t = 0; t < tets.size(); ++t)
      if(alive[t]) {
        const Tet& T = tets[t];
        mesh.tets.push_back({{index(T[0]), index(T[1]), index(T[2]), index(T[3])}});
        mesh.tet_refs.push_back(refs[t]);
      }
    if(!had_refs)
      mesh.tet_refs.clear();
    if(feature_edges_changed || !new_index.empty()) {
      const bool had_edge_refs = mesh.edge_refs.size() == mesh.edges.size() && !mesh.edges.empty();
      mesh.edges.clear();
      for(const auto& e : feature_edge_list)
        mesh.edges.push_back({{index(e[0]), index(e[1])}});
      if(had_edge_refs)
        mesh.edge_refs = feature_edge_list_refs;
    }
    if(listed != mesh.triangles || !new_index.empty()) { // boundary flips, splits or collapses changed some
      mesh.triangles.clear();
      for(const auto& f : listed)
        mesh.triangles.push_back({{index(f[0]), index(f[1]), index(f[2])}});
      mesh.triangle_refs = listed_refs;
    }
    if(!new_index.empty())
      for(int& c : mesh.corners)
        c = index(c); // corners are never removed
    return new_index;
  }

  bool is_feature_edge(int a, int b) const { return feature_edges.count(edge_key(a, b)) != 0; }

  /// the listed triangle on these vertices (its position), or -1
  int listed_triangle(int a, int b, int c) const
  {
    const auto it = listed_index.find(Face_key(a, b, c));
    return it == listed_index.end() ? -1 : int(it->second);
  }

  /// The patch of a protected boundary face: the ref of its listed triangle,
  /// or `unlisted_patch` for an unlisted one.
  int face_patch(int a, int b, int c) const
  {
    const int i = listed_triangle(a, b, c);
    return i < 0 ? unlisted_patch : listed_refs[std::size_t(i)];
  }
  static constexpr int unlisted_patch = std::numeric_limits<int>::min();

  /// After a boundary flip that replaced the boundary faces `old0`, `old1`
  /// (sharing the edge (a, b)) by `new0`, `new1` (sharing (c, d)), in the
  /// same plane and patch: updates the protected faces and edges and the
  /// listed triangles (each new one takes the slot of an old one, oriented
  /// like it: `new0`, `new1` must be given in the orientation to store).
  void replace_boundary_faces(const std::array<int, 3>& old0, const std::array<int, 3>& old1,
                              const std::array<int, 3>& new0, const std::array<int, 3>& new1, int a, int b, int c,
                              int d)
  {
    const std::array<int, 3>* olds[2] = {&old0, &old1};
    const std::array<int, 3>* news[2] = {&new0, &new1};
    for(int k = 0; k < 2; ++k) {
      const Face_key key_old((*olds[k])[0], (*olds[k])[1], (*olds[k])[2]);
      const Face_key key_new((*news[k])[0], (*news[k])[1], (*news[k])[2]);
      protected_faces.erase(key_old);
      protected_faces.insert(key_new);
      const auto it = listed_index.find(key_old);
      if(it != listed_index.end()) {
        const std::size_t slot = it->second;
        listed_index.erase(it);
        listed[slot] = *news[k];
        listed_index.emplace(key_new, slot);
      }
    }
    protected_edges.erase(edge_key(a, b));
    protected_edges.insert(edge_key(c, d));
  }

  /// Appends a vertex at `x` (an edge split's), with its constraint and its
  /// ref for `write_back()`; returns its index. Its tets come by `replace()`.
  int add_vertex(const Eigen::Vector3d& x, const Vertex_constraint& c, bool is_fixed, int point_ref)
  {
    points.push_back(x);
    vertex_tets.emplace_back();
    fixed.push_back(is_fixed ? 1 : 0);
    removed.push_back(0);
    constraint.push_back(c);
    added_point_refs.push_back(point_ref);
    return int(points.size()) - 1;
  }

  /// After the boundary edge (a, b) was split at `m`: each of its two
  /// listed boundary faces (a, b, p), p = p0, pk, becomes (a, m, p) (in its
  /// slot) and (m, b, p) (appended, same ref), both oriented like it; the
  /// protected faces and edges follow.
  void split_boundary_faces(int a, int b, int m, int p0, int pk)
  {
    for(int p : {p0, pk}) {
      const Face_key old_key(a, b, p);
      const auto it = listed_index.find(old_key);
      CGAL_assertion(it != listed_index.end());
      const std::size_t slot = it->second;
      listed_index.erase(it);
      std::array<int, 3> first = listed[slot], second = listed[slot];
      for(int k = 0; k < 3; ++k) {
        if(first[std::size_t(k)] == b)
          first[std::size_t(k)] = m;
        if(second[std::size_t(k)] == a)
          second[std::size_t(k)] = m;
      }
      listed[slot] = first;
      listed_index.emplace(Face_key(first[0], first[1], first[2]), slot);
      listed.push_back(second);
      listed_refs.push_back(listed_refs[slot]);
      listed_index.emplace(Face_key(second[0], second[1], second[2]), listed.size() - 1);
      protected_faces.erase(old_key);
      protected_faces.insert(Face_key(first[0], first[1], first[2]));
      protected_faces.insert(Face_key(second[0], second[1], second[2]));
      protected_edges.insert(edge_key(m, p));
    }
    protected_edges.erase(edge_key(a, b));
    protected_edges.insert(edge_key(a, m));
    protected_edges.insert(edge_key(m, b));
  }

  /// Before the edge collapse of `v` onto `w` (`v` inside one patch or free,
  /// its star of one subdomain): the boundary faces at `v` given as
  /// `faces` (each (v, x, y)) either contain `w` and go, or become
  /// (w, x, y) in their listed slot, same orientation and ref; the protected
  /// faces and edges follow. `v` is marked removed.
  void collapse_boundary_faces(int v, int w, const std::vector<std::array<int, 3>>& faces)
  {
    for(const auto& f : faces) {
      const Face_key old_key(f[0], f[1], f[2]);
      protected_faces.erase(old_key);
      for(int x : f)
        if(x != v)
          protected_edges.erase(edge_key(v, x));
      const auto it = listed_index.find(old_key);
      const bool has_w = f[0] == w || f[1] == w || f[2] == w;
      if(it != listed_index.end()) {
        const std::size_t slot = it->second;
        listed_index.erase(it);
        if(has_w) { // the last listed triangle takes its slot
          const std::size_t last = listed.size() - 1;
          if(slot != last) {
            listed[slot] = listed[last];
            listed_refs[slot] = listed_refs[last];
            listed_index[Face_key(listed[slot][0], listed[slot][1], listed[slot][2])] = slot;
          }
          listed.pop_back();
          listed_refs.pop_back();
        } else {
          for(int& x : listed[slot])
            if(x == v)
              x = w;
          listed_index.emplace(Face_key(listed[slot][0], listed[slot][1], listed[slot][2]), slot);
        }
      }
      if(!has_w) {
        std::array<int, 3> g = f;
        for(int& x : g)
          if(x == v)
            x = w;
        protected_faces.insert(Face_key(g[0], g[1], g[2]));
        protected_edges.insert(edge_key(g[0], g[1]));
        protected_edges.insert(edge_key(g[1], g[2]));
        protected_edges.insert(edge_key(g[2], g[0]));
      }
    }
    removed[std::size_t(v)] = 1;
  }

  /// the curve (edge ref) of a feature edge, or -1
  int feature_edge_curve(int a, int b) const
  {
    const auto it = feature_edge_ref.find(edge_key(a, b));
    return it == feature_edge_ref.end() ? -1 : it->second;
  }

  /// After the feature edge (a, b) was split at `m` (its boundary faces by
  /// `split_boundary_faces()`): the feature edges (a, m), (m, b) of the same
  /// curve replace it, and `a` and `b`, if they slide along a line or curve,
  /// have `m` as their neighbour there instead of each other.
  void split_feature_edge(int a, int b, int m)
  {
    const int curve = feature_edge_curve(a, b);
    for(std::size_t i = 0; i < feature_edge_list.size(); ++i) {
      auto& e = feature_edge_list[i];
      if(edge_key(e[0], e[1]) != edge_key(a, b))
        continue;
      const int first = e[0], second = e[1];
      e = {{first, m}};
      feature_edge_list.push_back({{m, second}});
      feature_edge_list_refs.push_back(feature_edge_list_refs[i]);
      break;
    }
    feature_edges.erase(edge_key(a, b));
    feature_edge_ref.erase(edge_key(a, b));
    for(int u : {a, b}) {
      feature_edges.insert(edge_key(u, m));
      protected_edges.insert(edge_key(u, m));
      feature_edge_ref.emplace(edge_key(u, m), curve);
    }
    feature_edges_changed = true;
    replace_curve_neighbour(a, b, m);
    replace_curve_neighbour(b, a, m);
  }

  /// If `x` slides along a line or curve, its neighbour there `from` becomes `to`.
  void replace_curve_neighbour(int x, int from, int to)
  {
    Vertex_constraint& c = constraint[std::size_t(x)];
    if(c.kind != Vertex_constraint::curve && c.kind != Vertex_constraint::line)
      return;
    for(int& end : c.ends)
      if(end == from)
        end = to;
    if(c.kind == Vertex_constraint::curve) {
      c.axis = (points[std::size_t(c.ends[1])] - points[std::size_t(c.ends[0])]).normalized();
      c.tangent[0] = c.axis;
    }
  }

  /// After the collapse of `v`, inside a feature curve, onto its curve
  /// neighbour `w` (the boundary faces by `collapse_boundary_faces()`), `u`
  /// being its other curve neighbour: the feature edge (v, w) goes, (u, v)
  /// becomes (u, w), and the line or curve constraints of `u` and `w` take
  /// each other as neighbours. A line constraint is kept only if `v` slid
  /// on the same straight line (then `w` is on it); otherwise that vertex
  /// becomes fixed.
  void collapse_feature_edge(int v, int w, int u)
  {
    const int curve = feature_edge_curve(v, w);
    for(std::size_t i = 0; i < feature_edge_list.size(); ++i) {
      auto& e = feature_edge_list[i];
      if(edge_key(e[0], e[1]) == edge_key(u, v)) {
        for(int& x : e)
          if(x == v)
            x = w;
      } else if(edge_key(e[0], e[1]) == edge_key(v, w)) {
        const std::size_t last = feature_edge_list.size() - 1;
        e = feature_edge_list[last];
        feature_edge_list_refs[i] = feature_edge_list_refs[last];
        feature_edge_list.pop_back();
        feature_edge_list_refs.pop_back();
        --i; // the moved entry is looked at again
      }
    }
    for(int x : {u, w}) {
      feature_edges.erase(edge_key(v, x));
      feature_edge_ref.erase(edge_key(v, x));
      protected_edges.erase(edge_key(v, x));
    }
    feature_edges.insert(edge_key(u, w));
    feature_edge_ref.emplace(edge_key(u, w), curve);
    protected_edges.insert(edge_key(u, w));
    feature_edges_changed = true;
    const bool straight = constraint[std::size_t(v)].kind == Vertex_constraint::line;
    for(int x : {u, w})
      if(constraint[std::size_t(x)].kind == Vertex_constraint::line && !straight)
        constraint[std::size_t(x)].kind = Vertex_constraint::fixed;
    replace_curve_neighbour(u, v, w);
    replace_curve_neighbour(w, v, u);
    constraint[std::size_t(v)].kind = Vertex_constraint::fixed;
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

  /// The open fan of the boundary edge (a, b): fan vertices p_0 .. p_k and
  /// the tets t_i = (a, b, p_i, p_{i+1}) (up to an even permutation), i < k,
  /// every `orientation(a, b, p_i, p_{i+1})` positive; (a, b, p_0) and
  /// (a, b, p_k) are then faces of one tet each (of the same tet if k = 1). Returns false if the tets
  /// around the edge are not one open fan, or more than `max_size`.
  bool edge_fan(int a, int b, std::size_t max_size, std::vector<int>& fan, std::vector<int>& fan_tets) const
  {
    fan.clear();
    fan_tets.clear();
    std::vector<std::array<int, 3>> links;
    for(int s : vertex_tets[std::size_t(a)]) {
      const Tet& T = tets[std::size_t(s)];
      if(!has_vertex(T, b))
        continue;
      int x = -1, y = -1;
      for(int v : T)
        if(v != a && v != b)
          (x < 0 ? x : y) = v;
      if(permutation_parity(T, a, b, x, y) != 0)
        std::swap(x, y);
      links.push_back({{x, y, s}});
      if(links.size() > max_size)
        return false;
    }
    const std::size_t n = links.size();
    if(n < 1)
      return false;
    // the start: the x that is no link's y
    std::size_t start = n;
    for(std::size_t i = 0; i < n; ++i) {
      bool is_target = false;
      for(std::size_t j = 0; j < n && !is_target; ++j)
        is_target = links[j][1] == links[i][0];
      if(!is_target) {
        if(start != n)
          return false; // two fans
        start = i;
      }
    }
    if(start == n)
      return false; // closed: an interior edge
    std::vector<char> used(n, 0);
    used[start] = 1;
    fan.push_back(links[start][0]);
    fan_tets.push_back(links[start][2]);
    int current = links[start][1];
    for(std::size_t k = 1; k < n; ++k) {
      std::size_t found = n;
      for(std::size_t i = 0; i < n; ++i)
        if(!used[i] && links[i][0] == current) {
          if(found != n)
            return false;
          found = i;
        }
      if(found == n)
        return false;
      used[found] = 1;
      fan.push_back(current);
      fan_tets.push_back(links[found][2]);
      current = links[found][1];
    }
    fan.push_back(current);
    return current != fan[0];
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
  /// vertices removed by edge collapses (no tets; dropped by `write_back()`)
  std::vector<char> removed;
  /// feature edges (also in `protected_edges`)
  std::unordered_set<std::uint64_t, Edge_key_hash> feature_edges;
  /// the listed triangles and their refs (boundary flips replace some), and
  /// the position of each
  std::vector<std::array<int, 3>> listed;
  std::vector<int> listed_refs;
  std::unordered_map<Face_key, std::size_t, Face_key_hash> listed_index;
  /// a face listed twice (then no boundary flips: both copies would have to change)
  bool has_duplicate_triangles = false;
  /// what a fixed vertex may still do (free vertices: `free`)
  std::vector<Vertex_constraint> constraint;
  /// the refs of the vertices added by `add_vertex()`, in order
  std::vector<int> added_point_refs;
  /// the feature edges and their refs as given, then as split or collapsed
  std::vector<std::array<int, 2>> feature_edge_list;
  std::vector<int> feature_edge_list_refs;
  std::unordered_map<std::uint64_t, int> feature_edge_ref;
  bool feature_edges_changed = false; // split or collapsed: the output lists them anew
  bool exterior_ref_0 = false;
  Surface_projection surface_projection;
  Surface_projection curve_projection;

private:
  /// P(v) as an exact point
  Exact_point X(int v) const
  {
    const Eigen::Vector3d& p = points[std::size_t(v)];
    return Exact_point(p[0], p[1], p[2]);
  }

  /// fills `constraint` (see `Vertex_constraint`); exact predicates only
  void classify_boundary_vertices(const Indexed_tet_mesh_3& mesh,
                                  const std::vector<std::pair<Face_key, int>>& face_patches)
  {
    const std::size_t np = points.size();
    constraint.assign(np, Vertex_constraint());
    std::vector<std::vector<std::size_t>> faces_at(np);
    for(std::size_t i = 0; i < face_patches.size(); ++i)
      for(int v : face_patches[i].first.v)
        faces_at[std::size_t(v)].push_back(i);
    std::vector<std::vector<int>> feature_neighbours(np);
    std::unordered_map<std::uint64_t, int> edge_refs; // feature edge -> its curve
    for(std::size_t i = 0; i < mesh.edges.size(); ++i) {
      const auto& e = mesh.edges[i];
      if(e[0] != e[1]) {
        feature_neighbours[std::size_t(e[0])].push_back(e[1]);
        feature_neighbours[std::size_t(e[1])].push_back(e[0]);
        edge_refs.emplace(edge_key(e[0], e[1]), i < mesh.edge_refs.size() ? mesh.edge_refs[i] : 0);
      }
    }
    std::vector<char> corner(np, 0);
    for(int c : mesh.corners)
      if(c >= 0 && std::size_t(c) < np)
        corner[std::size_t(c)] = 1;
    std::vector<std::pair<int, int>> link; // the other two vertices of each face at v
    for(std::size_t v = 0; v < np; ++v) {
      if(!fixed[v])
        continue;
      Vertex_constraint& c = constraint[v];
      c.kind = Vertex_constraint::fixed;
      if(corner[v] || faces_at[v].empty() || vertex_tets[v].empty())
        continue;
      link.clear();
      for(std::size_t i : faces_at[v]) {
        const auto& f = face_patches[i].first.v;
        int a = -1, b = -1;
        for(int u : f)
          if(u != int(v))
            (a < 0 ? a : b) = u;
        link.push_back({a, b});
      }
      // one closed fan: every link vertex is on exactly two faces
      std::vector<int> ends;
      for(const auto& l : link) {
        ends.push_back(l.first);
        ends.push_back(l.second);
      }
      std::sort(ends.begin(), ends.end());
      bool closed = true;
      for(std::size_t i = 0; i < ends.size(); i += 2)
        closed = closed && i + 1 < ends.size() && ends[i] == ends[i + 1] && (i + 2 >= ends.size() || ends[i + 2] != ends[i]);
      if(!closed || !is_one_cycle(link))
        continue;
      const Exact_point pv = X(int(v));
      const std::vector<int>& fn = feature_neighbours[v];
      if(fn.empty()) {
        const int patch = face_patches[faces_at[v].front()].second;
        bool same_patch = true;
        for(std::size_t i : faces_at[v])
          same_patch = same_patch && face_patches[i].second == patch;
        if(!same_patch)
          continue;
        // the plane of the first face; every face vertex must lie on it
        const Exact_point pa = X(link[0].first), pb = X(link[0].second);
        if(CGAL::collinear(pv, pa, pb))
          continue;
        bool planar = true;
        for(const auto& l : link)
          planar = planar && CGAL::orientation(pv, pa, pb, X(l.first)) == CGAL::COPLANAR &&
                   CGAL::orientation(pv, pa, pb, X(l.second)) == CGAL::COPLANAR;
        if(!planar) {
          // only on the domain boundary (an interface has active tets on both
          // sides: its outward area vectors cancel) and a listed patch
          double area = 0;
          for(const auto& l : link)
            area += 0.5 * (points[std::size_t(l.first)] - points[v]).cross(points[std::size_t(l.second)] - points[v]).norm();
          if(surface_projection && patch != std::numeric_limits<int>::min() &&
             boundary_normal(int(v)).norm() > 0.5 * area) {
            c.kind = Vertex_constraint::surface;
            c.patch = patch;
            c.origin = points[v];
          }
          continue;
        }
        c.kind = Vertex_constraint::plane;
        c.origin = points[v];
        c.axis = (points[std::size_t(link[0].first)] - points[v]).cross(points[std::size_t(link[0].second)] - points[v]);
        c.axis.normalize();
        c.exact_axis = -1;
        for(int k = 0; k < 3 && c.exact_axis < 0; ++k) {
          bool constant = true;
          for(const auto& l : link)
            constant = constant && points[std::size_t(l.first)][k] == points[v][k] &&
                       points[std::size_t(l.second)][k] == points[v][k];
          if(constant) {
            c.exact_axis = k;
            c.axis = Eigen::Vector3d::Unit(k);
          }
        }
        c.tangent[0] = c.axis.unitOrthogonal();
        c.tangent[1] = c.axis.cross(c.tangent[0]);
      } else if(fn.size() == 2 && fn[0] != fn[1]) {
        const Exact_point pa = X(fn[0]), pb = X(fn[1]);
        if(!CGAL::collinear(pa, pv, pb) || !CGAL::collinear_are_strictly_ordered_along_line(pa, pv, pb)) {
          // a curved feature curve: slides along it when both edges are on one curve
          auto ra = edge_refs.find(edge_key(int(v), fn[0])), rb = edge_refs.find(edge_key(int(v), fn[1]));
          if(curve_projection && ra != edge_refs.end() && rb != edge_refs.end() && ra->second == rb->second &&
             !CGAL::collinear(pa, pv, pb)) {
            c.kind = Vertex_constraint::curve;
            c.patch = ra->second;
            c.origin = points[v];
            c.axis = (points[std::size_t(fn[1])] - points[std::size_t(fn[0])]).normalized();
            c.tangent[0] = c.axis;
            c.tangent[1] = Eigen::Vector3d::Zero();
            c.ends[0] = fn[0];
            c.ends[1] = fn[1];
          }
          continue;
        }
        // every face around v in a plane through the line
        bool through = true;
        for(const auto& l : link) {
          const Exact_point pl = X(l.first), pm = X(l.second);
          through = through && CGAL::orientation(pv, pl, pm, pa) == CGAL::COPLANAR &&
                    CGAL::orientation(pv, pl, pm, pb) == CGAL::COPLANAR;
        }
        if(!through)
          continue;
        c.kind = Vertex_constraint::line;
        c.origin = points[v];
        c.axis = (points[std::size_t(fn[1])] - points[std::size_t(fn[0])]).normalized();
        c.ends[0] = fn[0];
        c.ends[1] = fn[1];
        c.exact_axis = -1;
        int constant = 0, moving = -1;
        for(int k = 0; k < 3; ++k) {
          if(points[std::size_t(fn[0])][k] == points[v][k] && points[std::size_t(fn[1])][k] == points[v][k])
            ++constant;
          else
            moving = k;
        }
        if(constant == 2) {
          c.exact_axis = moving;
          c.axis = Eigen::Vector3d::Unit(moving);
        }
        c.tangent[0] = c.axis;
        c.tangent[1] = Eigen::Vector3d::Zero();
      }
    }
  }

  /// true if the link edges (pairs of vertices) form a single cycle
  static bool is_one_cycle(const std::vector<std::pair<int, int>>& link)
  {
    if(link.size() < 3)
      return false;
    std::vector<char> used(link.size(), 0);
    used[0] = 1;
    const int start = link[0].first;
    int current = link[0].second;
    for(std::size_t k = 1; k < link.size(); ++k) {
      std::size_t found = link.size();
      for(std::size_t i = 0; i < link.size() && found == link.size(); ++i)
        if(!used[i] && (link[i].first == current || link[i].second == current))
          found = i;
      if(found == link.size())
        return false;
      used[found] = 1;
      current = link[found].first == current ? link[found].second : link[found].first;
    }
    return current == start;
  }
};

} // namespace improve
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_IMPROVE_MUTABLE_TET_MESH_H
