// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Feature detection at the size meshed. CGAL's detect_features(angle) makes a
// feature curve of every chain of sharp edges, however short: on a scanned or
// decimated surface (the armadillo, a femur, a coarse knot) most of them are
// isolated creases a fraction of an element long, each ending in two corners
// the packer must keep as nodes a fraction of an element apart, so the tets
// between them are needles no later stage can mend. A chain that has a free
// end (a crease that fades out into its patch) separates nothing: dropping it
// leaves every patch as it was. Dropping those shorter than one element
// (measured in the metric) keeps every feature the mesh can represent. For
// the same reason the sliver triangles along sharp edges below a tenth of an
// element are flipped or collapsed away first (the zigzag or ledge a CAD
// export leaves where two walls nearly meet), and a patch narrower than that
// (a chamfer strip, a fold of a scan) joins a neighbour.
#ifndef CGAL_BUBBLE_MESH_3_DETECT_FEATURES_H
#define CGAL_BUBBLE_MESH_3_DETECT_FEATURES_H

#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/internal/json.h>
#include <CGAL/Bubble_mesh_3/parameters.h>
#include <CGAL/Polygon_mesh_processing/detect_features.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {

/// What `detect_features()` found and what it dropped.
struct Feature_detection_report {
  std::size_t sharp_edges = 0;    ///< edges whose dihedral angle passed the angle test
  std::size_t dropped_chains = 0; ///< chains with a free end shorter than the minimum length
  std::size_t dropped_edges = 0;  ///< sharp edges in those chains
  std::size_t curves = 0;         ///< polylines given to the domain
  std::size_t corners = 0;        ///< distinct end points of the open polylines
  std::size_t patches = 0;        ///< surface patches (after the merging; unchanged by the dropping)
  std::size_t merged_patches = 0; ///< patches narrower than a tenth of an element, merged into a neighbour
  std::size_t merged_edges = 0;   ///< sharp edges between merged patches (no longer sharp)
  std::size_t replaced_faces = 0; ///< input faces flipped or collapsed away as slivers below the resolution
};

/// the report as a JSON object (keys as the member names)
inline std::string to_json(const Feature_detection_report& r)
{
  auto num = [](std::size_t x) { return internal::format_json_number(double(x)); };
  return "{\"sharp_edges\": " + num(r.sharp_edges) + ", \"dropped_chains\": " + num(r.dropped_chains) +
         ", \"dropped_edges\": " + num(r.dropped_edges) + ", \"curves\": " + num(r.curves) +
         ", \"corners\": " + num(r.corners) + ", \"patches\": " + num(r.patches) +
         ", \"merged_patches\": " + num(r.merged_patches) + ", \"merged_edges\": " + num(r.merged_edges) +
         ", \"replaced_faces\": " + num(r.replaced_faces) + "}";
}

/// The feature curves of a polyhedron, with the surface patches each one
/// borders, ready to be given to a `Polyhedral_mesh_domain_with_features_3`
/// built from that polyhedron.
template <typename Point_3, typename Patch_id = int>
struct Detected_features {
  std::vector<std::vector<Point_3>> polylines; ///< closed ones repeat their first point at the end
  std::vector<std::vector<Patch_id>> incident_patches;
  Feature_detection_report report;

  /// adds the curves to `domain` (which must have been built from the
  /// polyhedron `detect_features()` marked, and have no features yet)
  template <typename Domain>
  void add_to(Domain& domain) const
  {
    std::vector<std::pair<std::vector<typename Domain::Point_3>, std::vector<typename Domain::Surface_patch_index>>>
        with_patches;
    with_patches.reserve(polylines.size());
    for(std::size_t i = 0; i < polylines.size(); ++i) {
      with_patches.emplace_back();
      for(const Point_3& p : polylines[i])
        with_patches.back().first.emplace_back(p.x(), p.y(), p.z());
      for(const Patch_id& id : incident_patches[i])
        with_patches.back().second.push_back(typename Domain::Surface_patch_index(id));
    }
    typedef typename decltype(with_patches)::value_type Entry;
    domain.add_features_and_incidences(with_patches.begin(), with_patches.end(),
                                       CGAL::First_of_pair_property_map<Entry>(),
                                       CGAL::Second_of_pair_property_map<Entry>());
  }
};

