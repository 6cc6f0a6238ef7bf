#pragma once
// Gmsh meshes (docs/geometry.md, "Gmsh"): MSH 2.2 and 4.1, ASCII and binary. Triangles and
// quadrangles (first-order, and the corners of higher-order ones) are read, grouped by the
// physical surface each belongs to; points, lines and volume elements are counted and left.
// Every count the file states is bounded by the bytes left to hold it before anything is
// allocated.
#include "geometry/scene/mesh_io.hpp"

#include <map>
#include <string>
#include <vector>

namespace radnet::geometry {

struct GmshModel {
  /// One group per physical surface (its name, or its number when unnamed; "0" for elements
  /// in no physical group), in increasing physical number; each triangle's element is the
  /// file's element tag.
  std::vector<MeshGroup> groups;
  std::map<std::string, long> skipped;  ///< elements of other kinds, by kind, with their count
};

/// @throws GeometryError naming the file (and line, for ASCII) and what was expected
GmshModel readGmsh(const std::string& path, double scale);

}  // namespace radnet::geometry
