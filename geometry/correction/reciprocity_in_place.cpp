#include "geometry/reciprocity.hpp"

#include "geometry/correction/in_place.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <vector>

namespace radnet::geometry {
using namespace detail;
namespace {

// The pairs of a symmetric compressed pattern read where they lie in F and σ: each pair's
// variance is kept (in pair order: upper entries row by row, 0 once pinned, 8 B a pair
// instead of the list's 24), its estimate ĝ combined again from F and σ where a pass needs it.
// σ's values (Error: double, or float on F's pattern) lie at F's indices.
template <class Error>
class PairsInPlace {
 public:
  PairsInPlace(const Eigen::VectorXd& area, const Eigen::VectorXd& rays, ViewFactorEstimate& est, const Error* error)
      : area_(area),
        rays_(rays),
        floor_(rayFloorVariances(area, rays)),
        f_(est.view_factors),
        error_(error),
        n_(static_cast<int>(area.size())),
        upper_start_(static_cast<size_t>(n_)),
        first_pair_(static_cast<size_t>(n_) + 1, 0) {
    const int* outer = f_.outerIndexPtr();
    const int* inner = f_.innerIndexPtr();
    for (int i = 0; i < n_; ++i) {
      const size_t row = static_cast<size_t>(i);
      upper_start_[row] = static_cast<int>(std::lower_bound(inner + outer[i], inner + outer[i + 1], i) - inner);
      first_pair_[row + 1] = first_pair_[row] + static_cast<size_t>(outer[i + 1] - upper_start_[row]);
    }
    // Uninitialised (0.13 GB on a 6,144-node room): first touched by the pass below on all
    // cores, where a zero-filled vector was one core's memset of fresh pages first.
    var_.resize(static_cast<Eigen::Index>(first_pair_.back()));
    // The pass that reads the variances also forms the first closure system's sums (the
    // same blocks, the same order: closureMultipliers' bits) and each row's smallest ĝ / v.
    std::vector<char> block_symmetric(kCouplingBlocks, 1);
    std::vector<Eigen::VectorXd> smallest(kCouplingBlocks);
    std::vector<PairSums::Count> entries(kCouplingBlocks);
    solver::parallelFor(kCouplingBlocks, [&](long long b) {
      Eigen::VectorXd& least = smallest[size_t(b)] = Eigen::VectorXd::Constant(n_, INFINITY);
      block_symmetric[size_t(b)] = forEachPairOfBlock(static_cast<int>(b), [&](size_t u, int i, int j, int k, int k_ji) {
        const Pair p = pair(i, j, k, k_ji);
        var_[u] = p.var;
        if (p.var == 0.0) return;
        first_sums_.add(size_t(b), p);
        const double ratio = p.g_hat / p.var;
        least[i] = std::min(least[i], ratio), least[j] = std::min(least[j], ratio);
        entries[size_t(b)].value += i == j ? 1 : 2;
      });
    });
    symmetric_ = std::all_of(block_symmetric.begin(), block_symmetric.end(), [](char s) { return s != 0; });
    bound_.least_ratio = Eigen::VectorXd::Constant(n_, INFINITY);
    for (const Eigen::VectorXd& least : smallest) bound_.least_ratio = bound_.least_ratio.cwiseMin(least);
    for (const PairSums::Count& e : entries) bound_.free_entries += e.value;
  }
  bool symmetric() const { return symmetric_; }
  const PairSums& firstSums() const { return first_sums_; }

