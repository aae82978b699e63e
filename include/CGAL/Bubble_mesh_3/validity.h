// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_VALIDITY_H
#define CGAL_BUBBLE_MESH_3_VALIDITY_H

#include <CGAL/Bubble_mesh_3/internal/json.h>
#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Exact_rational.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <CGAL/Bubble_mesh_3/internal/boundary_self_intersections.h>

// The mesh validity checker of the package.
//
// CGAL's `c3t3.is_valid()` checks neither orientation, nor conformity, nor
// the surface (CGAL 5.5: it checks the triangulation data structure), so every stage of the
// package (advancing front, swaps, the `eval` tool) checks its output here.
//
// Why the checks below imply that no two tets overlap (item 7 of the brief),
// without any O(n^2) intersection test:
//
//   Let c(x) be the number of tets that contain a point x (x on no face).
//   For one positively oriented tet t, the winding number of its boundary,
//   taken as the 2-chain of its four *outward* faces, is 1 inside t and 0
//   outside: it equals the indicator of t. Winding numbers are linear in the
//   chain, so c(x) = w_B(x), where B is the sum of the outward faces of all
//   tets. If every interior face appears exactly once in each orientation
//   (the conformity check: at most two tets per face, never on the same
//   side), those pairs cancel in B and B is exactly the set of boundary
//   faces, each with its tet's outward orientation. Hence
//       c(x) = w_B(x)  for almost every x.
//   If B is the given closed surface and that surface is embedded (no
//   self-intersection; the input surface is, the boundary-consistency check
//   compares B with the listed triangles), w_B is 1 inside and 0 outside,
//   so c(x) <= 1: the tets tile the enclosed region exactly, with no overlap
//   and no gap. Integrating, sum of tet volumes = integral of w_B = volume
//   enclosed by B, which is what the volume checks measure: the identity
//   "sum of tet volumes == divergence-theorem volume of the boundary faces"
//   fails when the face bookkeeping is broken (a face on 3 tets, two tets on
//   the same side), and the optional comparison with the expected volume
//   (the volume of the input surface) catches a boundary that covers the
//   region twice (w_B = 2), e.g. a doubled layer with duplicated vertices.
//   That B is embedded is the last check (`check_boundary_self_intersections`,
//   on by default): PMP::self_intersections on each subdomain's boundary. It
//   is not implied by the input: a mesh whose boundary vertices moved can
//   fold a thin part over itself while every check above passes.
//
// Exactness: orientations use Epick's exact CGAL::orientation. Volume sums
// are Neumaier-compensated double sums of per-element determinants, compared
// with a relative tolerance (1e-9 by default) against the sum of |volumes|;
// the rounding error is about n * 1e-16 relative, far below. The identity is
// exact in rational arithmetic for a conforming complex, so when the double
// comparison fails it is recomputed in CGAL::Exact_rational (coordinates are
// dyadic, hence exact) before a failure is reported: the verdict of the
// volume identity is exact; only the cost of a failing check grows.
//
// Complexity: O(n log n) with n the number of tets (one sort of the 4n
// faces, 16 bytes each), single-threaded: 0.31 s for 1.1M tets in a
// release build (DISABLED_TimingOneMillionTets in test_validity.cpp).

namespace CGAL {
namespace Bubble_mesh_3 {

/// \ingroup PkgBubbleMesh3Ref
/// Options of `check_validity()`.
struct Validity_options {
  /// vertices used by no tet are an error unless this is set (they are counted anyway)
  bool allow_unused_vertices = false;
  /// compare the boundary and interface faces of the tets with `mesh.triangles`
  /// (only when the mesh has triangles)
  bool check_boundary_triangles = true;
  /// a listed boundary triangle whose orientation is not outward w.r.t. its
  /// tet is an error if set; otherwise it is only counted (MEDIT files from
  /// other tools orient triangles arbitrarily)
  bool require_outward_triangles = false;
  /// a face listed more than once in `triangles` is an error unless this is
  /// set (it is counted anyway). CGAL's `output_to_medit()` lists every
  /// surface facet twice, once per side (CGAL 5.5).
  bool allow_duplicate_triangles = false;
  /// relative tolerance of the identity sum(tet volumes) == volume enclosed
  /// by the boundary faces, relative to the sum of |tet volumes|
  double volume_relative_tolerance = 1e-9;
  /// if set, the sum of tet volumes must equal it within
  /// `expected_volume_relative_tolerance * |expected_volume|`
  std::optional<double> expected_volume;
  double expected_volume_relative_tolerance = 1e-6;
  /// compute the connected components of the boundary surface and their
  /// Euler characteristics (information only)
  bool compute_boundary_topology = true;
  /// check that the boundary of each subdomain does not intersect itself
  /// (`CGAL::Polygon_mesh_processing::self_intersections()`; only when the
  /// other checks passed). Without it, tets may overlap where the boundary
  /// folds over itself (see the header comment)
  bool check_boundary_self_intersections = true;
  /// number of problem messages kept in `Validity_report::problems`
  std::size_t max_listed_problems = 20;
};

/// \ingroup PkgBubbleMesh3Ref
/// One connected component (through shared vertices) of the boundary surface.
struct Boundary_component {
  std::size_t vertices = 0;
  std::size_t edges = 0;
  std::size_t faces = 0;
  long euler_characteristic = 0; ///< V - E + F: 2 for a sphere, 0 for a torus
};

/// \ingroup PkgBubbleMesh3Ref
/// Result of `check_validity()`: counts per kind of problem, a capped list
/// of human-readable messages (element indices are 0-based), and
/// information about the mesh (volumes, boundary topology).
struct Validity_report {
  // sizes
  std::size_t number_of_points = 0;
  std::size_t number_of_tets = 0;
  std::size_t number_of_triangles = 0;