namespace internal {

/// The width below which a patch is merged into a neighbour, as a fraction
/// of the largest size the metric asks on it: the floor of
/// `Feature_size_metric_field_3` (features closer than that are below the
/// resolution asked).
constexpr double narrow_patch_fraction() { return 0.1; }
/// how much wider than a narrow patch the neighbour it joins must be
constexpr double wider_neighbour_ratio() { return 4; }

/// A face with an angle above this (degrees) is a cap: flipped away when its
/// height is below the resolution (`remove_sliver_faces()`)
constexpr double sliver_cap_angle() { return 175; }
/// A face whose longest edge is this many times its shortest is a needle:
/// its shortest edge is collapsed when below the resolution
constexpr double sliver_needle_ratio() { return 10; }

/// Flips away the caps and collapses the needles along the sharp edges (at
/// `feature_angle`, degrees) of the input surface whose height or shortest
/// edge is below `narrow_patch_fraction()` of the
/// largest size `metric` asks (the smallest such size over the vertices), as
/// `Polygon_mesh_processing::experimental::remove_almost_degenerate_faces()`
/// does: the sliver facets a CAD export leaves where two walls nearly meet
/// (a zigzag of sharp edges a few thousandths apart along their corner, a
/// ledge as narrow) put curves and corners closer than the feature sizes go,
/// so the tets between them are flat; without them the surface moves by less
/// than that resolution. Kept as it was if the result intersects itself.
/// Returns the number of input faces no longer in the surface.
template <typename Polyhedron, typename MetricField>
std::size_t remove_sliver_faces(Polyhedron& polyhedron, const MetricField& metric, double feature_angle)
{
  typedef typename boost::property_traits<typename boost::property_map<Polyhedron, vertex_point_t>::type>::value_type
      Point_3;
  auto vpm = get(vertex_point, polyhedron);
  double smallest = std::numeric_limits<double>::infinity();
  for(auto v : vertices(polyhedron))
    smallest = std::min(smallest, metric(get(vpm, v)).principal_sizes().maxCoeff());
  const double resolution = narrow_patch_fraction() * smallest;
  if(!(resolution > 0) || !std::isfinite(resolution))
    return 0;
  // each face as the sorted triple of its corners' coordinates
  typedef std::array<std::array<double, 3>, 3> Face_key;
  auto face_keys = [&] {
    std::vector<Face_key> keys;
    keys.reserve(num_faces(polyhedron));
    for(auto f : faces(polyhedron)) {
      Face_key key;
      std::size_t i = 0;
      for(auto v : vertices_around_face(halfedge(f, polyhedron), polyhedron)) {
        const Point_3& p = get(vpm, v);
        if(i < 3)
          key[i] = {{CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())}};
        ++i;
      }
      std::sort(key.begin(), key.end());
      keys.push_back(key);
    }
    std::sort(keys.begin(), keys.end());
    return keys;
  };
  const std::vector<Face_key> before = face_keys();
  const Polyhedron original = polyhedron;
  // only the faces along sharp edges: a sliver in a smooth region is no
  // feature, and flipping it could make a crease
  typedef typename boost::graph_traits<Polyhedron>::vertex_descriptor vertex_descriptor;
  typedef typename boost::graph_traits<Polyhedron>::halfedge_descriptor halfedge_descriptor;
  std::vector<typename boost::graph_traits<Polyhedron>::face_descriptor> along_sharp_edges;
  const double cos_angle = std::cos(feature_angle * CGAL_PI / 180);
  auto sharp = [&](halfedge_descriptor h) {
    const auto n = CGAL::Polygon_mesh_processing::compute_face_normal(face(h, polyhedron), polyhedron);
    const auto m = CGAL::Polygon_mesh_processing::compute_face_normal(face(opposite(h, polyhedron), polyhedron),
                                                                      polyhedron);
    return CGAL::to_double(n * m) < cos_angle;
  };
  for(auto f : faces(polyhedron))
    for(halfedge_descriptor h : halfedges_around_face(halfedge(f, polyhedron), polyhedron))
      if(sharp(h)) {
        along_sharp_edges.push_back(f);
        break;
      }
  if(along_sharp_edges.empty())
    return 0;
  // Only what is below the resolution moves: a vertex inside a smooth sharp
  // curve (two sharp edges turning by less than 30 degrees: a finely cut rim)
  // stays, or collapsing its short edges would coarsen the curve, cascading
  // along it; so does a corner (any other vertex on sharp edges) unless a
  // sharp edge shorter than the resolution joins it to another corner (a jog
  // of a zigzag, a ledge's end)
  std::set<vertex_descriptor> on_smooth_curves, corners, constrained;
  std::map<vertex_descriptor, std::vector<halfedge_descriptor>> sharp_out;
  for(vertex_descriptor v : vertices(polyhedron)) {
    std::vector<halfedge_descriptor>& out = sharp_out[v];
    for(halfedge_descriptor h : halfedges_around_source(v, polyhedron))
      if(sharp(h))
        out.push_back(h);
    if(out.empty())
      continue;
    bool smooth = false;
    if(out.size() == 2) {
      const auto a = get(vpm, target(out[0], polyhedron)) - get(vpm, v),
                 b = get(vpm, target(out[1], polyhedron)) - get(vpm, v);
      const double ab = std::sqrt(CGAL::to_double(a * a) * CGAL::to_double(b * b));
      smooth = ab > 0 && CGAL::to_double(a * b) < -std::cos(30 * CGAL_PI / 180) * ab;
    }
    (smooth ? on_smooth_curves : corners).insert(v);
  }
  constrained = on_smooth_curves;
  for(vertex_descriptor v : corners) {
    bool jog = false;
    for(halfedge_descriptor h : sharp_out[v])
      jog = jog || (corners.count(target(h, polyhedron)) &&
                    CGAL::to_double(CGAL::squared_distance(get(vpm, v), get(vpm, target(h, polyhedron)))) <
                        resolution * resolution);
    if(!jog)
      constrained.insert(v);
  }
  CGAL::Polygon_mesh_processing::experimental::remove_almost_degenerate_faces(
      along_sharp_edges, polyhedron, std::cos(sliver_cap_angle() * CGAL_PI / 180), sliver_needle_ratio(), resolution,
      CGAL::parameters::flip_triangle_height_threshold(resolution)
          .vertex_is_constrained_map(CGAL::make_boolean_property_map(constrained)));
  const std::vector<Face_key> after = face_keys();
  std::vector<Face_key> gone;
  std::set_difference(before.begin(), before.end(), after.begin(), after.end(), std::back_inserter(gone));
  if(gone.empty())
    return 0;
  if(CGAL::Polygon_mesh_processing::does_self_intersect(polyhedron)) {
    polyhedron = original;
    return 0;
  }
  return gone.size();
}

