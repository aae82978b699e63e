// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_INTERPOLATED_METRIC_FIELD_3_H
#define CGAL_INTERPOLATED_METRIC_FIELD_3_H

#include <CGAL/Bubble_mesh_3/IO/medit.h>
#include <CGAL/Bubble_mesh_3/IO/sol.h>
#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>

#include <CGAL/Bbox_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/number_utils.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace CGAL {

/// \ingroup PkgBubbleMesh3MetricFields
/// A metric field given by its values at the vertices of a background
/// tetrahedral mesh (typically a MEDIT `.mesh` + `.sol` pair, as produced by
/// MMG or by an error estimator), interpolated in between.
///
/// - Inside a background tetrahedron, the metric is the log-Euclidean
///   interpolation `exp(sum_i l_i log M_i)` of the metrics `M_i` of its four
///   vertices, `l_i` being the barycentric coordinates of the query point.
///   The logarithms are computed once, at construction. A field whose
///   logarithm is affine in space is thus reproduced exactly (up to
///   rounding), and determinants interpolate geometrically (sizes never swell).
/// - At a background vertex (a query point whose coordinates are bitwise equal
///   to those of a vertex of the tetrahedron that contains it), and wherever a
///   single barycentric coordinate is non-zero, the stored metric of that
///   vertex is returned exactly, bitwise.
/// - Outside the background mesh, the metric of the nearest background vertex
///   (Euclidean distance) is returned. The field is therefore discontinuous
///   across the boundary of the background mesh; make the background mesh
///   cover the domain to mesh (`number_of_points_outside()` tells how much
///   of a domain it misses; the command-line tool warns, and refuses a
///   background mesh whose bounding box misses the domain's). Points within a relative tolerance of `1e-10`
///   (in barycentric coordinates) of a tetrahedron count as inside it.
///
/// Point location uses a uniform grid over the bounding box, with about two
/// cells per tetrahedron, each cell listing the tetrahedra that may meet it
/// (bounding box overlap, then no face plane separating them); the
/// tetrahedra are stored in Morton order for memory locality. The
/// nearest-vertex queries use a `CGAL::Kd_tree` built at construction. After construction the field is immutable: `operator()` is
/// thread-safe, and copies are cheap (they share the data).
///
/// The background mesh may be non-convex and its tetrahedra may have either
/// orientation; it should be conforming (tetrahedra meet along whole faces)
/// for the field to be continuous.
///
/// \cgalModels `MetricField_3`
/// \tparam K a CGAL kernel; only `K::Point_3` and `K::FT` are used, and query
///           coordinates are converted to `double`.
template <typename K>
class Interpolated_metric_field_3 {
public:
  typedef K Kernel;
  typedef typename K::FT FT;
  typedef typename K::Point_3 Point_3;
  typedef Bubble_mesh_3::Metric_3 Metric;

  /// Builds the field from the background mesh `background` (only its points
  /// and tetrahedra are used) and one metric per vertex of it. `name` (e.g.
  /// the mesh file name) starts every error message.
  ///
  /// Throws `Bubble_mesh_3::Invalid_input` if the mesh has no tetrahedra, if
  /// `metrics.size()` differs from the number of vertices, if a coordinate is
  /// not finite, if a tetrahedron has a vertex index out of range, or if a
  /// tetrahedron has zero volume (exact test); the message gives the index of
  /// the offending tetrahedron (0-based, and 1-based as in a MEDIT file).
  Interpolated_metric_field_3(const Bubble_mesh_3::Indexed_tet_mesh_3& background, std::vector<Metric> metrics,
                              const std::string& name = "background mesh")
    : data_(std::make_shared<const Data>(background, std::move(metrics), name))
  {}

  /// Reads the background mesh `mesh_path` (MEDIT `.mesh`) and its metric
  /// `sol_path` (MEDIT `.sol`, see `Bubble_mesh_3::IO::read_sol()`) and builds
  /// the field. Throws `Bubble_mesh_3::Invalid_file` or
  /// `Bubble_mesh_3::Invalid_metric` for file errors (naming the file, line
  /// and vertex) and `Bubble_mesh_3::Invalid_input` as the constructor does.
  static Interpolated_metric_field_3 from_files(const std::string& mesh_path, const std::string& sol_path)
  {
    const Bubble_mesh_3::Indexed_tet_mesh_3 mesh = Bubble_mesh_3::IO::read_medit(mesh_path);
    std::vector<Metric> metrics = Bubble_mesh_3::IO::read_sol(sol_path, mesh.points.size());
    return Interpolated_metric_field_3(mesh, std::move(metrics), mesh_path);
  }