  // 1. input sanity (errors)
  std::size_t invalid_indices = 0;        ///< tet/triangle/edge/corner vertex indices out of range
  std::size_t tets_with_repeated_vertex = 0;
  std::size_t triangles_with_repeated_vertex = 0;
  std::size_t non_finite_points = 0;      ///< points with a NaN or infinite coordinate
  std::size_t reference_size_mismatches = 0; ///< `tet_refs`/`triangle_refs`/... not parallel to their array

  // 2. orientation (errors)
  std::size_t negative_tets = 0;
  std::size_t flat_tets = 0;

  // 3. conformity (errors, except the face counts)
  std::size_t boundary_faces = 0;   ///< faces of exactly one tet
  std::size_t interior_faces = 0;   ///< faces of two tets, one on each side
  std::size_t interface_faces = 0;  ///< interior faces between two different subdomains
  std::size_t faces_shared_by_more_than_two_tets = 0;
  std::size_t faces_with_tets_on_same_side = 0; ///< two tets glued on the same side (overlap)
  std::size_t non_manifold_boundary_edges = 0;  ///< boundary edges not on exactly 2 boundary faces
  std::size_t non_manifold_boundary_vertices = 0; ///< boundary vertices whose link is not one cycle

  // 4. boundary consistency (errors when checked)
  bool boundary_triangles_checked = false;
  std::size_t missing_boundary_triangles = 0; ///< boundary/interface faces not in `triangles`
  std::size_t extra_triangles = 0;            ///< triangles that are no boundary/interface face
  std::size_t duplicate_triangles = 0;   ///< error unless `allow_duplicate_triangles`
  bool duplicate_triangles_allowed = false;
  std::size_t misoriented_boundary_triangles = 0; ///< error only with `require_outward_triangles`
  bool require_outward_triangles = false;

  // 5. volume
  bool volume_checked = false;          ///< false when coordinates are not finite
  double tet_volume = 0;                ///< sum of signed tet volumes
  double boundary_volume = 0;           ///< divergence theorem over the boundary faces
  bool volume_identity_holds = true;    ///< (exact verdict, see the header comment)
  bool expected_volume_checked = false;
  double expected_volume = 0;
  bool expected_volume_matches = true;

  // 6. vertices and boundary topology, embedding
  std::size_t unused_vertices = 0;      ///< vertices of no tet
  bool unused_vertices_allowed = false;
  std::size_t number_of_boundary_components = 0;
  std::vector<Boundary_component> boundary_components; ///< the first `max_listed_problems`
  bool self_intersections_checked = false;
  /// pairs of intersecting triangles on the boundary of a subdomain (error)
  std::size_t boundary_self_intersections = 0;

  // messages
  std::vector<std::string> problems;    ///< the first `max_listed_problems` messages
  std::size_t number_of_problems = 0;   ///< all problems, listed or not

  bool is_valid() const
  {
    return invalid_indices == 0 && tets_with_repeated_vertex == 0 && triangles_with_repeated_vertex == 0 &&
           non_finite_points == 0 && reference_size_mismatches == 0 && negative_tets == 0 && flat_tets == 0 &&
           faces_shared_by_more_than_two_tets == 0 && faces_with_tets_on_same_side == 0 &&
           non_manifold_boundary_edges == 0 && non_manifold_boundary_vertices == 0 &&
           missing_boundary_triangles == 0 && extra_triangles == 0 &&
           (duplicate_triangles_allowed || duplicate_triangles == 0) &&
           (!require_outward_triangles || misoriented_boundary_triangles == 0) && volume_identity_holds &&
           expected_volume_matches && (unused_vertices_allowed || unused_vertices == 0) &&
           boundary_self_intersections == 0;
  }
};

namespace internal {

// A face of a tet, as the sorted vertex triple plus the parity of the
// permutation that takes the sorted triple to the tet's outward orientation.
// Packed in two 64-bit words so that one std::sort groups equal faces.
struct Validity_face_entry {
  std::uint64_t hi; // (a << 32) | b
  std::uint64_t lo; // (c << 32) | (tet << 1) | parity

