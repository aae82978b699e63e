#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>
#include <CGAL/make_mesh_3.h>
#include <fstream>
#include <cmath>
typedef CGAL::Epick K;
typedef CGAL::Mesh_polyhedron_3<K>::type Polyhedron;
typedef CGAL::Polyhedral_mesh_domain_with_features_3<K> MD;
typedef CGAL::Mesh_triangulation_3<MD>::type Tr;
typedef CGAL::Mesh_complex_3_in_triangulation_3<Tr, MD::Corner_index, MD::Curve_index> C3t3;
typedef CGAL::Mesh_criteria_3<Tr> Criteria;
int main(int argc, char** argv) {
  int n = 64; double r = 1, h = 3; int rings = 12;
  std::ofstream off("cylinder.off");
  int nv = n * (rings + 1) + 2;
  int nf = 2 * n * rings + 2 * n;
  off << "OFF\n" << nv << " " << nf << " 0\n";
  for (int k = 0; k <= rings; ++k) for (int i = 0; i < n; ++i) {
    double a = 2 * M_PI * i / n; off << r * cos(a) << " " << r * sin(a) << " " << h * k / rings << "\n"; }
  off << "0 0 0\n0 0 " << h << "\n";
  for (int k = 0; k < rings; ++k) for (int i = 0; i < n; ++i) {
    int a = k * n + i, b = k * n + (i + 1) % n, c = (k + 1) * n + (i + 1) % n, d = (k + 1) * n + i;
    off << "3 " << a << " " << b << " " << c << "\n3 " << a << " " << c << " " << d << "\n"; }
  int bc = n * (rings + 1), tc = bc + 1;
  for (int i = 0; i < n; ++i) off << "3 " << bc << " " << (i + 1) % n << " " << i << "\n";
  for (int i = 0; i < n; ++i) off << "3 " << tc << " " << rings * n + i << " " << rings * n + (i + 1) % n << "\n";
  off.close();
  Polyhedron p; std::ifstream in("cylinder.off"); in >> p;
  MD domain(p); domain.detect_features(60);
  double s = argc > 1 ? atof(argv[1]) : 0.3;
  Criteria criteria(CGAL::parameters::edge_size = s, CGAL::parameters::facet_angle = 25, CGAL::parameters::facet_size = s,
                    CGAL::parameters::facet_distance = s / 10, CGAL::parameters::cell_radius_edge_ratio = 3, CGAL::parameters::cell_size = s);
  C3t3 c3t3 = CGAL::make_mesh_3<C3t3>(domain, criteria);
  std::ofstream m("cylinder.mesh"); c3t3.output_to_medit(m);
  std::cerr << c3t3.triangulation().number_of_vertices() << " vertices " << c3t3.number_of_cells_in_complex() << " cells\n";
}
