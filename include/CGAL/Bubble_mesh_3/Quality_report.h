// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_QUALITY_REPORT_H
#define CGAL_BUBBLE_MESH_3_QUALITY_REPORT_H

#include <CGAL/Bubble_mesh_3/IO/write_file_atomically.h>
#include <CGAL/Bubble_mesh_3/internal/json.h>
#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/metric_quality.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/enum.h>

#ifdef CGAL_LINKED_WITH_TBB
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#endif

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <limits>
#include <ostream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {

/// \ingroup PkgBubbleMesh3Classes
/// Summary of the quality of a tetrahedral mesh in a metric field, as in the
/// paper's section 6: the distribution of the per-tet minimum dihedral angle
/// measured in the metric at the tet's centroid, plus metric edge lengths,
/// orientation and volume checks. Filled by `compute_quality_report()`;
/// serialised by `to_json()`, `print_quality_summary()` and
/// `write_histogram_svg()`.
struct Quality_report {
  /// number of histogram bins: [0,5), [5,10), ..., [80,85), [85,90]
  static constexpr int number_of_bins = 18;
  /// width of a histogram bin, in degrees
  static constexpr double bin_width = 5.0;

  /// Statistics of the per-tet minimum dihedral angle in the metric (degrees).
  struct Min_dihedral {
    /// smallest value over all tets (0 for a flat tet)
    double worst = 0;
    /// index (in `Indexed_tet_mesh_3::tets`) of the first tet reaching `worst`
    std::size_t worst_tet = 0;
    /// 1st percentile, nearest-rank definition (see `nearest_rank_percentile()`)
    double p01 = 0;
    /// arithmetic mean
    double mean = 0;
    /// numbers of tets whose value is strictly below 5, 10 and 15 degrees
    std::size_t below5 = 0;
    std::size_t below10 = 0;
    std::size_t below15 = 0;
  };

  /// Statistics of the per-tet mean ratio `12 (3|V|)^(2/3) / sum of the six
  /// squared edge lengths`, in the same metric as the angles (1 for a
  /// regular tet, 0 for a flat one): the shape measure of the UGAWG
  /// benchmarks. Unlike the minimum dihedral angle it also sees needles (a
  /// tet much longer than wide with no small dihedral angle), so a mesh whose
  /// edges stray from the metric's length shows here first.
  struct Mean_ratio {
    /// smallest value over all tets
    double worst = 0;
    /// index of the first tet reaching `worst`
    std::size_t worst_tet = 0;
    /// 1st percentile, nearest rank
    double p01 = 0;
    double mean = 0;
  };

  /// Statistics of the metric lengths of the unique edges of the tets; the
  /// length of an edge is the mean of its lengths in the metrics of its two
  /// end vertices (`metric_edge_length(p, q, m_p, m_q)`).
  struct Edge_length {
    double min = 0;
    double max = 0;
    double mean = 0;
    /// fraction of edges whose length lies in [1/sqrt(2), sqrt(2)] (bounds included)
    double in_range_fraction = 0;
    /// fractions of edges shorter than 1/sqrt(2) and longer than sqrt(2): the
    /// out-of-range rest split into too short (clusters) and too long (gaps)
    double short_fraction = 0;
    double long_fraction = 0;
    std::size_t number_of_edges = 0;
  };

  /// number of distinct vertices referenced by the tets (unused points are not counted)
  std::size_t vertices = 0;
  /// number of tets
  std::size_t tets = 0;
  Min_dihedral min_dihedral;
  /// counts of tets per 5-degree bin of the metric minimum dihedral angle;
  /// bin `i` holds [5i, 5i+5) and the last bin [85, 90]. A value within 1e-9
  /// degree below a bin boundary goes to the upper bin, so that exact angles
  /// such as 45 degrees computed with rounding errors land where expected.
  std::array<std::size_t, number_of_bins> histogram_5deg{};
  Mean_ratio mean_ratio;
  Edge_length edge_length;
  /// tets with `CGAL::orientation(p0, p1, p2, p3) == CGAL::NEGATIVE` (exact)
  std::size_t inverted_tets = 0;
  /// tets with four coplanar vertices (`CGAL::COPLANAR`, exact), repeated vertices included
  std::size_t degenerate_tets = 0;
  /// sum of the signed Euclidean volumes
  double volume = 0;
  /// sum of the signed volumes in the metric at each tet's centroid
  double metric_volume = 0;
  /// free-form description of the metric field the report was computed in
  /// (JSON key `metric`)
  std::string metric_description;
};