  std::uint32_t a() const { return std::uint32_t(hi >> 32); }
  std::uint32_t b() const { return std::uint32_t(hi & 0xffffffffu); }
  std::uint32_t c() const { return std::uint32_t(lo >> 32); }
  std::uint32_t tet() const { return std::uint32_t(lo & 0xffffffffu) >> 1; }
  int parity() const { return int(lo & 1u); }
  bool same_face(const Validity_face_entry& o) const { return hi == o.hi && (lo >> 32) == (o.lo >> 32); }
  bool operator<(const Validity_face_entry& o) const { return hi < o.hi || (hi == o.hi && lo < o.lo); }
};

// Sorts (x, y, z) and returns the parity of the sorting permutation.
inline int validity_sort3(std::uint32_t& x, std::uint32_t& y, std::uint32_t& z)
{
  int p = 0;
  if(x > y) { std::swap(x, y); p ^= 1; }
  if(y > z) { std::swap(y, z); p ^= 1; }
  if(x > y) { std::swap(x, y); p ^= 1; }
  return p;
}

inline Validity_face_entry validity_make_face(std::uint32_t x, std::uint32_t y, std::uint32_t z, std::uint32_t tet)
{
  const int p = validity_sort3(x, y, z);
  Validity_face_entry f;
  f.hi = (std::uint64_t(x) << 32) | y;
  f.lo = (std::uint64_t(z) << 32) | (std::uint64_t(tet) << 1) | std::uint64_t(p);
  return f;
}

// The oriented boundary face: sorted triple, reordered by its parity.
inline std::array<std::uint32_t, 3> validity_oriented(const Validity_face_entry& f)
{
  if(f.parity() == 0)
    return {f.a(), f.b(), f.c()};
  return {f.a(), f.c(), f.b()};
}

inline double validity_det3(double ax, double ay, double az, double bx, double by, double bz, double cx, double cy,
                            double cz)
{
  return ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
}

class Validity_compensated_sum {
public:
  void add(double x)
  {
    const double t = sum_ + x;
    if(std::abs(sum_) >= std::abs(x))
      compensation_ += (sum_ - t) + x;
    else
      compensation_ += (x - t) + sum_;
    sum_ = t;
  }
  double value() const { return sum_ + compensation_; }

private:
  double sum_ = 0;
  double compensation_ = 0;
};

inline Exact_rational validity_exact_det(const std::array<double, 3>& o, const std::array<double, 3>& p,
                                         const std::array<double, 3>& q, const std::array<double, 3>& r)
{
  const Exact_rational ox(o[0]), oy(o[1]), oz(o[2]);
  const Exact_rational ax = Exact_rational(p[0]) - ox, ay = Exact_rational(p[1]) - oy, az = Exact_rational(p[2]) - oz;
  const Exact_rational bx = Exact_rational(q[0]) - ox, by = Exact_rational(q[1]) - oy, bz = Exact_rational(q[2]) - oz;
  const Exact_rational cx = Exact_rational(r[0]) - ox, cy = Exact_rational(r[1]) - oy, cz = Exact_rational(r[2]) - oz;
  return ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
}

// Collects messages: counts them all, keeps the first `cap`.
class Validity_problem_log {
public:
  Validity_problem_log(Validity_report& r, std::size_t cap) : r_(r), cap_(cap) {}
  bool wants_message() const { return r_.problems.size() < cap_; }
  void add(const std::string& message)
  {
    ++r_.number_of_problems;
    if(wants_message())
      r_.problems.push_back(message);
  }
  // Counts a problem; builds its message only if it will be kept.
  template <typename MakeMessage>
  void add_lazy(const MakeMessage& make)
  {
    ++r_.number_of_problems;
    if(wants_message())
      r_.problems.push_back(make());
  }

private:
  Validity_report& r_;
  std::size_t cap_;
};

inline std::string validity_triple(std::uint32_t a, std::uint32_t b, std::uint32_t c)
{
  return "(" + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(c) + ")";
}

struct Validity_union_find {
  std::vector<std::uint32_t> parent;
  explicit Validity_union_find(std::size_t n) : parent(n)
  {
    for(std::size_t i = 0; i < n; ++i)
      parent[i] = std::uint32_t(i);
  }
  std::uint32_t find(std::uint32_t x)
  {
    while(parent[x] != x) {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  }
  void unite(std::uint32_t x, std::uint32_t y)
  {
    x = find(x);
    y = find(y);
    if(x != y)
      parent[std::max(x, y)] = std::min(x, y);
  }
};

} // namespace internal

namespace internal {

// The steps of `check_validity()`, in order; each adds to the report what it
// finds. The later steps use what the earlier ones established (which tets
// and triangles have valid indices, the boundary faces).
class Validity_checker {
  typedef CGAL::Exact_predicates_inexact_constructions_kernel::Point_3 Point;

public:
  Validity_checker(const Indexed_tet_mesh_3& m, const Validity_options& o)
      : mesh(m), options(o), log(r, o.max_listed_problems), np(m.points.size()), nt(m.tets.size())
  {
    r.number_of_points = np;
    r.number_of_tets = nt;
    r.number_of_triangles = mesh.triangles.size();
    r.unused_vertices_allowed = options.allow_unused_vertices;
    r.require_outward_triangles = options.require_outward_triangles;
    r.duplicate_triangles_allowed = options.allow_duplicate_triangles;
    if(np > std::size_t(std::numeric_limits<std::int32_t>::max()) ||
       nt > std::size_t(std::numeric_limits<std::int32_t>::max()))
      throw std::length_error("check_validity: more than 2^31-1 points or tets");
  }

  Validity_report run()
  {
    check_input();
    check_orientation();
    collect_faces();
    check_boundary_edges();
    check_boundary_vertex_links();
    if(options.compute_boundary_topology && !boundary.empty())
      compute_boundary_topology();
    std::vector<std::uint64_t>().swap(unique_edges);
    if(options.check_boundary_triangles && !mesh.triangles.empty())
      check_listed_triangles();
    check_volume();
    check_unused_vertices();
    if(options.check_boundary_self_intersections && r.is_valid())
      check_embedding();
    return r;
  }

private:
  // 1. input sanity: reference array sizes, finite points, indices in range and distinct
  void check_input()
  {
    auto check_refs = [&](std::size_t refs, std::size_t elements, const char* what) {
      if(refs != elements && !(refs == 0 && elements == 0)) {
        ++r.reference_size_mismatches;
        log.add(std::string(what) + " has " + std::to_string(refs) + " entries for " + std::to_string(elements) +
                " elements");
      }
    };
    check_refs(mesh.point_refs.size(), np, "point_refs");
    check_refs(mesh.edge_refs.size(), mesh.edges.size(), "edge_refs");
    check_refs(mesh.triangle_refs.size(), mesh.triangles.size(), "triangle_refs");
    check_refs(mesh.tet_refs.size(), nt, "tet_refs");

    finite_point.assign(np, 1);
    for(std::size_t i = 0; i < np; ++i) {
      const auto& p = mesh.points[i];
      if(!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))) {
        finite_point[i] = 0;
        ++r.non_finite_points;
        log.add_lazy([&] { return "point " + std::to_string(i) + " has a non-finite coordinate"; });
      }
    }
    auto in_range = [this](int v) { return v >= 0 && std::size_t(v) < np; };

