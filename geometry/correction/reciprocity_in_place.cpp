#include "geometry/reciprocity.hpp"

#include "geometry/correction/pairs.hpp"

#include <algorithm>
#include <functional>
#include <optional>
#include <vector>

namespace radnet::geometry {
using namespace detail;

std::optional<ReciprocityCorrection> enforceReciprocityInPlace(const Eigen::VectorXd& area, ViewFactorEstimate& est,
                                                               const Eigen::VectorXd& rays,
                                                               const std::function<void(long long)>& before_overwrite) {
  RowSparse& f = est.view_factors;
  if (!samePattern(f, est.standard_error)) return std::nullopt;
  const int n = static_cast<int>(area.size());
  const int* outer = f.outerIndexPtr();
  const int* inner = f.innerIndexPtr();
  double* value = f.valuePtr();
  const double* error = est.standard_error.valuePtr();
  // Each pair's variance, in pair order (upper entries row by row): 0 once pinned. Its
  // estimate ĝ is combined again from F and σ where needed (8 B a pair instead of 24).
  std::vector<int> upper_start(static_cast<size_t>(n));  // row i's first entry with column ≥ i
  std::vector<size_t> first_pair(static_cast<size_t>(n) + 1, 0);  // row i's first pair's index
  for (int i = 0; i < n; ++i) {
    upper_start[static_cast<size_t>(i)] =
        static_cast<int>(std::lower_bound(inner + outer[i], inner + outer[i + 1], i) - inner);
    first_pair[static_cast<size_t>(i) + 1] =
        first_pair[static_cast<size_t>(i)] + static_cast<size_t>(outer[i + 1] - upper_start[static_cast<size_t>(i)]);
  }
  const size_t pair_count = first_pair.back();
  std::vector<double> var;
  var.reserve(pair_count);
  if (!forEachSymmetricPair(f, [&](int i, int j, int k, int k_ji) {
        var.push_back(combinedPair(area, rays, value, error, i, j, k, k_ji).var);
      }))
    return std::nullopt;
  auto free_pairs = [&](auto&& fn) {
    size_t u = 0;
    forEachSymmetricPair(f, [&](int i, int j, int k, int k_ji) {
      if (var[u++] != 0.0) fn(combinedPair(area, rays, value, error, i, j, k, k_ji));
    });
  };
  auto couplings = [&](int block, int blocks, auto&& fn) {  // rows holding a block's share of the pairs
    auto rowAt = [&](int b) {
      const size_t pair = pair_count * size_t(b) / size_t(blocks);
      return static_cast<int>(std::lower_bound(first_pair.begin(), first_pair.end() - 1, pair) - first_pair.begin());
    };
    const int last = block + 1 == blocks ? n : rowAt(block + 1);
    for (int i = rowAt(block); i < last; ++i) {
      size_t u = first_pair[static_cast<size_t>(i)];
      for (int k = upper_start[static_cast<size_t>(i)]; k < outer[i + 1]; ++k, ++u)
        if (var[u] != 0.0 && inner[k] != i) fn(i, inner[k], var[u]);
    }
  };
  long long corrected_nonzeros = 0;  // counted in the last round: the corrected F's entries
  NodeTerms terms(area, est, rays);
  const Eigen::VectorXd mu = pinnedMultipliers(area, terms, free_pairs, couplings, [&](const Eigen::VectorXd& m) {
    bool changed = false;
    size_t u = 0;
    corrected_nonzeros = 0;
    forEachSymmetricPair(f, [&](int i, int j, int k, int k_ji) {
      double& v = var[u++];
      if (v == 0.0) return;
      const double g = corrected(combinedPair(area, rays, value, error, i, j, k, k_ji), m);
      if (g < 0) {
        v = 0.0;
        changed = true;
      } else if (g > 0) {
        corrected_nonzeros += i == j ? 1 : 2;
      }
    });
    return changed;
  });
  // Only which pairs are pinned is read from here on (combinedPair gives ĝ and v again):
  // a bit each instead of 8 B, before the estimate is written out.
  std::vector<bool> pinned(pair_count);
  for (size_t q = 0; q < pair_count; ++q) pinned[q] = var[q] == 0.0;
  std::vector<double>().swap(var);
  solver::releaseFreedMemory();  // glibc keeps the 0.13 GB resident otherwise
  if (before_overwrite) before_overwrite(corrected_nonzeros);
  ReciprocityCorrection out;
  terms.corrected(mu, area, out);
  size_t u = 0;
  forEachSymmetricPair(f, [&](int i, int j, int k, int k_ji) {
    const double g = pinned[u++] ? 0.0 : corrected(combinedPair(area, rays, value, error, i, j, k, k_ji), mu);
    if (g > 0) {
      noteChange(i, j, g / area[i], value[k], error[k], rays[i], out);
      if (j != i) noteChange(j, i, g / area[j], value[k_ji], error[k_ji], rays[j], out);
    }
    value[k] = g > 0 ? g / area[i] : 0.0;
    value[k_ji] = g > 0 ? g / area[j] : 0.0;
  });
  std::vector<bool>().swap(pinned);
  f.prune([](const Eigen::Index&, const Eigen::Index&, const double& v) { return v > 0.0; });
  out.view_factors.swap(f);
  out.max_closure_error = largestClosureError(out);
  return out;
}

}  // namespace radnet::geometry