  /// the metric at `p` (see the class description). Throws
  /// `Bubble_mesh_3::Invalid_input` if `p` has a non-finite coordinate.
  Metric operator()(const Point_3& p) const
  {
    const Data& d = *data_;
    const Coordinates q = {{CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())}};
    std::array<double, 4> w;
    const int tet = d.locate(q, w);
    if(tet < 0)
      return d.metrics[d.nearest_vertex(q)];

    const std::array<int, 4>& t = d.tets[static_cast<std::size_t>(tet)];
    for(int k = 0; k < 4; ++k)
      if(d.points[static_cast<std::size_t>(t[k])] == q)
        return d.metrics[static_cast<std::size_t>(t[k])];
    int positive = 0;
    int last = 0;
    for(int k = 0; k < 4; ++k) {
      if(w[k] > 0) {
        ++positive;
        last = k;
      } else {
        w[k] = 0;
      }
    }
    if(positive == 1)
      return d.metrics[static_cast<std::size_t>(t[last])];
    const std::array<const Metric::Matrix*, 4> logs = {
      {&d.logs[static_cast<std::size_t>(t[0])], &d.logs[static_cast<std::size_t>(t[1])],
       &d.logs[static_cast<std::size_t>(t[2])], &d.logs[static_cast<std::size_t>(t[3])]}};
    return Bubble_mesh_3::log_euclidean_interpolation_of_logs<4>(logs, w);
  }

  /// the index (0-based) of a background tetrahedron containing `p`, or -1
  /// if `p` is outside the background mesh
  int locate(const Point_3& p) const
  {
    const Coordinates q = {{CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())}};
    std::array<double, 4> w;
    const int tet = data_->locate(q, w);
    return tet < 0 ? -1 : data_->original_tet[static_cast<std::size_t>(tet)];
  }

  /// P1 location: the index (0-based) of a background tetrahedron containing
  /// `p`, or -1 outside the background mesh; when found, `vertices` holds its
  /// four vertex indices and `weights` the barycentric coordinates of `p`
  /// for them (each at least -1e-10, summing to 1), so that
  /// `sum weights[k] * value[vertices[k]]` interpolates vertex values linearly
  int locate(const Point_3& p, std::array<int, 4>& vertices, std::array<double, 4>& weights) const
  {
    const Coordinates q = {{CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())}};
    const int tet = data_->locate(q, weights);
    if(tet < 0)
      return -1;
    vertices = data_->tets[static_cast<std::size_t>(tet)];
    return data_->original_tet[static_cast<std::size_t>(tet)];
  }

  /// the background mesh (its points and tetrahedra; tetrahedra in the
  /// order given at construction)
  Bubble_mesh_3::Indexed_tet_mesh_3 background_mesh() const
  {
    const Data& d = *data_;
    Bubble_mesh_3::Indexed_tet_mesh_3 mesh;
    mesh.points = d.points;
    mesh.tets.resize(d.tets.size());
    for(std::size_t i = 0; i < d.tets.size(); ++i)
      mesh.tets[std::size_t(d.original_tet[i])] = d.tets[i];
    return mesh;
  }

  /// the index (0-based) of the background vertex nearest to `p`
  std::size_t nearest_vertex(const Point_3& p) const
  {
    return data_->nearest_vertex(
      Coordinates{{CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())}});
  }

  /// how many of `points` (a range of `Point_3`) lie outside the background
  /// mesh, where the field takes the metric of the nearest background vertex:
  /// 0 when the background mesh covers them (e.g. the vertices of a domain's
  /// surface)
  template <typename PointRange>
  std::size_t number_of_points_outside(const PointRange& points) const
  {
    std::size_t n = 0;
    for(const Point_3& p : points)
      if(locate(p) < 0)
        ++n;
    return n;
  }

  /// the bounding box of the background mesh
  CGAL::Bbox_3 bbox() const
  {
    const Data& d = *data_;
    return CGAL::Bbox_3(d.low[0], d.low[1], d.low[2], d.high[0], d.high[1], d.high[2]);
  }

  std::size_t number_of_vertices() const { return data_->points.size(); }
  std::size_t number_of_tets() const { return data_->tets.size(); }
  /// the metric given at background vertex `i` (0-based)
  const Metric& metric_at_vertex(std::size_t i) const { return data_->metrics.at(i); }
  /// the name given at construction (used in messages)
  const std::string& name() const { return data_->name; }
  /// the position of background vertex `i` (0-based)
  Point_3 point_at_vertex(std::size_t i) const
  {
    const Coordinates& c = data_->points.at(i);
    return Point_3(c[0], c[1], c[2]);
  }

  /// the field over the same background mesh with other metrics at its
  /// vertices (one per vertex, in the same order); throws as the constructor
  Interpolated_metric_field_3 with_vertex_metrics(std::vector<Metric> metrics, const std::string& name) const
  {
    Bubble_mesh_3::Indexed_tet_mesh_3 background;
    background.points = data_->points;
    background.tets = data_->tets;
    return Interpolated_metric_field_3(background, std::move(metrics), name);
  }