/// Un-marks the sharp edges between patches of one group (`root` maps a patch
/// id 1..n to its group's representative) and renumbers the groups 1..m in
/// the order of their representatives' ids. Returns m.
template <typename Polyhedron, typename EdgeIsFeature, typename PatchId, typename Root>
std::size_t merge_patch_groups(Polyhedron& polyhedron, EdgeIsFeature eif, PatchId pid, Root& root, int n,
                               std::size_t& unmarked_edges)
{
  typedef boost::graph_traits<Polyhedron> GT;
  for(typename GT::edge_descriptor e : edges(polyhedron)) {
    if(!get(eif, e))
      continue;
    const typename GT::halfedge_descriptor h = halfedge(e, polyhedron);
    const int p = get(pid, face(h, polyhedron)), q = get(pid, face(opposite(h, polyhedron), polyhedron));
    if(p != q && root(p) == root(q)) {
      put(eif, e, false);
      ++unmarked_edges;
    }
  }
  std::vector<int> number(std::size_t(n) + 1, 0);
  int m = 0;
  for(int p = 1; p <= n; ++p)
    if(root(p) == p)
      number[std::size_t(p)] = ++m;
  for(typename GT::face_descriptor f : faces(polyhedron))
    put(pid, f, number[std::size_t(root(get(pid, f)))]);
  return std::size_t(m);
}

