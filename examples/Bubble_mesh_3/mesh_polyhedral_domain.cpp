// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// From CGAL Mesh_3 to Bubble_mesh_3 on a polyhedral domain with features.
// A Mesh_3 user writes
//
//   typedef CGAL::Mesh_triangulation_3<Domain>::type Tr;
//   typedef CGAL::Mesh_complex_3_in_triangulation_3<Tr, Domain::Corner_index, Domain::Curve_index> C3t3;
//   Mesh_criteria criteria(params::edge_size(0.1).cell_size(0.1) ...);
//   C3t3 c3t3 = CGAL::make_mesh_3<C3t3>(domain, criteria);
//
// and switches by changing the triangulation type, giving a metric (here a
// lambda) instead of the criteria, and calling make_anisotropic_mesh_3: the
// three lines marked (*). The result is a C3T3 that CGAL's own tools read.
//
//   mesh_polyhedral_domain [surface.off [out.mesh]]
// Without arguments: an L-shaped block with sharp edges, output
// mesh_polyhedral_domain.mesh.
#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/detect_features.h>
#include <CGAL/Function_metric_field_3.h>
#include <CGAL/make_anisotropic_mesh_3.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/File_medit.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>

#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Polyhedral_mesh_domain_with_features_3<K> Domain;
typedef CGAL::Anisotropic_mesh_triangulation_3<Domain>::type Tr; // (*) instead of Mesh_triangulation_3<Domain>::type
typedef CGAL::Mesh_complex_3_in_triangulation_3<Tr, Domain::Corner_index, Domain::Curve_index> C3t3;
typedef CGAL::Bubble_mesh_3::Metric_3 Metric;

int main(int argc, char** argv)
{
  Domain::Polyhedron polyhedron;
  std::stringstream l_shape("OFF\n12 20 0\n"
                            "0 0 0\n2 0 0\n2 1 0\n1 1 0\n1 2 0\n0 2 0\n0 0 1\n2 0 1\n2 1 1\n1 1 1\n1 2 1\n0 2 1\n"
                            "3 0 2 1\n3 0 3 2\n3 0 4 3\n3 0 5 4\n3 6 7 8\n3 6 8 9\n3 6 9 10\n3 6 10 11\n"
                            "3 0 1 7\n3 0 7 6\n3 1 2 8\n3 1 8 7\n3 2 3 9\n3 2 9 8\n3 3 4 10\n3 3 10 9\n"
                            "3 4 5 11\n3 4 11 10\n3 5 0 6\n3 5 6 11\n");
  std::ifstream file;
  std::istream* in = &l_shape;
  if(argc > 1) {
    file.open(argv[1]);
    in = &file;
  }
  if(!(*in >> polyhedron) || polyhedron.empty() || !polyhedron.is_closed() || !polyhedron.is_pure_triangle()) {
    std::cerr << "Error: " << (argc > 1 ? argv[1] : "the L shape") << " is not a closed triangle surface (OFF)\n";
    return EXIT_FAILURE;
  }
  // (*) the metric: elements 2x longer along x, and finer near the re-entrant edge x = y = 1
  auto metric = CGAL::make_function_metric_field_3<K>([](const K::Point_3& p) {
    const double d = std::hypot(p.x() - 1, p.y() - 1);
    const double h = 0.08 + 0.12 * std::min(d, 1.0);
    return Metric::from_directions_and_sizes(Eigen::Matrix3d::Identity(), Eigen::Vector3d(2 * h, h, h));
  });

  // Sharp edges (faces meeting more than 60 degrees from flat) as CGAL's
  // domain.detect_features(60) marks them, minus the creases shorter than an
  // element that fade out into their patch (noise on scanned surfaces)
  auto features = CGAL::Bubble_mesh_3::detect_features(polyhedron, metric);
  Domain domain(polyhedron);
  features.add_to(domain);


  try {
    CGAL::Bubble_mesh_3::Meshing_report report;
    // (*) instead of make_mesh_3<C3t3>(domain, criteria)
    C3t3 c3t3 = CGAL::make_anisotropic_mesh_3<C3t3>(
        domain, metric, CGAL::Bubble_mesh_3::parameters::random_seed(1u).meshing_report(&report));
    CGAL::Bubble_mesh_3::print_meshing_summary(std::cout, report);
    std::cout << c3t3.number_of_cells_in_complex() << " cells, " << c3t3.number_of_facets_in_complex()
              << " boundary facets, " << c3t3.number_of_edges_in_complex() << " feature edges in the complex\n";
    std::ofstream out(argc > 2 ? argv[2] : "mesh_polyhedral_domain.mesh");
    CGAL::IO::output_to_medit(out, c3t3);
    return out ? EXIT_SUCCESS : EXIT_FAILURE;
  } catch(const std::exception& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return EXIT_FAILURE;
  }
}