private:
  typedef std::array<double, 3> Coordinates;

  struct Data {
    typedef CGAL::Simple_cartesian<double> Search_kernel;
    typedef Search_kernel::Point_3 Search_point;
    typedef CGAL::Search_traits_3<Search_kernel> Search_base_traits;
    typedef CGAL::Pointer_property_map<Search_point>::const_type Search_point_map;
    typedef CGAL::Search_traits_adapter<std::size_t, Search_point_map, Search_base_traits> Search_traits;
    typedef CGAL::Orthogonal_k_neighbor_search<Search_traits> Neighbor_search;
    typedef typename Neighbor_search::Tree Search_tree;
    typedef typename Neighbor_search::Distance Search_distance;

    static constexpr double inside_tolerance = 1e-10;
    // Grid resolution. For random queries in a structured mesh, 1, 2, 4 and 8
    // cells per tet scan 7, 5.3, 3.9 and 3.1 tets per query but run at about
    // the same speed once the mesh exceeds the caches (memory latency
    // dominates); 2 keeps the grid at ~9 entries per cell (~90 bytes per tet).
    static constexpr std::size_t cells_per_tet = 2;

    std::string name;
    std::vector<Coordinates> points;
    std::vector<std::array<int, 4>> tets; // in Morton order of their centroids
    std::vector<int> original_tet;        // index in the input mesh
    // Affine map to barycentric coordinates: (l1, l2, l3) = rows * (q - origin),
    // l0 = 1 - l1 - l2 - l3; one contiguous record per tet for the hot loop.
    struct Barycentric_map {
      Coordinates origin;
      std::array<double, 9> rows;
    };
    std::vector<Barycentric_map> barycentric_maps;
    std::vector<Metric> metrics;
    std::vector<Metric::Matrix> logs;

    // uniform grid over the bounding box; each cell lists the tets that may meet it
    Coordinates origin, inverse_cell_size, low, high;
    std::array<std::size_t, 3> dims;
    std::vector<std::size_t> cell_offsets; // cell c lists cell_tets[cell_offsets[c] .. cell_offsets[c+1])
    std::vector<int> cell_tets;

    std::vector<Search_point> search_points;
    std::unique_ptr<Search_tree> tree;

    Data(const Bubble_mesh_3::Indexed_tet_mesh_3& mesh, std::vector<Metric>&& m, const std::string& n)
      : name(n), points(mesh.points), tets(mesh.tets), metrics(std::move(m))
    {
      validate();
      sort_tets_spatially();
      logs.reserve(metrics.size());
      for(std::size_t i = 0; i < metrics.size(); ++i) {
        logs.push_back(metrics[i].log());
        if(!logs.back().allFinite())
          throw Bubble_mesh_3::Invalid_metric(name + ": vertex " + std::to_string(i) +
                                              " (0-based): the logarithm of its metric is not finite");
      }
      build_grid();
      search_points.reserve(points.size());
      for(const Coordinates& p : points)
        search_points.emplace_back(p[0], p[1], p[2]);
      tree = std::make_unique<Search_tree>(
        boost::counting_iterator<std::size_t>(0), boost::counting_iterator<std::size_t>(points.size()),
        typename Search_tree::Splitter(), Search_traits(CGAL::make_property_map(std::as_const(search_points))));
      tree->build(); // never lazily during concurrent queries
    }

    std::string tet_text(std::size_t i) const
    {
      return "tetrahedron " + std::to_string(i) + " (0-based; " + std::to_string(i + 1) + " in a MEDIT file)";
    }

    void validate()
    {
      if(points.empty())
        throw Bubble_mesh_3::Invalid_input(name + ": the background mesh has no vertices");
      if(tets.empty())
        throw Bubble_mesh_3::Invalid_input(name + ": the background mesh has no tetrahedra");
      if(metrics.size() != points.size())
        throw Bubble_mesh_3::Invalid_input(name + ": " + std::to_string(metrics.size()) + " metrics given for " +
                                           std::to_string(points.size()) + " background vertices");
      if(points.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
        throw Bubble_mesh_3::Invalid_input(name + ": too many vertices");
      for(std::size_t i = 0; i < points.size(); ++i)
        for(int k = 0; k < 3; ++k)
          if(!std::isfinite(points[i][k]))
            throw Bubble_mesh_3::Invalid_input(name + ": vertex " + std::to_string(i) +
                                               " (0-based) has a non-finite coordinate");
      typedef CGAL::Exact_predicates_inexact_constructions_kernel Epick;
      auto epick = [this](int v) {
        const Coordinates& p = points[static_cast<std::size_t>(v)];
        return Epick::Point_3(p[0], p[1], p[2]);
      };
      barycentric_maps.resize(tets.size());
      for(std::size_t i = 0; i < tets.size(); ++i) {
        const std::array<int, 4>& t = tets[i];
        for(int v : t)
          if(v < 0 || static_cast<std::size_t>(v) >= points.size())
            throw Bubble_mesh_3::Invalid_input(name + ": " + tet_text(i) + " has vertex index " +
                                               std::to_string(v) + " out of range [0, " +
                                               std::to_string(points.size()) + ")");
        if(CGAL::orientation(epick(t[0]), epick(t[1]), epick(t[2]), epick(t[3])) == CGAL::COPLANAR)
          throw Bubble_mesh_3::Invalid_input(name + ": " + tet_text(i) + " has zero volume");
        if(!make_barycentric_map(pt(t[0]), pt(t[1]), pt(t[2]), pt(t[3]), barycentric_maps[i]))
          throw Bubble_mesh_3::Invalid_input(name + ": " + tet_text(i) +
                                             " is too flat: its volume is zero in double precision");
      }
    }

    const Coordinates& pt(int v) const { return points[static_cast<std::size_t>(v)]; }

    // The rows of the inverse of [b-a, c-a, d-a]: (c-a)x(d-a), (d-a)x(b-a),
    // (b-a)x(c-a), each divided by the determinant. False if not invertible.
    static bool make_barycentric_map(const Coordinates& a, const Coordinates& b, const Coordinates& c,
                                     const Coordinates& d, Barycentric_map& map)
    {
      const Metric::Vector pa(a[0], a[1], a[2]);
      const Metric::Vector u = Metric::Vector(b[0], b[1], b[2]) - pa;
      const Metric::Vector v = Metric::Vector(c[0], c[1], c[2]) - pa;
      const Metric::Vector w = Metric::Vector(d[0], d[1], d[2]) - pa;
      const Metric::Vector r1 = v.cross(w), r2 = w.cross(u), r3 = u.cross(v);
      const double det = u.dot(r1);
      const double inv = 1 / det;
      if(!(det != 0 && std::isfinite(inv)))
        return false;
      map.origin = a;
      for(int k = 0; k < 3; ++k) {
        map.rows[k] = r1[k] * inv;
        map.rows[3 + k] = r2[k] * inv;
        map.rows[6 + k] = r3[k] * inv;
      }
      for(double x : map.rows)
        if(!std::isfinite(x))
          return false;
      return true;
    }

    // Morton (Z-order) sort of the tets by centroid: the candidates of a grid
    // cell then sit close together in memory, which matters more than the
    // arithmetic once the mesh no longer fits in the caches.
    void sort_tets_spatially()
    {
      Coordinates lo = points[0], hi = points[0];
      for(const Coordinates& p : points)
        for(int k = 0; k < 3; ++k) {
          lo[k] = std::min(lo[k], p[k]);
          hi[k] = std::max(hi[k], p[k]);
        }
      auto spread = [](std::uint64_t x) { // 21 bits -> every third bit
        x &= 0x1fffff;
        x = (x | x << 32) & 0x1f00000000ffffull;
        x = (x | x << 16) & 0x1f0000ff0000ffull;
        x = (x | x << 8) & 0x100f00f00f00f00full;
        x = (x | x << 4) & 0x10c30c30c30c30c3ull;
        x = (x | x << 2) & 0x1249249249249249ull;
        return x;
      };
      std::vector<std::pair<std::uint64_t, int>> keys(tets.size());
      for(std::size_t i = 0; i < tets.size(); ++i) {
        std::uint64_t code = 0;
        for(int k = 0; k < 3; ++k) {
          double c = 0;
          for(int v : tets[i])
            c += pt(v)[k];
          const double extent = hi[k] - lo[k];
          const double f = extent > 0 ? (c / 4 - lo[k]) / extent : 0;
          const std::uint64_t cell = static_cast<std::uint64_t>(std::min(std::max(f, 0.0), 1.0) * 2097151.0);
          code |= spread(cell) << k;
        }
        keys[i] = std::make_pair(code, static_cast<int>(i));
      }
      std::sort(keys.begin(), keys.end());
      std::vector<std::array<int, 4>> sorted_tets(tets.size());
      std::vector<Barycentric_map> sorted_maps(tets.size());
      original_tet.resize(tets.size());
      for(std::size_t i = 0; i < keys.size(); ++i) {
        const std::size_t j = static_cast<std::size_t>(keys[i].second);
        sorted_tets[i] = tets[j];
        sorted_maps[i] = barycentric_maps[j];
        original_tet[i] = keys[i].second;
      }
      tets.swap(sorted_tets);
      barycentric_maps.swap(sorted_maps);
    }

    std::size_t cell_coordinate(double x, int axis) const
    {
      const double c = (x - origin[axis]) * inverse_cell_size[axis];
      if(!(c > 0))
        return 0;
      const std::size_t i = static_cast<std::size_t>(c);
      return std::min(i, dims[axis] - 1);
    }

    void build_grid()
    {
      low = points[static_cast<std::size_t>(tets[0][0])];
      high = low;
      for(const std::array<int, 4>& t : tets)
        for(int v : t)
          for(int k = 0; k < 3; ++k) {
            low[k] = std::min(low[k], pt(v)[k]);
            high[k] = std::max(high[k], pt(v)[k]);
          }
      // With the face-plane culling below, a cell of a structured mesh lists
      // ~9 tets.
      const double target_cells =
        static_cast<double>(std::min<std::size_t>(cells_per_tet * tets.size(), std::size_t(1) << 27));
      Coordinates extent;
      for(int k = 0; k < 3; ++k)
        extent[k] = high[k] - low[k]; // > 0: a tet has non-zero volume
      const double cell = std::cbrt(extent[0] * extent[1] * extent[2] / target_cells);
      for(int k = 0; k < 3; ++k) {
        const double n = std::ceil(extent[k] / cell);
        dims[k] = static_cast<std::size_t>(std::min(std::max(n, 1.0), 4096.0));
        origin[k] = low[k];
        inverse_cell_size[k] = static_cast<double>(dims[k]) / extent[k];
      }
      const std::size_t n_cells = dims[0] * dims[1] * dims[2];
      const double margin = 1e-10 * (extent[0] + extent[1] + extent[2]);
      Coordinates half_width;
      for(int k = 0; k < 3; ++k)
        half_width[k] = 0.5 * (1 + 1e-6) / inverse_cell_size[k] + margin;

      // A cell is listed for a tet if it meets the tet's bounding box and is
      // not entirely outside one of its face planes (checked on the slightly
      // enlarged cell, with the tolerance used by locate(): conservative, a
      // point that locate() accepts in the tet is never missed).
      auto for_each_cell_of = [&](std::size_t i, auto&& f) {
        const std::array<int, 4>& t = tets[i];
        Coordinates lo = pt(t[0]), hi = pt(t[0]);
        for(int j = 1; j < 4; ++j)
          for(int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], pt(t[j])[k]);
            hi[k] = std::max(hi[k], pt(t[j])[k]);
          }
        std::array<std::size_t, 3> a, b;
        for(int k = 0; k < 3; ++k) {
          a[k] = cell_coordinate(lo[k], k);
          b[k] = cell_coordinate(hi[k], k);
        }
        const Barycentric_map& map = barycentric_maps[i];
        const std::array<double, 9>& r = map.rows;
        const std::array<Coordinates, 4> gradient = {{{{-(r[0] + r[3] + r[6]), -(r[1] + r[4] + r[7]), -(r[2] + r[5] + r[8])}},
                                                      {{r[0], r[1], r[2]}},
                                                      {{r[3], r[4], r[5]}},
                                                      {{r[6], r[7], r[8]}}}};
        std::array<double, 4> reach; // max of |grad l_i . v| over v in the half cell
        for(int j = 0; j < 4; ++j)
          reach[j] = std::abs(gradient[j][0]) * half_width[0] + std::abs(gradient[j][1]) * half_width[1] +
                     std::abs(gradient[j][2]) * half_width[2];
        for(std::size_t z = a[2]; z <= b[2]; ++z)
          for(std::size_t y = a[1]; y <= b[1]; ++y)
            for(std::size_t x = a[0]; x <= b[0]; ++x) {
              const Coordinates centre = {{origin[0] + (static_cast<double>(x) + 0.5) / inverse_cell_size[0],
                                           origin[1] + (static_cast<double>(y) + 0.5) / inverse_cell_size[1],
                                           origin[2] + (static_cast<double>(z) + 0.5) / inverse_cell_size[2]}};
              const double dx = centre[0] - map.origin[0], dy = centre[1] - map.origin[1],
                           dz = centre[2] - map.origin[2];
              const double l1 = r[0] * dx + r[1] * dy + r[2] * dz;
              const double l2 = r[3] * dx + r[4] * dy + r[5] * dz;
              const double l3 = r[6] * dx + r[7] * dy + r[8] * dz;
              const double l0 = 1 - (l1 + l2 + l3);
              if(l0 + reach[0] < -inside_tolerance || l1 + reach[1] < -inside_tolerance ||
                 l2 + reach[2] < -inside_tolerance || l3 + reach[3] < -inside_tolerance)
                continue;
              f((z * dims[1] + y) * dims[0] + x);
            }
      };

      cell_offsets.assign(n_cells + 1, 0);
      for(std::size_t i = 0; i < tets.size(); ++i)
        for_each_cell_of(i, [this](std::size_t c) { ++cell_offsets[c + 1]; });
      for(std::size_t c = 0; c < n_cells; ++c)
        cell_offsets[c + 1] += cell_offsets[c];
      cell_tets.resize(cell_offsets[n_cells]);
      std::vector<std::size_t> fill(cell_offsets.begin(), cell_offsets.end() - 1);
      for(std::size_t i = 0; i < tets.size(); ++i)
        for_each_cell_of(i, [&](std::size_t c) { cell_tets[fill[c]++] = static_cast<int>(i); });

      // query tolerance on the grid box
      for(int k = 0; k < 3; ++k) {
        low[k] -= margin;
        high[k] += margin;
      }
    }

    // Index of a tet containing q (barycentric coordinates in `w`), or -1.
    int locate(const Coordinates& q, std::array<double, 4>& w) const
    {
      for(int k = 0; k < 3; ++k)
        if(!(q[k] >= low[k] && q[k] <= high[k]))
          return -1; // also for NaN
      const std::size_t c =
        (cell_coordinate(q[2], 2) * dims[1] + cell_coordinate(q[1], 1)) * dims[0] + cell_coordinate(q[0], 0);
      const double eps = inside_tolerance;
      int best = -1;
      double best_min = -std::numeric_limits<double>::infinity();
      for(std::size_t j = cell_offsets[c], end = cell_offsets[c + 1]; j != end; ++j) {
        const int i = cell_tets[j];
        const Barycentric_map& map = barycentric_maps[static_cast<std::size_t>(i)];
        const double x = q[0] - map.origin[0], y = q[1] - map.origin[1], z = q[2] - map.origin[2];
        const std::array<double, 9>& r = map.rows;
        const double l1 = r[0] * x + r[1] * y + r[2] * z;
        const double l2 = r[3] * x + r[4] * y + r[5] * z;
        const double l3 = r[6] * x + r[7] * y + r[8] * z;
        const double l0 = 1 - (l1 + l2 + l3);
        const double m = std::min(std::min(l0, l1), std::min(l2, l3));
        if(!(m >= -eps))
          continue;
        if(m > best_min) {
          best_min = m;
          best = i;
          w = {{l0, l1, l2, l3}};
          if(m >= 0)
            break;
        }
      }
      return best;
    }

    std::size_t nearest_vertex(const Coordinates& q) const
    {
      if(!(std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2])))
        throw Bubble_mesh_3::Invalid_input(name + ": metric queried at a non-finite point");
      const Search_distance distance(CGAL::make_property_map(search_points));
      Neighbor_search search(*tree, Search_point(q[0], q[1], q[2]), 1, 0, true, distance);
      return search.begin()->first;
    }
  };

  std::shared_ptr<const Data> data_;
};

} // namespace CGAL

#endif // CGAL_INTERPOLATED_METRIC_FIELD_3_H