/// Refills the incident patches of the vertices on sharp edges, as CGAL's
/// feature detection fills them (other vertices get none).
template <typename Polyhedron, typename EdgeIsFeature, typename PatchId, typename IncidentPatches>
void refill_incident_patches(const Polyhedron& polyhedron, EdgeIsFeature eif, PatchId pid, IncidentPatches vip)
{
  typedef boost::graph_traits<Polyhedron> GT;
  for(typename GT::vertex_descriptor v : vertices(polyhedron)) {
    auto& ids = vip[v];
    ids.clear();
    bool on_sharp_edge = false;
    for(typename GT::halfedge_descriptor h : halfedges_around_target(v, polyhedron))
      on_sharp_edge = on_sharp_edge || get(eif, edge(h, polyhedron));
    if(on_sharp_edge)
      for(typename GT::halfedge_descriptor h : halfedges_around_target(v, polyhedron))
        ids.insert(get(pid, face(h, polyhedron)));
  }
}

/// Merges every surface patch narrower than `narrow_patch_fraction()` of the
/// largest size `metric` asks on it into the neighbour it meets at the
/// gentlest turn among those `wider_neighbour_ratio()` times wider, by
/// un-marking the sharp edges between the two, until no patch is that
/// narrow; renumbers the patches 1..n and refills the vertices'
/// incident patches. A patch's width is 2 area / perimeter (the width of a
/// strip, half the height of a sliver triangle), its perimeter the length of
/// the sharp edges it shares with other patches. Such a patch (a chamfer
/// strip or a sliver facet of a CAD model, a fold of a scan) puts two curves,
/// or a curve and a corner, closer than the feature sizes go: the packed
/// nodes cannot represent it and the tets there are flat. Merged, the
/// remaining curve stays within the patch's width of the surface.
/// Returns the number of patches merged; `patches` is updated.
template <typename Polyhedron, typename MetricField, typename EdgeIsFeature, typename PatchId,
          typename IncidentPatches>
