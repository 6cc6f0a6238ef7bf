#pragma once
// STEP parts through a real CAD kernel (Debian's OpenCASCADE; docs/geometry.md, "STEP"): the
// file's solids and shells tessellated face by face, each CAD face one group. A STEP file
// states its own length unit; the kernel converts to metres, and `scale` multiplies on top.
#include "geometry/scene/mesh_io.hpp"

#include <string>
#include <vector>

namespace radnet::geometry {

/// Whether this build reads STEP (it was built with OpenCASCADE).
bool stepSupported();

/// The faces of a STEP file, in the kernel's exploration order, named by the file's face
/// label where it gives one used by no other face, else by index 0, 1, … (each face's
/// triangles have element = its index), fronts on the side the face's material is not (a
/// solid's faces outward).
/// @param mesh_size_m largest distance between the tessellation and the true surface (chord
///                    deflection), m; ≤ 0: 1e-3 of the model's bounding-box diagonal
/// @throws GeometryError naming the file when it cannot be read or holds no face
std::vector<MeshGroup> readStep(const std::string& path, double scale, double mesh_size_m);

}  // namespace radnet::geometry
