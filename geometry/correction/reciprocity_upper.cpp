// The in-place correction of an estimate held as its upper exchange areas
// (ViewFactorEstimate::upper_exchange): every pair is one entry, g_ij (j ≥ i) with its error
// e_ij, so a pair is read where it lies, with no walk to its partner entry F_ji, and the
// corrected g is written over it.
#include "geometry/correction/in_place.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace radnet::geometry::detail {
namespace {

// The pairs of an upper estimate. A pair's two directional estimates are one integral:
// ĝ = g, and its variance combines the two rows' views of it, v_i = max(e², floor_i) and
// v_j likewise, by inverse variance (as combinedPair does with two equal estimates). The
// variances are kept in float (4 B a pair, 0 once pinned): every pass reads the same
// numbers, so the closure the multipliers reach holds for the g they write.
class PairsUpper {
 public:
  PairsUpper(const Eigen::VectorXd& area, const Eigen::VectorXd& rays, ViewFactorEstimate& est)
      : area_(area),
        rays_(rays),
        floor_(rayFloorVariances(area, rays)),
        g_(est.exchange_upper),
        error_(est.exchange_error_upper.data()),
        n_(static_cast<int>(area.size())),
        block_first_(upperRowBlocks(g_, kCouplingBlocks)) {
    var_.resize(g_.nonZeros());  // first touched below, on all cores
    std::vector<Eigen::VectorXd> smallest(kCouplingBlocks);
    std::vector<PairSums::Count> entries(kCouplingBlocks);
    solver::parallelFor(kCouplingBlocks, [&](long long b) {
      Eigen::VectorXd& least = smallest[size_t(b)] = Eigen::VectorXd::Constant(n_, INFINITY);
      forEachPair(static_cast<int>(b), [&](int u, int i, int j) {
        var_[u] = variance(i, j, u);
        const Pair p = pair(i, j, u);
        first_sums_.add(size_t(b), p);
        const double ratio = p.g_hat / p.var;
        least[i] = std::min(least[i], ratio), least[j] = std::min(least[j], ratio);
        entries[size_t(b)].value += i == j ? 1 : 2;
      });
    });
    bound_.least_ratio = Eigen::VectorXd::Constant(n_, INFINITY);
    for (const Eigen::VectorXd& least : smallest) bound_.least_ratio = bound_.least_ratio.cwiseMin(least);
    for (const PairSums::Count& e : entries) bound_.free_entries += e.value;
  }
  const PairSums& firstSums() const { return first_sums_; }

  template <class Fn>
  void freePairs(int block, int blocks, Fn&& fn) const {
    checkBlocks(blocks);
    forEachPair(block, [&](int u, int i, int j) {
      if (var_[u] != 0.0f) fn(pair(i, j, u));
    });
  }
  template <class Fn>
  void couplings(int block, int blocks, Fn&& fn) const {
    checkBlocks(blocks);
    forEachPair(block, [&](int u, int i, int j) {
      if (var_[u] != 0.0f && j != i) fn(i, j, double(var_[u]));
    });
  }
  // pinDrivenNegative over the pairs where they lie.
  bool pinNegative(const Eigen::VectorXd& mu) {
    return pinDrivenNegative(
        bound_, mu, corrected_nonzeros_,
        [&](int b, auto&& fn) {
          forEachPair(b, [&](int u, int i, int j) {
            if (var_[u] != 0.0f) fn(size_t(u), pair(i, j, u));
          });
        },
        [&](size_t u) { var_[Eigen::Index(u)] = 0.0f; });
  }
  long long correctedNonZeros() const { return corrected_nonzeros_; }

  // Only which pairs are pinned is kept (a bit a pair) while the estimate is written out;
  // the variances are formed again, to the same bits, where the overwrite needs them.
  void keepOnlyPinned() {
    pinned_.resize(static_cast<size_t>(var_.size()));
    for (Eigen::Index u = 0; u < var_.size(); ++u) pinned_[static_cast<size_t>(u)] = var_[u] == 0.0f;
    Eigen::VectorXf().swap(var_);
    solver::releaseFreedMemory();
  }