std::size_t merge_narrow_patches(Polyhedron& polyhedron, const MetricField& metric, EdgeIsFeature eif, PatchId pid,
                                 IncidentPatches vip, std::size_t& patches, std::size_t& unmarked_edges)
{
  typedef boost::graph_traits<Polyhedron> GT;
  typedef typename GT::face_descriptor face_descriptor;
  typedef typename GT::edge_descriptor edge_descriptor;
  typedef typename GT::halfedge_descriptor halfedge_descriptor;
  typedef typename GT::vertex_descriptor vertex_descriptor;
  typedef typename boost::property_traits<typename boost::property_map<Polyhedron, vertex_point_t>::type>::value_type
      Point_3;
  auto vpm = get(vertex_point, polyhedron);
  auto at = [&](vertex_descriptor v) {
    const Point_3& p = get(vpm, v);
    return std::array<double, 3>{{CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())}};
  };
  // per face: twice its area, unit normal, centroid
  struct Face_data {
    double area;
    std::array<double, 3> normal, centroid;
  };
  std::map<face_descriptor, Face_data> data;
  for(face_descriptor f : faces(polyhedron)) {
    const halfedge_descriptor h = halfedge(f, polyhedron);
    const auto a = at(source(h, polyhedron)), b = at(target(h, polyhedron)),
               c = at(target(next(h, polyhedron), polyhedron));
    const std::array<double, 3> u{{b[0] - a[0], b[1] - a[1], b[2] - a[2]}}, v{{c[0] - a[0], c[1] - a[1], c[2] - a[2]}};
    std::array<double, 3> n{{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]}};
    const double twice_area = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for(double& x : n)
      x = twice_area > 0 ? x / twice_area : 0;
    data[f] = Face_data{0.5 * twice_area, n,
                        {{(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3}}};
  }
  auto turn = [&](face_descriptor f, face_descriptor g) { // degrees, 0: flat
    const auto &n = data[f].normal, &m = data[g].normal;
    return std::acos(std::max(-1.0, std::min(1.0, n[0] * m[0] + n[1] * m[1] + n[2] * m[2]))) * 180 / CGAL_PI;
  };

  std::size_t merged = 0;
  for(;;) {
    const int n = int(patches);
    std::vector<double> area(std::size_t(n) + 1, 0), perimeter(std::size_t(n) + 1, 0);
    std::vector<std::size_t> count(std::size_t(n) + 1, 0), seen(std::size_t(n) + 1, 0);
    for(face_descriptor f : faces(polyhedron)) {
      const int p = get(pid, f);
      area[std::size_t(p)] += data[f].area;
      ++count[std::size_t(p)];
    }
    // the shared boundary of each pair of patches: length, and length x turn
    std::map<std::pair<int, int>, std::array<double, 2>> shared;
    for(edge_descriptor e : edges(polyhedron)) {
      if(!get(eif, e))
        continue;
      const halfedge_descriptor h = halfedge(e, polyhedron);
      const face_descriptor f = face(h, polyhedron), g = face(opposite(h, polyhedron), polyhedron);
      const int p = get(pid, f), q = get(pid, g);
      if(p == q)
        continue;
      const auto a = at(source(h, polyhedron)), b = at(target(h, polyhedron));
      const double length = std::sqrt(CGAL::square(b[0] - a[0]) + CGAL::square(b[1] - a[1]) + CGAL::square(b[2] - a[2]));
      const double t = turn(f, g);
      perimeter[std::size_t(p)] += length;
      perimeter[std::size_t(q)] += length;
      for(const auto& key : {std::make_pair(p, q), std::make_pair(q, p)}) {
        std::array<double, 2>& s = shared[key];
        s[0] += length;
        s[1] += length * t;
      }
    }
    // narrow patches: the width against the floor at up to 16 of its faces
    // (the smallest largest size found: a patch is merged only where the
    // metric is coarse all over it)
    std::vector<double> floor(std::size_t(n) + 1, std::numeric_limits<double>::infinity());
    std::vector<char> candidate(std::size_t(n) + 1, 0);
    for(int p = 1; p <= n; ++p)
      candidate[std::size_t(p)] = perimeter[std::size_t(p)] > 0;
    for(face_descriptor f : faces(polyhedron)) {
      const std::size_t p = std::size_t(get(pid, f));
      if(!candidate[p] || seen[p]++ % std::max<std::size_t>(1, count[p] / 16) != 0)
        continue;
      const auto& c = data[f].centroid;
      const auto sizes = metric(Point_3(c[0], c[1], c[2])).principal_sizes();
      floor[p] = std::min(floor[p], narrow_patch_fraction() * sizes.maxCoeff());
    }
    std::vector<double> width(std::size_t(n) + 1, std::numeric_limits<double>::infinity());
    for(int p = 1; p <= n; ++p)
      if(candidate[std::size_t(p)])
        width[std::size_t(p)] = 2 * area[std::size_t(p)] / perimeter[std::size_t(p)];
    std::vector<std::pair<double, int>> narrow;
    for(int p = 1; p <= n; ++p)
      if(width[std::size_t(p)] < floor[std::size_t(p)])
        narrow.emplace_back(width[std::size_t(p)] / floor[std::size_t(p)], p);
    if(narrow.empty())
      break;
    const std::size_t merged_before = merged;
    std::sort(narrow.begin(), narrow.end());
    // each into the neighbour met at the gentlest mean turn (then the
    // longest shared boundary) among those at least `wider_neighbour_ratio()` times wider:
    // a patch is narrow against its neighbours, not only against the size
    // (the faces of a part smaller than an element stay: its corners and
    // curves are the part); merges chain through a union-find
    std::vector<int> parent(std::size_t(n) + 1);
    std::iota(parent.begin(), parent.end(), 0);
    std::function<int(int)> root = [&](int p) { return parent[std::size_t(p)] == p ? p : parent[std::size_t(p)] = root(parent[std::size_t(p)]); };
    for(const auto& entry : narrow) {
      const int p = entry.second;
      int best = -1;
      double best_turn = 0, best_length = 0;
      for(auto it = shared.lower_bound({p, 0}); it != shared.end() && it->first.first == p; ++it) {
        if(!(width[std::size_t(it->first.second)] >= wider_neighbour_ratio() * width[std::size_t(p)]))
          continue;
        const double mean_turn = it->second[1] / it->second[0];
        if(best < 0 || mean_turn < best_turn - 1e-9 ||
           (!(mean_turn > best_turn + 1e-9) && it->second[0] > best_length)) {
          best = it->first.second;
          best_turn = mean_turn;
          best_length = it->second[0];
        }
      }
      if(best < 0)
        continue;
      const int a = root(p), b = root(best);
      if(a != b) {
        parent[std::size_t(a)] = b;
        ++merged;
      }
    }
    if(merged == merged_before)
      break;
    patches = merge_patch_groups(polyhedron, eif, pid, root, n, unmarked_edges);
  }
  if(merged > 0)
    refill_incident_patches(polyhedron, eif, pid, vip);
  return merged;
}

} // namespace internal

