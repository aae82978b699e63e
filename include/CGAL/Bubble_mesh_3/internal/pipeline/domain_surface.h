// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_DOMAIN_SURFACE_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_DOMAIN_SURFACE_H

// Stage 0 of the pipeline: the triangulated surface the later stages mesh,
// chosen by the domain's type. A polyhedral domain is meshed as it is (after
// its input check); an implicit or labelled domain through a fine polyhedral
// copy of its boundary, its result moved back onto the domain's own surface
// (implicit_domain_surface.h). Both give the same four members:
// `meshed_domain()`, `moves_boundary`, `project_boundary()` and
// `c3t3_indices<C3T3>()`.

#include <CGAL/Bubble_mesh_3/Meshing_report.h>
#include <CGAL/Bubble_mesh_3/internal/c3t3/tet_soup_to_c3t3.h>
#include <CGAL/Bubble_mesh_3/internal/packing/domain_oracle.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/domain_mesh.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/implicit_domain_surface.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/input_stage.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/run_control.h>

#include <type_traits>
#include <utility>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

// whether the domain gives its surface as polyhedra (what the boundary front
// triangulates), as `Polyhedral_mesh_domain_with_features_3` does
using packing::Has_polyhedra;

// Whether the domain answers Mesh_3's inside test (`MeshDomain_3`).
template <typename D, typename = void>
struct Has_inside_test : std::false_type {};
template <typename D>
struct Has_inside_test<D, std::void_t<decltype(std::declval<const D&>().is_in_domain_object())>> : std::true_type {};

template <typename MeshDomain>
constexpr void check_domain_type()
{
  static_assert(Has_polyhedra<MeshDomain>::value || Has_inside_test<MeshDomain>::value,
                "make_anisotropic_mesh_3: the domain must be a model of Mesh_3's MeshDomain_3 (is_in_domain_object(), "
                "as Labeled_mesh_domain_3, optionally with Mesh_domain_with_polyline_features_3) or a "
                "Polyhedral_mesh_domain_with_features_3 (after detect_features())");
}

/// A polyhedral domain: meshed as it is.
template <typename MeshDomain>
class Polyhedral_domain_surface {
public:
  typedef MeshDomain Meshed_domain;
  static constexpr bool moves_boundary = false;

  template <typename MetricField>
  Polyhedral_domain_surface(const MeshDomain& domain, const MetricField&, const Run_control& control, Meshing_report&)
      : domain_(domain)
  {
    check_domain_surface(domain); // a bad surface would fail only after the packing
    control.check("the input checks");
  }
  const MeshDomain& meshed_domain() const { return domain_; }
  void project_boundary(Domain_mesh&, Meshing_report&) const {}
  template <typename C3T3>
  Domain_indices<C3T3, MeshDomain> c3t3_indices() const
  {
    return Domain_indices<C3T3, MeshDomain>{domain_};
  }

private:
  const MeshDomain& domain_;
};

/// The stage-0 surface type of a domain type.
template <typename MeshDomain>
using Domain_surface = std::conditional_t<Has_polyhedra<MeshDomain>::value, Polyhedral_domain_surface<MeshDomain>,
                                          Implicit_domain_surface<MeshDomain>>;

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_DOMAIN_SURFACE_H
