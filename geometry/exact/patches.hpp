#pragma once
// Patches and occluders of the deterministic view-factor method (docs/geometry.md).
//
// A patch is the flat part of one node's side: the node's coplanar triangles merged into
// their boundary loops, so a face meshed 32 × 32 costs what one polygon costs. Curved
// surfaces come out as one patch per facet. Inactive sides are patches too (node −1):
// what reaches them is the blocked fraction. Occluders are the same triangles grouped
// by plane alone (sides do not matter to a ray) and merged where the union is convex.
#include "geometry/exact/polygon_factor.hpp"
#include "geometry/scene/scene.hpp"

#include <vector>

namespace radnet::geometry {

struct Patch {
  int node = -1;             ///< node of this side, −1: an inactive side
  PlanarRegion region;       ///< merged boundary loops (the contour integral's input)
  std::vector<Loop> pieces;  ///< convex pieces covering the patch (clipping, quadrature)
  double offset = 0.0;       ///< plane: region.normal·x = offset, m
  double area_m2 = 0.0;
  Vec3 lo, hi;               ///< bounding box, m
  int faces = 0;             ///< scene triangles merged into it
};

struct Occluder {
  Loop polygon;  ///< convex
  Vec3 normal;   ///< unit, either side
  double offset = 0.0;
  Vec3 lo, hi;
  Vec3 centre;  ///< vertex mean (inside: a convex polygon's)
};

/// One patch per (node side, plane); merged boundaries where the triangles chain into
/// loops, the triangles themselves otherwise.
std::vector<Patch> buildPatches(const Scene& scene);

/// Whether every point lies on or behind `plane` (within tol, m): nothing of them is in
/// front of it (a pair so placed cannot see each other).
bool allBehind(const std::vector<Vec3>& points, const Patch& plane, double tol);
/// Whether some point lies behind `plane` by more than tol (the other side must be clipped
/// to the part in front).
bool anyBehind(const std::vector<Vec3>& points, const Patch& plane, double tol);

/// The corners of a patch's pieces, m.
std::vector<Vec3> pointsOf(const Patch& p);
/// The convex pieces of `a` in front of b's plane.
std::vector<Loop> clippedPieces(const Patch& a, const Patch& b);

/// Every scene triangle as part of one convex occluder.
std::vector<Occluder> buildOccluders(const Scene& scene);

}  // namespace radnet::geometry
