// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_FEATURE_SIZE_METRIC_FIELD_3_H
#define CGAL_FEATURE_SIZE_METRIC_FIELD_3_H

#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/internal/packing/domain_oracle.h>
#include <CGAL/Bubble_mesh_3/internal/surface_thickness.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Fuzzy_sphere.h>
#include <CGAL/Kd_tree.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/property_map.h>

#include <boost/tuple/tuple.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <map>
#include <tuple>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

namespace CGAL {

/// \ingroup PkgBubbleMesh3Classes
///
/// A model of `MetricField_3`: a user's metric field refined where the
/// domain's feature curves and corners are closer to each other than the
/// elements the field asks for.
///
/// Corners and feature curves are nodes of every mesh: two corners at
/// distance `d` much below the element size `h`, or a curve passing at `d`
/// from another, force elements with an edge of about `d` next to edges of
/// about `h`, hence flat tets, whatever the connection does. The packing
/// cannot fix this; sizes of about `d` there can. So, as CGAL Mesh_3 protects
/// small features with small balls, this field computes a *local feature
/// size* `a(s)` at samples `s` of the corners and curves:
///   - the distance from a corner to every other corner, and to every curve
///     that does not end at it;
///   - the distance from a curve point to every corner that does not end its
///     curve, to every curve that shares no corner with it, and to its own
///     curve where it comes back (the distance along the curve is more than
///     twice the straight one);
///   - the length of the curve (a third of it for a closed curve: it needs
///     three nodes);
/// and the *thickness* of thin parts at samples `s` of the surface: the
/// distance to the surface straight inside `s`, where the inward ray leaves
/// the part through a face turned against `s`'s (a plate, a blade, a wall;
/// given as `Facing_pair`s), unless a corner or curve is within twice that
/// distance of `s` (a sharp wedge is thin near its edge too, but finer
/// elements there do not make its tets better);
/// and the distance from a curve to a patch it does not bound, at samples
/// `s` of the curve whose perpendicular falls inside a face of that patch
/// (given as `Facing_pair`s: a rim running along another wall), unless a
/// corner is within twice that distance of `s` (a curve leaving a patch at
/// a corner meets it at an angle no refinement improves);
/// (a pair whose distance is at least 1 in the user's metric at `s` counts
/// for nothing: an anisotropic metric fine across a thin plate resolves its
/// rims already)
/// counted only below the largest size the user's metric asks at `s`
/// (so nothing changes where the features are far enough apart) and never
/// below a tenth of it (`smallest_relative_size()`). Curves meeting at a corner are not compared
/// with each other: their distance vanishes at the corner whatever the
/// angle. At a point `x` the size asked is `min_s a(s) + gradation |x - s|`,
/// so the refinement fades with a bounded growth (the number of nodes it
/// adds grows like the logarithm of `h / a`, not like `(h / a)^3`); the
/// field is the user's metric intersected with that isotropic size.
///
/// Thread-safe queries; copies share the feature data.
///
/// \tparam MetricField a model of `MetricField_3`
template <typename MetricField>
class Feature_size_metric_field_3 {
public:
  typedef typename MetricField::Kernel Kernel;
  typedef typename Kernel::FT FT;
  typedef typename Kernel::Point_3 Point_3;
  typedef Bubble_mesh_3::Metric_3 Metric;
  typedef MetricField Base_field;
  typedef std::array<double, 3> Point;

  /// A feature curve: its points in order (for a closed curve, the first
  /// point is not repeated at the end), and the corners at its ends
  /// (indices in the corner list; -1: none, for a closed curve).
  struct Curve {
    std::vector<Point> points;
    int first_corner = -1, last_corner = -1;
    bool closed = false;
  };

  /// a surface point and the point straight inside it on the other side of
  /// a thin part (`Bubble_mesh_3::internal::facing_pairs` computes them)
  typedef Bubble_mesh_3::internal::Facing_pair Facing_pair;

