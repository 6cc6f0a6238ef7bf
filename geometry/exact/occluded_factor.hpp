#pragma once
// A_P F_PQ between patches with blockers in between (docs/geometry.md): adaptive
// quadrature over the emitter of the exact point-to-visible-polygon factor. From each
// quadrature point the shadow volume of every blocker (the cone from the point through
// the blocker, beyond the blocker's plane) is cut out of the receiving pieces by plane
// splits, and Lambert's contour formula is summed over what is left. Visibility is thus
// exact at every point; the only error is the quadrature's, whose estimate (fine − coarse
// of Dunavant's degree-5 rule on a triangle and its four children) drives the refinement,
// worst triangle first, until the summed estimate meets the target or the work is spent.
#include "geometry/exact/patches.hpp"

#include <vector>

namespace radnet::geometry {

struct OccludedPair {
  const std::vector<Loop>* emitter = nullptr;   ///< convex pieces of P, in front of Q's plane
  Vec3 emitter_normal;                          ///< P's side normal
  const std::vector<Loop>* receiver = nullptr;  ///< convex pieces of Q, in front of P's plane
  std::vector<const Occluder*> blockers;
  /// Per blocker: +1 when the whole receiver lies on its front side, −1 behind, 0 across
  /// (filled by occludedExchangeArea). A point on the receiver's side casts no shadow there.
  std::vector<int> receiver_side;
};

/// Point evaluations an occluded pair may take (each clips the receiver by every blocker's
/// shadow, 0.1–1 µs a blocker): the refinement stops there and reports the error it reached.
constexpr long long kMaxOccludedEvaluations = 20000;

/// A_P F_PQ (m²) and its quadrature error estimate.
/// @param tolerance  absolute target on A_P F_PQ, m²
/// @param max_depth  deepest 4-way split of an emitter triangle
FactorEstimate occludedExchangeArea(OccludedPair& pair, double tolerance, int max_depth);

/// The form factor from a point of P to the part of Q it sees past the blockers.
double visibleFactor(const Vec3& point, const OccludedPair& pair);

}  // namespace radnet::geometry