  // closureMultipliers' visitors: the pairs not pinned, and their couplings by blocks of
  // rows, each starting at the first row at or after its share of the pairs.
  template <class Fn>
  void freePairs(int block, int blocks, Fn&& fn) const {
    if (blocks != kCouplingBlocks) throw std::logic_error("the in-place pairs walk kCouplingBlocks blocks");
    forEachPairOfBlock(block, [&](size_t u, int i, int j, int k, int k_ji) {
      if (var_[u] != 0.0) fn(pair(i, j, k, k_ji));
    });
  }
  template <class Fn>
  void couplings(int block, int blocks, Fn&& fn) const {
    const int* outer = f_.outerIndexPtr();
    const int* inner = f_.innerIndexPtr();
    const int last = block + 1 == blocks ? n_ : rowAt(block + 1, blocks);
    for (int i = rowAt(block, blocks); i < last; ++i) {
      size_t u = first_pair_[static_cast<size_t>(i)];
      for (int k = upper_start_[static_cast<size_t>(i)]; k < outer[i + 1]; ++k, ++u)
        if (var_[u] != 0.0 && inner[k] != i) fn(i, inner[k], var_[u]);
    }
  }
  // pinDrivenNegative over the pairs where they lie.
  bool pinNegative(const Eigen::VectorXd& mu) {
    return pinDrivenNegative(
        bound_, mu, corrected_nonzeros_,
        [&](int b, auto&& fn) {
          forEachPairOfBlock(b, [&](size_t u, int i, int j, int k, int k_ji) {
            if (var_[u] != 0.0) fn(u, pair(i, j, k, k_ji));
          });
        },
        [&](size_t u) { var_[u] = 0.0; });
  }
  long long correctedNonZeros() const { return corrected_nonzeros_; }

  // Once μ is known only which pairs are pinned is read from the variances (combinedPair
  // gives v again): a bit a pair instead of 8 B, before the estimate is written out.
  void keepOnlyPinned() {
    pinned_.resize(static_cast<size_t>(var_.size()));
    for (Eigen::Index q = 0; q < var_.size(); ++q) pinned_[static_cast<size_t>(q)] = var_[q] == 0.0;
    Eigen::VectorXd().swap(var_);
    solver::releaseFreedMemory();  // glibc keeps the 0.13 GB resident otherwise
  }

  // The corrected F over the estimate's own values (then pruned of the pairs at zero), each
  // entry's move noted in `out` as it is overwritten (after keepOnlyPinned).
  void overwrite(const Eigen::VectorXd& mu, ReciprocityCorrection& out) {
    double* value = f_.valuePtr();
    std::vector<ReciprocityCorrection> part(kCouplingBlocks);  // each block's report, merged below
    solver::parallelFor(kCouplingBlocks, [&](long long b) {
      ReciprocityCorrection& mine = part[size_t(b)];
      forEachPairOfBlock(static_cast<int>(b), [&](size_t u, int i, int j, int k, int k_ji) {
        const double g = pinned_[u] ? 0.0 : corrected(pair(i, j, k, k_ji), mu);
        if (g > 0) {
          noteChange(i, j, g / area_[i], value[k], error_[k], rays_[i], mine);
          if (j != i) noteChange(j, i, g / area_[j], value[k_ji], error_[k_ji], rays_[j], mine);
        }
        value[k] = g > 0 ? g / area_[i] : 0.0;
        value[k_ji] = g > 0 ? g / area_[j] : 0.0;
      });
    });
    for (const ReciprocityCorrection& mine : part) mergeChange(mine, out);
    f_.prune([](const Eigen::Index&, const Eigen::Index&, const double& v) { return v > 0.0; });
  }