    // tet_ok: indices in range and distinct; tet_geometric: also finite points
    tet_ok.assign(nt, 0);
    used.assign(np, 0);
    for(std::size_t t = 0; t < nt; ++t) {
      const auto& T = mesh.tets[t];
      if(!(in_range(T[0]) && in_range(T[1]) && in_range(T[2]) && in_range(T[3]))) {
        ++r.invalid_indices;
        log.add_lazy([&] {
          return "tet " + std::to_string(t) + ": vertex index out of range [0, " + std::to_string(np) + ")";
        });
        continue;
      }
      if(T[0] == T[1] || T[0] == T[2] || T[0] == T[3] || T[1] == T[2] || T[1] == T[3] || T[2] == T[3]) {
        ++r.tets_with_repeated_vertex;
        log.add_lazy([&] { return "tet " + std::to_string(t) + ": repeated vertex"; });
        continue;
      }
      tet_ok[t] = 1;
      for(int v : T)
        used[std::size_t(v)] = 1;
    }
    triangle_ok.assign(mesh.triangles.size(), 0);
    for(std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      const auto& F = mesh.triangles[i];
      if(!(in_range(F[0]) && in_range(F[1]) && in_range(F[2]))) {
        ++r.invalid_indices;
        log.add_lazy([&] { return "triangle " + std::to_string(i) + ": vertex index out of range"; });
      } else if(F[0] == F[1] || F[0] == F[2] || F[1] == F[2]) {
        ++r.triangles_with_repeated_vertex;
        log.add_lazy([&] { return "triangle " + std::to_string(i) + ": repeated vertex"; });
      } else {
        triangle_ok[i] = 1;
      }
    }
    for(std::size_t i = 0; i < mesh.edges.size(); ++i) {
      if(!(in_range(mesh.edges[i][0]) && in_range(mesh.edges[i][1]))) {
        ++r.invalid_indices;
        log.add_lazy([&] { return "edge " + std::to_string(i) + ": vertex index out of range"; });
      }
    }
    for(std::size_t i = 0; i < mesh.corners.size(); ++i) {
      if(!in_range(mesh.corners[i])) {
        ++r.invalid_indices;
        log.add_lazy([&] { return "corner " + std::to_string(i) + ": vertex index out of range"; });
      }
    }
  }

  // 2. orientation: every tet positive (exact)
  void check_orientation()
  {
    auto point = [&](std::uint32_t v) {
      const auto& p = mesh.points[v];
      return Point(p[0], p[1], p[2]);
    };
    auto tet_finite = [&](std::size_t t) {
      const auto& T = mesh.tets[t];
      return finite_point[T[0]] && finite_point[T[1]] && finite_point[T[2]] && finite_point[T[3]];
    };
    for(std::size_t t = 0; t < nt; ++t) {
      if(!tet_ok[t] || !tet_finite(t))
        continue;
      const auto& T = mesh.tets[t];
      const CGAL::Orientation o = CGAL::orientation(point(T[0]), point(T[1]), point(T[2]), point(T[3]));
      if(o == CGAL::POSITIVE)
        continue;
      if(o == CGAL::NEGATIVE)
        ++r.negative_tets;
      else
        ++r.flat_tets;
      log.add_lazy([&] {
        return "tet " + std::to_string(t) + " (" + std::to_string(T[0]) + " " + std::to_string(T[1]) + " " +
               std::to_string(T[2]) + " " + std::to_string(T[3]) + ") is " +
               (o == CGAL::NEGATIVE ? "negatively oriented" : "flat");
      });
    }
  }

  // 3. conformity: faces on at most two tets, on opposite sides; the boundary and interface faces
  void collect_faces()
  {
    // For a positively oriented tet (0,1,2,3) the outward faces are
    // (1,2,3), (0,3,2), (0,1,3), (0,2,1).
    std::vector<Validity_face_entry> faces;
    faces.reserve(4 * nt);
    for(std::size_t t = 0; t < nt; ++t) {
      if(!tet_ok[t])
        continue;
      const auto& T = mesh.tets[t];
      const std::uint32_t v0 = std::uint32_t(T[0]), v1 = std::uint32_t(T[1]), v2 = std::uint32_t(T[2]),
                          v3 = std::uint32_t(T[3]);
      const std::uint32_t tt = std::uint32_t(t);
      faces.push_back(internal::validity_make_face(v1, v2, v3, tt));
      faces.push_back(internal::validity_make_face(v0, v3, v2, tt));
      faces.push_back(internal::validity_make_face(v0, v1, v3, tt));
      faces.push_back(internal::validity_make_face(v0, v2, v1, tt));
    }
    std::sort(faces.begin(), faces.end());

    auto tet_ref = [&](std::uint32_t t) { return t < mesh.tet_refs.size() ? mesh.tet_refs[t] : 0; };
    // faces that must be listed as triangles: boundary faces (outward) and
    // interface faces (parity: that of the first tet in sort order)
    for(std::size_t i = 0; i < faces.size();) {
      std::size_t j = i + 1;
      while(j < faces.size() && faces[j].same_face(faces[i]))
        ++j;
      const std::size_t n = j - i;
      const Validity_face_entry& f = faces[i];
      if(n == 1) {
        ++r.boundary_faces;
        boundary.push_back(f);
        required.push_back(f);
      } else if(n == 2) {
        if(faces[i].parity() != faces[i + 1].parity()) {
          ++r.interior_faces;
          if(tet_ref(faces[i].tet()) != tet_ref(faces[i + 1].tet())) {
            ++r.interface_faces;
            required.push_back(f);
          }
        } else {
          ++r.faces_with_tets_on_same_side;
          log.add_lazy([&] {
            return "face " + internal::validity_triple(f.a(), f.b(), f.c()) + ": tets " + std::to_string(f.tet()) +
                   " and " + std::to_string(faces[i + 1].tet()) + " lie on the same side (they overlap)";
          });
        }
      } else {
        ++r.faces_shared_by_more_than_two_tets;
        log.add_lazy([&] {
          return "face " + internal::validity_triple(f.a(), f.b(), f.c()) + " is shared by " + std::to_string(n) +
                 " tets";
        });
      }
      i = j;
    }
    std::vector<Validity_face_entry>().swap(faces);
  }

