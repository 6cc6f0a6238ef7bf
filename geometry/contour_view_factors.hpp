#pragma once
// Deterministic view factors: adaptive quadrature over the emitting node's triangles
// (Dunavant's 7-point rule, refined by splitting a triangle into four until the estimate
// settles) of the exact differential-area-to-polygon form factor (Lambert's contour
// formula, after clipping each receiving triangle to the emitter's tangent plane):
//     F_dA→P = (1/2π) |Σ_k γ_k n·(R_k × R_{k+1}) / |R_k × R_{k+1}||,
// γ_k the angle subtended by edge k. Occlusion is sampled: each (point, receiving
// triangle) term is weighted by the fraction of shadow rays to a few points of the
// triangle that arrive unblocked; with no blockers the method is exact up to quadrature.
#include "geometry/ray_caster.hpp"

#include <Eigen/Dense>

namespace radnet::geometry {

struct ContourOptions {
  double tolerance = 1e-7;  ///< absolute error target per emitter triangle and receiver, view-factor units
  int max_depth = 10;       ///< deepest 4-way split of an emitter triangle
  int visibility_rays = 4;  ///< shadow rays per (point, receiving triangle); 0: assume nothing occludes
};

struct ContourResult {
  Eigen::MatrixXd view_factors;    ///< F (n×n), –
  Eigen::MatrixXd error_estimate;  ///< |fine − coarse| of the accepted quadrature, summed, –
  Eigen::VectorXd space;           ///< 1 − Σ_j F_ij (assumes no inactive sides), –
  long long point_evaluations = 0;
  double seconds = 0.0;
};

/// All rows. Parallel over emitting nodes (OpenMP); deterministic for any thread count.
ContourResult contourViewFactors(const RayCaster& caster, const ContourOptions& options);

/// The form factor from a point with unit normal n to triangle (a, b, c), unoccluded,
/// counting only the part in front of the point's tangent plane; 0 when the point sees
/// the triangle's other side than `receiver_normal` faces.
double pointToTriangle(const Vec3& p, const Vec3& n, const Vec3& a, const Vec3& b, const Vec3& c,
                       const Vec3& receiver_normal);

}  // namespace radnet::geometry
