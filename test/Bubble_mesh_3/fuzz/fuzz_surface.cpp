// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// libFuzzer harness: the SURFACE path of tools/bubble_mesh_3.cpp, i.e.
// IO::read_triangle_surface<Epick>(path) (OFF, OBJ, STL, PLY through the
// package's own parsers, IO/read_polygon_soup.h), then, for an accepted
// surface, what the tool does next before meshing: copy into a Polyhedron,
// bounding box, Polyhedral_mesh_domain_with_features_3 and
// detect_features(60). The reader only takes a path, so the input goes to a
// temporary file whose extension is chosen by the first byte (0: .off,
// 1: .obj, 2: .stl, 3: .ply, modulo 4).
// Oracle: Invalid_input, or a closed, valid, pure-triangle surface mesh.
//
// Until the package parsed the files itself, CGAL 5.5's OFF and PLY readers
// crashed, hung or exhausted memory on malformed input and this harness
// skipped those input families (see doc/Bubble_mesh_3/fuzzing.md); nothing
// is skipped any more.
#include <CGAL/Bubble_mesh_3/IO/read_triangle_surface.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polyhedral_mesh_domain_with_features_3.h>
#include <CGAL/boost/graph/copy_face_graph.h>

#include "fuzz_common.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <unistd.h>

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Polyhedral_mesh_domain_with_features_3<K> Domain;
namespace BIO = CGAL::Bubble_mesh_3::IO;
using bubble_mesh_3_fuzz::check;

namespace {

// One file per process (libFuzzer -fork/-jobs run several), in tmpfs when
// there is one: every input is written once.
std::string temporary_stem()
{
  const char* dir = std::getenv("TMPDIR");
  std::string d = dir && *dir ? dir : (access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp");
  return d + "/bubble_mesh_3_fuzz_surface_" + std::to_string(getpid());
}

void check_surface(const CGAL::Surface_mesh<K::Point_3>& surface)
{
  check(!surface.is_empty(), "empty surface accepted");
  check(CGAL::is_closed(surface), "open surface accepted");
  check(CGAL::is_triangle_mesh(surface), "non-triangle surface accepted");
  check(CGAL::is_valid_polygon_mesh(surface), "invalid polygon mesh accepted");
  for(auto v : surface.vertices()) {
    const K::Point_3& p = surface.point(v);
    check(std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()), "non-finite point accepted");
  }
  // The tool's next steps on the accepted surface.
  Domain::Polyhedron polyhedron;
  CGAL::copy_face_graph(surface, polyhedron);
  check(polyhedron.size_of_facets() == surface.number_of_faces(), "copy_face_graph lost faces");
  const CGAL::Bbox_3 bb = CGAL::Polygon_mesh_processing::bbox(surface);
  check(bb.xmin() <= bb.xmax() && bb.ymin() <= bb.ymax() && bb.zmin() <= bb.zmax(), "empty bounding box");
  Domain domain(polyhedron);
  domain.detect_features(60.0);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  if(size == 0)
    return 0;
  static const char* const extensions[4] = {"off", "obj", "stl", "ply"};
  static const std::string stem = temporary_stem();
  const std::string path = stem + "." + extensions[data[0] % 4];
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if(!f)
    bubble_mesh_3_fuzz::fail("cannot write the temporary file " + path);
  const std::size_t written = size > 1 ? std::fwrite(data + 1, 1, size - 1, f) : 0;
  std::fclose(f);
  check(written == size - 1, "short write to the temporary file");

  CGAL::Surface_mesh<K::Point_3> surface;
  if(bubble_mesh_3_fuzz::run_expecting_only_invalid_input([&] { surface = BIO::read_triangle_surface<K>(path); }))
    bubble_mesh_3_fuzz::run_expecting_no_exception("accepted surface", [&] { check_surface(surface); });
  std::remove(path.c_str());
  return 0;
}