  // 3. each boundary edge on exactly two boundary faces
  void check_boundary_edges()
  {
    // Boundary edges: each must be on exactly two boundary faces. Keys are
    // (min << 32 | max); edge_face_count holds the counts of the sorted keys.
    std::vector<std::uint64_t> edge_keys;
    edge_keys.reserve(3 * boundary.size());
    for(const Validity_face_entry& f : boundary) {
      const std::array<std::uint32_t, 3> v = {f.a(), f.b(), f.c()};
      edge_keys.push_back((std::uint64_t(v[0]) << 32) | v[1]);
      edge_keys.push_back((std::uint64_t(v[1]) << 32) | v[2]);
      edge_keys.push_back((std::uint64_t(v[0]) << 32) | v[2]);
    }
    std::sort(edge_keys.begin(), edge_keys.end());
    unique_edges.clear();
    for(std::size_t i = 0; i < edge_keys.size();) {
      std::size_t j = i + 1;
      while(j < edge_keys.size() && edge_keys[j] == edge_keys[i])
        ++j;
      unique_edges.push_back(edge_keys[i]);
      if(j - i != 2) {
        ++r.non_manifold_boundary_edges;
        log.add_lazy([&] {
          return "boundary edge (" + std::to_string(edge_keys[i] >> 32) + " " +
                 std::to_string(edge_keys[i] & 0xffffffffu) + ") is on " + std::to_string(j - i) +
                 " boundary faces (non-manifold)";
        });
      }
      i = j;
    }
    std::vector<std::uint64_t>().swap(edge_keys);
  }

  // 3. each boundary vertex with a single cycle as its link
  void check_boundary_vertex_links()
  {
    // Boundary vertices: the link of v in the boundary surface (one edge
    // (x, y) per boundary face (v, x, y)) must be a single cycle: every link
    // vertex of degree 2 and the link connected.
    {
      std::vector<std::array<std::uint32_t, 3>> star; // (v, x, y)
      star.reserve(3 * boundary.size());
      for(const Validity_face_entry& f : boundary) {
        star.push_back({f.a(), f.b(), f.c()});
        star.push_back({f.b(), f.c(), f.a()});
        star.push_back({f.c(), f.a(), f.b()});
      }
      std::sort(star.begin(), star.end(),
                [](const std::array<std::uint32_t, 3>& x, const std::array<std::uint32_t, 3>& y) { return x[0] < y[0]; });
      std::vector<std::uint32_t> link;   // distinct link vertices
      std::vector<int> degree;
      std::vector<std::uint32_t> parent; // local union-find over link
      for(std::size_t i = 0; i < star.size();) {
        std::size_t j = i + 1;
        while(j < star.size() && star[j][0] == star[i][0])
          ++j;
        link.clear();
        for(std::size_t k = i; k < j; ++k) {
          link.push_back(star[k][1]);
          link.push_back(star[k][2]);
        }
        std::sort(link.begin(), link.end());
        link.erase(std::unique(link.begin(), link.end()), link.end());
        degree.assign(link.size(), 0);
        parent.resize(link.size());
        for(std::size_t k = 0; k < link.size(); ++k)
          parent[k] = std::uint32_t(k);
        auto find = [&](std::uint32_t x) {
          while(parent[x] != x)
            x = parent[x] = parent[parent[x]];
          return x;
        };
        auto index = [&](std::uint32_t v) {
          return std::uint32_t(std::lower_bound(link.begin(), link.end(), v) - link.begin());
        };
        std::size_t components = link.size();
        for(std::size_t k = i; k < j; ++k) {
          const std::uint32_t x = index(star[k][1]), y = index(star[k][2]);
          ++degree[x];
          ++degree[y];
          const std::uint32_t rx = find(x), ry = find(y);
          if(rx != ry) {
            parent[rx] = ry;
            --components;
          }
        }
        const bool all_degree_2 = std::all_of(degree.begin(), degree.end(), [](int d) { return d == 2; });
        if(components != 1 || !all_degree_2) {
          ++r.non_manifold_boundary_vertices;
          const std::uint32_t v = star[i][0];
          log.add_lazy([&] {
            return "boundary vertex " + std::to_string(v) + " is non-manifold (its link has " +
                   std::to_string(components) + " component(s)" + (all_degree_2 ? "" : ", not a cycle") + ")";
          });
        }
        i = j;
      }
    }
  }

