#pragma once
// Seams between surfaces that meet by design. Curved primitives keep their area by moving
// their vertices off the exact surface, each by its own factor (geometry/scene/primitives.hpp):
// a disc's rim moves out by sqrt(2π / (N sin(2π/N))), a cylinder's by π / (N sin(π/N)), so a
// can closed by two discs had a slit at each rim (N = 8: 2.8 % of the radius) and its
// inside leaked 0.7–2.7 % of its emission to space; a dome on its base disc 0.06–0.11 %.
// Closing them: the vertices of different surfaces whose nominal (exact-surface) positions
// coincide, at least one of them on its surface's border, are moved to one point, the mean
// of where their surfaces put them. The areas then differ from the exact ones by about half
// the two factors' difference times the rim's strip, which is reported.
#include "geometry/scene/scene.hpp"

#include <string>
#include <utility>
#include <vector>

namespace radnet::geometry {

struct SeamReport {
  int vertices_moved = 0;             ///< mesh vertices moved onto a shared seam point
  double largest_move_m = 0.0;        ///< the largest distance one of them moved, m
  double largest_area_change = 0.0;   ///< the largest relative change of a node's area, –
  /// Surfaces (indices into Scene::surfaceNames()) that meet at some rim vertices but whose
  /// rims run on between them with vertices the other has not (different facet counts):
  /// the seam stays open between the common corners.
  std::vector<std::pair<int, int>> partial;
};

/// Closes the seams of `scene` in place (see above); surfaces that only touch where their
/// nominal vertices already coincide are left as they are. Deterministic.
SeamReport closeSeams(Scene& scene);

/// One sentence per partial seam of `report`, for the scene's warnings.
std::vector<std::string> partialSeamWarnings(const Scene& scene, const SeamReport& report);

}  // namespace radnet::geometry
