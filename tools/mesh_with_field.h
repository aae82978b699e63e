// bubble_mesh_3 (the command-line tool): meshing with one metric field, the
// part of `run_mesh` that instantiates the whole pipeline. It is declared
// here and instantiated once per field type in its own translation unit
// (mesh_with_*.cpp), so the three instantiations compile in parallel and
// the rest of the tool does not wait for them.
#ifndef BUBBLE_MESH_3_TOOLS_MESH_WITH_FIELD_H
#define BUBBLE_MESH_3_TOOLS_MESH_WITH_FIELD_H

#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/Meshing_report.h>
#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/Quality_report.h>
#include <CGAL/Constant_metric_field_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Function_metric_field_3.h>
#include <CGAL/Interpolated_metric_field_3.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>

#include <functional>
#include <string>
#include <vector>

namespace bubble_mesh_3_tool {

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Polyhedral_mesh_domain_with_features_3<K> Domain;
/// the three kinds of metric field the command line gives
typedef CGAL::Constant_metric_field_3<K> Constant_field;
typedef CGAL::Interpolated_metric_field_3<K> Interpolated_field;
typedef std::function<CGAL::Bubble_mesh_3::Metric_3(const K::Point_3&)> Metric_function;
typedef CGAL::Function_metric_field_3<K, Metric_function> Function_field;

/// What `run_mesh` asks of one meshing and what it gets back.
struct Field_meshing {
  // the request
  const Domain* domain = nullptr;
  double surface_distance = 0; // 0: off; negative: a fraction of the diagonal
  bool small_features = true;
  unsigned seed = 0;
  int threads = 0;
  double max_nodes = 0;
  bool improve = true;
  double time_limit = 0;
  bool per_tet_quality = false; // fill `per_tet`
  std::function<bool()> should_stop;
  std::function<void(const std::string&)> progress;
  // the result; `description` comes in as the user's metric's and goes out
  // as the metric measured (with the surface bound and small features)
  std::string description;
  CGAL::Bubble_mesh_3::Meshing_report meshing;
  CGAL::Bubble_mesh_3::Indexed_tet_mesh_3 mesh;
  CGAL::Bubble_mesh_3::Quality_report quality;
  std::vector<double> per_tet;
};

/// the user's field, intersected near the surface with the curvature sizes
/// of the distance bound and refined at small features, meshed; the quality
/// measured in that field
template <typename UserField>
void mesh_with_field(const UserField& user_field, Field_meshing& run);

extern template void mesh_with_field<Constant_field>(const Constant_field&, Field_meshing&);
extern template void mesh_with_field<Interpolated_field>(const Interpolated_field&, Field_meshing&);
extern template void mesh_with_field<Function_field>(const Function_field&, Field_meshing&);

} // namespace bubble_mesh_3_tool

#endif // BUBBLE_MESH_3_TOOLS_MESH_WITH_FIELD_H
