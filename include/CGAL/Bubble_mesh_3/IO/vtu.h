// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_IO_VTU_H
#define CGAL_BUBBLE_MESH_3_IO_VTU_H

#include <CGAL/Bubble_mesh_3/IO/medit.h>
#include <CGAL/Bubble_mesh_3/Indexed_tet_mesh_3.h>
#include <CGAL/Bubble_mesh_3/exceptions.h>

#include <array>
#include <cmath>
#include <ostream>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace IO {

/// \ingroup PkgBubbleMesh3IO
/// Named scalar arrays attached to the points or the cells of a VTU file:
/// each pair is (array name, one value per point or per cell).
typedef std::vector<std::pair<std::string, std::vector<double>>> Vtu_scalar_arrays;

namespace internal {

inline std::string xml_escaped(const std::string& s)
{
  std::string r;
  for(char c : s) {
    switch(c) {
    case '&': r += "&amp;"; break;
    case '<': r += "&lt;"; break;
    case '>': r += "&gt;"; break;
    case '"': r += "&quot;"; break;
    case '\'': r += "&apos;"; break;
    default: r += c;
    }
  }
  return r;
}

// Throws Invalid_input unless every array has a distinct non-empty name,
// `n` finite values, and does not use a reserved name.
inline void check_vtu_arrays(const Vtu_scalar_arrays& arrays, std::size_t n, const char* what,
                             const std::set<std::string>& reserved)
{
  std::set<std::string> names = reserved;
  for(const auto& a : arrays) {
    if(a.first.empty())
      throw Invalid_input(std::string("write_vtu: a ") + what + " array has an empty name");
    if(!names.insert(a.first).second)
      throw Invalid_input(std::string("write_vtu: ") + what + " array name '" + a.first + "' is used twice");
    if(a.second.size() != n)
      throw Invalid_input(std::string("write_vtu: ") + what + " array '" + a.first + "' has " +
                          std::to_string(a.second.size()) + " values, expected " + std::to_string(n));
    for(std::size_t i = 0; i < n; ++i)
      if(!std::isfinite(a.second[i]))
        throw Invalid_input(std::string("write_vtu: ") + what + " array '" + a.first + "' value " +
                            std::to_string(i) + " is not finite (VTK ASCII readers reject it)");
  }
}

inline void check_vtu_points(const std::vector<std::array<double, 3>>& points)
{
  for(std::size_t i = 0; i < points.size(); ++i)
    for(int k = 0; k < 3; ++k)
      if(!std::isfinite(points[i][k]))
        throw Invalid_input("write_vtu: point " + std::to_string(i) + " has a non-finite coordinate");
}

inline void write_vtu_scalar_arrays(Number_writer& w, const Vtu_scalar_arrays& arrays)
{
  for(const auto& a : arrays) {
    w.text("        <DataArray type=\"Float64\" Name=\"").text(xml_escaped(a.first))
     .text("\" NumberOfComponents=\"1\" format=\"ascii\">\n");
    std::size_t column = 0;
    for(double x : a.second) {
      w.number(x).put(++column % 8 == 0 ? '\n' : ' ');
    }
    w.text("\n        </DataArray>\n");
  }
}

// Shared by the tet-mesh and point-set writers: `cells` gives, for each
// cell, its vertex indices (`cell_size` of them) and the VTK cell type.
template <typename Cell_vertex>
void write_vtu_piece(std::ostream& os, const std::vector<std::array<double, 3>>& points, std::size_t n_cells,
                     int cell_size, int vtk_type, Cell_vertex cell_vertex, const std::vector<int>* subdomains,
                     const Vtu_scalar_arrays& cell_scalars, const Vtu_scalar_arrays& point_scalars)
{
  Number_writer w(os);
  w.text("<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         "  <UnstructuredGrid>\n"
         "    <Piece NumberOfPoints=\"")
   .number(points.size()).text("\" NumberOfCells=\"").number(n_cells).text("\">\n");

  if(!point_scalars.empty()) {
    w.text("      <PointData Scalars=\"").text(xml_escaped(point_scalars.front().first)).text("\">\n");
    write_vtu_scalar_arrays(w, point_scalars);
    w.text("      </PointData>\n");
  }
  if(subdomains != nullptr || !cell_scalars.empty()) {
    w.text("      <CellData");
    if(subdomains != nullptr)
      w.text(" Scalars=\"subdomain\"");
    w.text(">\n");
    if(subdomains != nullptr) {
      w.text("        <DataArray type=\"Int32\" Name=\"subdomain\" NumberOfComponents=\"1\" format=\"ascii\">\n");
      for(std::size_t i = 0; i < n_cells; ++i)
        w.number(subdomains->empty() ? 0 : (*subdomains)[i]).put((i + 1) % 16 == 0 ? '\n' : ' ');
      w.text("\n        </DataArray>\n");
    }
    write_vtu_scalar_arrays(w, cell_scalars);
    w.text("      </CellData>\n");
  }

  w.text("      <Points>\n"
         "        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
  for(const std::array<double, 3>& p : points)
    w.number(p[0]).put(' ').number(p[1]).put(' ').number(p[2]).put('\n');
  w.text("        </DataArray>\n"
         "      </Points>\n"
         "      <Cells>\n"
         "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
  for(std::size_t i = 0; i < n_cells; ++i) {
    for(int k = 0; k < cell_size; ++k)
      w.number(cell_vertex(i, k)).put(k + 1 == cell_size ? '\n' : ' ');
  }
  w.text("        </DataArray>\n"
         "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
  for(std::size_t i = 0; i < n_cells; ++i)
    w.number(static_cast<long long>((i + 1) * static_cast<std::size_t>(cell_size))).put((i + 1) % 16 == 0 ? '\n' : ' ');
  w.text("\n        </DataArray>\n"
         "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
  for(std::size_t i = 0; i < n_cells; ++i)
    w.number(vtk_type).put((i + 1) % 32 == 0 ? '\n' : ' ');
  w.text("\n        </DataArray>\n"
         "      </Cells>\n"
         "    </Piece>\n"
         "  </UnstructuredGrid>\n"
         "</VTKFile>\n");
  w.flush();
}

} // namespace internal

/// \ingroup PkgBubbleMesh3IO
/// Writes the tetrahedra of `mesh` as an ASCII VTK XML UnstructuredGrid
/// (`.vtu`, readable by ParaView): one `VTK_TETRA` (10) cell per tet, the
/// subdomain references as the integer cell array `"subdomain"` (0 when
/// `mesh.tet_refs` is empty), then the optional `cell_scalars` (one value per
/// tet, e.g. `"min_dihedral"`) and `point_scalars` (one value per vertex) as
/// `Float64` arrays. Triangles and edges of `mesh` are not written.
///
/// Throws `Invalid_input` before writing anything if an index is out of
/// range, an array has the wrong length, a non-finite value or a repeated,
/// empty or reserved (`"subdomain"`) name.
inline void write_vtu(std::ostream& os, const Indexed_tet_mesh_3& mesh,
                      const Vtu_scalar_arrays& cell_scalars = Vtu_scalar_arrays(),
                      const Vtu_scalar_arrays& point_scalars = Vtu_scalar_arrays())
{
  internal::check_mesh_for_writing(mesh);
  internal::check_vtu_arrays(cell_scalars, mesh.tets.size(), "cell", {"subdomain"});
  internal::check_vtu_arrays(point_scalars, mesh.points.size(), "point", {});
  internal::write_vtu_piece(
    os, mesh.points, mesh.tets.size(), 4, 10, [&mesh](std::size_t i, int k) { return mesh.tets[i][k]; },
    &mesh.tet_refs, cell_scalars, point_scalars);
}

/// \ingroup PkgBubbleMesh3IO
/// Writes `mesh` to the `.vtu` file `path` (see the stream overload),
/// through a temporary file renamed at the end (never a partial `path`).
/// Throws `Invalid_file` if the file cannot be written.
inline void write_vtu(const std::string& path, const Indexed_tet_mesh_3& mesh,
                      const Vtu_scalar_arrays& cell_scalars = Vtu_scalar_arrays(),
                      const Vtu_scalar_arrays& point_scalars = Vtu_scalar_arrays())
{
  internal::check_mesh_for_writing(mesh);
  internal::check_vtu_arrays(cell_scalars, mesh.tets.size(), "cell", {"subdomain"});
  internal::check_vtu_arrays(point_scalars, mesh.points.size(), "point", {});
  write_file_atomically(
    path, [&](std::ostream& os) { write_vtu(os, mesh, cell_scalars, point_scalars); });
}

/// \ingroup PkgBubbleMesh3IO
/// Writes a point set (e.g. bubble centres) as an ASCII VTK XML
/// UnstructuredGrid with one `VTK_VERTEX` (1) cell per point, and the
/// optional per-point `point_scalars` (e.g. bubble size). Throws
/// `Invalid_input` on a non-finite coordinate or a bad array.
inline void write_vtu_points(std::ostream& os, const std::vector<std::array<double, 3>>& points,
                             const Vtu_scalar_arrays& point_scalars = Vtu_scalar_arrays())
{
  internal::check_vtu_points(points);
  internal::check_vtu_arrays(point_scalars, points.size(), "point", {});
  internal::write_vtu_piece(
    os, points, points.size(), 1, 1, [](std::size_t i, int) { return static_cast<long long>(i); }, nullptr,
    Vtu_scalar_arrays(), point_scalars);
}

/// \ingroup PkgBubbleMesh3IO
/// Writes a point set to the `.vtu` file `path` (see the stream overload),
/// through a temporary file renamed at the end (never a partial `path`).
inline void write_vtu_points(const std::string& path, const std::vector<std::array<double, 3>>& points,
                             const Vtu_scalar_arrays& point_scalars = Vtu_scalar_arrays())
{
  internal::check_vtu_points(points);
  internal::check_vtu_arrays(point_scalars, points.size(), "point", {});
  write_file_atomically(path, [&](std::ostream& os) { write_vtu_points(os, points, point_scalars); });
}

} // namespace IO
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_IO_VTU_H
