// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_MAKE_ANISOTROPIC_MESH_3_H
#define CGAL_MAKE_ANISOTROPIC_MESH_3_H

// The pipeline (doc/design.md, "Data flow"): each stage is a function in its
// own header of internal/pipeline/, called in order by mesh_domain_with_metric().
#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/Meshing_report.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/parameters.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/boundary_stage.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/c3t3_stage.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/domain_mesh.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/domain_surface.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/improvement_stage.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/metric_stage.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/packing_stage.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/run_control.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/validation_stage.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/volume_stage.h>

#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Triangulation_3.h>

#include <type_traits>
#include <utility>
#include <vector>

namespace CGAL {

/// \ingroup PkgBubbleMesh3Classes
/// The triangulation type to put in the `Mesh_complex_3_in_triangulation_3`
/// filled by `make_anisotropic_mesh_3()`: a plain `Triangulation_3` over
/// Mesh_3's geometric traits and data structure. A regular triangulation
/// (Mesh_3's default) asserts in debug builds when it holds a mesh that is not
/// regular, which an anisotropic mesh is not (CGAL 5.5); this
/// type holds any valid mesh and works with `output_to_medit()`,
/// `output_to_vtu()` and the C3T3 iterators.
template <typename MeshDomain>
struct Anisotropic_mesh_triangulation_3 {
  typedef typename CGAL::Mesh_triangulation_3<MeshDomain>::type Mesh_3_triangulation;
  typedef CGAL::Triangulation_3<typename Mesh_3_triangulation::Geom_traits,
                                typename Mesh_3_triangulation::Triangulation_data_structure>
      type;
};

namespace Bubble_mesh_3 {
namespace internal {

/// The stages in the order of the data flow (doc/design.md), each in its own
/// header of internal/pipeline/ and owning its inputs and outputs; `surface`
/// is stage 0's (domain_surface.h).
template <typename Surface, typename MetricField>
Domain_mesh mesh_domain_with_metric(const Surface& surface, const MetricField& field, const Meshing_settings& s,
                                    const Run_control& control, Meshing_report& rep)
{
  const auto& domain = surface.meshed_domain();
  const auto nodes = pack_nodes(domain, field, s, control, rep);
  Domain_mesh out;
  const Domain_boundary boundary = boundary_stage(domain, field, nodes, control, rep, out);
  volume_stage(domain, field, nodes, s, control, rep, out);
  if(s.improve)
    improvement_stage(field, boundary, s, control, rep, out);
  rep.final_tets = out.mesh.tets.size();
  control.check("the improvement", false);
  surface.project_boundary(out, rep);
  // the boundary front checks its triangles, the improvement what it
  // changed; the projection onto an implicit surface is checked here
  validation_stage(out.mesh, boundary, /*boundary_checked_for_self_intersections=*/!Surface::moves_boundary, control,
                   rep);
  return out;
}

/// The whole pipeline after stage 0: the field to mesh (metric_stage.h),
/// then the stages.
template <typename Surface, typename MetricField>
Domain_mesh mesh_domain(const Surface& surface, const MetricField& field, Pipeline_run& run)
{
  return with_prepared_metric(surface.meshed_domain(), field, run.settings, run.control, run.report,
                              [&](const auto& prepared) {
                                return mesh_domain_with_metric(surface, prepared, run.settings, run.control,
                                                               run.report);
                              });
}

} // namespace internal

/// \ingroup PkgBubbleMesh3Functions
/// The anisotropic mesh of `domain` as plain arrays (what MEDIT files hold):
/// boundary triangles with their patch ids, feature edges with their curve
/// ids, corners, tets with their subdomain id. Same parameters as
/// `CGAL::make_anisotropic_mesh_3()`; no padding, no C3T3.
template <typename MeshDomain, typename MetricField, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Indexed_tet_mesh_3 make_indexed_anisotropic_mesh_3(const MeshDomain& domain, const MetricField& field,
                                                   const NamedParameters& np = CGAL::parameters::default_values())
{
  internal::check_domain_type<MeshDomain>();
  internal::Pipeline_run run(np);
  const internal::Domain_surface<MeshDomain> surface(domain, field, run.control, run.report);
  Indexed_tet_mesh_3 mesh = internal::mesh_domain(surface, field, run).mesh;
  run.finish();
  return mesh;
}

} // namespace Bubble_mesh_3

/// \ingroup PkgBubbleMesh3Functions
/// Generates an anisotropic tetrahedral mesh of `domain` whose edges have
/// metric length about 1 in `field`: bubble packing (corners, curves,
/// patches, interior), boundary front on the surface nodes, anisotropic
/// advancing front. The complex holds the domain's cells (subdomain index),
/// boundary facets (surface patch index), feature edges (curve index) and
/// corners; the rest of the triangulation's convex hull is filled with cells
/// of subdomain 0 (exterior padding by TetGen's constrained tetrahedralization
/// of the box minus the domain; a build without TetGen handles convex domains
/// only and throws `Bubble_mesh_3::Meshing_failure` otherwise).
///
/// \tparam C3T3 `Mesh_complex_3_in_triangulation_3<Tr, MeshDomain::Corner_index,
///   MeshDomain::Curve_index>` with `Tr = Anisotropic_mesh_triangulation_3<MeshDomain>::type`
/// \tparam MeshDomain `Polyhedral_mesh_domain_with_features_3` (after `detect_features()`), or a model of
///   `MeshDomain_3` of one subdomain such as `Labeled_mesh_domain_3` (an implicit function, a labelling function,
///   a segmented image), optionally with `Mesh_domain_with_polyline_features_3`: its boundary is meshed by CGAL
///   Mesh_3 into a fine polyhedral copy (chord error a fiftieth of the metric's smallest size on the surface, between
///   2e-5 and 1e-4 of the bounding box diagonal), the stages mesh that copy, and the boundary vertices are then moved onto the
///   domain's surface and curves (`Meshing_report::snapped_boundary_vertices`); the complex gets the domain's
///   indices
/// \tparam MetricField a model of `MetricField_3`
///
/// \cgalNamedParamsBegin
///   \cgalParamNBegin{random_seed} \cgalParamType{unsigned int} \cgalParamDefault{0} \cgalParamNEnd
///   \cgalParamNBegin{number_of_iterations} \cgalParamDescription{iteration cap of each packing stage}
///     \cgalParamType{int} \cgalParamDefault{400} \cgalParamNEnd
///   \cgalParamNBegin{number_of_threads} \cgalParamDescription{threads of the packing (0: all); the mesh does not
///     depend on it} \cgalParamType{int} \cgalParamDefault{0} \cgalParamNEnd
///   \cgalParamNBegin{maximum_number_of_bubbles} \cgalParamDescription{refuse (`Bubble_mesh_3::Too_many_nodes`, before
///     any packing) when the estimated node count exceeds this; the default keeps a run under about 16 GB}
///     \cgalParamType{double} \cgalParamDefault{`Bubble_mesh_3::default_maximum_number_of_nodes`} \cgalParamNEnd
///   \cgalParamNBegin{time_limit} \cgalParamDescription{seconds for the whole run: when a check point (between
///     stages, every packing iteration, every 2,000 tets of the front) is passed after it, `Bubble_mesh_3::Time_limit_exceeded` is thrown; the
///     improvement is cut to the time left instead (the mesh is returned), later stages are not cut}
///     \cgalParamType{double} \cgalParamDefault{no limit} \cgalParamNEnd
///   \cgalParamNBegin{should_stop} \cgalParamDescription{polled at the same check points and in every packing iteration (from the calling
///     thread); when it returns true, `Bubble_mesh_3::Interrupted` is thrown. The command-line tool sets it from
///     SIGINT} \cgalParamType{std::function<bool()>} \cgalParamDefault{none} \cgalParamNEnd
///   \cgalParamNBegin{allow_steiner_points} \cgalParamDescription{cavities the front cannot close may get points
///     strictly inside} \cgalParamType{bool} \cgalParamDefault{true} \cgalParamNEnd
///   \cgalParamNBegin{mesh_improvement} \cgalParamDescription{metric flips and smoothing after the front
///     (`Bubble_mesh_3::improve_mesh()`)} \cgalParamType{bool} \cgalParamDefault{true} \cgalParamNEnd
///   \cgalParamNBegin{improvement_time_limit} \cgalParamDescription{seconds for it (negative: 2 s + 10 s per 100k
///     tets); without it the work is bounded by a number of passes and the result is reproducible, with it a run
///     cut by the limit is not} \cgalParamType{double} \cgalParamDefault{no limit} \cgalParamNEnd
///   \cgalParamNBegin{surface_distance} \cgalParamDescription{bound D on the distance of the boundary
///     triangles to the input surface: near the surface the metric is intersected with sizes sqrt(3 D / |k|)
///     along the principal curvature directions (`CGAL::Surface_approximation_metric_field_3`), so curved
///     parts get the nodes they need, and the improvement splits the boundary edges of the triangles that
///     still stray farther (`Bubble_mesh_3::Improvement_options::surface_distance`; the report counts the
///     splits and the triangles left beyond D); negative: the bounding box diagonal times
///     `Bubble_mesh_3::default_relative_surface_distance` (1/200); 0 or infinity: the metric as given. Off by
///     default for now: on organic inputs at coarse sizes it multiplies the node count (armadillo at diag/10,
///     measured with a first version of the field: 306 to 9,616 vertices, volume error 35 % to 0.9 %) and the
///     field costs about 1 microsecond per evaluation (elephant at 0.03: 2.3 s to 20 s). A field that is already a `Surface_approximation_metric_field_3` is used as it is}
///     \cgalParamType{double} \cgalParamDefault{0 (off)} \cgalParamNEnd
///   \cgalParamNBegin{realizable_metric} \cgalParamDescription{reduce the metric's large sizes where its frame
///     turns faster than straight edges of those sizes can follow (`CGAL::Realizable_metric_field_3`: a boundary
///     layer around a curved wall gets the tangential sizes whose chords stay within the layer; a field
///     interpolated from a background mesh is checked once per background vertex); false: the metric as given.
///     On UGAWG polar-1 the mesh's worst mean ratio in the given metric goes from 0.038 to 0.27}
///     \cgalParamType{bool} \cgalParamDefault{true} \cgalParamNEnd
///   \cgalParamNBegin{small_feature_refinement} \cgalParamDescription{refine the metric where the domain's corners
///     and feature curves are closer to each other than its sizes (`CGAL::Feature_size_metric_field_3`: sizes down
///     to the features' distance there, growing by half the distance away from them), so short curves and corner
///     clusters do not force flat tets. A field that is already a `Feature_size_metric_field_3` is used as it is}
///     \cgalParamType{bool} \cgalParamDefault{true} \cgalParamNEnd
///   \cgalParamNBegin{callback} \cgalParamDescription{CGAL's meaning: called at every check point with the
///     advancement of the run (0 to 1, reaching 1 at the end); when it returns false, `Bubble_mesh_3::Interrupted`
///     is thrown} \cgalParamType{std::function<bool(double)>} \cgalParamDefault{none} \cgalParamNEnd
///   \cgalParamNBegin{progress_messages} \cgalParamDescription{one line per stage (nodes, tets, seconds)}
///     \cgalParamType{std::function<void(const std::string&)>} \cgalParamDefault{none} \cgalParamNEnd
///   \cgalParamNBegin{verbose} \cgalParamDescription{the stage lines (unless `progress_messages` takes them) and
///     the final summary (`Bubble_mesh_3::print_meshing_summary()`) to `std::cerr`} \cgalParamType{bool}
///     \cgalParamDefault{false} \cgalParamNEnd
///   \cgalParamNBegin{meshing_report} \cgalParamDescription{filled with counts and times}
///     \cgalParamType{Bubble_mesh_3::Meshing_report*} \cgalParamDefault{nullptr} \cgalParamNEnd
/// \cgalNamedParamsEnd
///
/// Throws `Bubble_mesh_3::Invalid_input` (a domain surface refused by
/// `Bubble_mesh_3::IO::check_triangle_surface()`: zero-area faces, flat,
/// self-intersecting, components oriented against their nesting; an implicit
/// domain with no inside point on a 48^3 grid over its bounding box, or with
/// several subdomains; a bad
/// metric; `Bubble_mesh_3::Too_many_nodes`), `Bubble_mesh_3::Meshing_failure` (no valid mesh, including a
/// mesh the exterior padding or the C3T3 conversion refuses)
/// or `Bubble_mesh_3::Interrupted` / `Bubble_mesh_3::Time_limit_exceeded`
/// (stopped on request); never returns a partial mesh. Several components,
/// disjoint or nested (a hollow shell), make one subdomain.
template <typename C3T3, typename MeshDomain, typename MetricField,
          typename NamedParameters = CGAL::parameters::Default_named_parameters>
void make_anisotropic_mesh_3(C3T3& c3t3, const MeshDomain& domain, const MetricField& field,
                             const NamedParameters& np = CGAL::parameters::default_values())
{
  namespace BMI = Bubble_mesh_3::internal;
  BMI::check_domain_type<MeshDomain>();
  BMI::Pipeline_run run(np);
  const BMI::Domain_surface<MeshDomain> surface(domain, field, run.control, run.report);
  const BMI::Domain_mesh dm = BMI::mesh_domain(surface, field, run);
  BMI::c3t3_stage(dm, surface.template c3t3_indices<C3T3>(), run.control, run.report, c3t3);
  run.finish();
}

/// \ingroup PkgBubbleMesh3Functions
/// Same as above, returning the complex.
template <typename C3T3, typename MeshDomain, typename MetricField,
          typename NamedParameters = CGAL::parameters::Default_named_parameters>
C3T3 make_anisotropic_mesh_3(const MeshDomain& domain, const MetricField& field,
                             const NamedParameters& np = CGAL::parameters::default_values())
{
  C3T3 c3t3;
  make_anisotropic_mesh_3(c3t3, domain, field, np);
  return c3t3;
}

} // namespace CGAL

#endif // CGAL_MAKE_ANISOTROPIC_MESH_3_H