/// \ingroup PkgBubbleMesh3Functions
/// Nearest-rank percentile: the `k`-th smallest of `values` (1-based) with
/// `k = max(1, ceil(percent * n / 100))`, i.e. the smallest value such that at
/// least `percent`% of the values are less than or equal to it. Always one of
/// the values (no interpolation). `percent = 1` gives the 1st percentile,
/// 50 a median, 100 the maximum. Throws `Invalid_input` when `values` is empty
/// or `percent` is not in [0, 100].
inline double nearest_rank_percentile(std::vector<double> values, double percent)
{
  if(values.empty())
    throw Invalid_input("nearest_rank_percentile: no values");
  if(!(percent >= 0 && percent <= 100))
    throw Invalid_input("nearest_rank_percentile: percent must be in [0, 100]");
  const double n = static_cast<double>(values.size());
  // percent * n is exact for the sizes met here, so an exact integer rank is
  // not pushed up by rounding.
  std::size_t rank = static_cast<std::size_t>(std::ceil(percent * n / 100));
  rank = std::min(std::max<std::size_t>(rank, 1), values.size());
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(rank - 1), values.end());
  return values[rank - 1];
}

namespace internal {

/// Runs `f(begin, end)` on consecutive sub-ranges of [0, n), in parallel when
/// TBB is available. `f` must only write to slots owned by its sub-range.
template <typename Function>
void quality_parallel_for(std::size_t n, const Function& f)
{
#ifdef CGAL_LINKED_WITH_TBB
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024),
                    [&f](const tbb::blocked_range<std::size_t>& r) { f(r.begin(), r.end()); });
#else
  f(std::size_t(0), n);
#endif
}

/// Neumaier-compensated sum, serial and in index order: the same bits
/// whatever the number of threads that produced the terms.
inline double compensated_sum(const std::vector<double>& terms)
{
  double sum = 0;
  double compensation = 0;
  for(double x : terms) {
    const double t = sum + x;
    if(std::abs(sum) >= std::abs(x))
      compensation += (sum - t) + x;
    else
      compensation += (x - t) + sum;
    sum = t;
  }
  return sum + compensation;
}

inline int histogram_5deg_bin(double angle)
{
  const int bin = static_cast<int>(std::floor((angle + 1e-9) / Quality_report::bin_width));
  return std::min(std::max(bin, 0), Quality_report::number_of_bins - 1);
}

/// Throws `Invalid_input` unless the mesh has tets whose indices are valid and
/// whose vertices have finite coordinates. Fills `used` (per point).
inline void check_mesh_for_quality(const Indexed_tet_mesh_3& mesh, std::vector<char>& used)
{
  if(mesh.tets.empty())
    throw Invalid_input("quality report: the mesh has no tetrahedra");
  const std::size_t np = mesh.points.size();
  used.assign(np, 0);
  for(std::size_t t = 0; t < mesh.tets.size(); ++t)
    for(int i = 0; i < 4; ++i) {
      const int v = mesh.tets[t][i];
      if(v < 0 || static_cast<std::size_t>(v) >= np)
        throw Invalid_input("quality report: tet " + std::to_string(t) + " references vertex " + std::to_string(v) +
                            " but the mesh has " + std::to_string(np) + " points");
      used[v] = 1;
    }
  for(std::size_t v = 0; v < np; ++v)
    if(used[v]) {
      const std::array<double, 3>& p = mesh.points[v];
      if(!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])))
        throw Invalid_input("quality report: vertex " + std::to_string(v) + " has a non-finite coordinate");
    }
}

