#pragma once
// A mesh split into thermal nodes (docs/geometry.md, "Meshes from CAD and FE models"): one
// node, its file's groups (read by the readers), its connected pieces, its faces as a CAD
// model has them (regions bounded by edges sharper than a feature angle), or one node per
// element. Every split is deterministic: parts are numbered from 0 in the order of their
// first triangle in the file.
#include "geometry/scene/mesh_io.hpp"

#include <string>
#include <vector>

namespace radnet::geometry {

enum class MeshNodes { Single, Groups, Components, Faces, Elements };

/// Default feature angle of `nodes: faces`, deg: a box's faces and a cylinder's lids are
/// split off, the facets of a cylinder with more than 18 sides are not.
inline constexpr double kDefaultFeatureAngleDeg = 20.0;

/// Splits a cleaned soup (geometry/scene/mesh_repair.hpp: vertices welded, `element` filled).
/// Components: triangles joined by shared vertices; Faces: joined across edges of exactly two
/// triangles whose normals differ by at most `feature_angle_deg`; Elements: per
/// TriangleSoup::element (named by it). Single and Groups return the soup whole, named "".
std::vector<MeshGroup> splitMesh(const TriangleSoup& soup, MeshNodes how, double feature_angle_deg);

}  // namespace radnet::geometry