  // information: the boundary components and their Euler characteristics
  void compute_boundary_topology()
  {
    internal::Validity_union_find uf(np);
    for(const Validity_face_entry& f : boundary) {
      uf.unite(f.a(), f.b());
      uf.unite(f.a(), f.c());
    }
    std::vector<std::uint32_t> roots;
    std::vector<char> is_boundary_vertex(np, 0);
    for(const Validity_face_entry& f : boundary)
      is_boundary_vertex[f.a()] = is_boundary_vertex[f.b()] = is_boundary_vertex[f.c()] = 1;
    std::vector<std::int64_t> component_of(np, -1);
    std::vector<Boundary_component> components;
    for(std::size_t v = 0; v < np; ++v) {
      if(!is_boundary_vertex[v])
        continue;
      const std::uint32_t root = uf.find(std::uint32_t(v));
      if(component_of[root] < 0) {
        component_of[root] = std::int64_t(components.size());
        components.emplace_back();
      }
      ++components[std::size_t(component_of[root])].vertices;
    }
    for(std::uint64_t e : unique_edges)
      ++components[std::size_t(component_of[uf.find(std::uint32_t(e >> 32))])].edges;
    for(const Validity_face_entry& f : boundary)
      ++components[std::size_t(component_of[uf.find(f.a())])].faces;
    r.number_of_boundary_components = components.size();
    for(Boundary_component& c : components) {
      c.euler_characteristic = long(c.vertices) - long(c.edges) + long(c.faces);
      if(r.boundary_components.size() < options.max_listed_problems)
        r.boundary_components.push_back(c);
    }
  }

  // 4. the listed triangles are exactly the boundary and interface faces (outward)
  void check_listed_triangles()
  {
    r.boundary_triangles_checked = true;
    std::vector<Validity_face_entry> listed; // tet field = triangle index
    listed.reserve(mesh.triangles.size());
    for(std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      if(!triangle_ok[i])
        continue;
      const auto& F = mesh.triangles[i];
      listed.push_back(
          internal::validity_make_face(std::uint32_t(F[0]), std::uint32_t(F[1]), std::uint32_t(F[2]), std::uint32_t(i)));
    }
    std::sort(listed.begin(), listed.end());
    std::sort(required.begin(), required.end());
    // which required faces are boundary faces (to check outward orientation)
    std::size_t a = 0;
    std::size_t b = 0;
    while(a < listed.size() || b < required.size()) {
      if(a + 1 < listed.size() && listed[a + 1].same_face(listed[a])) {
        ++r.duplicate_triangles;
        const Validity_face_entry& f = listed[a + 1];
        if(!options.allow_duplicate_triangles)
          log.add_lazy([&] {
            return "triangle " + std::to_string(f.tet()) + " " + internal::validity_triple(f.a(), f.b(), f.c()) +
                   " is listed twice (also triangle " + std::to_string(listed[a].tet()) + ")";
          });
        ++a;
        continue;
      }
      if(b >= required.size() || (a < listed.size() && listed[a].hi < required[b].hi) ||
         (a < listed.size() && listed[a].hi == required[b].hi && (listed[a].lo >> 32) < (required[b].lo >> 32))) {
        ++r.extra_triangles;
        const Validity_face_entry& f = listed[a];
        log.add_lazy([&] {
          return "triangle " + std::to_string(f.tet()) + " " + internal::validity_triple(f.a(), f.b(), f.c()) +
                 " is neither a boundary face nor an interface between subdomains";
        });
        ++a;
      } else if(a >= listed.size() || !listed[a].same_face(required[b])) {
        ++r.missing_boundary_triangles;
        const Validity_face_entry& f = required[b];
        log.add_lazy([&] {
          return "face " + internal::validity_triple(f.a(), f.b(), f.c()) + " of tet " + std::to_string(f.tet()) +
                 " is a boundary or interface face but is not listed in the triangles";
        });
        ++b;
      } else {
        // matched; boundary faces (one tet) carry the outward parity
        const bool is_boundary_face =
            std::binary_search(boundary.begin(), boundary.end(), required[b]);
        if(is_boundary_face && listed[a].parity() != required[b].parity()) {
          ++r.misoriented_boundary_triangles;
          if(options.require_outward_triangles) {
            const Validity_face_entry& f = listed[a];
            log.add_lazy([&] {
              return "triangle " + std::to_string(f.tet()) + " is not oriented outward w.r.t. tet " +
                     std::to_string(required[b].tet());
            });
          }
        }
        ++a;
        ++b;
      }
    }
  }

