#pragma once
// Exact view factors between planar polygons, and the geometric helpers of the
// deterministic method (docs/geometry.md, "Deterministic view factors").
//
// Unoccluded polygon to polygon: Stokes' theorem turns the double area integral into a
// double contour integral (Sparrow 1963; Mitalas & Stephenson 1966):
//     A_P F_PQ = (1/2π) Σ_edges e of P Σ_edges f of Q (u_e·u_f) ∫_e ∫_f ln r dt ds,
// loops oriented counter-clockwise about each polygon's own (facing) normal. The inner
// integral over f is done in closed form,
//     ∫ ½ ln(x² + h²) dx = ½ x ln(x² + h²) − x + h atan(x/h),
// so shared, touching and collinear edges (r → 0) need no special case: the outer
// integrand stays continuous and only its derivative is singular, which the adaptive
// Gauss–Legendre rule on the outer edge refines towards.
//
// Point to polygon (Lambert): F_dA→P = (1/2π) Σ_k γ_k n·(R_k × R_k+1)/|R_k × R_k+1|.
#include "geometry/scene/scene.hpp"

#include <vector>

namespace radnet::geometry {

/// A closed polygon: vertices in order, the last joined to the first.
using Loop = std::vector<Vec3>;

/// A planar region bounded by loops: outer loops counter-clockwise about `normal`,
/// holes clockwise (the contour integral needs no more than that).
struct PlanarRegion {
  std::vector<Loop> loops;
  Vec3 normal;  ///< unit, the side that emits and receives
};

/// A factor with its error estimate.
struct FactorEstimate {
  double value = 0.0;  ///< m² (A_P F_PQ) or – (point factors)
  double error = 0.0;  ///< estimated absolute error, same unit
  long long evaluations = 0;
};

/// A_P F_PQ (m²) for polygons that see each other unoccluded and lie in front of each
/// other's plane (clip first where they straddle it).
/// @param tolerance  absolute target on A_P F_PQ, m²
FactorEstimate polygonExchangeArea(const PlanarRegion& p, const PlanarRegion& q, double tolerance);

/// Form factor from a point with unit normal n to a convex polygon facing it (loop
/// counter-clockwise about the polygon's normal, the point in front of it), unoccluded.
/// The polygon must lie in the point's front half-space (clip it first).
double pointToConvexPolygon(const Vec3& point, const Vec3& n, const Loop& polygon);

/// The part of a convex polygon with plane_normal·(x − plane_point) ≥ 0 (empty if none).
Loop clipToHalfSpace(const Loop& polygon, const Vec3& plane_point, const Vec3& plane_normal);

/// Splits a convex polygon by the plane m·x = c into the part with m·x ≥ c (`outside`)
/// and the rest (`inside`); either may come out empty.
void splitByPlane(const Loop& polygon, const Vec3& m, double c, Loop& outside, Loop& inside);

/// Polygon area (m²) of a planar loop, signed positive when counter-clockwise about n.
double signedArea(const Loop& loop, const Vec3& n);

}  // namespace radnet::geometry