/// Per-tet measures: minimum dihedral angle in the metric at the centroid,
/// Euclidean and metric signed volumes, exact orientation.
template <typename MetricField_3>
void compute_tet_measures(const Indexed_tet_mesh_3& mesh, const MetricField_3& field,
                          std::vector<double>& min_dihedral, std::vector<double>* volume,
                          std::vector<double>* metric_volume, std::vector<signed char>* orientation,
                          std::vector<double>* mean_ratio = nullptr)
{
  typedef typename MetricField_3::Point_3 Field_point;
  typedef CGAL::Exact_predicates_inexact_constructions_kernel::Point_3 Exact_point;
  const std::size_t nt = mesh.tets.size();
  min_dihedral.resize(nt);
  if(volume)
    volume->resize(nt);
  if(metric_volume)
    metric_volume->resize(nt);
  if(orientation)
    orientation->resize(nt);
  if(mean_ratio)
    mean_ratio->resize(nt);
  quality_parallel_for(nt, [&](std::size_t begin, std::size_t end) {
    for(std::size_t t = begin; t < end; ++t) {
      const std::array<int, 4>& tet = mesh.tets[t];
      const std::array<double, 3>& a0 = mesh.points[tet[0]];
      const std::array<double, 3>& a1 = mesh.points[tet[1]];
      const std::array<double, 3>& a2 = mesh.points[tet[2]];
      const std::array<double, 3>& a3 = mesh.points[tet[3]];
      const Eigen::Vector3d p0(a0[0], a0[1], a0[2]);
      const Eigen::Vector3d p1(a1[0], a1[1], a1[2]);
      const Eigen::Vector3d p2(a2[0], a2[1], a2[2]);
      const Eigen::Vector3d p3(a3[0], a3[1], a3[2]);
      const Eigen::Vector3d c = 0.25 * (p0 + p1 + p2 + p3);
      const auto& m = field(Field_point(c[0], c[1], c[2]));
      const Metric_3& metric = m;
      // Exact orientation of the double coordinates (Epick's static filter
      // makes this cheap); a flat tet gets exactly 0 degrees.
      const CGAL::Orientation o =
          CGAL::orientation(Exact_point(a0[0], a0[1], a0[2]), Exact_point(a1[0], a1[1], a1[2]),
                            Exact_point(a2[0], a2[1], a2[2]), Exact_point(a3[0], a3[1], a3[2]));
      if(orientation)
        (*orientation)[t] = static_cast<signed char>(o);
      if(o == CGAL::COPLANAR) {
        min_dihedral[t] = 0;
        if(mean_ratio)
          (*mean_ratio)[t] = 0;
      } else {
        const Eigen::Matrix3d& q = metric.Q();
        const Eigen::Vector3d e1 = map_by_upper(q, p1 - p0), e2 = map_by_upper(q, p2 - p0),
                              e3 = map_by_upper(q, p3 - p0);
        min_dihedral[t] = minimum_dihedral_angle_of_edge_vectors(e1, e2, e3);
        if(mean_ratio)
          (*mean_ratio)[t] = mean_ratio_of_edge_vectors(e1, e2, e3);
      }
      if(volume || metric_volume) {
        const double v = signed_volume(p0, p1, p2, p3);
        if(volume)
          (*volume)[t] = v;
        if(metric_volume)
          (*metric_volume)[t] = metric.sqrt_determinant() * v;
      }
    }
  });
}

/// Unique edges of the tets as a compressed adjacency: for each vertex `a`,
/// its neighbours `b > a` are `targets[offsets[a] .. offsets[a+1])`, sorted.
/// Edges joining a vertex to itself (repeated vertex in a tet) are skipped.
inline void unique_tet_edges(const Indexed_tet_mesh_3& mesh, std::vector<std::size_t>& offsets,
                             std::vector<int>& targets)
{
  static constexpr int local_edges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  const std::size_t np = mesh.points.size();
  std::vector<std::size_t> start(np + 1, 0);
  for(const std::array<int, 4>& tet : mesh.tets)
    for(const auto& e : local_edges) {
      const int a = tet[e[0]];
      const int b = tet[e[1]];
      if(a != b)
        ++start[std::min(a, b) + 1];
    }
  for(std::size_t v = 0; v < np; ++v)
    start[v + 1] += start[v];
  std::vector<int> all(start[np]);
  {
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for(const std::array<int, 4>& tet : mesh.tets)
      for(const auto& e : local_edges) {
        const int a = tet[e[0]];
        const int b = tet[e[1]];
        if(a != b)
          all[fill[std::min(a, b)]++] = std::max(a, b);
      }
  }
  // Sort and deduplicate each vertex's short list (independent, so parallel).
  std::vector<std::size_t> unique_count(np, 0);
  quality_parallel_for(np, [&](std::size_t begin, std::size_t end) {
    for(std::size_t v = begin; v < end; ++v) {
      auto first = all.begin() + static_cast<std::ptrdiff_t>(start[v]);
      auto last = all.begin() + static_cast<std::ptrdiff_t>(start[v + 1]);
      std::sort(first, last);
      unique_count[v] = static_cast<std::size_t>(std::unique(first, last) - first);
    }
  });
  offsets.assign(np + 1, 0);
  for(std::size_t v = 0; v < np; ++v)
    offsets[v + 1] = offsets[v] + unique_count[v];
  targets.resize(offsets[np]);
  for(std::size_t v = 0; v < np; ++v)
    std::copy_n(all.begin() + static_cast<std::ptrdiff_t>(start[v]), unique_count[v],
                targets.begin() + static_cast<std::ptrdiff_t>(offsets[v]));
}

