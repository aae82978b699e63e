// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Post-processing a CGAL Mesh_3 mesh in a metric: mesh a box with CGAL's
// make_mesh_3 (isotropic), then improve it for an anisotropic metric with
// improve_anisotropic_mesh_3 (flips and smoothing; the box's faces and
// edges stay where they are, their vertices slide in them). The result goes
// into a complex over a plain triangulation (Anisotropic_mesh_triangulation_3):
// an improved mesh is not Delaunay, which a regular triangulation would
// refuse.
//
//   improve_mesh_3_output [out.mesh]
#include <CGAL/Bubble_mesh_3/Quality_report.h>
#include <CGAL/Bubble_mesh_3/improve_c3t3.h>
#include <CGAL/Function_metric_field_3.h>
#include <CGAL/make_anisotropic_mesh_3.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/File_medit.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>
#include <CGAL/make_mesh_3.h>

#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Polyhedral_mesh_domain_with_features_3<K> Domain;
// CGAL Mesh_3's complex
typedef CGAL::Mesh_triangulation_3<Domain>::type Mesh3_tr;
typedef CGAL::Mesh_complex_3_in_triangulation_3<Mesh3_tr, Domain::Corner_index, Domain::Curve_index> Mesh3_c3t3;
typedef CGAL::Mesh_criteria_3<Mesh3_tr> Criteria;
// the improved complex
typedef CGAL::Anisotropic_mesh_triangulation_3<Domain>::type Tr;
typedef CGAL::Mesh_complex_3_in_triangulation_3<Tr, Domain::Corner_index, Domain::Curve_index> C3t3;
namespace BM = CGAL::Bubble_mesh_3;

int main(int argc, char** argv)
{
  Domain::Polyhedron polyhedron;
  std::stringstream box("OFF\n8 12 0\n0 0 0\n2 0 0\n2 1 0\n0 1 0\n0 0 1\n2 0 1\n2 1 1\n0 1 1\n"
                        "3 0 2 1\n3 0 3 2\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n"
                        "3 1 2 6\n3 1 6 5\n3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n");
  box >> polyhedron;
  Domain domain(polyhedron);
  domain.detect_features(60);
  namespace P = CGAL::parameters;
  Criteria criteria(P::edge_size = 0.2, P::facet_angle = 25, P::facet_size = 0.2, P::facet_distance = 0.02,
                    P::cell_radius_edge_ratio = 3, P::cell_size = 0.2);
  const Mesh3_c3t3 mesh3 = CGAL::make_mesh_3<Mesh3_c3t3>(domain, criteria);

  // the metric: sizes 0.4 along x, 0.2 across (1:2)
  auto metric = CGAL::make_function_metric_field_3<K>([](const K::Point_3&) {
    return BM::Metric_3::from_directions_and_sizes(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.4, 0.2, 0.2));
  });

  try {
    C3t3 improved;
    const BM::Improvement_report r = BM::improve_anisotropic_mesh_3(mesh3, improved, metric);
    std::cout << "Mesh_3: " << r.tets_before << " cells, worst metric min dihedral " << r.worst_before
              << " deg, 1st percentile " << r.p01_before << ", " << r.slivers_before << " slivers\n"
              << "improved: " << r.tets_after << " cells, worst " << r.worst_after << " deg, 1st percentile "
              << r.p01_after << ", " << r.slivers_after << " slivers (" << r.smoothing_moves << " moves, "
              << r.boundary_moves << " of them on the boundary, "
              << r.flips_2_3 + r.flips_3_2 + r.flips_4_4 + r.edge_removals << " flips, " << r.seconds << " s)\n"
              << improved.number_of_facets_in_complex() << " boundary facets, "
              << improved.number_of_edges_in_complex() << " feature edges, " << improved.number_of_corners()
              << " corners (as in the input: " << mesh3.number_of_facets_in_complex() << ", "
              << mesh3.number_of_edges_in_complex() << ", " << mesh3.number_of_corners() << ")\n";
    std::ofstream out(argc > 1 ? argv[1] : "improve_mesh_3_output.mesh");
    CGAL::IO::output_to_medit(out, improved);
    return out && r.worst_after >= r.worst_before ? EXIT_SUCCESS : EXIT_FAILURE;
  } catch(const std::exception& e) {
    std::cerr << "Error: " << e.what() << "\n";
    return EXIT_FAILURE;
  }
}
