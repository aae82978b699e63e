// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// Packs anisotropic bubbles in a domain bounded by a closed triangle surface
// and writes the nodes as a PLY point set (x y z, the dimension of the entity
// each node lies on, and the metric size along x) to look at, e.g. in
// ParaView or MeshLab, like the paper's figures.
//
//   pack_bubbles [surface.off [nodes.ply]]
// Without arguments: a 1 x 1 x 0.5 box, output pack_bubbles.ply.
#include <CGAL/Bubble_packer_3.h>
#include <CGAL/Function_metric_field_3.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_polyhedron_3.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Mesh_polyhedron_3<K>::type Polyhedron;
typedef CGAL::Polyhedral_mesh_domain_with_features_3<K> Domain;
typedef CGAL::Bubble_mesh_3::Metric_3 Metric;

int main(int argc, char** argv)
{
  Polyhedron polyhedron;
  if(argc > 1) {
    std::ifstream in(argv[1]);
    if(!(in >> polyhedron) || polyhedron.empty() || !polyhedron.is_closed() || !polyhedron.is_pure_triangle()) {
      std::cerr << "Error: " << argv[1] << " is not a closed triangle surface (OFF)\n";
      return EXIT_FAILURE;
    }
  } else {
    std::stringstream off("OFF\n8 12 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 0.5\n1 0 0.5\n1 1 0.5\n0 1 0.5\n"
                          "3 0 3 2\n3 0 2 1\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n3 1 2 6\n3 1 6 5\n"
                          "3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n");
    off >> polyhedron;
  }
  const std::string output = argc > 2 ? argv[2] : "pack_bubbles.ply";

  Domain domain(polyhedron);
  domain.detect_features(60); // sharp edges: dihedral angle below 120 degrees

  // The user metric: elements stretched 1:3 around the z axis (tangential size
  // 3x the radial one), sizes relative to the bounding box.
  const CGAL::Bbox_3 bb = domain.bbox();
  const double scale = std::max({bb.xmax() - bb.xmin(), bb.ymax() - bb.ymin(), bb.zmax() - bb.zmin()});
  const double cx = 0.5 * (bb.xmin() + bb.xmax()), cy = 0.5 * (bb.ymin() + bb.ymax());
  auto field = CGAL::make_function_metric_field_3<K>([=](const K::Point_3& p) {
    double dx = p.x() - cx, dy = p.y() - cy;
    const double r = std::sqrt(dx * dx + dy * dy);
    if(r < 1e-12 * scale) {
      dx = 1;
      dy = 0;
    } else {
      dx /= r;
      dy /= r;
    }
    Eigen::Matrix3d directions;
    directions << -dy, dx, 0, dx, dy, 0, 0, 0, 1; // tangential, radial, axial
    const double h = 0.05 * scale;
    return Metric::from_directions_and_sizes(directions, Eigen::Vector3d(3 * h, h, 1.5 * h));
  });

  typedef CGAL::Bubble_packer_3<Domain, decltype(field)> Packer;
  Packer packer(domain, field);
  packer.run();

  const auto& st = packer.statistics();
  const char* names[] = {"corners", "curves", "patches", "interior"};
  for(int d = 0; d < 4; ++d)
    std::cout << names[d] << ": " << st.stages[d].bubbles << " bubbles, " << st.stages[d].iterations
              << " iterations, " << st.stages[d].seconds << " s\n";
  std::cout << "nearest-neighbour metric distance: min " << st.nearest_min << ", median " << st.nearest_p50
            << ", max " << st.nearest_max << "\n";

  const auto nodes = packer.nodes();
  std::ofstream out(output);
  out << "ply\nformat ascii 1.0\nelement vertex " << nodes.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nproperty int dimension\nend_header\n";
  for(const auto& n : nodes)
    out << n.point.x() << " " << n.point.y() << " " << n.point.z() << " " << n.dimension << "\n";
  std::cout << "wrote " << nodes.size() << " nodes to " << output << "\n";
  return out ? EXIT_SUCCESS : EXIT_FAILURE;
}