  // 5. volume: the tets fill what the boundary encloses (exact when in doubt)
  void check_volume()
  {
    r.volume_checked = (r.non_finite_points == 0);
    if(r.volume_checked) {
      // reference point: the centre of the bounding box of the used points
      std::array<double, 3> lo = {0, 0, 0}, hi = {0, 0, 0};
      bool first = true;
      for(std::size_t v = 0; v < np; ++v) {
        if(!used[v])
          continue;
        for(int k = 0; k < 3; ++k) {
          lo[k] = first ? mesh.points[v][k] : std::min(lo[k], mesh.points[v][k]);
          hi[k] = first ? mesh.points[v][k] : std::max(hi[k], mesh.points[v][k]);
        }
        first = false;
      }
      const std::array<double, 3> o = {0.5 * lo[0] + 0.5 * hi[0], 0.5 * lo[1] + 0.5 * hi[1], 0.5 * lo[2] + 0.5 * hi[2]};
      internal::Validity_compensated_sum tets_sum, abs_sum, boundary_sum;
      for(std::size_t t = 0; t < nt; ++t) {
        if(!tet_ok[t])
          continue;
        const auto& T = mesh.tets[t];
        const auto& p0 = mesh.points[T[0]];
        const auto& p1 = mesh.points[T[1]];
        const auto& p2 = mesh.points[T[2]];
        const auto& p3 = mesh.points[T[3]];
        const double d = internal::validity_det3(p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2], p2[0] - p0[0],
                                                 p2[1] - p0[1], p2[2] - p0[2], p3[0] - p0[0], p3[1] - p0[1],
                                                 p3[2] - p0[2]);
        tets_sum.add(d);
        abs_sum.add(std::abs(d));
      }
      for(const Validity_face_entry& f : boundary) {
        const std::array<std::uint32_t, 3> v = internal::validity_oriented(f);
        const auto& a = mesh.points[v[0]];
        const auto& b = mesh.points[v[1]];
        const auto& c = mesh.points[v[2]];
        boundary_sum.add(internal::validity_det3(a[0] - o[0], a[1] - o[1], a[2] - o[2], b[0] - o[0], b[1] - o[1],
                                                 b[2] - o[2], c[0] - o[0], c[1] - o[1], c[2] - o[2]));
      }
      r.tet_volume = tets_sum.value() / 6;
      r.boundary_volume = boundary_sum.value() / 6;
      const double scale = abs_sum.value() / 6;
      r.volume_identity_holds =
          std::abs(r.tet_volume - r.boundary_volume) <= options.volume_relative_tolerance * scale;
      if(!r.volume_identity_holds) {
        // settle it exactly (dyadic inputs: Exact_rational is exact)
        Exact_rational exact_tets = 0;
        Exact_rational exact_boundary = 0;
        for(std::size_t t = 0; t < nt; ++t) {
          if(!tet_ok[t])
            continue;
          const auto& T = mesh.tets[t];
          exact_tets += internal::validity_exact_det(mesh.points[T[0]], mesh.points[T[1]], mesh.points[T[2]],
                                                     mesh.points[T[3]]);
        }
        for(const Validity_face_entry& f : boundary) {
          const std::array<std::uint32_t, 3> v = internal::validity_oriented(f);
          exact_boundary += internal::validity_exact_det(o, mesh.points[v[0]], mesh.points[v[1]], mesh.points[v[2]]);
        }
        r.volume_identity_holds = (exact_tets == exact_boundary);
        if(!r.volume_identity_holds) {
          std::ostringstream s;
          s.precision(17);
          s << "sum of tet volumes " << r.tet_volume << " differs from the volume enclosed by the boundary faces "
            << r.boundary_volume << " (exact comparison)";
          log.add(s.str());
        }
      }
      if(options.expected_volume) {
        r.expected_volume_checked = true;
        r.expected_volume = *options.expected_volume;
        r.expected_volume_matches = std::abs(r.tet_volume - r.expected_volume) <=
                                    options.expected_volume_relative_tolerance * std::abs(r.expected_volume);
        if(!r.expected_volume_matches) {
          std::ostringstream s;
          s.precision(17);
          s << "sum of tet volumes " << r.tet_volume << " differs from the expected volume " << r.expected_volume
            << " by more than " << options.expected_volume_relative_tolerance << " relative";
          log.add(s.str());
        }
      }
    }
  }

  // 6. every vertex used by a tet
  void check_unused_vertices()
  {
    for(std::size_t v = 0; v < np; ++v) {
      if(used[v])
        continue;
      ++r.unused_vertices;
      if(!options.allow_unused_vertices)
        log.add_lazy([&] { return "vertex " + std::to_string(v) + " is used by no tet"; });
    }
  }

  // 7. embedding: no subdomain boundary intersects itself
  void check_embedding()
  {
    std::size_t unchecked = 0;
    r.boundary_self_intersections = internal::boundary_self_intersections(mesh, &unchecked);
    r.self_intersections_checked = unchecked == 0;
    if(r.boundary_self_intersections > 0)
      log.add("the boundary intersects itself (" + std::to_string(r.boundary_self_intersections) +
              " pairs of triangles): tets overlap there");
  }

  const Indexed_tet_mesh_3& mesh;
  const Validity_options& options;
  Validity_report r;
  Validity_problem_log log;
  const std::size_t np, nt;
  // established by check_input()
  std::vector<char> finite_point, tet_ok, used, triangle_ok;
  // established by collect_faces(): faces of exactly one tet, and those with
  // the interfaces between subdomains (the faces to be listed as triangles)
  std::vector<Validity_face_entry> boundary, required;
  std::vector<std::uint64_t> unique_edges; // boundary edges, (min << 32) | max
};

} // namespace internal

/// \ingroup PkgBubbleMesh3Ref
/// Checks that `mesh` is a valid tetrahedral mesh: indices and coordinates,
/// positive orientation of every tet (exact), conformity (each face on at
/// most two tets, on opposite sides), a manifold boundary, boundary and
/// interface faces equal to the listed triangles (when there are any),
/// the volume identity, and unused vertices. See the comment at the top of
/// this file for why these checks exclude overlapping tets.
/// Never throws on a bad mesh: every problem goes into the report.
inline Validity_report check_validity(const Indexed_tet_mesh_3& mesh, const Validity_options& options = {})
{
  return internal::Validity_checker(mesh, options).run();
}

