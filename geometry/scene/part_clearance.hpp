#pragma once
// Whether a turned part runs into the rest of the spacecraft: pairs of surfaces, one moving
// and one fixed, whose triangles cross or touch.
#include "geometry/scene/scene.hpp"

#include <utility>
#include <vector>

namespace radnet::geometry {

/// (moving surface, fixed surface) pairs with a triangle of one meeting a triangle of the
/// other (bounding boxes swept first, then CGAL's triangle–triangle test), sorted, each once.
/// A part touching the body where it is hinged meets it at every angle: callers compare
/// against the geometry as written.
std::vector<std::pair<int, int>> meetingSurfaces(const Scene& scene, const std::vector<int>& moving);

}  // namespace radnet::geometry