/// \ingroup PkgBubbleMesh3Functions
/// Detects the sharp features of `polyhedron` for meshing with `metric`:
/// marks its sharp edges and numbers its surface patches as
/// `Polyhedral_mesh_domain_with_features_3::detect_features()` does (an edge
/// is sharp when the normals of its two faces differ by more than the feature
/// angle), then un-marks every chain of sharp edges that has a free end and is
/// shorter, in `metric`, than the minimum feature length, repeatedly (a chain
/// left with a free end by the removal of its branches is tested in turn).
/// Such a chain borders the same patch on both sides, so patches do not
/// change; chains between corners where three or more chains meet and closed
/// chains are always kept. First, the sliver triangles along sharp edges
/// whose height (a cap: an angle above 175 degrees) or shortest edge (a
/// needle: 10 times shorter than its longest) is below a tenth of the
/// smallest of the largest sizes the metric asks are flipped or collapsed
/// away (`Polygon_mesh_processing::experimental::remove_almost_degenerate_faces()`;
/// vertices inside smooth curves and corners stay, except corners joined to
/// another by a sharp edge below that resolution; the polyhedron changes,
/// by less than that; kept as it was if the result would intersect itself): the zigzag of sliver facets a CAD export leaves
/// along the corner of two walls, a ledge as narrow, put curves and corners
/// closer than the feature sizes go. Then every patch narrower than a tenth of
/// the largest size the metric asks on it (2 area / perimeter: a chamfer
/// strip, a sliver facet) is merged into the neighbour it meets at the
/// gentlest turn (the sharp edges between them are un-marked): its curves
/// would be closer than the feature sizes go, and the mesh stays within its
/// width of the surface. Returns the remaining chains split into polylines
/// (at corners and at turns of 90 degrees or sharper, as CGAL splits them),
/// to be given to the domain:
/// \code
///   auto features = CGAL::Bubble_mesh_3::detect_features(polyhedron, metric);
///   Domain domain(polyhedron);
///   features.add_to(domain);
/// \endcode
///
/// \tparam Polyhedron `Mesh_polyhedron_3<K>::type` (the polyhedron type of
///   `Polyhedral_mesh_domain_with_features_3`), closed and triangulated
/// \tparam MetricField a model of `MetricField_3`
/// \param np optional named parameters: `feature_angle` (degrees, default 60,
///   as CGAL's), `minimum_feature_length` (metric length below which a chain
///   with a free end is dropped; default 1, one element; 0 keeps everything,
///   slivers and narrow patches too, which is CGAL's `detect_features()`)
/// \throws Invalid_input if the angle is not in [0, 180] or the length is
///   negative or not a number
template <typename Polyhedron, typename MetricField, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Detected_features<typename boost::property_traits<typename boost::property_map<Polyhedron, vertex_point_t>::type>::value_type>
detect_features(Polyhedron& polyhedron, const MetricField& metric,
                const NamedParameters& np = CGAL::parameters::default_values())
{
  typedef boost::graph_traits<Polyhedron> GT;
  typedef typename GT::vertex_descriptor vertex_descriptor;
  typedef typename GT::halfedge_descriptor halfedge_descriptor;
  typedef typename GT::edge_descriptor edge_descriptor;
  typedef typename boost::property_traits<typename boost::property_map<Polyhedron, vertex_point_t>::type>::value_type
      Point_3;
  typedef int Patch_id;

  const double angle = CGAL::parameters::choose_parameter(
      CGAL::parameters::get_parameter(np, internal_np::feature_angle), 60.0);
  const double min_length = CGAL::parameters::choose_parameter(
      CGAL::parameters::get_parameter(np, internal_np::minimum_feature_length), 1.0);
  if(!(angle >= 0 && angle <= 180))
    throw Invalid_input("detect_features: the feature angle must be between 0 and 180 degrees");
  if(!(min_length >= 0))
    throw Invalid_input("detect_features: the minimum feature length must be a number >= 0");

  auto vpm = get(vertex_point, polyhedron);
  auto eif = get(CGAL::edge_is_feature, polyhedron);
  auto pid = get(CGAL::face_patch_id_t<Patch_id>(), polyhedron);
  auto vip = get(CGAL::vertex_incident_patches_t<Patch_id>(), polyhedron);

  Detected_features<Point_3> out;
  // sliver facets below the resolution meshed go first: the patches and
  // curves are those of the surface meshed
  if(min_length > 0)
    out.report.replaced_faces = internal::remove_sliver_faces(polyhedron, metric, angle);
  // patch ids from 1, as CGAL numbers them (0 would read as "no patch")
  out.report.patches = CGAL::Polygon_mesh_processing::sharp_edges_segmentation(
      polyhedron, angle, eif, pid,
      CGAL::parameters::first_index(1)
          .face_index_map(get_initialized_face_index_map(polyhedron))
          .vertex_incident_patches_map(vip));

  // patches narrower than a tenth of an element join a neighbour (before
  // the chains are walked: the edges between them are no longer sharp)
  if(min_length > 0)
    out.report.merged_patches =
        internal::merge_narrow_patches(polyhedron, metric, eif, pid, vip, out.report.patches, out.report.merged_edges);

  // the sharp-edge graph: per vertex, its sharp halfedges (pointing away).
  // Walked in the order the vertices were first met (`sharp_vertices`), not
  // in the map's: a Polyhedron_3 descriptor compares by address, so the
  // map's order, and with it the curves' order and every node placed after,
  // would change with the heap's layout (the command line's arguments did).
  std::map<vertex_descriptor, std::vector<halfedge_descriptor>> around;
  std::vector<vertex_descriptor> sharp_vertices;
  auto add_sharp = [&](vertex_descriptor v, halfedge_descriptor h) {
    std::vector<halfedge_descriptor>& at = around[v];
    if(at.empty())
      sharp_vertices.push_back(v);
    at.push_back(h);
  };
  for(edge_descriptor e : edges(polyhedron))
    if(get(eif, e)) {
      ++out.report.sharp_edges;
      const halfedge_descriptor h = halfedge(e, polyhedron);
      add_sharp(source(h, polyhedron), h);
      add_sharp(target(h, polyhedron), opposite(h, polyhedron));
    }
  auto is_sharp = [&](halfedge_descriptor h) { return bool(get(eif, edge(h, polyhedron))); };
  auto degree = [&](vertex_descriptor v) {
    std::size_t d = 0;
    for(halfedge_descriptor h : around[v])
      d += is_sharp(h) ? 1 : 0;
    return d;
  };
  auto first_sharp = [&](vertex_descriptor v) {
    for(halfedge_descriptor h : around[v])
      if(is_sharp(h))
        return h;
    return around[v].front();
  };
  auto next_sharp = [&](vertex_descriptor v, halfedge_descriptor came_in) {
    // the other sharp halfedge leaving v (v has degree 2)
    for(halfedge_descriptor h : around[v])
      if(is_sharp(h) && edge(h, polyhedron) != edge(came_in, polyhedron))
        return h;
    return came_in;
  };
  auto metric_length = [&](halfedge_descriptor h) {
    const Point_3& a = get(vpm, source(h, polyhedron));
    const Point_3& b = get(vpm, target(h, polyhedron));
    const Point_3 mid = CGAL::midpoint(a, b);
    return metric(mid).length_of(b - a);
  };

  // drop short chains with a free end, from the free ends inward
  if(min_length > 0) {
    std::vector<vertex_descriptor> free_ends;
    for(vertex_descriptor v : sharp_vertices)
      if(degree(v) == 1)
        free_ends.push_back(v);
    while(!free_ends.empty()) {
      const vertex_descriptor v = free_ends.back();
      free_ends.pop_back();
      if(degree(v) != 1)
        continue;
      std::vector<halfedge_descriptor> chain;
      double length = 0;
      bool one_patch = true;
      halfedge_descriptor h = first_sharp(v);
      for(;;) {
        chain.push_back(h);
        length += metric_length(h);
        one_patch = one_patch && get(pid, face(h, polyhedron)) == get(pid, face(opposite(h, polyhedron), polyhedron));
        const vertex_descriptor w = target(h, polyhedron);
        if(degree(w) != 2 || w == v || length >= min_length)
          break;
        h = next_sharp(w, h);
      }
      if(length >= min_length || !one_patch)
        continue;
      for(halfedge_descriptor c : chain)
        put(eif, edge(c, polyhedron), false);
      ++out.report.dropped_chains;
      out.report.dropped_edges += chain.size();
      const vertex_descriptor far_end = target(chain.back(), polyhedron);
      if(degree(far_end) == 1)
        free_ends.push_back(far_end);
    }
  }

  // split what is left into polylines at corners and at turns of 90 degrees
  // or sharper
  auto is_terminal = [&](vertex_descriptor v) {
    const std::size_t d = degree(v);
    if(d != 2)
      return d > 0;
    std::vector<vertex_descriptor> ends;
    for(halfedge_descriptor h : around[v])
      if(is_sharp(h))
        ends.push_back(target(h, polyhedron));
    return CGAL::angle(get(vpm, ends[0]), get(vpm, v), get(vpm, ends[1])) != CGAL::OBTUSE;
  };
  std::set<edge_descriptor> used;
  std::set<Point_3> corners;
  auto trace = [&](halfedge_descriptor h) {
    std::vector<Point_3> line{get(vpm, source(h, polyhedron))};
    std::set<Patch_id> patches;
    const vertex_descriptor start = source(h, polyhedron);
    for(;;) {
      used.insert(edge(h, polyhedron));
      patches.insert(get(pid, face(h, polyhedron)));
      patches.insert(get(pid, face(opposite(h, polyhedron), polyhedron)));
      const vertex_descriptor w = target(h, polyhedron);
      line.push_back(get(vpm, w));
      if(w == start || is_terminal(w))
        break;
      h = next_sharp(w, h);
    }
    if(line.front() != line.back()) {
      corners.insert(line.front());
      corners.insert(line.back());
    }
    out.polylines.push_back(std::move(line));
    out.incident_patches.emplace_back(patches.begin(), patches.end());
  };
  for(vertex_descriptor v : sharp_vertices)
    if(is_terminal(v))
      for(halfedge_descriptor h : around[v])
        if(is_sharp(h) && !used.count(edge(h, polyhedron)))
          trace(h);
  for(vertex_descriptor v : sharp_vertices) // closed chains without a corner
    for(halfedge_descriptor h : around[v])
      if(is_sharp(h) && !used.count(edge(h, polyhedron)))
        trace(h);
  out.report.curves = out.polylines.size();
  out.report.corners = corners.size();
  return out;
}

} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_DETECT_FEATURES_H