inline double length_in_entries(const std::array<double, 6>& m, double x, double y, double z)
{
  // entries m11 m12 m13 m22 m23 m33
  const double q = m[0] * x * x + m[3] * y * y + m[5] * z * z + 2 * (m[1] * x * y + m[2] * x * z + m[4] * y * z);
  return std::sqrt(std::max(q, 0.0));
}

inline std::string escape_xml(const std::string& s)
{
  std::string out;
  for(char ch : s) {
    switch(ch) {
    case '&': out += "&amp;"; break;
    case '<': out += "&lt;"; break;
    case '>': out += "&gt;"; break;
    case '"': out += "&quot;"; break;
    case '\'': out += "&apos;"; break;
    default: out += ch;
    }
  }
  return out;
}

inline std::string fixed(double x, int digits)
{
  std::ostringstream os;
  os << std::fixed << std::setprecision(digits) << x;
  return os.str();
}

/// Metric lengths of the unique edges of the tets (`used`: the vertices a tet
/// references): each the mean of its lengths in its end vertices' metrics,
/// the field evaluated once per used vertex.
template <typename MetricField_3>
Quality_report::Edge_length metric_edge_lengths(const Indexed_tet_mesh_3& mesh, const MetricField_3& field,
                                                const std::vector<char>& used)
{
  typedef typename MetricField_3::Point_3 Field_point;
  const std::size_t np = mesh.points.size();
  // vertex metrics (six entries each), one evaluation per referenced vertex.
  std::vector<std::array<double, 6>> vertex_metrics(np);
  internal::quality_parallel_for(np, [&](std::size_t begin, std::size_t end) {
    for(std::size_t v = begin; v < end; ++v)
      if(used[v]) {
        const std::array<double, 3>& p = mesh.points[v];
        const auto& m = field(Field_point(p[0], p[1], p[2]));
        const Metric_3& metric = m;
        vertex_metrics[v] = metric.entries();
      }
  });

  // unique edges and their lengths
  std::vector<std::size_t> offsets;
  std::vector<int> targets;
  internal::unique_tet_edges(mesh, offsets, targets);
  std::vector<double> lengths(targets.size());
  internal::quality_parallel_for(np, [&](std::size_t begin, std::size_t end) {
    for(std::size_t a = begin; a < end; ++a) {
      const std::array<double, 3>& pa = mesh.points[a];
      for(std::size_t k = offsets[a]; k < offsets[a + 1]; ++k) {
        const std::size_t b = static_cast<std::size_t>(targets[k]);
        const std::array<double, 3>& pb = mesh.points[b];
        const double x = pb[0] - pa[0];
        const double y = pb[1] - pa[1];
        const double z = pb[2] - pa[2];
        lengths[k] = 0.5 * (internal::length_in_entries(vertex_metrics[a], x, y, z) +
                            internal::length_in_entries(vertex_metrics[b], x, y, z));
      }
    }
  });

  Quality_report::Edge_length el;
  el.number_of_edges = lengths.size();
  if(!lengths.empty()) {
    const double low = 1 / std::sqrt(2.0);
    const double high = std::sqrt(2.0);
    el.min = lengths[0];
    el.max = lengths[0];
    std::size_t in_range = 0, too_short = 0;
    for(double l : lengths) {
      el.min = std::min(el.min, l);
      el.max = std::max(el.max, l);
      if(l >= low && l <= high)
        ++in_range;
      else if(l < low)
        ++too_short;
    }
    el.mean = internal::compensated_sum(lengths) / static_cast<double>(lengths.size());
    const double n = static_cast<double>(lengths.size());
    el.in_range_fraction = static_cast<double>(in_range) / n;
    el.short_fraction = static_cast<double>(too_short) / n;
    el.long_fraction = static_cast<double>(lengths.size() - in_range - too_short) / n;
  }
  return el;
}

} // namespace internal

