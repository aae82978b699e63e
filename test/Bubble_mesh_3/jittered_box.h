// A jittered, graded box mesh for the tests of metric fields built on a
// background mesh (Hessian recovery, Hessian metric fields).
#ifndef BUBBLE_MESH_3_TEST_JITTERED_BOX_H
#define BUBBLE_MESH_3_TEST_JITTERED_BOX_H

#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

// The box [0,1]^3 as a Kuhn grid (6 tets per cell), its interior vertices
// jittered by up to `jitter` cells and its coordinates graded by x -> x^grade:
// an unstructured, non-uniform mesh on which the fits must still be exact.
inline CGAL::Bubble_mesh_3::Indexed_tet_mesh_3 jittered_box(int n, double jitter, double grade, unsigned seed)
{
  CGAL::Bubble_mesh_3::Indexed_tet_mesh_3 mesh;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  auto index = [&](int i, int j, int k) { return (i * (n + 1) + j) * (n + 1) + k; };
  for(int i = 0; i <= n; ++i)
    for(int j = 0; j <= n; ++j)
      for(int k = 0; k <= n; ++k) {
        std::array<double, 3> c{{double(i), double(j), double(k)}};
        const bool inside = i > 0 && j > 0 && k > 0 && i < n && j < n && k < n;
        for(double& x : c)
          x = std::pow(std::clamp((x + (inside ? u(rng) : 0.0)) / n, 0.0, 1.0), grade);
        mesh.points.push_back(c);
      }
  for(int i = 0; i < n; ++i)
    for(int j = 0; j < n; ++j)
      for(int k = 0; k < n; ++k) {
        const int c[8] = {index(i, j, k),         index(i + 1, j, k),         index(i + 1, j + 1, k),
                          index(i, j + 1, k),     index(i, j, k + 1),         index(i + 1, j, k + 1),
                          index(i + 1, j + 1, k + 1), index(i, j + 1, k + 1)};
        const int six[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
        for(const auto& t : six)
          mesh.tets.push_back({{c[t[0]], c[t[1]], c[t[2]], c[t[3]]}});
      }
  return mesh;
}

#endif // BUBBLE_MESH_3_TEST_JITTERED_BOX_H
