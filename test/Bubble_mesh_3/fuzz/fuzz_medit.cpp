// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// libFuzzer harness: the MEDIT .mesh reader (IO/medit.h). It calls the parser
// that both read_medit() overloads run on the file's bytes, directly on the
// fuzz buffer (the public entry points first copy the stream or file into a
// buffer of >= 1 MB, which would dominate the cost of an execution).
// Oracle: the reader either throws Invalid_input or returns a mesh whose
// indices are in range and whose reference arrays match, and which writes
// and reads back identically.
#include <CGAL/Bubble_mesh_3/IO/medit.h>

#include "fuzz_common.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

namespace BIO = CGAL::Bubble_mesh_3::IO;
using CGAL::Bubble_mesh_3::Indexed_tet_mesh_3;
using bubble_mesh_3_fuzz::check;

namespace {

template <class Elements>
void check_indices(const Elements& elements, std::size_t nv, const char* what)
{
  for(const auto& e : elements)
    for(int v : e)
      if(v < 0 || static_cast<std::size_t>(v) >= nv)
        bubble_mesh_3_fuzz::fail(std::string(what) + ": index out of range");
}

bool same(const Indexed_tet_mesh_3& a, const Indexed_tet_mesh_3& b)
{
  return a.points == b.points && a.point_refs == b.point_refs && a.edges == b.edges && a.edge_refs == b.edge_refs &&
         a.triangles == b.triangles && a.triangle_refs == b.triangle_refs && a.tets == b.tets &&
         a.tet_refs == b.tet_refs && a.corners == b.corners;
}

void check_mesh(const Indexed_tet_mesh_3& mesh)
{
  const std::size_t nv = mesh.points.size();
  check(mesh.point_refs.size() == nv, "point_refs size");
  check(mesh.edge_refs.size() == mesh.edges.size(), "edge_refs size");
  check(mesh.triangle_refs.size() == mesh.triangles.size(), "triangle_refs size");
  check(mesh.tet_refs.size() == mesh.tets.size(), "tet_refs size");
  for(const auto& p : mesh.points)
    for(double x : p)
      check(std::isfinite(x), "non-finite coordinate accepted");
  check_indices(mesh.edges, nv, "edges");
  check_indices(mesh.triangles, nv, "triangles");
  check_indices(mesh.tets, nv, "tets");
  for(int c : mesh.corners)
    check(c >= 0 && static_cast<std::size_t>(c) < nv, "corners: index out of range");

  // Whatever was accepted must be writable and read back bitwise identical.
  std::ostringstream out;
  BIO::write_medit(out, mesh);
  std::istringstream in(out.str());
  const Indexed_tet_mesh_3 again = BIO::read_medit(in, "round trip");
  check(same(mesh, again), "write_medit/read_medit round trip changed the mesh");
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const char* begin = reinterpret_cast<const char*>(data);
  Indexed_tet_mesh_3 mesh;
  if(bubble_mesh_3_fuzz::run_expecting_only_invalid_input(
         [&] { mesh = BIO::internal::parse_medit(begin, begin + size, "fuzz.mesh"); }))
    // an accepted mesh that cannot be written back is a bug, not bad input
    bubble_mesh_3_fuzz::run_expecting_no_exception("accepted .mesh", [&] { check_mesh(mesh); });
  return 0;
}
