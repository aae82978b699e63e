// Copyright (c) 2026  Bubble_mesh_3 developers. All rights reserved.
//
// This file is part of the Bubble_mesh_3 package for CGAL.
// SPDX-License-Identifier: GPL-3.0-or-later
#ifndef CGAL_BUBBLE_MESH_3_IO_WRITE_FILE_ATOMICALLY_H
#define CGAL_BUBBLE_MESH_3_IO_WRITE_FILE_ATOMICALLY_H

#include <CGAL/Bubble_mesh_3/exceptions.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <ostream>
#include <random>
#include <string>

namespace CGAL {
namespace Bubble_mesh_3 {
namespace IO {
namespace internal {

inline std::string errno_text(int e)
{
  return e == 0 ? std::string("unknown error") : std::string(std::strerror(e));
}

inline std::string unique_suffix()
{
  static std::atomic<unsigned long long> counter(0);
  std::random_device rd;
  const unsigned long long a = (static_cast<unsigned long long>(rd()) << 32) ^ rd();
  const unsigned long long b = static_cast<unsigned long long>(
                                 std::chrono::steady_clock::now().time_since_epoch().count()) ^
                               (counter.fetch_add(1) << 48);
  char tmp[40];
  std::snprintf(tmp, sizeof(tmp), "%016llx", a ^ b);
  return tmp;
}

} // namespace internal

/// \ingroup PkgBubbleMesh3IO
/// Writes through `write(std::ostream&)` into a temporary file next to `path`
/// and renames it to `path` only when everything was written: a failed or
/// interrupted write never leaves a partial file under the final name.
/// Throws `Invalid_file` naming `path` on any failure.
template <typename Write>
void write_file_atomically(const std::string& path, Write&& write)
{
  const std::string tmp = path + "." + internal::unique_suffix() + ".tmp";
  std::ofstream os(tmp, std::ios::binary | std::ios::trunc);
  if(!os)
    throw Invalid_file(path + ": cannot create file " + tmp + " (" + internal::errno_text(errno) + ")");
  try {
    write(static_cast<std::ostream&>(os));
    os.flush();
    if(!os)
      throw Invalid_file(path + ": write error (" + internal::errno_text(errno) + ", disk full?)");
    os.close();
    if(os.fail())
      throw Invalid_file(path + ": error while closing " + tmp + " (" + internal::errno_text(errno) + ")");
  } catch(...) {
    if(os.is_open())
      os.close();
    std::remove(tmp.c_str());
    throw;
  }
  if(std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int e = errno;
    std::remove(tmp.c_str());
    throw Invalid_file(path + ": cannot rename " + tmp + " to it (" + internal::errno_text(e) + ")");
  }
}

/// \ingroup PkgBubbleMesh3IO
/// writes `text` to `path` with `write_file_atomically`
inline void write_text_file(const std::string& path, const std::string& text)
{
  write_file_atomically(path, [&](std::ostream& os) { os << text; });
}

} // namespace IO
} // namespace Bubble_mesh_3
} // namespace CGAL

#endif // CGAL_BUBBLE_MESH_3_IO_WRITE_FILE_ATOMICALLY_H
