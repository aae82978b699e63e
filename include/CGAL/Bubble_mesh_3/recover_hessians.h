// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_RECOVER_HESSIANS_H
#define CGAL_BUBBLE_MESH_3_RECOVER_HESSIANS_H

#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {

namespace internal {

// Vertex adjacency of a tet mesh (vertices sharing a tet), as sorted lists.
inline std::vector<std::vector<int>> vertex_neighbours(const Indexed_tet_mesh_3& mesh)
{
  std::vector<std::vector<int>> adjacent(mesh.points.size());
  for(const auto& t : mesh.tets)
    for(int a = 0; a < 4; ++a)
      for(int b = 0; b < 4; ++b)
        if(a != b)
          adjacent[std::size_t(t[a])].push_back(t[b]);
  for(auto& list : adjacent) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return adjacent;
}

} // namespace internal

/// \ingroup PkgBubbleMesh3Functions
/// Recovers the Hessian of a scalar field given by its values at the vertices
/// of a tetrahedral mesh (P1 values, e.g. a solution read from a MEDIT `.sol`
/// of type 1), one symmetric matrix per vertex.
///
/// Method: at each vertex, a least-squares fit of the quadratic
/// `u(x) = u_i + g.(x - x_i) + (x - x_i)^T H (x - x_i) / 2` (9 unknowns; the
/// value at the vertex is kept) to the values of the vertices sharing a
/// tetrahedron with it, widened to the next ring of neighbours while fewer
/// than 12 vertices (or too flat a set) determine the fit, up to 3 rings.
/// The fit reproduces a quadratic exactly (up to rounding) on any mesh,
/// boundary vertices included (the fit is one-sided there); for a smooth
/// field the error of `H` is first order in the local edge length
/// (measured on cubics: test `HessianRecovery.CubicConvergesAtFirstOrder`).
/// Vertices in no tetrahedron get the zero matrix.
///
/// Throws `Invalid_input` (messages start with `name`) when the mesh has no
/// tetrahedra, a tetrahedron has a vertex index out of range, the number of
/// values differs from the number of vertices, a value or a coordinate is not
/// finite, or three rings around a vertex do not determine a quadratic.
inline std::vector<Metric_3::Matrix> recover_hessians(const Indexed_tet_mesh_3& mesh,
                                                      const std::vector<double>& values,
                                                      const std::string& name = "Hessian recovery")
{
  typedef Metric_3::Matrix Matrix;
  const std::size_t n = mesh.points.size();
  if(mesh.tets.empty())
    throw Invalid_input(name + ": the mesh has no tetrahedra");
  if(values.size() != n)
    throw Invalid_input(name + ": " + std::to_string(values.size()) + " values for " + std::to_string(n) +
                        " vertices");
  for(std::size_t i = 0; i < n; ++i) {
    if(!std::isfinite(values[i]))
      throw Invalid_input(name + ": the value at vertex " + std::to_string(i + 1) + " is not finite");
    for(double c : mesh.points[i])
      if(!std::isfinite(c))
        throw Invalid_input(name + ": vertex " + std::to_string(i + 1) + " has a non-finite coordinate");
  }
  for(std::size_t t = 0; t < mesh.tets.size(); ++t)
    for(int v : mesh.tets[t])
      if(v < 0 || std::size_t(v) >= n)
        throw Invalid_input(name + ": tetrahedron " + std::to_string(t + 1) + " has vertex index " +
                            std::to_string(v + 1) + ", out of range");

  const std::vector<std::vector<int>> adjacent = internal::vertex_neighbours(mesh);
  std::vector<Matrix> hessians(n, Matrix::Zero());
  std::vector<int> mark(n, -1); // the vertex whose patch last took it
  std::vector<int> patch, next;
  for(std::size_t i = 0; i < n; ++i) {
    if(adjacent[i].empty())
      continue;
    patch.assign(adjacent[i].begin(), adjacent[i].end());
    mark[i] = int(i);
    for(int v : patch)
      mark[std::size_t(v)] = int(i);
    const auto& xi = mesh.points[i];
    bool solved = false;
    for(int ring = 1; ring <= 3 && !solved; ++ring) {
      if(patch.size() >= 12 || ring == 3) {
        // coordinates scaled by the patch radius, for the conditioning
        double radius = 0;
        for(int v : patch)
          for(int c = 0; c < 3; ++c)
            radius = (std::max)(radius, std::abs(mesh.points[std::size_t(v)][c] - xi[c]));
        Eigen::MatrixXd a(patch.size(), 9);
        Eigen::VectorXd b(patch.size());
        for(std::size_t r = 0; r < patch.size(); ++r) {
          const auto& xj = mesh.points[std::size_t(patch[r])];
          const double d0 = (xj[0] - xi[0]) / radius, d1 = (xj[1] - xi[1]) / radius, d2 = (xj[2] - xi[2]) / radius;
          a.row(Eigen::Index(r)) << d0, d1, d2, 0.5 * d0 * d0, 0.5 * d1 * d1, 0.5 * d2 * d2, d0 * d1, d0 * d2, d1 * d2;
          b[Eigen::Index(r)] = values[std::size_t(patch[r])] - values[i];
        }
        // a rank test relative to the largest singular value: a patch in a
        // plane or on a quadric cone through x_i does not fix every term
        Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinU | Eigen::ComputeThinV);
        const auto& sv = svd.singularValues();
        if(patch.size() >= 9 && sv[8] > 1e-8 * sv[0]) {
          const Eigen::VectorXd x = svd.solve(b);
          const double s = 1.0 / (radius * radius);
          Matrix& h = hessians[i];
          h << x[3], x[6], x[7], x[6], x[4], x[8], x[7], x[8], x[5];
          h *= s;
          solved = true;
          break;
        }
      }
      if(ring == 3)
        break;
      // widen to the next ring
      next.clear();
      for(int v : patch)
        for(int w : adjacent[std::size_t(v)])
          if(mark[std::size_t(w)] != int(i)) {
            mark[std::size_t(w)] = int(i);
            next.push_back(w);
          }
      patch.insert(patch.end(), next.begin(), next.end());
    }
    if(!solved)
      throw Invalid_input(name + ": the neighbours of vertex " + std::to_string(i + 1) +
                          " (three rings) do not determine a quadratic (too few, or flat)");
  }
  return hessians;
}

} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_RECOVER_HESSIANS_H
