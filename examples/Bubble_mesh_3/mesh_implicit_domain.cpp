// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// An implicit domain, as CGAL Mesh_3 users give one: a function negative
// inside (here a cylinder with rounded ends cut flat at z = 0.8), the circle where the flat cap meets the wall given as a
// feature curve (Mesh_domain_with_polyline_features_3), and a metric that
// stretches the elements along the wall: thin across a layer near it (1:4),
// isotropic on the axis. The same three changes as from make_mesh_3 on a
// polyhedral domain (mesh_polyhedral_domain.cpp): the triangulation type, a
// metric instead of criteria, make_anisotropic_mesh_3. The boundary vertices
// of the result lie on the function's zero set (checked below).
//
//   mesh_implicit_domain [out.mesh]
#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Function_metric_field_3.h>
#include <CGAL/make_anisotropic_mesh_3.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/File_medit.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_domain_with_polyline_features_3.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <vector>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_3 Point;
typedef CGAL::Mesh_domain_with_polyline_features_3<CGAL::Labeled_mesh_domain_3<K>> Domain;
typedef CGAL::Anisotropic_mesh_triangulation_3<Domain>::type Tr; // (*) instead of Mesh_triangulation_3<Domain>::type
typedef CGAL::Mesh_complex_3_in_triangulation_3<Tr, Domain::Corner_index, Domain::Curve_index> C3t3;
typedef CGAL::Bubble_mesh_3::Metric_3 Metric;

// a capsule of radius 0.5 around the z axis from z = -1 to z = 1, cut at z = 0.8
double capsule(const Point& p)
{
  const double z = std::clamp(p.z(), -0.5, 0.5);
  const double round = std::sqrt(p.x() * p.x() + p.y() * p.y() + (p.z() - z) * (p.z() - z)) - 0.5;
  return std::max(round, p.z() - 0.8);
}

int main(int argc, char** argv)
{
  namespace params = CGAL::parameters;
  Domain domain(Domain::create_implicit_mesh_domain(capsule, K::Sphere_3(CGAL::ORIGIN, 1.5 * 1.5),
                                                    params::relative_error_bound = 1e-8));
  // the rim of the flat cap: the circle of radius sqrt(0.25 - 0.3^2) = 0.4 at z = 0.8
  std::vector<std::vector<Point>> rim(1);
  for(int i = 0; i < 256; ++i)
    rim[0].push_back(Point(0.4 * std::cos(2 * CGAL_PI * i / 256), 0.4 * std::sin(2 * CGAL_PI * i / 256), 0.8));
  rim[0].push_back(rim[0].front());
  domain.add_features(rim.begin(), rim.end());

  // (*) the metric: along the wall 0.12, across it from 0.03 at the wall to
  // 0.12 on the axis (frame: radial, around, along z)
  auto metric = CGAL::make_function_metric_field_3<K>([](const Point& p) {
    const double r = std::hypot(p.x(), p.y());
    const double across = 0.03 + 0.09 * std::clamp(1 - r / 0.5, 0.0, 1.0);
    Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();
    if(r > 1e-9)
      frame << p.x() / r, -p.y() / r, 0, p.y() / r, p.x() / r, 0, 0, 0, 1;
    return Metric::from_directions_and_sizes(frame, Eigen::Vector3d(across, 0.12, 0.12));
  });

  try {
    CGAL::Bubble_mesh_3::Meshing_report report;
    // (*) instead of make_mesh_3<C3t3>(domain, criteria)
    const C3t3 c3t3 = CGAL::make_anisotropic_mesh_3<C3t3>(
        domain, metric, CGAL::Bubble_mesh_3::parameters::random_seed(1u).meshing_report(&report));
    CGAL::Bubble_mesh_3::print_meshing_summary(std::cout, report);
    double off_surface = 0;
    for(auto v = c3t3.triangulation().finite_vertices_begin(); v != c3t3.triangulation().finite_vertices_end(); ++v)
      if(c3t3.in_dimension(v) == 2)
        off_surface = std::max(off_surface, std::abs(capsule(v->point().point())));
    std::cout << c3t3.number_of_cells_in_complex() << " cells, " << c3t3.number_of_facets_in_complex()
              << " boundary facets, " << c3t3.number_of_edges_in_complex()
              << " feature edges; largest |f| at a boundary vertex " << off_surface << "\n";
    std::ofstream out(argc > 1 ? argv[1] : "mesh_implicit_domain.mesh");
    CGAL::IO::output_to_medit(out, c3t3);
    // the vertices the projection could not move stay within the chord error
    return out && off_surface < 10 * report.implicit_surface_chord_error ? EXIT_SUCCESS : EXIT_FAILURE;
  } catch(const std::exception& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return EXIT_FAILURE;
  }
}
