// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Analytic metric families, as callables to wrap in `Function_metric_field_3`:
// the paper's cylindrical anisotropy around an axis, a surface-aligned
// boundary-layer metric, and the analytic metrics of the UGAWG benchmark.
#ifndef CGAL_BUBBLE_MESH_3_ANALYTIC_METRIC_FIELDS_H
#define CGAL_BUBBLE_MESH_3_ANALYTIC_METRIC_FIELDS_H

#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/Surface_mesh.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

namespace CGAL {
namespace Bubble_mesh_3 {

/// \ingroup PkgBubbleMesh3Classes
/// Cylindrical anisotropy around the axis through `point` along `direction`:
/// size `h` along the axis and radially, and `h (1 + (ratio - 1) min(r / radius, 1))`
/// around it (r: distance to the axis), i.e. isotropic on the axis and
/// stretched `1:ratio` tangentially from distance `radius` on, as in the
/// paper's mechanical part.
class Cylindrical_metric {
public:
  Cylindrical_metric(const Eigen::Vector3d& point, const Eigen::Vector3d& direction, double h, double ratio,
                     double radius)
      : p_(point), h_(h), ratio_(ratio), radius_(radius)
  {
    if(!(direction.norm() > 0) || !direction.allFinite() || !point.allFinite())
      throw Invalid_input("cylindrical metric: the axis needs a finite point and a non-zero direction");
    if(!(h > 0) || !std::isfinite(h) || !(ratio >= 1) || !std::isfinite(ratio) || !(radius > 0) ||
       !std::isfinite(radius))
      throw Invalid_input("cylindrical metric: need size > 0, ratio >= 1, radius > 0");
    a_ = direction.normalized();
  }

  template <typename Point>
  Metric_3 operator()(const Point& x) const
  {
    const Eigen::Vector3d v(CGAL::to_double(x.x()) - p_[0], CGAL::to_double(x.y()) - p_[1],
                            CGAL::to_double(x.z()) - p_[2]);
    const Eigen::Vector3d radial = v - v.dot(a_) * a_;
    const double r = radial.norm();
    const double ht = h_ * (1 + (ratio_ - 1) * std::min(r / radius_, 1.0));
    if(!(r > 1e-12 * radius_))
      return Metric_3::isotropic(h_);
    const Eigen::Vector3d er = radial / r;
    const Eigen::Vector3d et = a_.cross(er);
    Eigen::Matrix3d dirs;
    dirs.col(0) = a_;
    dirs.col(1) = er;
    dirs.col(2) = et;
    return Metric_3::from_directions_and_sizes(dirs, Eigen::Vector3d(h_, h_, ht));
  }

private:
  Eigen::Vector3d p_, a_;
  double h_, ratio_, radius_;
};

/// \ingroup PkgBubbleMesh3Classes
/// Surface-aligned boundary-layer metric of a closed triangle surface:
/// tangential size `h_tangent` everywhere; normal size `h_normal` on the
/// surface growing linearly to `h_tangent` at distance `thickness` (the
/// normal is that of the closest surface triangle). Thread-safe queries.
template <typename K>
class Boundary_layer_metric {
public:
  typedef CGAL::Surface_mesh<typename K::Point_3> Mesh;

  Boundary_layer_metric(const Mesh& surface, double h_normal, double h_tangent, double thickness)
      : mesh_(std::make_shared<Mesh>(surface)), hn_(h_normal), ht_(h_tangent), t_(thickness)
  {
    if(!(h_normal > 0) || !(h_tangent >= h_normal) || !(thickness > 0) || !std::isfinite(h_tangent) ||
       !std::isfinite(thickness))
      throw Invalid_input("boundary-layer metric: need 0 < normal size <= tangential size and thickness > 0");
    if(mesh_->number_of_faces() == 0)
      throw Invalid_input("boundary-layer metric: empty surface");
    tree_ = std::make_shared<Tree>(faces(*mesh_).first, faces(*mesh_).second, *mesh_);
    tree_->accelerate_distance_queries();
    tree_->closest_point(mesh_->point(*vertices(*mesh_).first)); // build before concurrent use
  }

