// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_INPUT_STAGE_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_INPUT_STAGE_H

// The first thing the pipeline does: refuse a domain surface it cannot mesh,
// before any expensive work (a bad one would fail only after the packing).

#include <CGAL/Bubble_mesh_3/IO/read_triangle_surface.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>

#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/copy_face_graph.h>
#include <CGAL/boost/graph/helpers.h>

#include <string>
#include <type_traits>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

/// Refuses a domain whose boundary cannot be meshed (`check_triangle_surface()`
/// on all its polyhedra together), before any expensive work.
template <typename MeshDomain>
void check_domain_surface(const MeshDomain& domain)
{
  typedef typename std::decay_t<decltype(domain.polyhedra().front())>::Traits::Point_3 Point;
  CGAL::Surface_mesh<Point> sm;
  for(const auto& poly : domain.polyhedra())
    CGAL::copy_face_graph(poly, sm);
  if(num_faces(sm) == 0)
    throw Invalid_input("domain: the polyhedral surface has no faces");
  if(!CGAL::is_closed(sm))
    throw Invalid_input("domain: the surface is not closed");
  if(!CGAL::is_triangle_mesh(sm))
    throw Invalid_input("domain: the surface has faces that are not triangles");
  const std::string problem = IO::check_triangle_surface(sm, false);
  if(!problem.empty())
    throw Invalid_input("domain: " + problem);
}

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_INPUT_STAGE_H
