// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// A solution-adaptive loop: a function with a sharp curved layer (u = tanh of
// the distance to a sphere over a width of 0.01) is sampled at the vertices of
// a mesh, its Hessian gives a metric for a target number of vertices (graded,
// CGAL::make_graded_hessian_metric_field_3), the domain is meshed again for
// that metric (CGAL::Bubble_mesh_3::remesh_anisotropic_3), and so on. The P1
// interpolation error of u on each mesh (L2 and L-infinity, measured on a
// fixed quasi-random sample of the domain) is compared with uniform isotropic
// meshes of the same domain and about the same vertex count.
//
//   adaptation_loop [--full] [--cube-only] [--width W] [--csv OUT.csv]
// (--width: the layer's width, default 0.01)
// Without --full (the run ctest does): the unit cube, targets 4,000 and 8,000,
// 3 remeshings each; the program fails unless the adapted L2 error is at
// least 5 times below the uniform mesh's at each target and falls at least as
// fast as N^(-1/2) between them. (At 2,000 vertices the layer is not resolved
// yet: 5.0 to 5.2 times.) --full (the manual's figure): the cube
// and an L-shaped block, targets 2,000 to 32,000, 5 remeshings each.
#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/detect_features.h>
#include <CGAL/Bubble_mesh_3/remesh_anisotropic_3.h>
#include <CGAL/Constant_metric_field_3.h>
#include <CGAL/Hessian_metric_field_3.h>
#include <CGAL/make_anisotropic_mesh_3.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Polyhedral_mesh_domain_with_features_3<K> Domain;
namespace BM = CGAL::Bubble_mesh_3;

namespace {

// the solution: a layer of width `layer_width` along the sphere of radius 0.75 around the origin
double layer_width = 0.01;
double solution(const std::array<double, 3>& p)
{
  return std::tanh((std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - 0.75) / layer_width);
}

struct Test_domain {
  std::string name;
  std::string off;
  double volume;
  bool (*inside)(const std::array<double, 3>&);
};

const Test_domain cube{"cube",
                       "OFF\n8 12 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n"
                       "3 0 2 3\n3 0 3 1\n3 4 5 7\n3 4 7 6\n3 0 1 5\n3 0 5 4\n3 2 6 7\n3 2 7 3\n"
                       "3 0 4 6\n3 0 6 2\n3 1 3 7\n3 1 7 5\n",
                       1.0, [](const std::array<double, 3>&) { return true; }};
// [0,1]^3 minus [0.5,1] x [0.5,1] x [0,1]: the layer crosses the re-entrant edge
const Test_domain l_block{"L-block",
                          "OFF\n12 20 0\n"
                          "0 0 0\n1 0 0\n1 0.5 0\n0.5 0.5 0\n0.5 1 0\n0 1 0\n"
                          "0 0 1\n1 0 1\n1 0.5 1\n0.5 0.5 1\n0.5 1 1\n0 1 1\n"
                          "3 0 2 1\n3 0 3 2\n3 0 4 3\n3 0 5 4\n3 6 7 8\n3 6 8 9\n3 6 9 10\n3 6 10 11\n"
                          "3 0 1 7\n3 0 7 6\n3 1 2 8\n3 1 8 7\n3 2 3 9\n3 2 9 8\n3 3 4 10\n3 3 10 9\n"
                          "3 4 5 11\n3 4 11 10\n3 5 0 6\n3 5 6 11\n",
                          0.75, [](const std::array<double, 3>& p) { return !(p[0] > 0.5 && p[1] > 0.5); }};

// a fixed quasi-random sample of the domain (Halton sequence, bases 2, 3, 5)
std::vector<std::array<double, 3>> sample(const Test_domain& d, std::size_t n)
{
  auto halton = [](std::size_t i, int base) {
    double f = 1, r = 0;
    for(; i > 0; i /= std::size_t(base)) {
      f /= base;
      r += f * double(i % std::size_t(base));
    }
    return r;
  };
  std::vector<std::array<double, 3>> points;
  for(std::size_t i = 1; points.size() < n; ++i) {
    const std::array<double, 3> p{{halton(i, 2), halton(i, 3), halton(i, 5)}};
    if(d.inside(p))
      points.push_back(p);
  }
  return points;
}

struct Error {
  double l2, linf;
};

// the P1 interpolation error of the solution on `mesh`, at the sample points
Error interpolation_error(const BM::Indexed_tet_mesh_3& mesh, const std::vector<std::array<double, 3>>& points,
                          double volume)
{
  std::vector<double> values;
  for(const auto& p : mesh.points)
    values.push_back(solution(p));
  const std::vector<double> at = BM::interpolate_vertex_values(mesh, values, points);
  double sum = 0, worst = 0;
  for(std::size_t i = 0; i < points.size(); ++i) {
    const double e = std::abs(at[i] - solution(points[i]));
    sum += e * e;
    worst = std::max(worst, e);
  }
  return {std::sqrt(volume * sum / double(points.size())), worst};
}

BM::Indexed_tet_mesh_3 uniform_mesh(const Domain& domain, double size)
{
  return BM::make_indexed_anisotropic_mesh_3(domain, CGAL::Constant_metric_field_3<K>(BM::Metric_3::isotropic(size)),
                                             BM::parameters::random_seed(1u));
}

} // namespace

