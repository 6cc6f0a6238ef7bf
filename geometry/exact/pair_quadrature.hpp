#pragma once
// Cheap exchange areas for patch pairs that see each other whole (docs/geometry.md,
// "Adaptive order per pair"). The double area integral
//     A_P F_PQ = ∫_P ∫_Q cos θ_P cos θ_Q / (π r²) dA_Q dA_P
// is smooth when the patches are small against their distance, so a product rule of a few
// points on each side gets it to the pair's target far more cheaply than the contour
// integral. A ladder of rules, each checked against the one below it:
//   order 0  centroid to centroid (View3D's 1AI), I_0;
//   order 0+ I_0 plus its second-order Taylor term T = A_P A_Q ½ tr(H (M_P + M_Q)), H the
//            kernel's Hessian at the centroids' offset and M the patches' second moments
//            about their centroids: one kernel value and a 3 × 3 contraction;
//   order 1  degree 3: 2 × 2 Gauss on a parallelogram, the 3-point rule on fan triangles;
//   order 2  degree 5 (4 on triangles): 3 × 3 Gauss, Dunavant's 6-point rule.
// Order 0+ is accepted when |T| + 8 ρ² |I_0| (ρ: the patches' spread against their distance
// squared, the bound of the next term) is within the target, order k ≥ 1 when |I_k − I_(k−1)| is,
// and that quantity is the error reported: it measures the order below's error, of which
// the accepted one's is a small fraction (the centroid value errs as (size/distance)², order
// 0+ and order 1 as ⁴, order 2 as ⁶). Order 0+ takes the pairs order 1 would have (|T| and
// |I_1 − I_0| agree to leading order) for one kernel value and ~60 flops instead of 16 kernel
// values (the room's integration CPU fell by a quarter to a third). Pairs too near for the
// ladder (ratio of radii to distance ≥ kNearRatio) or of patches of many pieces are left to
// the contour integral.
#include "geometry/exact/patches.hpp"

#include <vector>

namespace radnet::geometry {

/// Sum of the two patches' radii over their centroids' distance above which a pair goes
/// straight to the contour integral: nearer, the low orders cannot meet usual targets and
/// the difference of two rules stops being a reliable estimate.
constexpr double kNearRatio = 0.5;

/// Quadrature points of every patch, by order, as flat arrays.
class PatchRules {
 public:
  explicit PatchRules(const std::vector<Patch>& patches);
  /// Whether the ladder may take pairs of this patch (few enough points).
  bool usable(size_t patch) const { return usable_[patch] != 0; }
  const Vec3& centroid(size_t patch) const { return centroid_[patch]; }
  double radius(size_t patch) const { return radius_[patch]; }

  /// A_P F_PQ (m²) of two patches that lie in front of each other's planes with nothing in
  /// between. `found` is false when the pair needs the contour integral (too near, or the
  /// target was not met by order 2); the estimate then holds the best value for a target.
  FactorEstimate exchangeArea(size_t p, size_t q, double absolute_target, double relative_target,
                              bool& found) const;

  /// The centroid-to-centroid value (order 0), m²: a scale for relative targets.
  double centroidValue(size_t p, size_t q) const;

 private:
  struct Points {
    std::vector<double> x, y, z, w;  // w: weight, m² (sums to the patch's area)
    std::vector<int> start;          // per patch, its first point; start[n] = total
  };
  double product(const Points& rule, size_t p, size_t q) const;
  double secondOrderTerm(size_t p, size_t q) const;  // the centroid value's Taylor term, m²
  void addRules(const Patch& patch);

  std::vector<Vec3> centroid_, normal_;
  std::vector<double> area_, radius_;
  struct Spread {  // second moment about the centroid per unit area, m² (symmetric: 6 terms)
    double xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0;
    double trace() const { return xx + yy + zz; }
  };
  std::vector<Spread> spread_;
  std::vector<char> usable_;
  Points order1_, order2_;
};

}  // namespace radnet::geometry
