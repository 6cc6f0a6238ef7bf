#pragma once
// Triangle meshes from files: OFF, OBJ, STL and PLY through CGAL's polygon-soup readers,
// with a unit scale; OBJ groups (`g` / `o`) can become one node each.
#include "geometry/scene/scene.hpp"

#include <string>
#include <vector>

namespace radnet::geometry {

/// Reads a mesh file (format by extension, case-insensitive), scales it (file units → m)
/// and fan-triangulates polygons with more than three corners (they must be convex).
/// @throws GeometryError naming the file: missing, unreadable, truncated or empty
TriangleSoup readMesh(const std::string& path, double scale);

struct MeshGroup {
  std::string name;
  TriangleSoup soup;
};

/// An OBJ file split by its `g`/`o` statements (faces before any, in a group named "default").
std::vector<MeshGroup> readObjGroups(const std::string& path, double scale);

}  // namespace radnet::geometry
