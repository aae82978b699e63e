// bubble_mesh_3 (the command-line tool): the definition of
// `mesh_with_field`, included only by the mesh_with_*.cpp files.
#ifndef BUBBLE_MESH_3_TOOLS_MESH_WITH_FIELD_IMPL_H
#define BUBBLE_MESH_3_TOOLS_MESH_WITH_FIELD_IMPL_H

#include "mesh_with_field.h"

#include <CGAL/Bubble_mesh_3/metric_quality.h>
#include <CGAL/Feature_size_metric_field_3.h>
#include <CGAL/Surface_approximation_metric_field_3.h>
#include <CGAL/make_anisotropic_mesh_3.h>

#include <sstream>
#include <type_traits>

namespace bubble_mesh_3_tool {

template <typename UserField>
void mesh_with_field(const UserField& user_field, Field_meshing& run)
{
  namespace BM = CGAL::Bubble_mesh_3;
  const Domain& domain = *run.domain;
  const auto approximating = CGAL::make_surface_approximation_metric_field_3(domain, user_field, run.surface_distance);
  if(approximating.bounded()) {
    std::ostringstream d;
    d << run.description << " with surface distance " << approximating.distance();
    run.description = d.str();
    run.progress("metric near the surface: curvature sizes for a distance bound of " +
                 std::to_string(approximating.distance()));
  }
  // refined where corners and curves are closer than its sizes
  const auto field =
      run.small_features ? CGAL::make_feature_size_metric_field_3(domain, approximating)
                         : CGAL::Feature_size_metric_field_3<std::decay_t<decltype(approximating)>>(approximating);
  if(field.refines())
    run.description += ", refined at small features";
  run.mesh = BM::make_indexed_anisotropic_mesh_3(domain, field,
                                                 BM::parameters::random_seed(run.seed)
                                                     .number_of_threads(run.threads)
                                                     .maximum_number_of_bubbles(run.max_nodes)
                                                     .meshing_report(&run.meshing)
                                                     .mesh_improvement(run.improve)
                                                     .time_limit(run.time_limit)
                                                     .should_stop(run.should_stop)
                                                     .progress_messages(run.progress));
  run.quality = BM::compute_quality_report(run.mesh, field);
  if(run.per_tet_quality)
    run.per_tet = BM::metric_minimum_dihedral_angles(run.mesh, field);
}

} // namespace bubble_mesh_3_tool

#endif // BUBBLE_MESH_3_TOOLS_MESH_WITH_FIELD_IMPL_H
