// Metric fields: a constant one, one from a lambda, and one interpolated from
// a background mesh + MEDIT .sol (the exchange format of MMG, Gmsh and CFD
// adaptation loops). The example samples the lambda on a background grid,
// writes it as .mesh + .sol, reads it back as an interpolated field and
// reports how closely the interpolation follows the lambda.
#include <CGAL/Bubble_mesh_3/IO/medit.h>
#include <CGAL/Bubble_mesh_3/IO/sol.h>
#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Constant_metric_field_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Function_metric_field_3.h>
#include <CGAL/Interpolated_metric_field_3.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <string>
#include <vector>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_3 Point_3;
using CGAL::Bubble_mesh_3::Metric_3;

// The unit cube as an n x n x n grid, each cell split into 6 tets around its diagonal.
CGAL::Bubble_mesh_3::Indexed_tet_mesh_3 grid_mesh(int n)
{
  CGAL::Bubble_mesh_3::Indexed_tet_mesh_3 mesh;
  auto id = [n](int i, int j, int k) { return (k * (n + 1) + j) * (n + 1) + i; };
  for(int k = 0; k <= n; ++k)
    for(int j = 0; j <= n; ++j)
      for(int i = 0; i <= n; ++i) {
        mesh.points.push_back({double(i) / n, double(j) / n, double(k) / n});
        mesh.point_refs.push_back(0);
      }
  // Kuhn subdivision: the 6 monotone paths from corner 000 to corner 111.
  const int paths[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for(int k = 0; k < n; ++k)
    for(int j = 0; j < n; ++j)
      for(int i = 0; i < n; ++i)
        for(const auto& path : paths) {
          int c[3] = {0, 0, 0};
          std::array<int, 4> tet;
          tet[0] = id(i, j, k);
          for(int s = 0; s < 3; ++s) {
            c[path[s]] = 1;
            tet[s + 1] = id(i + c[0], j + c[1], k + c[2]);
          }
          // odd permutations of the axes give negatively oriented tets
          const bool odd = (path[0] == 0 && path[1] == 2) || (path[0] == 1 && path[1] == 0) ||
                           (path[0] == 2 && path[1] == 1);
          if(odd)
            std::swap(tet[0], tet[1]);
          mesh.tets.push_back(tet);
          mesh.tet_refs.push_back(1);
        }
  return mesh;
}

int main()
{
  // 1. Constant: elements 0.1 long along x, 0.02 across.
  Metric_3::Matrix axes = Metric_3::Matrix::Identity();
  CGAL::Constant_metric_field_3<K> stretched(
      Metric_3::from_directions_and_sizes(axes, Metric_3::Vector(0.1, 0.02, 0.02)));
  std::cout << "constant field: metric length of (0.1,0,0) = "
            << stretched(Point_3(0, 0, 0)).length(Metric_3::Vector(0.1, 0, 0)) << "\n";

  // 2. A lambda: sizes grade from 0.05 at x = 0 to 0.2 at x = 1, stretched 1:4 along y.
  auto graded = CGAL::make_function_metric_field_3<K>([](const Point_3& p) {
    const double h = 0.05 * std::pow(4.0, std::clamp(p.x(), 0.0, 1.0));
    return Metric_3::from_directions_and_sizes(Metric_3::Matrix::Identity(), Metric_3::Vector(h, 4 * h, h));
  });

  // 3. Sample the lambda at the vertices of a background grid, write .mesh + .sol, read back.
  CGAL::Bubble_mesh_3::Indexed_tet_mesh_3 background = grid_mesh(8);
  std::vector<Metric_3> values;
  for(const auto& p : background.points)
    values.push_back(graded(Point_3(p[0], p[1], p[2])));
  CGAL::Bubble_mesh_3::IO::write_medit("background.mesh", background);
  CGAL::Bubble_mesh_3::IO::write_sol("background.sol", values);
  auto interpolated = CGAL::Interpolated_metric_field_3<K>::from_files("background.mesh", "background.sol");

  // Log-Euclidean interpolation reproduces this field exactly where log M is
  // linear; here log h is linear in x, so the error is round-off only.
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(0, 1);
  double worst = 0;
  for(int i = 0; i < 1000; ++i) {
    Point_3 p(u(rng), u(rng), u(rng));
    const Metric_3::Matrix a = graded(p).matrix();
    const Metric_3::Matrix b = interpolated(p).matrix();
    worst = std::max(worst, (a - b).norm() / a.norm());
  }
  std::cout << "interpolated field: " << background.tets.size() << " background tets, worst relative error "
            << worst << " on 1000 random points\n";
  // Outside the background mesh the nearest vertex's value is used.
  std::cout << "outside (2,0.5,0.5): size along x = "
            << interpolated(Point_3(2, 0.5, 0.5)).principal_sizes().minCoeff() << "\n";
  return worst < 1e-9 ? 0 : 1;
}
