// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Curvature of a triangle surface at its vertices, patch by patch: at each
// vertex, for each patch around it, a quadric h = a u^2 + b u w + c w^2 + d u + e w
// is fitted by least squares to the vertices of the patch's faces within two
// rings, raised where an edge at the vertex bends more than the fit says, in the frame of the patch's area-weighted normal (an osculating
// quadric fit; the linear terms absorb the error of that normal). Its second
// fundamental form gives the principal curvatures and directions. Working per patch keeps sharp edges (patch boundaries) from
// being read as curvature; a vertex on a feature curve gets one estimate per
// patch it bounds.
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_SURFACE_CURVATURE_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_SURFACE_CURVATURE_H

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

/// The curvature of one patch at one vertex: the tensor sum_i |k_i| t_i t_i^T
/// over the two principal curvatures k_i and directions t_i (unit, tangent),
/// plus |k1| n n^T along the normal n (the sizes taken from it are then no
/// larger across the surface than along its most curved direction).
struct Patch_curvature {
  int patch = -1;
  Eigen::Matrix3d tensor = Eigen::Matrix3d::Zero();
  double k1 = 0, k2 = 0; ///< principal curvatures, |k1| >= |k2|
};

namespace curvature_detail {

inline Eigen::Vector3d vec(const std::array<double, 3>& p) { return Eigen::Vector3d(p[0], p[1], p[2]); }

// the quadric fit around `origin` with normal `n` to `neighbours`; false if
// there are too few of them
inline bool fit(const Eigen::Vector3d& origin, const Eigen::Vector3d& n, const std::vector<Eigen::Vector3d>& neighbours,
                Patch_curvature& out)
{
  if(neighbours.size() < 3)
    return false;
  Eigen::Vector3d e1 = std::abs(n[0]) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  e1 = (e1 - e1.dot(n) * n).normalized();
  const Eigen::Vector3d e2 = n.cross(e1);
  double scale = 0;
  for(const auto& q : neighbours)
    scale += (q - origin).norm();
  scale /= double(neighbours.size());
  if(!(scale > 0))
    return false;
  const bool with_slope = neighbours.size() >= 6;
  const int columns = with_slope ? 5 : 3;
  Eigen::MatrixXd a(neighbours.size(), columns);
  Eigen::VectorXd h(neighbours.size());
  for(std::size_t i = 0; i < neighbours.size(); ++i) {
    const Eigen::Vector3d d = (neighbours[i] - origin) / scale;
    const double u = d.dot(e1), w = d.dot(e2);
    a(Eigen::Index(i), 0) = u * u;
    a(Eigen::Index(i), 1) = u * w;
    a(Eigen::Index(i), 2) = w * w;
    if(with_slope) {
      a(Eigen::Index(i), 3) = u;
      a(Eigen::Index(i), 4) = w;
    }
    h(Eigen::Index(i)) = d.dot(n);
  }
  const Eigen::VectorXd x = a.colPivHouseholderQr().solve(h);
  if(!x.allFinite())
    return false;
  // second fundamental form in (e1, e2), back in the input's units
  const double slope = with_slope ? std::sqrt(1 + x[3] * x[3] + x[4] * x[4]) : 1.0;
  Eigen::Matrix2d second;
  second << 2 * x[0], x[1], x[1], 2 * x[2];
  second /= scale * slope;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(second);
  const Eigen::Vector2d k = eig.eigenvalues();
  const Eigen::Matrix2d dirs = eig.eigenvectors();
  out.tensor.setZero();
  for(int i = 0; i < 2; ++i) {
    const Eigen::Vector3d t = dirs(0, i) * e1 + dirs(1, i) * e2;
    out.tensor += std::abs(k[i]) * t * t.transpose();
  }
  out.k1 = std::abs(k[0]) >= std::abs(k[1]) ? k[0] : k[1];
  out.k2 = std::abs(k[0]) >= std::abs(k[1]) ? k[1] : k[0];
  return true;
}

} // namespace curvature_detail

