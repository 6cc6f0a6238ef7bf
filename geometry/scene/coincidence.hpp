#pragma once
// Coincident surfaces: two triangles in one plane, overlapping, with an active side facing
// the same way (a radiator rectangle laid exactly on a box face, a mesh holding a face
// twice). Rays cannot tell them apart: both sides take the full sun and see the same things,
// and every load and exchange of that area is counted twice.
#include "geometry/scene/scene.hpp"

#include <vector>

namespace radnet::geometry {

struct Coincidence {
  int face_a = -1, face_b = -1;  ///< scene face indices
  double overlap_m2 = 0.0;       ///< area of their overlap
};

/// Pairs of faces whose planes agree to 1e-9 of the scene's extent, whose overlap exceeds
/// 1e-6 of the smaller face and that have an active side facing the same way; at most
/// `max_pairs`. Sorted sweeps within each plane: O(m log m) for m faces of a plane, plus the
/// pairs whose bounding boxes overlap.
std::vector<Coincidence> coincidentFaces(const Scene& scene, size_t max_pairs = 16);

}  // namespace radnet::geometry
