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

/// Two faces are in one plane when every corner of each lies within this fraction of the
/// scene's extent of the other's plane (measured from the other's corner, so a model far
/// from the origin is judged as one at it).
inline constexpr double kCoincidencePlaneTolerance = 1e-9;
/// ... and they coincide when their overlap exceeds this share of the smaller face (and the
/// strip that round-off can open along their edges, `tol` × perimeter).
inline constexpr double kCoincidenceMinShare = 1e-6;

/// Pairs of coplanar faces (kCoincidencePlaneTolerance) whose overlap exceeds
/// kCoincidenceMinShare of the smaller face and that have an active side facing the same way;
/// at most `max_pairs`. Each plane's faces are projected into one frame the plane shares, so
/// neighbours that share an edge or meet at a T-junction overlap by nothing. Sorted sweeps
/// within each plane: O(m log m) for m faces of a plane, plus the pairs whose bounding boxes
/// overlap.
std::vector<Coincidence> coincidentFaces(const Scene& scene, size_t max_pairs = 16);

}  // namespace radnet::geometry
