#pragma once
// What the two in-place corrections share (correction/reciprocity_in_place.cpp: F and σ on a
// symmetric pattern; correction/reciprocity_upper.cpp: each pair held once): the pinning pass
// and the order of their passes. Internal to geometry/.
#include "geometry/correction/pairs.hpp"

#include <functional>
#include <vector>

namespace radnet::geometry::detail {

// What the two in-place corrections (PairsInPlace, PairsUpper) track while pinning: each row's
// smallest ĝ / v of its free pairs as first read, those pairs' F entries, and whether any
// round has pinned a pair.
struct PinBound {
  Eigen::VectorXd least_ratio;  // per row (∞: none)
  long long free_entries = 0;
  bool pinned_any = false;
};

// Pins the pairs μ drives below zero; counts the corrected F's entries into `corrected_nonzeros`.
// A pair's corrected g = v (ĝ/v + μ_i + μ_j) is positive wherever row i's smallest ĝ/v (a
// bound on every pair it holds) plus μ_i and the smallest μ_j is: when every row passes, no
// pair is visited (on a room of exact pairs the bound holds a thousandfold; the pass was a
// sixth of the correction). free_pairs(b, fn(u, pair)) visits block b's free pairs (u: the
// pair's index), pin(u) pins one. Returns whether any pair was pinned.
template <class FreePairs, class Pin>
bool pinDrivenNegative(PinBound& bound, const Eigen::VectorXd& mu, long long& corrected_nonzeros,
                       const FreePairs& free_pairs, const Pin& pin) {
  const Eigen::Index n = bound.least_ratio.size();
  if (!bound.pinned_any && mu.size() == n && mu.allFinite()) {
    // A margin of 1e-9 of the ratio: g is formed in floating point, where a bound met by
    // rounding's width would not keep it positive.
    const double mu_least = std::min(0.0, mu.minCoeff());
    const Eigen::VectorXd& least = bound.least_ratio;
    bool all_positive = true;
    for (Eigen::Index i = 0; i < n && all_positive; ++i)
      all_positive = std::isinf(least[i]) || least[i] + mu[i] + mu_least > 1e-9 * std::abs(least[i]);
    if (all_positive) {
      corrected_nonzeros = bound.free_entries;
      return false;
    }
  }
  bound.pinned_any = true;  // the bound is of the pairs as first read: from here, every pair visited
  std::vector<PairSums::Count> pinned(kCouplingBlocks), entries(kCouplingBlocks);
  solver::parallelFor(kCouplingBlocks, [&](long long b) {
    free_pairs(static_cast<int>(b), [&](size_t u, const Pair& p) {
      const double g = corrected(p, mu);
      if (g < 0) {
        pin(u);
        ++pinned[size_t(b)].value;
      } else if (g > 0) {
        entries[size_t(b)].value += p.i == p.j ? 1 : 2;
      }
    });
  });
  long long any_pinned = 0;
  corrected_nonzeros = 0;
  for (size_t b = 0; b < entries.size(); ++b) corrected_nonzeros += entries[b].value, any_pinned += pinned[b].value;
  return any_pinned > 0;
}

// The passes both in-place corrections make over their pairs (PairsInPlace, PairsUpper:
// freePairs, couplings, pinNegative, firstSums, keepOnlyPinned, correctedNonZeros,
// overwrite): the multipliers with pinning, the estimate handed to before_overwrite while
// still whole, then the corrected values laid over it and the terms into `out`.
template <class Pairs>
void correctPairs(Pairs& pairs, const Eigen::VectorXd& area, const ViewFactorEstimate& est, const Eigen::VectorXd& rays,
                  const std::function<void(long long)>& before_overwrite, ReciprocityCorrection& out) {
  NodeTerms terms(area, est, rays);
  const Eigen::VectorXd mu = pinnedMultipliers(
      area, terms, [&](int block, int blocks, auto&& fn) { pairs.freePairs(block, blocks, fn); },
      [&](int block, int blocks, auto&& fn) { pairs.couplings(block, blocks, fn); },
      [&](const Eigen::VectorXd& m) { return pairs.pinNegative(m); }, &pairs.firstSums());
  pairs.keepOnlyPinned();
  if (before_overwrite) before_overwrite(pairs.correctedNonZeros());
  terms.corrected(mu, area, out);
  pairs.overwrite(mu, out);
}

// enforceReciprocityInPlace for an upper_exchange estimate (reciprocity_upper.cpp): the
// corrected exchange areas in the result's exchange_upper, est's released.
ReciprocityCorrection correctUpperInPlace(const Eigen::VectorXd& area, ViewFactorEstimate& est,
                                          const Eigen::VectorXd& rays,
                                          const std::function<void(long long)>& before_overwrite);

}  // namespace radnet::geometry::detail