  // The corrected g over the estimate's own (then pruned of the pairs at zero), each
  // direction's move of F noted in `out` as it is overwritten (after keepOnlyPinned).
  void overwrite(const Eigen::VectorXd& mu, ReciprocityCorrection& out) {
    double* value = g_.valuePtr();
    std::vector<ReciprocityCorrection> part(kCouplingBlocks);
    solver::parallelFor(kCouplingBlocks, [&](long long b) {
      ReciprocityCorrection& mine = part[size_t(b)];
      forEachPair(static_cast<int>(b), [&](int u, int i, int j) {
        const double before = value[u];
        const double g = pinned_[size_t(u)] ? 0.0 : corrected({i, j, before, double(variance(i, j, u))}, mu);
        const double after = std::max(g, 0.0);
        if (g > 0) {  // σ_ij as the expanded σ holds it (float of e / A_i)
          noteChange(i, j, after / area_[i], before / area_[i], sigma(u, i), rays_[i], mine);
          if (j != i) noteChange(j, i, after / area_[j], before / area_[j], sigma(u, j), rays_[j], mine);
        }
        value[u] = after;
      });
    });
    for (const ReciprocityCorrection& mine : part) mergeChange(mine, out);
    g_.prune([](const Eigen::Index&, const Eigen::Index&, const double& v) { return v > 0.0; });
  }

 private:
  void checkBlocks(int blocks) const {
    if (blocks != kCouplingBlocks) throw std::logic_error("the upper pairs walk kCouplingBlocks blocks");
  }
  template <class Visit>
  void forEachPair(int block, Visit&& visit) const {
    const int* outer = g_.outerIndexPtr();
    const int* inner = g_.innerIndexPtr();
    for (int i = block_first_[size_t(block)]; i < block_first_[size_t(block) + 1]; ++i)
      for (int u = outer[i]; u < outer[i + 1]; ++u) visit(u, i, inner[u]);
  }
  // The pair's variance in float, never 0 (0 marks a pinned pair).
  float variance(int i, int j, int u) const {
    const double e2 = std::pow(double(error_[u]), 2);
    const double vi = std::max(e2, floor_[i]);
    const double v = j == i ? vi : 1.0 / (1.0 / vi + 1.0 / std::max(e2, floor_[j]));
    return std::max(static_cast<float>(v), std::numeric_limits<float>::min());
  }
  double sigma(int u, int row) const { return static_cast<float>(double(error_[u]) / area_[row]); }
  Pair pair(int i, int j, int u) const { return {i, j, g_.valuePtr()[u], double(var_[u])}; }

  const Eigen::VectorXd &area_, &rays_;
  Eigen::VectorXd floor_;
  RowSparse& g_;
  const float* error_;
  int n_;
  std::vector<int> block_first_;  // each coupling block's first row (equal shares of pairs), then n
  Eigen::VectorXf var_;
  std::vector<bool> pinned_;
  long long corrected_nonzeros_ = 0;
  PairSums first_sums_{n_};
  PinBound bound_;
};

}  // namespace

ReciprocityCorrection correctUpperInPlace(const Eigen::VectorXd& area, ViewFactorEstimate& est,
                                          const Eigen::VectorXd& rays,
                                          const std::function<void(long long)>& before_overwrite) {
  if (est.exchange_upper.rows() != area.size() || est.exchange_error_upper.size() != est.exchange_upper.nonZeros() ||
      !est.exchange_upper.isCompressed())
    throw std::invalid_argument("an upper estimate's exchange areas and errors must match the nodes");
  ReciprocityCorrection out;
  {
    PairsUpper pairs(area, rays, est);
    correctPairs(pairs, area, est, rays, before_overwrite, out);
  }
  out.exchange_upper.swap(est.exchange_upper);
  Eigen::VectorXf().swap(est.exchange_error_upper);
  est.upper_exchange = false;  // upper_area kept: a caller may pass it as `area`
  const Eigen::VectorXd sums = upperRowSums(out.exchange_upper, area);
  for (Eigen::Index i = 0; i < sums.size(); ++i)
    out.max_closure_error = std::max(out.max_closure_error, std::abs(sums[i] + out.space[i] + out.blocked[i] - 1.0));
  return out;
}

}  // namespace radnet::geometry::detail