/// \ingroup PkgBubbleMesh3Functions
/// The minimum dihedral angle (degrees) of every tet of `mesh` in the metric
/// `field` evaluated at the tet's centroid, in the order of `mesh.tets` (for
/// per-cell output, e.g. VTU). Throws `Invalid_input` like `compute_quality_report()`.
template <typename MetricField_3>
std::vector<double> metric_minimum_dihedral_angles(const Indexed_tet_mesh_3& mesh, const MetricField_3& field)
{
  std::vector<char> used;
  internal::check_mesh_for_quality(mesh, used);
  std::vector<double> angles;
  internal::compute_tet_measures(mesh, field, angles, nullptr, nullptr, nullptr);
  return angles;
}

/// \ingroup PkgBubbleMesh3Functions
/// Measures the quality of `mesh` in the metric field `field` (a model of
/// `MetricField_3`):
/// - the quality of a tet is its minimum dihedral angle after mapping its
///   vertices by `Q`, where `field(centroid) = Q^T Q` (paper, section 6);
/// - edges are the unique edges of the tets; the length of an edge is the mean
///   of its lengths in the metrics of its end vertices (the field is evaluated
///   once per vertex);
/// - inverted and flat tets are found with the exact `CGAL::orientation` of
///   the Epick kernel on the double coordinates.
///
/// Only vertices referenced by a tet are counted and evaluated. With TBB
/// (`CGAL_LINKED_WITH_TBB`) the per-tet, per-vertex and per-edge work runs in
/// parallel; values are stored per element and reduced serially in index
/// order, so the report is bit-identical for any number of threads.
/// `metric_description` is copied into `Quality_report::metric_description`.
///
/// Throws `Invalid_input` if the mesh has no tets, a tet references a missing
/// point, or a referenced point has a non-finite coordinate; exceptions of
/// `field` (e.g. `Invalid_metric`) propagate.
template <typename MetricField_3>
Quality_report compute_quality_report(const Indexed_tet_mesh_3& mesh, const MetricField_3& field,
                                      const std::string& metric_description = std::string())
{
  std::vector<char> used;
  internal::check_mesh_for_quality(mesh, used);

  Quality_report report;
  report.metric_description = metric_description;
  report.tets = mesh.tets.size();
  report.vertices = static_cast<std::size_t>(std::count(used.begin(), used.end(), char(1)));

  // Per-tet measures.
  std::vector<double> angles;
  std::vector<double> volumes;
  std::vector<double> metric_volumes;
  std::vector<signed char> orientations;
  std::vector<double> ratios;
  internal::compute_tet_measures(mesh, field, angles, &volumes, &metric_volumes, &orientations, &ratios);

  // Serial reductions in index order.
  Quality_report::Min_dihedral& md = report.min_dihedral;
  md.worst = angles[0];
  md.worst_tet = 0;
  for(std::size_t t = 0; t < angles.size(); ++t) {
    const double a = angles[t];
    if(a < md.worst) {
      md.worst = a;
      md.worst_tet = t;
    }
    if(a < 5)
      ++md.below5;
    if(a < 10)
      ++md.below10;
    if(a < 15)
      ++md.below15;
    ++report.histogram_5deg[static_cast<std::size_t>(internal::histogram_5deg_bin(a))];
    if(orientations[t] < 0)
      ++report.inverted_tets;
    else if(orientations[t] == 0)
      ++report.degenerate_tets;
  }
  md.mean = internal::compensated_sum(angles) / static_cast<double>(angles.size());
  report.volume = internal::compensated_sum(volumes);
  report.metric_volume = internal::compensated_sum(metric_volumes);
  md.p01 = nearest_rank_percentile(std::move(angles), 1.0);

  Quality_report::Mean_ratio& mr = report.mean_ratio;
  const auto worst_ratio = std::min_element(ratios.begin(), ratios.end()); // the first of equal ones
  mr.worst = *worst_ratio;
  mr.worst_tet = static_cast<std::size_t>(worst_ratio - ratios.begin());
  mr.mean = internal::compensated_sum(ratios) / static_cast<double>(ratios.size());
  mr.p01 = nearest_rank_percentile(std::move(ratios), 1.0);

  report.edge_length = internal::metric_edge_lengths(mesh, field, used);
  return report;
}

