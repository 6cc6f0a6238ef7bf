#pragma once
// Triangle meshes from files: OFF, OBJ, STL and PLY through CGAL's polygon-soup readers,
// with a unit scale; OBJ groups (`g` / `o`) and ASCII STL solids can become one node each.
// Each triangle remembers the file's face it came from (TriangleSoup::element).
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

/// An ASCII STL file split by its `solid <name>` blocks (unnamed: "solid<k>"); a binary STL
/// is refused (it has one solid and no names). Every facet keeps its own three vertices.
std::vector<MeshGroup> readStlSolids(const std::string& path, double scale);

/// The groups of an OBJ or ASCII STL file; other formats have none.
/// @throws GeometryError naming the file (and line) and what was expected
std::vector<MeshGroup> readMeshGroups(const std::string& path, double scale);

}  // namespace radnet::geometry