  /// What the field found; sizes are in the input's units.
  struct Statistics {
    std::size_t samples = 0;         ///< corner and curve samples compared
    std::size_t refined_samples = 0; ///< samples where the features ask for smaller sizes
    std::size_t kept_samples = 0;    ///< of those, the ones not implied by another (queried)
    std::size_t floored_samples = 0; ///< samples whose feature size was raised to the floor
    std::size_t thickness_samples = 0; ///< facing pairs compared (thin-part candidates)
    std::size_t thin_samples = 0;      ///< of those, the ones that ask for smaller sizes (counted in refined_samples)
    std::size_t near_patch_samples = 0; ///< curve samples near a patch they do not bound (compared)
    std::size_t near_patch_refined = 0; ///< of those, the ones that ask for smaller sizes (counted in refined_samples)
    double smallest_size = std::numeric_limits<double>::infinity(); ///< smallest feature size asked
    double smallest_ratio = std::numeric_limits<double>::infinity(); ///< its smallest ratio to the user's size
    double seconds = 0;                                              ///< time the construction took
  };

  /// A field that is `field` itself.
  explicit Feature_size_metric_field_3(const MetricField& field) : field_(field), data_(std::make_shared<Data>()) {}

  /// `corners` and `curves` are the domain's features, `facing` the pairs
  /// across its thin parts, `near_patch` the curve points paired with the
  /// nearest point of a patch they do not bound; `gradation` the growth
  /// of the size asked per unit distance from a small feature (> 0). Throws
  /// `Bubble_mesh_3::Invalid_input` for a bad gradation or curve.
  Feature_size_metric_field_3(const MetricField& field, const std::vector<Point>& corners,
                              const std::vector<Curve>& curves, double gradation = 0.5,
                              const std::vector<Facing_pair>& facing = {},
                              const std::vector<Facing_pair>& near_patch = {})
      : field_(field), data_(std::make_shared<Data>())
  {
    if(!(gradation > 0) || !std::isfinite(gradation))
      throw Bubble_mesh_3::Invalid_input("feature sizes: the gradation must be a positive number");
    for(const Curve& c : curves) {
      if(c.points.size() < 2)
        throw Bubble_mesh_3::Invalid_input("feature sizes: a curve has fewer than 2 points");
      for(int k : {c.first_corner, c.last_corner})
        if(k >= int(corners.size()) || (k < 0 && !c.closed))
          throw Bubble_mesh_3::Invalid_input("feature sizes: an open curve without a corner at an end");
    }
    data_->gradation = gradation;
    const auto t0 = std::chrono::steady_clock::now();
    build(corners, curves, facing, near_patch);
    data_->statistics.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  /// the metric at `p`: the user's, intersected with the feature size there
  Metric operator()(const Point_3& p) const
  {
    Metric user = field_(p);
    const Data& d = *data_;
    if(d.cells.empty())
      return user;
    const Eigen::Vector3d x(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
    const double size = feature_size(x);
    if(!(size < std::numeric_limits<double>::infinity()))
      return user;
    // the user's smallest eigenvalue is at least det / (trace^2 / 4): where
    // the feature size asks for no more, the user's metric stands
    const double inverse = 1 / (size * size);
    const double trace = user(0, 0) + user(1, 1) + user(2, 2);
    if(4 * user.determinant() / (trace * trace) >= inverse)
      return user;
    // intersection with an isotropic metric: the eigenvalues below 1/size^2
    // are raised to it, the directions kept
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(user.matrix());
    if(eig.eigenvalues().minCoeff() >= inverse)
      return user;
    const Eigen::Vector3d raised = eig.eigenvalues().cwiseMax(inverse);
    const Eigen::Matrix3d m = eig.eigenvectors() * raised.asDiagonal() * eig.eigenvectors().transpose();
    return Metric(Eigen::Matrix3d(0.5 * (m + m.transpose())), "feature size metric");
  }

  /// the isotropic size the features ask at `p` (infinity: none)
  double feature_size(const Point_3& p) const
  {
    return feature_size(Eigen::Vector3d(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())));
  }

  const MetricField& base_field() const { return field_; }
  /// whether some feature asks for smaller sizes than the base field
  bool refines() const { return !data_->cells.empty(); }
  double gradation() const { return data_->gradation; }
  const Statistics& statistics() const { return data_->statistics; }

  /// the floor of a feature size, as a fraction of the user's largest size.
  /// Features closer than that are below the resolution asked (noise, or
  /// sliver faces of a CAD model) and refining to them costs far more than
  /// it gives: at diagonal / 30, a floor of a thousandth took
  /// mpi_triang from 3 s to over 300 s (the packing at its iteration caps,
  /// the front at its work budget) and femur from 2 s to 70 s for worst
  /// angles 0.1 and 4.1 degrees; a tenth gives 35 s and 44 s for the same
  /// angles, and cheese 6.8 against 9.0 degrees at 0.03.
  static constexpr double smallest_relative_size() { return 0.1; }

private:
  typedef CGAL::Exact_predicates_inexact_constructions_kernel EK;
  typedef boost::tuple<EK::Point_3, int> Indexed_point;
  typedef CGAL::Search_traits_adapter<Indexed_point, CGAL::Nth_of_tuple_property_map<0, Indexed_point>,
                                      CGAL::Search_traits_3<EK>>
      Search_traits;
  typedef CGAL::Kd_tree<Search_traits> Tree;
  typedef CGAL::Fuzzy_sphere<Search_traits> Sphere;

  struct Sample {
    Eigen::Vector3d p;
    int curve = -1;  // -1: a corner
    int corner = -1; // the corner's index, for a corner
    double arc = 0;  // arc length from the curve's start
  };
  typedef std::array<std::int64_t, 3> Cell;
  struct Cell_hash {
    std::size_t operator()(const Cell& c) const
    {
      return std::size_t(c[0] * 73856093) ^ std::size_t(c[1] * 19349663) ^ std::size_t(c[2] * 83492791);
    }
  };
  struct Source { // a refining sample: size a at p
    Eigen::Vector3d p;
    double a;
    double h; // the user's largest size there
  };

  struct Data {
    double gradation = 0.5, cell = 1;
    std::vector<Source> sources;
    std::unordered_map<Cell, std::vector<int>, Cell_hash> cells; // sources whose reach meets the cell
    Statistics statistics;
  };

  static Cell key(std::int64_t i, std::int64_t j, std::int64_t k) { return Cell{{i, j, k}}; }
  std::int64_t cell_of(double c) const { return std::int64_t(std::floor(c / data_->cell)); }

  double feature_size(const Eigen::Vector3d& x) const
  {
    const Data& d = *data_;
    if(d.cells.empty())
      return std::numeric_limits<double>::infinity();
    const auto it = d.cells.find(key(cell_of(x[0]), cell_of(x[1]), cell_of(x[2])));
    double best = std::numeric_limits<double>::infinity();
    if(it == d.cells.end())
      return best;
    for(int i : it->second) {
      const Source& s = d.sources[std::size_t(i)];
      best = std::min(best, s.a + d.gradation * (x - s.p).norm());
    }
    return best;
  }

  // the largest and smallest sizes of the user's metric at p
  std::pair<double, double> user_sizes(const Eigen::Vector3d& p) const
  {
    return sizes_of(field_(Point_3(p[0], p[1], p[2])));
  }
  static std::pair<double, double> sizes_of(const Metric& m)
  {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.computeDirect(m.matrix(), Eigen::EigenvaluesOnly);
    return {1 / std::sqrt(eig.eigenvalues().minCoeff()), 1 / std::sqrt(eig.eigenvalues().maxCoeff())};
  }

  void build(const std::vector<Point>& corners, const std::vector<Curve>& curves,
             const std::vector<Facing_pair>& facing, const std::vector<Facing_pair>& near_patch)
  {
    Data& d = *data_;
    std::vector<double> length;
    const std::vector<Sample> samples = feature_samples(corners, curves, length);
    d.statistics.samples = samples.size();
    double largest_reach = 0;
    // (no corners and no curves, a torus, a sphere: only thin parts refine)
    std::vector<Source> refining;
    if(!samples.empty())
      refining = refining_sources(samples, corners, curves, length, largest_reach);
    thin_part_sources(samples, facing, refining, largest_reach);
    near_patch_sources(corners, near_patch, refining, largest_reach);
    if(refining.empty())
      return;
    index_sources(refining, largest_reach);
    d.statistics.kept_samples = d.sources.size();
  }

  static Eigen::Vector3d vec(const Point& p) { return Eigen::Vector3d(p[0], p[1], p[2]); }

  /// the corners, and the curves' points with their segments split to a
  /// quarter of the smallest size asked at their ends (at most 10^5 pieces
  /// per segment); `length`: of each curve
  std::vector<Sample> feature_samples(const std::vector<Point>& corners, const std::vector<Curve>& curves,
                                      std::vector<double>& length) const
  {
    std::vector<Sample> samples;
    for(std::size_t k = 0; k < corners.size(); ++k) {
      Sample s;
      s.p = vec(corners[k]);
      s.corner = int(k);
      samples.push_back(s);
    }
    length.assign(curves.size(), 0);
    for(std::size_t c = 0; c < curves.size(); ++c) {
      const Curve& curve = curves[c];
      const std::size_t n = curve.points.size();
      const std::size_t segments = curve.closed ? n : n - 1;
      double arc = 0;
      double h_prev = user_sizes(vec(curve.points[0])).second;
      for(std::size_t i = 0; i < segments; ++i) {
        const Eigen::Vector3d a = vec(curve.points[i]), b = vec(curve.points[(i + 1) % n]);
        const double h_next = user_sizes(b).second;
        const double l = (b - a).norm();
        const double step = 0.25 * std::min(h_prev, h_next);
        const std::size_t pieces =
            std::min<std::size_t>(100000, std::max<std::size_t>(1, std::size_t(std::ceil(l / step))));
        const bool corner_start = (i == 0 && !curve.closed);
        for(std::size_t j = corner_start ? 1 : 0; j < pieces; ++j) {
          Sample s;
          s.p = a + (b - a) * (double(j) / double(pieces));
          s.curve = int(c);
          s.arc = arc + l * double(j) / double(pieces);
          samples.push_back(s);
        }
        arc += l;
        h_prev = h_next;
      }
      length[c] = arc;
      // an open curve's last point is its end corner: not a curve sample
    }
    return samples;
  }

  /// the samples whose features are closer than the user's size there, as
  /// sources of their feature size (floored, counted in the statistics);
  /// `largest_reach`: the largest distance one of them refines
  std::vector<Source> refining_sources(const std::vector<Sample>& samples, const std::vector<Point>& corners,
                                       const std::vector<Curve>& curves, const std::vector<double>& length,
                                       double& largest_reach)
  {
    // the feature size of each sample, from the samples within the user's
    // largest size there
    std::vector<Indexed_point> indexed;
    indexed.reserve(samples.size());
    for(std::size_t i = 0; i < samples.size(); ++i)
      indexed.emplace_back(EK::Point_3(samples[i].p[0], samples[i].p[1], samples[i].p[2]), int(i));
    Tree tree(indexed.begin(), indexed.end());
    tree.build();
    auto ends_curve = [&](int corner, int c) {
      return corner >= 0 && (curves[std::size_t(c)].first_corner == corner || curves[std::size_t(c)].last_corner == corner);
    };
    auto share_corner = [&](int c, int e) {
      const Curve& a = curves[std::size_t(c)];
      return (a.first_corner >= 0 && ends_curve(a.first_corner, e)) ||
             (a.last_corner >= 0 && ends_curve(a.last_corner, e));
    };
    // two open curves between the same two corners: a patch between them
    auto same_ends = [&](int c, int e) {
      const Curve& a = curves[std::size_t(c)];
      const Curve& b = curves[std::size_t(e)];
      return !a.closed && !b.closed && a.first_corner >= 0 && a.last_corner >= 0 && a.first_corner != a.last_corner &&
             ((a.first_corner == b.first_corner && a.last_corner == b.last_corner) ||
              (a.first_corner == b.last_corner && a.last_corner == b.first_corner));
    };
    std::vector<std::vector<int>> curves_at(corners.size());
    for(std::size_t c = 0; c < curves.size(); ++c)
      for(int k : {curves[c].first_corner, curves[c].last_corner})
        if(k >= 0 && (curves_at[std::size_t(k)].empty() || curves_at[std::size_t(k)].back() != int(c)))
          curves_at[std::size_t(k)].push_back(int(c));
    auto curve_bound = [&](int c) {
      const Curve& curve = curves[std::size_t(c)];
      const bool one_corner = curve.closed || curve.first_corner == curve.last_corner;
      return one_corner ? length[std::size_t(c)] / 3 : length[std::size_t(c)];
    };
    std::vector<Source> refining;
    std::vector<Indexed_point> found;
    for(std::size_t i = 0; i < samples.size(); ++i) {
      const Sample& s = samples[i];
      const Metric user = field_(Point_3(s.p[0], s.p[1], s.p[2]));
      const double h = sizes_of(user).first;
      double a = std::numeric_limits<double>::infinity();
      if(s.curve >= 0)
        a = curve_bound(s.curve);
      else
        for(int c : curves_at[std::size_t(s.corner)])
          a = std::min(a, curve_bound(c));
      found.clear();
      tree.search(std::back_inserter(found), Sphere(EK::Point_3(s.p[0], s.p[1], s.p[2]), std::min(h, a)));
      for(const Indexed_point& f : found) {
        const std::size_t j = std::size_t(boost::get<1>(f));
        if(j == i)
          continue;
        const Sample& t = samples[j];
        bool counts;
        if(s.curve < 0 && t.curve < 0)
          counts = true;
        else if(s.curve < 0)
          counts = !ends_curve(s.corner, t.curve);
        else if(t.curve < 0)
          counts = !ends_curve(t.corner, s.curve);
        else if(s.curve == t.curve) {
          // the curve coming back near itself
          double along = std::abs(s.arc - t.arc);
          if(curves[std::size_t(s.curve)].closed)
            along = std::min(along, length[std::size_t(s.curve)] - along);
          counts = along > 2 * (s.p - t.p).norm();
        } else if(same_ends(s.curve, t.curve)) {
          // a lens: the patch between them is thinner here than half the
          // way to either corner (the triceratops' one-triangle patches,
          // 0.018 wide and 0.36 long, held 5-degree tets at d/30). Near the
          // corners the two meet at an angle no refinement improves.
          const double apart = (s.p - t.p).norm();
          const Curve& lens = curves[std::size_t(s.curve)];
          counts = true;
          for(int k : {lens.first_corner, lens.last_corner}) {
            const Eigen::Vector3d x = vec(corners[std::size_t(k)]);
            counts = counts && (s.p - x).norm() > 2 * apart && (t.p - x).norm() > 2 * apart;
          }
        } else
          counts = !share_corner(s.curve, t.curve);
        // a pair the user's metric already resolves (an anisotropic metric
        // fine across a thin plate) asks for nothing
        if(counts && user.length(Eigen::Vector3d(t.p - s.p)) < 1)
          a = std::min(a, (s.p - t.p).norm());
      }
      if(a < h)
        add_source(s.p, a, h, refining, largest_reach);
    }
    return refining;
  }

  /// appends a source of size `a` (raised to the floor) at `p`, where the
  /// user's largest size is `h`, counted in the statistics
  void add_source(const Eigen::Vector3d& p, double a, double h, std::vector<Source>& refining, double& largest_reach)
  {
    Statistics& st = data_->statistics;
    ++st.refined_samples;
    const double floor = smallest_relative_size() * h;
    if(a < floor) {
      a = floor;
      ++st.floored_samples;
    }
    st.smallest_size = std::min(st.smallest_size, a);
    st.smallest_ratio = std::min(st.smallest_ratio, a / h);
    refining.push_back(Source{p, a, h});
    largest_reach = std::max(largest_reach, reach(refining.back(), h));
  }

  /// the facing pairs across parts thinner than the user's size (and its
  /// metric: a pair of metric length 1 or more asks for nothing), far enough
  /// from corners and curves, as sources of their thickness (floored like
  /// the others), appended to `refining`
  void thin_part_sources(const std::vector<Sample>& samples, const std::vector<Facing_pair>& facing,
                         std::vector<Source>& refining, double& largest_reach)
  {
    Data& d = *data_;
    d.statistics.thickness_samples = facing.size();
    if(facing.empty())
      return;
    std::vector<Indexed_point> indexed;
    indexed.reserve(samples.size());
    for(std::size_t i = 0; i < samples.size(); ++i)
      indexed.emplace_back(EK::Point_3(samples[i].p[0], samples[i].p[1], samples[i].p[2]), int(i));
    Tree tree(indexed.begin(), indexed.end());
    if(!indexed.empty())
      tree.build();
    std::vector<Indexed_point> found;
    for(const Facing_pair& pair : facing) {
      const Eigen::Vector3d p = vec(pair.p), q = vec(pair.q);
      const double t = (q - p).norm();
      const Metric user = field_(Point_3(p[0], p[1], p[2]));
      const std::pair<double, double> hs = sizes_of(user);
      const double h = hs.first;
      if(!(t < h) || !(user.length(Eigen::Vector3d(q - p)) < 1))
        continue;
      // a corner or curve near p: a wedge's edge or a plate's rim, which the
      // corner and curve samples size already (curve samples are at most a
      // quarter of the smallest size apart, hence the second bound)
      if(!indexed.empty()) {
        found.clear();
        tree.search(std::back_inserter(found),
                    Sphere(EK::Point_3(p[0], p[1], p[2]), std::max(2 * t, 0.25 * hs.second)));
        if(!found.empty())
          continue;
      }
      ++d.statistics.thin_samples;
      add_source(p, t, h, refining, largest_reach);
    }
  }

  /// the curve points nearer to a patch they do not bound than the user's
  /// size (and its metric), farther than twice that from every corner, as
  /// sources of that distance (floored like the others), appended to
  /// `refining`
  void near_patch_sources(const std::vector<Point>& corners, const std::vector<Facing_pair>& near_patch,
                          std::vector<Source>& refining, double& largest_reach)
  {
    Data& d = *data_;
    d.statistics.near_patch_samples = near_patch.size();
    if(near_patch.empty())
      return;
    std::vector<Indexed_point> indexed;
    for(std::size_t i = 0; i < corners.size(); ++i)
      indexed.emplace_back(EK::Point_3(corners[i][0], corners[i][1], corners[i][2]), int(i));
    Tree tree(indexed.begin(), indexed.end());
    if(!indexed.empty())
      tree.build();
    std::vector<Indexed_point> found;
    for(const Facing_pair& pair : near_patch) {
      const Eigen::Vector3d p = vec(pair.p), q = vec(pair.q);
      const double t = (q - p).norm();
      const Metric user = field_(Point_3(p[0], p[1], p[2]));
      const double h = sizes_of(user).first;
      if(!(t < h) || !(user.length(Eigen::Vector3d(q - p)) < 1))
        continue;
      if(!indexed.empty()) {
        found.clear();
        tree.search(std::back_inserter(found), Sphere(EK::Point_3(p[0], p[1], p[2]), 2 * t));
        if(!found.empty())
          continue;
      }
      ++d.statistics.near_patch_refined;
      add_source(p, t, h, refining, largest_reach);
    }
  }

  /// keeps the sources no other one implies, listed in hash-grid cells each
  /// pruned to the sources that can give its smallest size
  void index_sources(std::vector<Source>& refining, double largest_reach)
  {
    Data& d = *data_;
    // the queried sources: the smallest first, each kept unless a kept one
    // already asks as little everywhere (a_t + g |s - t| <= a_s implies it
    // for every x by the triangle inequality)
    std::sort(refining.begin(), refining.end(), [](const Source& x, const Source& y) { return x.a < y.a; });
    std::vector<double> reaches;
    for(const Source& s : refining)
      reaches.push_back(reach(s, s.h));
    std::vector<double> sorted_reaches = reaches;
    std::nth_element(sorted_reaches.begin(), sorted_reaches.begin() + std::ptrdiff_t(sorted_reaches.size() / 2),
                     sorted_reaches.end());
    // cells of a quarter of the median reach (at most 33 cells across a
    // reach): a source is listed in every cell its reach meets, then each
    // cell keeps the sources that can give its smallest size somewhere in it
    d.cell = std::max(0.25 * sorted_reaches[sorted_reaches.size() / 2], largest_reach / 16);
    double extent = 0;
    for(const Source& src : refining)
      extent = std::max(extent, (src.p - refining.front().p).cwiseAbs().maxCoeff());
    d.cell = std::max(d.cell, 1e-7 * (extent + std::abs(refining.front().p.maxCoeff()) +
                                      std::abs(refining.front().p.minCoeff())));
    const double g = d.cell;
    for(std::size_t i = 0; i < refining.size(); ++i) {
      const Source& s = refining[i];
      if(feature_size(s.p) <= s.a)
        continue;
      const int id = int(d.sources.size());
      d.sources.push_back(s);
      const double r = reaches[i];
      for(std::int64_t a = cell_of(s.p[0] - r); a <= cell_of(s.p[0] + r); ++a)
        for(std::int64_t b = cell_of(s.p[1] - r); b <= cell_of(s.p[1] + r); ++b)
          for(std::int64_t c = cell_of(s.p[2] - r); c <= cell_of(s.p[2] + r); ++c) {
            const Eigen::Vector3d lo(double(a) * g, double(b) * g, double(c) * g);
            if(box_distances(s.p, lo, g).first <= r)
              d.cells[key(a, b, c)].push_back(id);
          }
    }
    for(auto& cell : d.cells) {
      const Eigen::Vector3d lo(double(cell.first[0]) * g, double(cell.first[1]) * g, double(cell.first[2]) * g);
      double best_upper = std::numeric_limits<double>::infinity();
      for(int id : cell.second) {
        const Source& src = d.sources[std::size_t(id)];
        best_upper = std::min(best_upper, src.a + d.gradation * box_distances(src.p, lo, g).second);
      }
      std::vector<int> kept;
      for(int id : cell.second) {
        const Source& src = d.sources[std::size_t(id)];
        if(src.a + d.gradation * box_distances(src.p, lo, g).first <= best_upper)
          kept.push_back(id);
      }
      cell.second.swap(kept);
    }
  }

  // the smallest and largest distances from p to the cube of side g at lo
  static std::pair<double, double> box_distances(const Eigen::Vector3d& p, const Eigen::Vector3d& lo, double g)
  {
    double near = 0, far = 0;
    for(int k = 0; k < 3; ++k) {
      const double below = lo[k] - p[k], above = p[k] - (lo[k] + g);
      const double n = std::max({below, above, 0.0});
      const double f = std::max(std::abs(p[k] - lo[k]), std::abs(p[k] - lo[k] - g));
      near += n * n;
      far += f * f;
    }
    return {std::sqrt(near), std::sqrt(far)};
  }

  // how far a source can ask for less than the user's size h at it; twice
  // that, so a user's size growing away from the source is still met
  double reach(const Source& s, double h) const { return 2 * (h - s.a) / data_->gradation; }

  MetricField field_;
  std::shared_ptr<Data> data_;
};


namespace Bubble_mesh_3 {

/// \ingroup PkgBubbleMesh3Ref
/// the default growth of the feature sizes per unit distance
/// (`CGAL::Feature_size_metric_field_3`)
constexpr double default_feature_size_gradation = 0.5;

} // namespace Bubble_mesh_3

/// \ingroup PkgBubbleMesh3Functions
/// `field` refined where the corners and feature curves of `domain` (a model
/// of `MeshDomainWithFeatures_3`) are closer to each other than its sizes
/// (`CGAL::Feature_size_metric_field_3`). This is the field
/// `make_anisotropic_mesh_3()` meshes with (unless its
/// `small_feature_refinement` is false): measure the mesh's quality in it.
template <typename MeshDomain, typename MetricField>
CGAL::Feature_size_metric_field_3<MetricField>
make_feature_size_metric_field_3(const MeshDomain& domain, const MetricField& field,
                                 double gradation = Bubble_mesh_3::default_feature_size_gradation)
{
  typedef CGAL::Feature_size_metric_field_3<MetricField> Field;
  typedef typename MeshDomain::Point_3 Point_3;
  typedef typename MeshDomain::Index Index;
  typedef typename MeshDomain::Corner_index Corner_index;
  typedef typename MeshDomain::Curve_index Curve_index;
  auto point = [](const Point_3& p) {
    return std::array<double, 3>{{CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())}};
  };
  std::vector<std::pair<Corner_index, Point_3>> domain_corners;
  domain.get_corners(std::back_inserter(domain_corners));
  std::vector<std::array<double, 3>> corners;
  std::map<Corner_index, int> corner_id;
  for(const auto& c : domain_corners) {
    corner_id.emplace(c.first, int(corners.size()));
    corners.push_back(point(c.second));
  }
  typedef std::tuple<Curve_index, std::pair<Point_3, Index>, std::pair<Point_3, Index>> Curve_tuple;
  std::vector<Curve_tuple> domain_curves;
  domain.get_curves(std::back_inserter(domain_curves));
  std::vector<typename Field::Curve> curves;
  for(const auto& t : domain_curves) {
    typename Field::Curve c;
    const Curve_index index = std::get<0>(t);
    const Point_3& start = std::get<1>(t).first;
    const double length = CGAL::to_double(domain.curve_length(index));
    c.closed = domain.is_loop(index);
    if(!c.closed) {
      const auto a = corner_id.find(domain.corner_index(std::get<1>(t).second));
      const auto b = corner_id.find(domain.corner_index(std::get<2>(t).second));
      if(a == corner_id.end() || b == corner_id.end())
        throw Bubble_mesh_3::Invalid_input("feature sizes: a curve of the domain does not end at its corners");
      c.first_corner = a->second;
      c.last_corner = b->second;
    }
    // points along the curve at most a quarter of the smallest size apart
    // (and at least 16 per curve); the field splits them further if needed
    c.points.push_back(point(start));
    double s = 0;
    while(true) {
      const auto m = field(Point_3(c.points.back()[0], c.points.back()[1], c.points.back()[2]));
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
      eig.computeDirect(m.matrix(), Eigen::EigenvaluesOnly);
      const double step = std::max(length * 1e-5, std::min(0.25 / std::sqrt(eig.eigenvalues().maxCoeff()), length / 16));
      s += step;
      if(!(s < length * (1 - 1e-9)))
        break;
      c.points.push_back(point(domain.construct_point_on_curve(start, index, s)));
    }
    if(!c.closed)
      c.points.push_back(point(std::get<2>(t).first));
    curves.push_back(std::move(c));
  }
  std::vector<typename Field::Facing_pair> facing, near_patch;
  if constexpr(Bubble_mesh_3::internal::packing::Has_polyhedra<MeshDomain>::value) {
    auto sizes = [&](const std::array<double, 3>& p) {
      const auto m = field(Point_3(p[0], p[1], p[2]));
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
      eig.computeDirect(m.matrix(), Eigen::EigenvaluesOnly);
      return std::make_pair(1 / std::sqrt(eig.eigenvalues().minCoeff()), 1 / std::sqrt(eig.eigenvalues().maxCoeff()));
    };
    // rays half the largest size apart (the thickness is a property of the
    // shape, not of the metric's directions), as long as the largest size
    const auto surface = Bubble_mesh_3::internal::front::boundary_surface_from_polyhedral_domain(domain);
    facing = Bubble_mesh_3::internal::facing_pairs(
        surface, [&](const std::array<double, 3>& p) { return 0.5 * sizes(p).first; },
        [&](const std::array<double, 3>& p) { return sizes(p).first; });
    // curve points as far apart as the rays, as far reaching
    near_patch = Bubble_mesh_3::internal::curve_patch_pairs(
        surface, [&](const std::array<double, 3>& p) { return 0.5 * sizes(p).first; },
        [&](const std::array<double, 3>& p) { return sizes(p).first; });
  }
  return Field(field, corners, curves, gradation, facing, near_patch);
}


} // namespace CGAL

#endif // CGAL_FEATURE_SIZE_METRIC_FIELD_3_H