/// \ingroup PkgBubbleMesh3Functions
/// The report as a JSON object (UTF-8, no trailing newline), with the keys
/// `vertices`, `tets`, `metric`, `min_dihedral` {`worst`, `worst_tet`, `p01`,
/// `mean`, `below5`, `below10`, `below15`}, `mean_ratio` {`worst`, `worst_tet`,
/// `p01`, `mean`}, `histogram_5deg` (18 counts),
/// `histogram_bin_degrees`, `edge_length` {`min`, `max`, `mean`,
/// `in_range_fraction`, `short_fraction`, `long_fraction`, `number_of_edges`}, `inverted_tets`,
/// `degenerate_tets`, `volume`, `metric_volume`. Numbers are written in the
/// shortest form that reads back to the same double; a non-finite value is
/// written as `null`.
inline std::string to_json(const Quality_report& r)
{
  using internal::format_json_number;
  std::ostringstream os;
  os << "{\n";
  os << "  \"vertices\": " << r.vertices << ",\n";
  os << "  \"tets\": " << r.tets << ",\n";
  os << "  \"metric\": \"" << internal::escape_json(r.metric_description) << "\",\n";
  os << "  \"min_dihedral\": {\"worst\": " << format_json_number(r.min_dihedral.worst)
     << ", \"worst_tet\": " << r.min_dihedral.worst_tet << ", \"p01\": " << format_json_number(r.min_dihedral.p01)
     << ", \"mean\": " << format_json_number(r.min_dihedral.mean) << ", \"below5\": " << r.min_dihedral.below5
     << ", \"below10\": " << r.min_dihedral.below10 << ", \"below15\": " << r.min_dihedral.below15 << "},\n";
  os << "  \"mean_ratio\": {\"worst\": " << format_json_number(r.mean_ratio.worst)
     << ", \"worst_tet\": " << r.mean_ratio.worst_tet << ", \"p01\": " << format_json_number(r.mean_ratio.p01)
     << ", \"mean\": " << format_json_number(r.mean_ratio.mean) << "},\n";
  os << "  \"histogram_5deg\": [";
  for(int i = 0; i < Quality_report::number_of_bins; ++i)
    os << (i ? ", " : "") << r.histogram_5deg[static_cast<std::size_t>(i)];
  os << "],\n";
  os << "  \"histogram_bin_degrees\": " << format_json_number(Quality_report::bin_width) << ",\n";
  os << "  \"edge_length\": {\"min\": " << format_json_number(r.edge_length.min)
     << ", \"max\": " << format_json_number(r.edge_length.max)
     << ", \"mean\": " << format_json_number(r.edge_length.mean)
     << ", \"in_range_fraction\": " << format_json_number(r.edge_length.in_range_fraction)
     << ", \"short_fraction\": " << format_json_number(r.edge_length.short_fraction)
     << ", \"long_fraction\": " << format_json_number(r.edge_length.long_fraction)
     << ", \"number_of_edges\": " << r.edge_length.number_of_edges << "},\n";
  os << "  \"inverted_tets\": " << r.inverted_tets << ",\n";
  os << "  \"degenerate_tets\": " << r.degenerate_tets << ",\n";
  os << "  \"volume\": " << format_json_number(r.volume) << ",\n";
  os << "  \"metric_volume\": " << format_json_number(r.metric_volume) << "\n";
  os << "}";
  return os.str();
}