int main(int argc, char** argv)
{
  bool full = false, cube_only = false;
  std::string csv_path;
  for(int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if(a == "--full")
      full = true;
    else if(a == "--csv" && i + 1 < argc)
      csv_path = argv[++i];
    else if(a == "--width" && i + 1 < argc && std::atof(argv[i + 1]) > 0)
      layer_width = std::atof(argv[++i]);
    else if(a == "--cube-only")
      cube_only = true;
    else {
      std::cerr << "usage: adaptation_loop [--full] [--cube-only] [--width W] [--csv OUT.csv]\n";
      return EXIT_FAILURE;
    }
  }
  const std::vector<Test_domain> domains =
      full && !cube_only ? std::vector<Test_domain>{cube, l_block} : std::vector<Test_domain>{cube};
  const std::vector<double> targets =
      full ? std::vector<double>{2000, 4000, 8000, 16000, 32000} : std::vector<double>{4000, 8000};
  const int iterations = full ? 5 : 3;
  std::ostringstream csv;
  csv << "domain,mesh,target,iteration,vertices,l2,linf\n";
  bool ok = true;
  std::cout << std::setprecision(4) << std::unitbuf;
  try {
  for(const Test_domain& d : domains) {
    std::istringstream off(d.off);
    Domain::Polyhedron polyhedron;
    off >> polyhedron;
    const auto start_size = CGAL::Constant_metric_field_3<K>(BM::Metric_3::isotropic(0.1));
    auto features = BM::detect_features(polyhedron, start_size);
    Domain domain(polyhedron);
    features.add_to(domain);
    const std::vector<std::array<double, 3>> points = sample(d, full ? 1000000 : 200000);
    std::vector<double> adapted_n, adapted_l2;
    for(double target : targets) {
      // start from a uniform mesh of the target's size
      const double size = std::cbrt(1.4 * d.volume / target);
      BM::Indexed_tet_mesh_3 mesh = uniform_mesh(domain, size);
      const Error uniform = interpolation_error(mesh, points, d.volume);
      csv << d.name << ",uniform," << target << ",0," << mesh.points.size() << "," << uniform.l2 << "," << uniform.linf
          << "\n";
      std::cout << d.name << ", target " << target << ": uniform " << mesh.points.size() << " vertices, L2 "
                << uniform.l2 << ", Linf " << uniform.linf << "\n";
      Error adapted{0, 0};
      for(int it = 1; it <= iterations; ++it) {
        std::vector<double> values;
        for(const auto& p : mesh.points)
          values.push_back(solution(p));
        const auto metric = CGAL::make_graded_hessian_metric_field_3<K>(
            mesh, values, 1.5, BM::parameters::target_number_of_vertices(target));
        mesh = BM::remesh_anisotropic_3(mesh, metric, BM::parameters::random_seed(1u));
        adapted = interpolation_error(mesh, points, d.volume);
        csv << d.name << ",adapted," << target << "," << it << "," << mesh.points.size() << "," << adapted.l2 << ","
            << adapted.linf << "\n";
        std::cout << "  remesh " << it << ": " << mesh.points.size() << " vertices, L2 " << adapted.l2 << ", Linf "
                  << adapted.linf << "\n";
      }
      adapted_n.push_back(double(mesh.points.size()));
      adapted_l2.push_back(adapted.l2);
      const double gain = uniform.l2 / adapted.l2;
      std::cout << "  L2 error " << gain << " times lower than uniform\n";
      if(!(gain >= 5)) {
        std::cerr << "Error: at target " << target << " the adapted L2 error is only " << gain
                  << " times below the uniform mesh's (5 expected)\n";
        ok = false;
      }
    }
    // the rate over the targets: least-squares slope of log L2 against log N
    double mx = 0, my = 0;
    for(std::size_t i = 0; i < adapted_n.size(); ++i) {
      mx += std::log(adapted_n[i]) / double(adapted_n.size());
      my += std::log(adapted_l2[i]) / double(adapted_n.size());
    }
    double sxy = 0, sxx = 0;
    for(std::size_t i = 0; i < adapted_n.size(); ++i) {
      sxy += (std::log(adapted_n[i]) - mx) * (std::log(adapted_l2[i]) - my);
      sxx += (std::log(adapted_n[i]) - mx) * (std::log(adapted_n[i]) - mx);
    }
    const double slope = sxy / sxx;
    std::cout << d.name << ": adapted L2 error ~ N^" << slope << " (optimal anisotropic rate: N^-0.667)\n";
    if(!(slope <= -0.5)) {
      std::cerr << "Error: the adapted L2 error falls as N^" << slope << ", slower than N^-0.5\n";
      ok = false;
    }
  }
  } catch(const std::exception& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return EXIT_FAILURE;
  }
  if(!csv_path.empty()) {
    std::ofstream out(csv_path);
    out << csv.str();
    if(!out) {
      std::cerr << "Error: cannot write " << csv_path << "\n";
      return EXIT_FAILURE;
    }
  }
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