  template <typename Point>
  Metric_3 operator()(const Point& x) const
  {
    const typename K::Point_3 q(CGAL::to_double(x.x()), CGAL::to_double(x.y()), CGAL::to_double(x.z()));
    const auto cp = tree_->closest_point_and_primitive(q);
    const double d = std::sqrt(CGAL::to_double(CGAL::squared_distance(q, cp.first)));
    const auto n = CGAL::Polygon_mesh_processing::compute_face_normal(cp.second, *mesh_);
    Eigen::Vector3d en(CGAL::to_double(n.x()), CGAL::to_double(n.y()), CGAL::to_double(n.z()));
    if(!(en.norm() > 0))
      return Metric_3::isotropic(ht_);
    en.normalize();
    const double hn = hn_ + (ht_ - hn_) * std::min(d / t_, 1.0);
    // M = n n^T / hn^2 + (I - n n^T) / ht^2
    const Eigen::Matrix3d m =
        en * en.transpose() / (hn * hn) + (Eigen::Matrix3d::Identity() - en * en.transpose()) / (ht_ * ht_);
    return Metric_3(0.5 * (m + m.transpose()));
  }

private:
  typedef CGAL::AABB_face_graph_triangle_primitive<Mesh> Primitive;
  typedef CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>> Tree;
  std::shared_ptr<Mesh> mesh_;
  std::shared_ptr<Tree> tree_;
  double hn_, ht_, t_;
};

/// \ingroup PkgBubbleMesh3Classes
/// The analytic metrics of the Unstructured Grid Adaptation Working Group's
/// first benchmark (Ibanez et al., IMR 2017), with h0 = 0.001:
/// - `linear` (on the unit cube): h_x = h_y = 0.1, h_z = h0 + 2 (0.1 - h0) |z - 0.5|,
///   a 1:100 layer at z = 0.5;
/// - `polar_1` (on the cube-cylinder, the unit cube minus the cylinder of radius
///   0.5 about the z axis): h_r = h0 + 2 (0.1 - h0) |r - 0.5|, h_theta = h_z = 0.1,
///   r = sqrt(x^2 + y^2), a 1:100 layer on the curved wall;
/// - `polar_2` (on the cube-cylinder): as `polar_1` with the tangential size
///   refined near the wall, h_theta = 0.1 d + 0.025 (1 - d), d = min(10 |r - 0.5|, 1),
///   so that the metric grades gently along the wall.
/// Every size is multiplied by `scale` (2 gives about 8 times fewer nodes).
class Ugawg_metric {
public:
  enum Kind { linear, polar_1, polar_2 };

  explicit Ugawg_metric(Kind kind, double scale = 1) : kind_(kind), scale_(scale)
  {
    if(!(scale > 0) || !std::isfinite(scale))
      throw Invalid_input("UGAWG metric: the scale must be a positive number");
  }

  /// `"linear"`, `"polar-1"` or `"polar-2"`; throws `Invalid_input` for any other name
  static Kind kind_from_name(const std::string& name)
  {
    if(name == "linear")
      return linear;
    if(name == "polar-1")
      return polar_1;
    if(name == "polar-2")
      return polar_2;
    throw Invalid_input("UGAWG metric: unknown case '" + name + "' (known: linear, polar-1, polar-2)");
  }

  template <typename Point>
  Metric_3 operator()(const Point& p) const
  {
    const double h0 = 0.001, x = CGAL::to_double(p.x()), y = CGAL::to_double(p.y()), z = CGAL::to_double(p.z());
    if(kind_ == linear) {
      const double hz = h0 + 2 * (0.1 - h0) * std::abs(z - 0.5);
      return Metric_3::from_directions_and_sizes(Eigen::Matrix3d::Identity(),
                                                 scale_ * Eigen::Vector3d(0.1, 0.1, hz));
    }
    const double r = std::sqrt(x * x + y * y);
    const double hr = h0 + 2 * (0.1 - h0) * std::abs(r - 0.5);
    double ht = 0.1;
    if(kind_ == polar_2) {
      const double d = std::min(10 * std::abs(r - 0.5), 1.0);
      ht = 0.1 * d + 0.025 * (1 - d);
    }
    if(!(r > 1e-12)) // on the axis (outside the benchmark's domain): no radial direction
      return Metric_3::isotropic(scale_ * hr);
    Eigen::Matrix3d dirs;
    dirs.col(0) = Eigen::Vector3d(x / r, y / r, 0);
    dirs.col(1) = Eigen::Vector3d(-y / r, x / r, 0);
    dirs.col(2) = Eigen::Vector3d(0, 0, 1);
    return Metric_3::from_directions_and_sizes(dirs, scale_ * Eigen::Vector3d(hr, ht, 0.1));
  }

private:
  Kind kind_;
  double scale_;
};

} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_ANALYTIC_METRIC_FIELDS_H