/// \ingroup PkgBubbleMesh3Functions
/// Writes a compact human-readable summary (about 20 lines) with a text
/// histogram of the minimum dihedral angles (bars of `#`, scaled to the
/// largest bin). Bins above the last non-empty one beyond 75 degrees are
/// omitted (a minimum dihedral angle never exceeds 70.53 degrees).
inline void print_quality_summary(std::ostream& out, const Quality_report& r)
{
  using internal::fixed;
  std::ostringstream os; // leaves the caller's stream formatting untouched
  const Quality_report::Min_dihedral& md = r.min_dihedral;
  const Quality_report::Edge_length& el = r.edge_length;
  os << "Mesh quality" << (r.metric_description.empty() ? std::string() : " in metric \"" + r.metric_description + "\"") << ": "
     << r.vertices << " vertices, " << r.tets << " tets, " << el.number_of_edges << " edges\n";
  os << "  min dihedral (deg): worst " << fixed(md.worst, 2) << " (tet " << md.worst_tet << "), p01 "
     << fixed(md.p01, 2) << ", mean " << fixed(md.mean, 2) << "\n";
  os << "  tets below 5/10/15 deg: " << md.below5 << " / " << md.below10 << " / " << md.below15 << "\n";
  os << "  mean ratio: worst " << fixed(r.mean_ratio.worst, 3) << " (tet " << r.mean_ratio.worst_tet << "), p01 "
     << fixed(r.mean_ratio.p01, 3) << ", mean " << fixed(r.mean_ratio.mean, 3) << "\n";
  os << "  metric edge length: min " << fixed(el.min, 3) << ", max " << fixed(el.max, 3) << ", mean "
     << fixed(el.mean, 3) << ", in [0.707, 1.414]: " << fixed(100 * el.in_range_fraction, 1) << "% (shorter "
     << fixed(100 * el.short_fraction, 1) << "%, longer " << fixed(100 * el.long_fraction, 1) << "%)\n";
  os << "  inverted tets: " << r.inverted_tets << ", flat tets: " << r.degenerate_tets << ", volume "
     << std::setprecision(10) << r.volume << ", metric volume " << r.metric_volume << "\n";
  os << "  histogram of min dihedral angles:\n";
  std::size_t largest = 0;
  int last = 14;
  for(int i = 0; i < Quality_report::number_of_bins; ++i) {
    largest = std::max(largest, r.histogram_5deg[static_cast<std::size_t>(i)]);
    if(r.histogram_5deg[static_cast<std::size_t>(i)] > 0)
      last = std::max(last, i);
  }
  const int bar_width = 50;
  for(int i = 0; i <= last; ++i) {
    const std::size_t count = r.histogram_5deg[static_cast<std::size_t>(i)];
    int bar = 0;
    if(largest > 0)
      bar = static_cast<int>(std::llround(static_cast<double>(bar_width) * static_cast<double>(count) /
                                          static_cast<double>(largest)));
    if(count > 0 && bar == 0)
      bar = 1; // a non-empty bin is always visible
    os << "  " << std::setw(2) << 5 * i << "-" << std::setw(2) << 5 * (i + 1) << (i == Quality_report::number_of_bins - 1 ? "]" : ")")
       << " |" << std::string(static_cast<std::size_t>(bar), '#') << std::string(static_cast<std::size_t>(bar_width - bar), ' ')
       << " " << count << "\n";
  }
  out << os.str();
}