 private:
  // Visits the pairs (index u in pair order, i, j ≥ i, k_ij, k_ji) of the rows holding block
  // b's share of the pairs (couplings' blocks), with cursors of its own: rows j ≥ the block's
  // first, each at its first entry from that column on, so the blocks can run at once (their
  // pairs, and the entries they write, are disjoint). False at an entry without its partner,
  // seen from this block: a lower entry of a row of the block, or of a later row, in the
  // block's columns that no row of the block visited.
  template <class Visit>
  bool forEachPairOfBlock(int block, Visit&& visit) const {
    const int* outer = f_.outerIndexPtr();
    const int* inner = f_.innerIndexPtr();
    const int first = rowAt(block, kCouplingBlocks);
    const int last = block + 1 == kCouplingBlocks ? n_ : rowAt(block + 1, kCouplingBlocks);
    std::vector<int> cursor(static_cast<size_t>(n_ - first));
    for (int j = first; j < n_; ++j)
      cursor[size_t(j - first)] = static_cast<int>(std::lower_bound(inner + outer[j], inner + outer[j + 1], first) - inner);
    size_t u = first_pair_[static_cast<size_t>(first)];
    for (int i = first; i < last; ++i) {
      if (cursor[size_t(i - first)] != upper_start_[static_cast<size_t>(i)]) return false;
      for (int k = upper_start_[static_cast<size_t>(i)]; k < outer[i + 1]; ++k, ++u) {
        const int j = inner[k];
        if (j == i) {
          visit(u, i, i, k, k);
          continue;
        }
        int& c = cursor[size_t(j - first)];
        if (c >= outer[j + 1] || inner[c] != i) return false;
        visit(u, i, j, k, c++);
      }
    }
    for (int j = last; j < n_; ++j) {  // later rows' entries in this block's columns: all visited
      const int c = cursor[size_t(j - first)];
      if (c < outer[j + 1] && inner[c] < last) return false;
    }
    return true;
  }
  Pair pair(int i, int j, int k, int k_ji) const {
    return combinedPair(area_, floor_, f_.valuePtr(), error_, i, j, k, k_ji);
  }
  int rowAt(int block, int blocks) const {
    const size_t share = first_pair_.back() * size_t(block) / size_t(blocks);
    return static_cast<int>(std::lower_bound(first_pair_.begin(), first_pair_.end() - 1, share) - first_pair_.begin());
  }

  const Eigen::VectorXd &area_, &rays_;
  Eigen::VectorXd floor_;  // per row, one ray's worth of variance
  RowSparse& f_;
  const Error* error_;
  int n_;
  std::vector<int> upper_start_;      // row i's first entry with column ≥ i
  std::vector<size_t> first_pair_;    // row i's first pair's index (n + 1: the count last)
  Eigen::VectorXd var_;               // per pair, its variance v (0: pinned)
  std::vector<bool> pinned_;
  bool symmetric_ = false;
  long long corrected_nonzeros_ = 0;
  PairSums first_sums_{n_};
  PinBound bound_;
};

// The correction over σ's values `error` (at F's indices).
template <class Error>
ReciprocityCorrection correctInPlace(const Eigen::VectorXd& area, ViewFactorEstimate& est, const Eigen::VectorXd& rays,
                                     const Error* error, const std::function<void(long long)>& before_overwrite,
                                     bool& symmetric) {
  PairsInPlace<Error> pairs(area, rays, est, error);
  symmetric = pairs.symmetric();
  ReciprocityCorrection out;
  if (!symmetric) return out;
  correctPairs(pairs, area, est, rays, before_overwrite, out);
  return out;
}

}  // namespace

std::optional<ReciprocityCorrection> enforceReciprocityInPlace(const Eigen::VectorXd& area, ViewFactorEstimate& est,
                                                               const Eigen::VectorXd& rays,
                                                               const std::function<void(long long)>& before_overwrite) {
  if (est.upper_exchange) return correctUpperInPlace(area, est, rays, before_overwrite);
  const bool on_pattern = est.errors_on_pattern;
  if (on_pattern ? est.error_on_pattern.size() != est.view_factors.nonZeros() || !est.view_factors.isCompressed()
                 : !samePattern(est.view_factors, est.standard_error))
    return std::nullopt;
  bool symmetric = false;
  ReciprocityCorrection out =
      on_pattern ? correctInPlace(area, est, rays, est.error_on_pattern.data(), before_overwrite, symmetric)
                 : correctInPlace(area, est, rays, est.standard_error.valuePtr(), before_overwrite, symmetric);
  if (!symmetric) return std::nullopt;
  out.view_factors.swap(est.view_factors);
  if (on_pattern) {  // its pattern is gone with the raw F
    Eigen::VectorXf().swap(est.error_on_pattern);
    est.errors_on_pattern = false;
  }
  out.max_closure_error = largestClosureError(out);
  return out;
}

}  // namespace radnet::geometry