/// The curvature of each patch around each vertex (see the file comment):
/// `result[v]` holds one entry per patch of the faces around v.
inline std::vector<std::vector<Patch_curvature>> patch_curvatures(const std::vector<std::array<double, 3>>& points,
                                                                  const std::vector<std::array<int, 3>>& triangles,
                                                                  const std::vector<int>& patches)
{
  using curvature_detail::vec;
  std::vector<std::vector<int>> faces_of(points.size());
  for(std::size_t f = 0; f < triangles.size(); ++f)
    for(int v : triangles[f])
      faces_of[std::size_t(v)].push_back(int(f));
  std::vector<std::vector<Patch_curvature>> result(points.size());
  for(std::size_t v = 0; v < points.size(); ++v) {
    std::map<int, std::vector<int>> faces_by_patch;
    for(int f : faces_of[v])
      faces_by_patch[patches[std::size_t(f)]].push_back(f);
    for(const auto& pf : faces_by_patch) {
      const int patch = pf.first;
      Eigen::Vector3d normal = Eigen::Vector3d::Zero();
      std::set<int> ring; // the patch's vertices within two rings of v
      for(int f : pf.second) {
        const auto& t = triangles[std::size_t(f)];
        normal += (vec(points[std::size_t(t[1])]) - vec(points[std::size_t(t[0])]))
                      .cross(vec(points[std::size_t(t[2])]) - vec(points[std::size_t(t[0])]));
        ring.insert(t.begin(), t.end());
      }
      ring.erase(int(v));
      const std::set<int> first(ring.begin(), ring.end());
      for(int u : first)
        for(int f : faces_of[std::size_t(u)])
          if(patches[std::size_t(f)] == patch)
            ring.insert(triangles[std::size_t(f)].begin(), triangles[std::size_t(f)].end());
      ring.erase(int(v));
      Patch_curvature c;
      c.patch = patch;
      if(normal.norm() > 0) {
        std::vector<Eigen::Vector3d> neighbours;
        for(int u : ring)
          neighbours.push_back(vec(points[std::size_t(u)]));
        curvature_detail::fit(vec(points[v]), normal.normalized(), neighbours, c);
        // A feature narrower than two rings (a rounded rim, a tight fillet)
        // is flattened by the fit; the bend across each edge of the patch at
        // v tells it: the angle between the two faces' normals over the
        // distance of their centroids is the normal curvature in that
        // direction, at the input's resolution (within a factor 1.5 on
        // skinny triangles of a sphere, whose normals are those above their
        // circumcentres). Where that exceeds twice the fit's largest
        // curvature, the tensor gets the difference across that edge.
        double strongest = 0;
        Eigen::Vector3d across = Eigen::Vector3d::Zero();
        for(std::size_t i = 0; i < pf.second.size(); ++i)
          for(std::size_t j = i + 1; j < pf.second.size(); ++j) {
            const auto& f = triangles[std::size_t(pf.second[i])];
            const auto& g = triangles[std::size_t(pf.second[j])];
            int shared = -1; // the other vertex of the edge v-shared, if f and g share it
            for(int a : f)
              if(a != int(v) && std::find(g.begin(), g.end(), a) != g.end())
                shared = a;
            if(shared < 0)
              continue;
            const Eigen::Vector3d p0 = vec(points[v]), p1 = vec(points[std::size_t(shared)]);
            auto normal_and_area = [&](const std::array<int, 3>& t, double& area) {
              const Eigen::Vector3d n = (vec(points[std::size_t(t[1])]) - vec(points[std::size_t(t[0])]))
                                            .cross(vec(points[std::size_t(t[2])]) - vec(points[std::size_t(t[0])]));
              area = 0.5 * n.norm();
              return n;
            };
            double af = 0, ag = 0;
            const Eigen::Vector3d nf = normal_and_area(f, af), ng = normal_and_area(g, ag);
            const double length = (p1 - p0).norm();
            if(!(af > 0) || !(ag > 0) || !(length > 0))
              continue;
            // the faces are consistently oriented in a patch: the angle
            // between their normals
            const double bend = std::atan2(nf.cross(ng).norm(), nf.dot(ng));
            auto centroid = [&](const std::array<int, 3>& t) -> Eigen::Vector3d {
              return (vec(points[std::size_t(t[0])]) + vec(points[std::size_t(t[1])]) +
                      vec(points[std::size_t(t[2])])) / 3;
            };
            const Eigen::Vector3d step = centroid(g) - centroid(f);
            const Eigen::Vector3d n = (nf.normalized() + ng.normalized()).normalized();
            const Eigen::Vector3d tangent = step - step.dot(n) * n;
            if(!(step.norm() > 0) || !(tangent.norm() > 0))
              continue;
            const double k = bend / step.norm();
            if(k > strongest) {
              strongest = k;
              across = tangent.normalized();
            }
          }
        if(strongest > 2 * std::abs(c.k1) && across.allFinite() && across.norm() > 0) {
          c.tensor += (strongest - std::abs(c.k1)) * across * across.transpose();
          c.k1 = strongest;
        }
        // across the surface the largest curvature too: an element next to
        // a curved wall no thicker than the wall's finest tangential size (a
        // bubble reaching farther would meet the wall's other side, and a
        // thick element over a fine surface is a sliver or a cap)
        const Eigen::Vector3d n = normal.normalized();
        c.tensor += std::abs(c.k1) * n * n.transpose();
      }
      result[v].push_back(c);
    }
  }
  return result;
}

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_SURFACE_CURVATURE_H
