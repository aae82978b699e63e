// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Last resort of the advancing front: closes the cavities it could not mesh.
// A cavity is a connected set of remaining front triangles (the unmeshed side
// positive). In order:
//  1. a fan from one of the cavity's vertices, when every other triangle of
//     the cavity sees it strictly on its inner side (no new point);
//  2. a fan from one Steiner point that every triangle sees strictly on its
//     inner side (a star-shaped cavity, e.g. Schönhardt's twisted prism);
//  3. TetGen's constrained tetrahedralization of all remaining triangles at
//     once (`-pY`: no Steiner point on them, Steiner points strictly inside
//     only), its tets kept by a flood from the inner side of the triangles,
//     and used only if they are positive and their boundary chain is exactly
//     the remaining triangles (tet_boundary_chain.h): a TetGen that fails,
//     dies or returns a wrong result is a failure of this step, which the
//     front answers by enlarging the cavity and filling again.
// A fan is accepted only if all its tets are positive and no live node lies in
// one of them (closed), which together make it a tiling of the cavity: the
// triangles wind once around every inner point. Anything left throws
// `Meshing_failure`.
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_FRONT_CAVITY_FILLING_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_FRONT_CAVITY_FILLING_H

#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/internal/front/front_geometry.h>

#include <algorithm>
#include <functional>
#include <array>
#include <map>
#include <numeric>
#include <set>
#include <string>
#include <vector>