/// \ingroup PkgBubbleMesh3Functions
/// Writes a standalone SVG bar chart of `r.histogram_5deg` to `path`, with
/// axis labels, tick values, `title`, and vertical markers at the worst angle
/// and at the 1st percentile. The file is written to a temporary file and then
/// renamed, so a reader never sees a partial file. Throws `Invalid_file` if
/// it cannot be written.
inline void write_histogram_svg(const std::string& path, const Quality_report& r, const std::string& title)
{
  using internal::escape_xml;
  using internal::fixed;
  const double width = 760;
  const double height = 440;
  const double left = 80;
  const double right = 30;
  const double top = 60;
  const double bottom = 70;
  const double plot_w = width - left - right;
  const double plot_h = height - top - bottom;
  const double x_max = 90;

  std::size_t largest = 0;
  for(std::size_t c : r.histogram_5deg)
    largest = std::max(largest, c);
  // A "nice" y range: 1, 2 or 5 times a power of ten per tick, about 5 ticks.
  double tick = 1;
  {
    const double raw = std::max(1.0, static_cast<double>(largest) / 5);
    const double p = std::pow(10.0, std::floor(std::log10(raw)));
    for(double f : {1.0, 2.0, 5.0, 10.0})
      if(f * p >= raw) {
        tick = f * p;
        break;
      }
  }
  const double y_max = std::max(tick, std::ceil(static_cast<double>(largest) / tick) * tick);
  auto sx = [&](double angle) { return left + plot_w * angle / x_max; };
  auto sy = [&](double count) { return top + plot_h * (1 - count / y_max); };

  std::ostringstream svg;
  svg << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width << "\" height=\"" << height
      << "\" viewBox=\"0 0 " << width << " " << height << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  svg << "<rect x=\"0\" y=\"0\" width=\"" << width << "\" height=\"" << height << "\" fill=\"white\"/>\n";
  svg << "<text x=\"" << width / 2 << "\" y=\"24\" text-anchor=\"middle\" font-size=\"16\">" << escape_xml(title)
      << "</text>\n";
  svg << "<text x=\"" << width / 2 << "\" y=\"42\" text-anchor=\"middle\" fill=\"#555\">" << r.tets << " tets, "
      << r.inverted_tets << " inverted"
      << (r.metric_description.empty() ? std::string() : ", metric: " + escape_xml(r.metric_description)) << "</text>\n";
  // Grid and y ticks.
  for(double c = 0; c <= y_max + 0.5 * tick; c += tick) {
    const double y = sy(c);
    svg << "<line x1=\"" << left << "\" y1=\"" << y << "\" x2=\"" << left + plot_w << "\" y2=\"" << y
        << "\" stroke=\"#ddd\"/>\n";
    svg << "<text x=\"" << left - 6 << "\" y=\"" << y + 4 << "\" text-anchor=\"end\">"
        << static_cast<unsigned long long>(std::llround(c)) << "</text>\n";
  }
  // Bars.
  for(int i = 0; i < Quality_report::number_of_bins; ++i) {
    const std::size_t count = r.histogram_5deg[static_cast<std::size_t>(i)];
    if(count == 0)
      continue;
    const double x0 = sx(Quality_report::bin_width * i) + 1;
    const double x1 = sx(Quality_report::bin_width * (i + 1)) - 1;
    const double y = sy(static_cast<double>(count));
    svg << "<rect x=\"" << x0 << "\" y=\"" << y << "\" width=\"" << x1 - x0 << "\" height=\"" << top + plot_h - y
        << "\" fill=\"#4a7ebb\"><title>[" << 5 * i << ", " << 5 * (i + 1)
        << (i == Quality_report::number_of_bins - 1 ? "]" : ")") << ": " << count
        << "</title></rect>\n";
  }
  // Axes and x ticks.
  svg << "<line x1=\"" << left << "\" y1=\"" << top + plot_h << "\" x2=\"" << left + plot_w << "\" y2=\""
      << top + plot_h << "\" stroke=\"black\"/>\n";
  svg << "<line x1=\"" << left << "\" y1=\"" << top << "\" x2=\"" << left << "\" y2=\"" << top + plot_h
      << "\" stroke=\"black\"/>\n";
  for(int a = 0; a <= 90; a += 10) {
    const double x = sx(a);
    svg << "<line x1=\"" << x << "\" y1=\"" << top + plot_h << "\" x2=\"" << x << "\" y2=\"" << top + plot_h + 5
        << "\" stroke=\"black\"/>\n";
    svg << "<text x=\"" << x << "\" y=\"" << top + plot_h + 19 << "\" text-anchor=\"middle\">" << a << "</text>\n";
  }
  svg << "<text x=\"" << left + plot_w / 2 << "\" y=\"" << height - 22
      << "\" text-anchor=\"middle\">minimum dihedral angle in the metric (degrees)</text>\n";
  svg << "<text transform=\"translate(20 " << top + plot_h / 2
      << ") rotate(-90)\" text-anchor=\"middle\">number of tets</text>\n";
  // Markers: worst angle and 1st percentile.
  auto marker = [&](double angle, const char* colour, const std::string& label, double label_y) {
    const double x = sx(std::min(std::max(angle, 0.0), x_max));
    svg << "<line x1=\"" << x << "\" y1=\"" << top << "\" x2=\"" << x << "\" y2=\"" << top + plot_h
        << "\" stroke=\"" << colour << "\" stroke-width=\"2\" stroke-dasharray=\"6 4\"/>\n";
    svg << "<text x=\"" << x + 4 << "\" y=\"" << label_y << "\" fill=\"" << colour << "\">" << label << "</text>\n";
  };
  marker(r.min_dihedral.worst, "#c0392b", "worst " + fixed(r.min_dihedral.worst, 2) + "\u00b0", top + 14);
  marker(r.min_dihedral.p01, "#e67e22", "p01 " + fixed(r.min_dihedral.p01, 2) + "\u00b0", top + 30);
  svg << "</svg>\n";

  IO::write_text_file(path, svg.str());
}

} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_QUALITY_REPORT_H
