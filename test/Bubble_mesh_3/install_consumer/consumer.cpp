// Compiled against the *installed* headers: proves the package config works.
#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Constant_metric_field_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <iostream>

int main()
{
  typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
  CGAL::Constant_metric_field_3<K> field = CGAL::Constant_metric_field_3<K>::isotropic(0.5);
  const double l = field(K::Point_3(0, 0, 0)).length(CGAL::Bubble_mesh_3::Metric_3::Vector(1, 0, 0));
  std::cout << "metric length " << l << "\n";
  return l == 2.0 ? 0 : 1;
}