#if defined(BUBBLE_MESH_3_HAS_TETGEN) || defined(TETLIBRARY)
#  ifndef TETLIBRARY
#    define TETLIBRARY
#  endif
#  include <CGAL/Bubble_mesh_3/internal/tet_boundary_chain.h>
#  include <CGAL/Bubble_mesh_3/internal/tetgen_isolated.h>
#  define CGAL_BUBBLE_MESH_3_CAVITY_USES_TETGEN 1
#endif

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {
namespace front {

struct Cavity_fill_statistics {
  std::size_t cavities = 0;
  std::size_t vertex_star_fills = 0;
  std::size_t steiner_star_fills = 0;
  std::size_t tetgen_fills = 0;
};

/// whether the cavity filler can call TetGen in this build
#ifdef CGAL_BUBBLE_MESH_3_CAVITY_USES_TETGEN
constexpr bool cavity_filling_has_tetgen = true;
#else
constexpr bool cavity_filling_has_tetgen = false;
#endif

/// connected components of triangles sharing an edge
inline std::vector<std::vector<Tri>> edge_connected_components(const std::vector<Tri>& faces)
{
  std::vector<int> parent(faces.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int i) {
    while(parent[i] != i)
      i = parent[i] = parent[parent[i]];
    return i;
  };
  std::map<std::pair<int, int>, int> first;
  for(int f = 0; f < static_cast<int>(faces.size()); ++f)
    for(int k = 0; k < 3; ++k) {
      const int a = faces[f][k], b = faces[f][(k + 1) % 3];
      auto it = first.emplace(std::make_pair(std::min(a, b), std::max(a, b)), f);
      if(!it.second)
        parent[find(f)] = find(it.first->second);
    }
  std::map<int, std::vector<Tri>> by_root;
  for(int f = 0; f < static_cast<int>(faces.size()); ++f)
    by_root[find(f)].push_back(faces[f]);
  std::vector<std::vector<Tri>> out;
  for(auto& kv : by_root)
    out.push_back(std::move(kv.second));
  return out;
}

/// The fan from point `apex` (an id in pts) over the triangles not incident to
/// it, if it tiles the cavity (see the file comment); `watch` are the live
/// nodes that must not lie in it.
template <typename Traits>
bool fan(const std::vector<Tri>& cavity, int apex, const std::vector<int>& watch,
         const std::vector<typename Traits::Point_3>& pts, const Traits& traits, std::vector<Tet>& out)
{
  auto orientation = traits.orientation_3_object();
  std::vector<Tet> tets;
  for(const Tri& f : cavity) {
    if(f[0] == apex || f[1] == apex || f[2] == apex)
      continue;
    if(orientation(pts[f[0]], pts[f[1]], pts[f[2]], pts[apex]) != CGAL::POSITIVE)
      return false;
    tets.push_back(Tet{{f[0], f[1], f[2], apex}});
  }
  if(tets.empty())
    return false;
  for(const Tet& t : tets)
    for(int q : watch) {
      if(q == t[0] || q == t[1] || q == t[2] || q == t[3])
        continue;
      if(in_closed_tet(pts[q], t, pts, traits))
        return false;
    }
  out.insert(out.end(), tets.begin(), tets.end());
  return true;
}

#ifdef CGAL_BUBBLE_MESH_3_CAVITY_USES_TETGEN
/// TetGen on all the remaining triangles; returns the tets of the cavities
template <typename Traits>
std::vector<Tet> tetgen_fill(const std::vector<Tri>& faces, const std::vector<int>& free_nodes,
                             std::vector<typename Traits::Point_3>& pts, bool allow_steiner, const Traits& traits,
                             const std::function<bool()>& should_stop)
{
  typedef typename Traits::Point_3 Point_3;
  std::vector<int> ids;
  for(const Tri& f : faces)
    ids.insert(ids.end(), f.begin(), f.end());
  ids.insert(ids.end(), free_nodes.begin(), free_nodes.end());
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  std::map<int, int> local;
  for(int i = 0; i < static_cast<int>(ids.size()); ++i)
    local[ids[i]] = i;

  tetgenio in;
  in.firstnumber = 0;
  in.numberofpoints = static_cast<int>(ids.size());
  in.pointlist = new REAL[3 * ids.size()];
  for(std::size_t i = 0; i < ids.size(); ++i) {
    in.pointlist[3 * i] = CGAL::to_double(pts[ids[i]].x());
    in.pointlist[3 * i + 1] = CGAL::to_double(pts[ids[i]].y());
    in.pointlist[3 * i + 2] = CGAL::to_double(pts[ids[i]].z());
  }
  in.numberoffacets = static_cast<int>(faces.size());
  in.facetlist = new tetgenio::facet[faces.size()];
  for(std::size_t f = 0; f < faces.size(); ++f) {
    tetgenio::facet& facet = in.facetlist[f];
    tetgenio::init(&facet);
    facet.numberofpolygons = 1;
    facet.polygonlist = new tetgenio::polygon[1];
    tetgenio::polygon& poly = facet.polygonlist[0];
    tetgenio::init(&poly);
    poly.numberofvertices = 3;
    poly.vertexlist = new int[3];
    for(int k = 0; k < 3; ++k)
      poly.vertexlist[k] = local[faces[f][k]];
  }
  // p: PLC, Y: no Steiner point on the triangles, M: keep coplanar triangles
  // apart, z: 0-based, Q: quiet; in a child process (tetgen_isolated.h)
  Tetgen_output out;
  std::string error;
  if(!tetrahedralize_isolated("pYMzQ", in, out, error, should_stop))
    throw Meshing_failure("advancing front: TetGen could not tetrahedralize the remaining cavities (" + error + ")");
  const int number_of_points = int(out.points.size() / 3);
  std::vector<int> global(std::size_t(number_of_points), -1);
  for(std::size_t i = 0; i < ids.size(); ++i)
    global[i] = ids[i];
  std::vector<Tet> all;
  for(std::size_t t = 0; 4 * t + 3 < out.tets.size(); ++t) {
    Tet tet;
    for(int k = 0; k < 4; ++k) {
      const int o = out.tets[4 * t + std::size_t(k)];
      if(o < 0 || o >= number_of_points)
        throw Meshing_failure("advancing front: bad TetGen vertex id");
      tet[k] = o;
    }
    all.push_back(tet);
  }
  // positions of TetGen's own points, as they will be appended
  std::vector<Point_3> tg(static_cast<std::size_t>(number_of_points));
  for(int i = 0; i < number_of_points; ++i)
    tg[i] = global[i] >= 0 ? pts[global[i]]
                           : Point_3(out.points[3 * i], out.points[3 * i + 1], out.points[3 * i + 2]);
  auto orientation = traits.orientation_3_object();
  for(Tet& t : all) {
    const CGAL::Orientation o = orientation(tg[t[0]], tg[t[1]], tg[t[2]], tg[t[3]]);
    if(o == CGAL::NEGATIVE)
      std::swap(t[2], t[3]);
    else if(o != CGAL::POSITIVE)
      throw Meshing_failure("advancing front: TetGen returned a flat tet in a cavity");
  }
  // flood from the inner side of the remaining triangles across the others
  std::map<Tri, std::vector<int>> tets_of;
  for(int t = 0; t < static_cast<int>(all.size()); ++t)
    for(const Tri& o : outward_faces(all[t]))
      tets_of[sorted(o)].push_back(t);
  std::set<Tri> walls;
  std::vector<int> stack;
  std::vector<char> inside(all.size(), 0);
  for(const Tri& f : faces) {
    const Tri lf{{local[f[0]], local[f[1]], local[f[2]]}};
    walls.insert(sorted(lf));
    auto it = tets_of.find(sorted(lf));
    if(it == tets_of.end())
      throw Meshing_failure("advancing front: TetGen lost a cavity triangle");
    bool seeded = false;
    for(int t : it->second) {
      int w = -1;
      for(int v : all[t])
        if(v != lf[0] && v != lf[1] && v != lf[2])
          w = v;
      if(orientation(tg[lf[0]], tg[lf[1]], tg[lf[2]], tg[w]) == CGAL::POSITIVE) {
        seeded = true;
        if(!inside[t]) {
          inside[t] = 1;
          stack.push_back(t);
        }
      }
    }
    if(!seeded)
      throw Meshing_failure("advancing front: TetGen left a cavity triangle without a tet");
  }
  while(!stack.empty()) {
    const int t = stack.back();
    stack.pop_back();
    for(const Tri& o : outward_faces(all[t])) {
      const Tri key = sorted(o);
      if(walls.count(key))
        continue;
      for(int u : tets_of[key])
        if(!inside[u]) {
          inside[u] = 1;
          stack.push_back(u);
        }
    }
  }
  std::vector<Tet> result;
  for(std::size_t t = 0; t < all.size(); ++t) {
    if(!inside[t])
      continue;
    Tet g;
    for(int k = 0; k < 4; ++k) {
      int& id = global[all[t][k]];
      if(id < 0) {
        if(!allow_steiner)
          throw Meshing_failure("advancing front: the remaining cavities need Steiner points, which are disallowed");
        id = static_cast<int>(pts.size());
        pts.push_back(tg[all[t][k]]);
      }
      g[k] = id;
    }
    result.push_back(g);
  }
  std::vector<Tri> expected; // the triangles seen from the tets: reversed
  for(const Tri& f : faces)
    expected.push_back(Tri{{f[0], f[2], f[1]}});
  if(!tets_tile_surface(result, expected))
    throw Meshing_failure("advancing front: TetGen's tets do not tile the remaining cavities (a wrong result)");
  return result;
}
#endif

/// Closes every cavity bounded by `faces` (see the file comment). Appends
/// Steiner points to `pts`; returns the new tets (positive).
template <typename Traits>
std::vector<Tet> fill_cavities(const std::vector<Tri>& faces, const std::vector<int>& free_nodes,
                               std::vector<typename Traits::Point_3>& pts, bool allow_steiner, const Traits& traits,
                               Cavity_fill_statistics& stats, const std::function<bool()>& should_stop = {})
{
  typedef typename Traits::Point_3 Point_3;
  std::vector<Tet> result;
  if(faces.empty())
    return result;
  // every live node: the vertices of all remaining triangles and the free nodes
  std::vector<int> watch = free_nodes;
  for(const Tri& f : faces)
    watch.insert(watch.end(), f.begin(), f.end());
  std::sort(watch.begin(), watch.end());
  watch.erase(std::unique(watch.begin(), watch.end()), watch.end());

  std::vector<Tri> left;
  for(const std::vector<Tri>& cavity : edge_connected_components(faces)) {
    ++stats.cavities;
    std::vector<int> verts;
    for(const Tri& f : cavity)
      verts.insert(verts.end(), f.begin(), f.end());
    std::sort(verts.begin(), verts.end());
    verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
    bool done = false;
    if(cavity.size() <= 400)
      for(int v : verts)
        if(fan(cavity, v, watch, pts, traits, result)) {
          ++stats.vertex_star_fills;
          done = true;
          break;
        }
    if(!done && allow_steiner) {
      // candidates: the vertex centroid and the area-weighted centroid of the triangles
      double c[3] = {0, 0, 0}, w[3] = {0, 0, 0}, wsum = 0;
      for(int v : verts) {
        c[0] += CGAL::to_double(pts[v].x()) / double(verts.size());
        c[1] += CGAL::to_double(pts[v].y()) / double(verts.size());
        c[2] += CGAL::to_double(pts[v].z()) / double(verts.size());
      }
      for(const Tri& f : cavity) {
        const double a = std::sqrt(CGAL::to_double(
            CGAL::squared_area(pts[f[0]], pts[f[1]], pts[f[2]])));
        for(int k = 0; k < 3; ++k) {
          w[0] += a * CGAL::to_double(pts[f[k]].x()) / 3;
          w[1] += a * CGAL::to_double(pts[f[k]].y()) / 3;
          w[2] += a * CGAL::to_double(pts[f[k]].z()) / 3;
        }
        wsum += a;
      }
      std::vector<Point_3> tries{Point_3(c[0], c[1], c[2])};
      if(wsum > 0)
        tries.emplace_back(w[0] / wsum, w[1] / wsum, w[2] / wsum);
      for(const Point_3& s : tries) {
        pts.push_back(s);
        if(fan(cavity, static_cast<int>(pts.size()) - 1, watch, pts, traits, result)) {
          ++stats.steiner_star_fills;
          done = true;
          break;
        }
        pts.pop_back();
      }
    }
    if(!done)
      left.insert(left.end(), cavity.begin(), cavity.end());
  }
  if(left.empty())
    return result;
#ifdef CGAL_BUBBLE_MESH_3_CAVITY_USES_TETGEN
  std::vector<Tet> filled = tetgen_fill(left, free_nodes, pts, allow_steiner, traits, should_stop);
  ++stats.tetgen_fills;
  result.insert(result.end(), filled.begin(), filled.end());
  return result;
#else
  throw Meshing_failure("advancing front: " + std::to_string(left.size()) +
                        " front triangles enclose volume that no node choice could mesh and that is not "
                        "star-shaped; this build has no TetGen to fill it");
#endif
}

} // namespace front
} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_FRONT_CAVITY_FILLING_H
