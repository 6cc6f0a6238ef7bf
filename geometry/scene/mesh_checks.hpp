#pragma once
// Mesh files checked before a reader allocates for them. CGAL's readers trust the counts a
// file states (vertices, faces, corners of a face) and reserve memory for them: a 70-byte
// OFF whose face claims 2e9 corners took 15 GB, a binary PLY list count of 2³²−1 16 GB, a
// binary OFF header 23 GB. Every count is bounded here by the bytes the file has left to
// hold it, and the file must be a regular file (a FIFO blocks, /dev/zero never ends).
#include "geometry/scene/scene.hpp"

#include <string>

namespace radnet::geometry {

/// Checks `path` (format by its extension: .off, .ply, .stl; .obj needs only the first check).
/// @throws GeometryError naming the file (and the line, where there is one) and the count
void checkMeshFile(const std::string& path);

}  // namespace radnet::geometry