/// \ingroup PkgBubbleMesh3Ref
/// One-line-per-topic human-readable summary of `r`, followed by the listed problems.
inline void print_validity_summary(std::ostream& out, const Validity_report& r)
{
  out << "validity: " << (r.is_valid() ? "VALID" : "INVALID") << " (" << r.number_of_problems << " problem"
      << (r.number_of_problems == 1 ? "" : "s") << ")\n";
  out << "  input:       " << r.invalid_indices << " bad indices, " << r.tets_with_repeated_vertex
      << " tets and " << r.triangles_with_repeated_vertex << " triangles with a repeated vertex, "
      << r.non_finite_points << " non-finite points\n";
  out << "  orientation: " << r.negative_tets << " negative, " << r.flat_tets << " flat tets\n";
  out << "  faces:       " << r.boundary_faces << " boundary, " << r.interior_faces << " interior ("
      << r.interface_faces << " interface), " << r.faces_shared_by_more_than_two_tets << " on >2 tets, "
      << r.faces_with_tets_on_same_side << " with tets on the same side\n";
  out << "  boundary:    " << r.non_manifold_boundary_edges << " non-manifold edges, "
      << r.non_manifold_boundary_vertices << " non-manifold vertices, " << r.number_of_boundary_components
      << " component(s), Euler characteristic";
  for(const Boundary_component& c : r.boundary_components)
    out << " " << c.euler_characteristic;
  if(r.boundary_components.size() < r.number_of_boundary_components)
    out << " ...";
  out << "\n";
  if(r.boundary_triangles_checked)
    out << "  triangles:   " << r.missing_boundary_triangles << " missing, " << r.extra_triangles << " extra, "
        << r.duplicate_triangles << " duplicate" << (r.duplicate_triangles_allowed ? " (allowed), " : ", ")
        << r.misoriented_boundary_triangles
        << " not oriented outward\n";
  else
    out << "  triangles:   not checked (none listed)\n";
  if(r.volume_checked) {
    out << "  volume:      tets " << r.tet_volume << ", enclosed by boundary " << r.boundary_volume
        << (r.volume_identity_holds ? " (match)" : " (MISMATCH)");
    if(r.expected_volume_checked)
      out << ", expected " << r.expected_volume << (r.expected_volume_matches ? " (match)" : " (MISMATCH)");
    out << "\n";
  } else {
    out << "  volume:      not checked (non-finite coordinates)\n";
  }
  out << "  vertices:    " << r.unused_vertices << " unused" << (r.unused_vertices_allowed ? " (allowed)" : "")
      << "\n";
  if(r.self_intersections_checked || r.boundary_self_intersections > 0)
    out << "  embedding:   " << r.boundary_self_intersections << " pairs of intersecting boundary triangles\n";
  for(const std::string& p : r.problems)
    out << "  problem: " << p << "\n";
  if(r.problems.size() < r.number_of_problems)
    out << "  ... and " << (r.number_of_problems - r.problems.size()) << " more\n";
}

/// \ingroup PkgBubbleMesh3Ref
/// `r` as a JSON object (one line), e.g. to embed in the `eval` report.
inline std::string to_json(const Validity_report& r)
{
  using internal::format_json_number;
  std::ostringstream os;
  auto b = [](bool x) { return x ? "true" : "false"; };
  os << "{\"valid\": " << b(r.is_valid()) << ", \"number_of_problems\": " << r.number_of_problems
     << ", \"invalid_indices\": " << r.invalid_indices
     << ", \"tets_with_repeated_vertex\": " << r.tets_with_repeated_vertex
     << ", \"triangles_with_repeated_vertex\": " << r.triangles_with_repeated_vertex
     << ", \"non_finite_points\": " << r.non_finite_points
     << ", \"reference_size_mismatches\": " << r.reference_size_mismatches
     << ", \"negative_tets\": " << r.negative_tets << ", \"flat_tets\": " << r.flat_tets
     << ", \"boundary_faces\": " << r.boundary_faces << ", \"interior_faces\": " << r.interior_faces
     << ", \"interface_faces\": " << r.interface_faces
     << ", \"faces_shared_by_more_than_two_tets\": " << r.faces_shared_by_more_than_two_tets
     << ", \"faces_with_tets_on_same_side\": " << r.faces_with_tets_on_same_side
     << ", \"non_manifold_boundary_edges\": " << r.non_manifold_boundary_edges
     << ", \"non_manifold_boundary_vertices\": " << r.non_manifold_boundary_vertices
     << ", \"boundary_triangles_checked\": " << b(r.boundary_triangles_checked)
     << ", \"missing_boundary_triangles\": " << r.missing_boundary_triangles
     << ", \"extra_triangles\": " << r.extra_triangles << ", \"duplicate_triangles\": " << r.duplicate_triangles
     << ", \"misoriented_boundary_triangles\": " << r.misoriented_boundary_triangles
     << ", \"volume_checked\": " << b(r.volume_checked)
     << ", \"tet_volume\": " << format_json_number(r.tet_volume)
     << ", \"boundary_volume\": " << format_json_number(r.boundary_volume)
     << ", \"volume_identity_holds\": " << b(r.volume_identity_holds);
  if(r.expected_volume_checked)
    os << ", \"expected_volume\": " << format_json_number(r.expected_volume)
       << ", \"expected_volume_matches\": " << b(r.expected_volume_matches);
  os << ", \"boundary_self_intersections\": " << r.boundary_self_intersections
     << ", \"self_intersections_checked\": " << b(r.self_intersections_checked);
  os << ", \"unused_vertices\": " << r.unused_vertices
     << ", \"boundary_components\": " << r.number_of_boundary_components << ", \"boundary_euler_characteristics\": [";
  for(std::size_t i = 0; i < r.boundary_components.size(); ++i)
    os << (i ? ", " : "") << r.boundary_components[i].euler_characteristic;
  os << "], \"problems\": [";
  for(std::size_t i = 0; i < r.problems.size(); ++i)
    os << (i ? ", " : "") << internal::json_string(r.problems[i]);
  os << "]}";
  return os.str();
}

} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_VALIDITY_H
