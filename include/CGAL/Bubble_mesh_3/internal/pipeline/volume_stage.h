// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_VOLUME_STAGE_H
#define CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_VOLUME_STAGE_H

// Stage 3 of the pipeline (paper, section 3.2): the interior nodes inside the
// boundary front connected with the boundary nodes into tets by the
// anisotropic advancing front (modified Delaunay criterion, best-quality
// fallback, recoveries). The stage chooses the interior nodes it uses.

#include <CGAL/Anisotropic_advancing_front_3.h>
#include <CGAL/Bubble_mesh_3/Meshing_report.h>
#include <CGAL/Bubble_mesh_3/Metric_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/domain_mesh.h>
#include <CGAL/Bubble_mesh_3/internal/pipeline/run_control.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace internal {

/// Adds to `out` the packed interior nodes the front can use and returns
/// their subdomain. The front's chords cut curved walls: an interior node
/// packed between a chord and the true surface lies outside the front, and
/// one within metric distance 0.25 of a front triangle would only make a flat
/// tet; both are dropped (counted).
template <typename MeshDomain, typename MetricField, typename Node>
int add_interior_nodes(const MeshDomain& domain, const MetricField& field, const std::vector<Node>& nodes,
                       Meshing_report& rep, Domain_mesh& out)
{
  typedef typename MetricField::Kernel K;
  typedef typename K::Point_3 P;
  typedef CGAL::Surface_mesh<P> Front_mesh;
  int subdomain = 1;
  Front_mesh fm;
  std::vector<typename Front_mesh::Vertex_index> vi;
  for(const auto& p : out.mesh.points)
    vi.push_back(fm.add_vertex(P(p[0], p[1], p[2])));
  for(const auto& t : out.mesh.triangles)
    fm.add_face(vi[std::size_t(t[0])], vi[std::size_t(t[1])], vi[std::size_t(t[2])]);
  const CGAL::Side_of_triangle_mesh<Front_mesh, K> side(fm);
  typedef CGAL::AABB_face_graph_triangle_primitive<Front_mesh> Primitive;
  CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>> tree(faces(fm).first, faces(fm).second, fm);
  tree.accelerate_distance_queries();
  for(const auto& n : nodes) {
    if(n.dimension != 3)
      continue;
    const P q(CGAL::to_double(n.point.x()), CGAL::to_double(n.point.y()), CGAL::to_double(n.point.z()));
    if(side(q) != CGAL::ON_BOUNDED_SIDE) {
      ++rep.dropped_outside;
      continue;
    }
    const P c = tree.closest_point(q);
    const Metric_3 mq = Metric_3(field(q));
    if(mq.length(Eigen::Vector3d(CGAL::to_double(c.x() - q.x()), CGAL::to_double(c.y() - q.y()),
                                 CGAL::to_double(c.z() - q.z()))) < 0.25) {
      ++rep.dropped_near_boundary;
      continue;
    }
    subdomain = static_cast<int>(domain.subdomain_index(n.index));
    out.add_point(q.x(), q.y(), q.z(), 3, subdomain);
  }
  return subdomain;
}

/// Stage 3: the interior nodes, then the tets of the advancing front over the
/// boundary triangles of `out` (and the Steiner points it may add).
template <typename MeshDomain, typename MetricField, typename Node>
void volume_stage(const MeshDomain& domain, const MetricField& field, const std::vector<Node>& nodes,
                  const Meshing_settings& s, const Run_control& control, Meshing_report& rep, Domain_mesh& out)
{
  const int subdomain = add_interior_nodes(domain, field, nodes, rep, out);
  if(rep.dropped_outside + rep.dropped_near_boundary > 0)
    control.say("dropped interior nodes: " + std::to_string(rep.dropped_outside) + " outside the boundary front, " +
                std::to_string(rep.dropped_near_boundary) + " within 0.25 of it");
  control.advance(0.55);
  const auto t0 = std::chrono::steady_clock::now();
  typedef Anisotropic_advancing_front_3<MetricField> Front;
  typename Front::Parameters fp;
  fp.allow_steiner_points = s.allow_steiner;
  // The progress hook doubles as a check point: every 2,000 tets when a stop
  // is possible (about 50 ms of work), the messages every 100,000; the
  // advancement runs to 0.8 at about 6 tets per node.
  const std::size_t message_interval = fp.progress_interval;
  if(control.active())
    fp.progress_interval = 2000;
  const double expected_tets = 6.0 * double(out.mesh.points.size()) + 1;
  if(control.says() || control.active())
    fp.progress = [control, message_interval, expected_tets](std::size_t tets, std::size_t front) {
      control.advance(0.55 + 0.25 * std::min(1.0, double(tets) / expected_tets));
      control.check("the advancing front");
      if(tets % message_interval == 0)
        control.say("advancing front: " + std::to_string(tets) + " tets, front " + std::to_string(front) +
                    " triangles");
    };
  if(control.says() || control.active())
    fp.work_progress = [control](const typename Front::Work_progress& w) {
      control.check("the advancing front");
      control.say("advancing front: " + std::to_string(w.tets) + " tets, front " + std::to_string(w.front_triangles) +
                  " triangles (" + std::to_string(w.waiting_triangles) + " with no removable Delaunay pair), " +
                  std::to_string(w.removability_tests) + " of " + std::to_string(std::size_t(w.work_budget)) +
                  " removability tests of its work budget, " + std::to_string(w.best_quality_tets) +
                  " best-quality tets, " + std::to_string(w.undo_rounds) + " recoveries");
    };
  install_stop_check(fp, control, "the advancing front");
  std::vector<typename Front::Point_3> points;
  points.reserve(out.mesh.points.size());
  for(const auto& p : out.mesh.points)
    points.emplace_back(p[0], p[1], p[2]);
  Front front(field, fp);
  const typename Front::Result r = front.run(points, out.mesh.triangles);
  rep.front_seconds = seconds_since(t0);
  rep.tets = r.tets.size();
  rep.front = r.statistics;
  control.say("advancing front: " + std::to_string(r.tets.size()) + " tets, " + std::to_string(rep.front_seconds) +
              " s");
  for(std::size_t i = points.size(); i < r.points.size(); ++i)
    out.add_point(r.points[i].x(), r.points[i].y(), r.points[i].z(), 3, subdomain); // Steiner points
  out.mesh.tets = r.tets;
  out.mesh.tet_refs.assign(out.mesh.tets.size(), subdomain);
  if(r.statistics.unused_nodes > 0) // nodes outside the boundary front (the packer's never are)
    throw Meshing_failure("advancing front: " + std::to_string(r.statistics.unused_nodes) +
                          " packed nodes lie outside the boundary front");
  control.check("the advancing front");
}

} // namespace internal
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_INTERNAL_PIPELINE_VOLUME_STAGE_H
