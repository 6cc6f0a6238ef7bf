#include "geometry/reciprocity.hpp"

#include "geometry/correction/pairs.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace radnet::geometry {
using namespace detail;
namespace {

// Every pair of F's pattern, combined (combinedPair). Row i's upper entries (j ≥ i) are
// walked in order; the partner F_ji is found by a cursor into row j that only moves forward
// (rows are visited in increasing i, so column i is the next of row j's lower entries still
// unvisited): no transpose of F or σ (2.8 of the 4.1 s of the correction on a 6,144-node
// room). A lower entry a cursor steps over had no partner.
std::vector<Pair> combinedPairs(const Eigen::VectorXd& area, const ViewFactorEstimate& est,
                                const Eigen::VectorXd& rays) {
  const RowSparse &f = est.view_factors, &sigma = est.standard_error;
  const int n = static_cast<int>(area.size());
  const int* outer = f.outerIndexPtr();
  const int* inner = f.innerIndexPtr();
  const double* value = f.valuePtr();
  const double* error = sigma.valuePtr();
  const Eigen::VectorXd floor = rayFloorVariances(area, rays);
  std::vector<Pair> pairs, one_sided;
  // At most one pair per upper entry: reserved (pages untouched until written), so the list
  // is never copied as it grows (15.7 M pairs on a 6,144-node room).
  pairs.reserve(static_cast<size_t>(f.nonZeros()) / 2 + static_cast<size_t>(n) + 1);
  auto lowerOnly = [&](int row, int k) {  // F_row,col (col < row) whose partner F_col,row is absent
    const Pair p = combinedPair(area, floor, value, error, row, inner[k], k, -1);
    one_sided.push_back({inner[k], row, p.g_hat, p.var});
  };
  std::vector<int> cursor(outer, outer + n);  // each row's next lower entry not yet visited
  for (int i = 0; i < n; ++i) {
    // Row i's lower entries left unvisited by rows 0 … i−1: their partners are absent.
    for (int& c = cursor[static_cast<size_t>(i)]; c < outer[i + 1] && inner[c] < i; ++c) lowerOnly(i, c);
    for (int k = cursor[static_cast<size_t>(i)]; k < outer[i + 1]; ++k) {
      const int j = inner[k];
      int k_ji = k;
      if (j != i) {
        int& c = cursor[static_cast<size_t>(j)];
        for (; c < outer[j + 1] && inner[c] < i; ++c) lowerOnly(j, c);
        k_ji = c < outer[j + 1] && inner[c] == i ? c++ : -1;
      }
      pairs.push_back(combinedPair(area, floor, value, error, i, j, k, k_ji));
    }
  }
  if (!one_sided.empty()) {  // sorted by (i, j) like the rest, then merged in
    auto before = [](const Pair& a, const Pair& b) { return a.i != b.i ? a.i < b.i : a.j < b.j; };
    std::sort(one_sided.begin(), one_sided.end(), before);
    const auto middle = static_cast<std::ptrdiff_t>(pairs.size());
    pairs.insert(pairs.end(), one_sided.begin(), one_sided.end());
    std::inplace_merge(pairs.begin(), pairs.begin() + middle, pairs.end(), before);
  }
  return pairs;
}

// σ laid on F's pattern (compressed F): an entry σ does not hold is 0 (all of them when σ
// was left empty or has another shape).
RowSparse sigmaOnPattern(const RowSparse& f, const RowSparse& sigma) {
  RowSparse out = f;
  if (sigma.rows() != f.rows() || sigma.cols() != f.cols()) {
    std::fill(out.valuePtr(), out.valuePtr() + out.nonZeros(), 0.0);
    return out;
  }
  for (Eigen::Index i = 0; i < f.outerSize(); ++i) {
    RowSparse::InnerIterator e(sigma, i);
    for (RowSparse::InnerIterator it(out, i); it; ++it) {
      while (e && e.col() < it.col()) ++e;
      it.valueRef() = (e && e.col() == it.col()) ? e.value() : 0.0;
    }
  }
  return out;
}

// The pair list's visitors for closureMultipliers, by blocks: a block runs from the first row
// starting at or after its share of the pairs (as the in-place correction splits them: the
// same sums).
template <class Fn>
void forPairsOfBlock(const std::vector<Pair>& pairs, int block, int blocks, Fn&& fn) {
  auto rowStart = [&](int b) {
    size_t q = pairs.size() * size_t(b) / size_t(blocks);
    while (q > 0 && q < pairs.size() && pairs[q].i == pairs[q - 1].i) ++q;
    return q;
  };
  const size_t first = rowStart(block), last = block + 1 == blocks ? pairs.size() : rowStart(block + 1);
  for (size_t q = first; q < last; ++q)
    if (!pairs[q].pinned()) fn(pairs[q]);
}
auto freePairsOf(const std::vector<Pair>& pairs) {
  return [&pairs](int block, int blocks, auto&& fn) { forPairsOfBlock(pairs, block, blocks, fn); };
}
auto couplingsOf(const std::vector<Pair>& pairs) {
  return [&pairs](int block, int blocks, auto&& fn) {
    forPairsOfBlock(pairs, block, blocks, [&](const Pair& p) {
      if (p.i != p.j) fn(p.i, p.j, p.var);
    });
  };
}

}  // namespace

// How far each entry moved, in view-factor units and in standard errors, and the closure.
// The corrected rows hold a subset of the estimate's columns: both are walked together.
void reportCorrection(const ViewFactorEstimate& est, const Eigen::VectorXd& rays, ReciprocityCorrection& out,
                      const solver::RowShare& share) {
  const int n = static_cast<int>(rays.size());
  for (int i = 0; i < n; ++i) {
    if (!share.holds(i)) continue;
    RowSparse::InnerIterator f(est.view_factors, i), e(est.standard_error, i);
    for (RowSparse::InnerIterator it(out.view_factors, i); it; ++it) {
      const int j = static_cast<int>(it.col());
      while (f && f.col() < j) ++f;
      while (e && e.col() < j) ++e;
      const double before = (f && f.col() == j) ? f.value() : 0.0;
      const double sigma = (e && e.col() == j) ? e.value() : 0.0;
      noteChange(i, j, it.value(), before, sigma, rays[i], out);
    }
    const double closure = out.view_factors.row(i).sum() + out.space[i] + out.blocked[i] - 1.0;
    out.max_closure_error = std::max(out.max_closure_error, std::abs(closure));
  }
  if (share.whole()) return;
  // The largest move and, among equal ones, the first pair in row order: its −(i n + j) the largest.
  const double largest = share.largest(out.max_change);
  double first = out.max_change == largest && out.worst_from >= 0
                     ? -(double(out.worst_from) * n + out.worst_to)
                     : -1e300;
  first = share.largest(first);
  out.max_change = largest;
  if (first > -1e300) {
    out.worst_from = static_cast<int>(-first / n);
    out.worst_to = static_cast<int>(-first - double(out.worst_from) * n);
  }
  out.max_change_sigma = share.largest(out.max_change_sigma);
  out.max_closure_error = share.largest(out.max_closure_error);
}

namespace {

// The corrected F in compressed rows, straight from the pairs (sorted by i, then j ≥ i):
// row r receives g_ir / A_r from the pairs (i < r, r) in increasing i, then g_rj / A_r from
// its own pairs in increasing j, so every row comes out in column order.
RowSparse correctedRows(const std::vector<Pair>& pairs, const Eigen::VectorXd& mu, const Eigen::VectorXd& area) {
  const Eigen::Index n = area.size();
  std::vector<Eigen::Index> start(static_cast<size_t>(n) + 1, 0);
  for (size_t q = 0; q < pairs.size(); ++q) {
    if (corrected(pairs[q], mu) <= 0) continue;
    ++start[static_cast<size_t>(pairs[q].i) + 1];
    if (pairs[q].i != pairs[q].j) ++start[static_cast<size_t>(pairs[q].j) + 1];
  }
  for (size_t i = 0; i < static_cast<size_t>(n); ++i) start[i + 1] += start[i];
  RowSparse f(n, n);
  f.resizeNonZeros(start.back());
  std::vector<Eigen::Index> fill(start.begin(), start.end() - 1);
  auto put = [&](int row, int col, double value) {
    const Eigen::Index at = fill[static_cast<size_t>(row)]++;
    f.innerIndexPtr()[at] = col;
    f.valuePtr()[at] = value;
  };
  for (const Pair& p : pairs) {
    const double g = corrected(p, mu);
    if (g <= 0) continue;
    put(p.i, p.j, g / area[p.i]);
    if (p.i != p.j) put(p.j, p.i, g / area[p.j]);
  }
  for (Eigen::Index i = 0; i <= n; ++i) f.outerIndexPtr()[i] = static_cast<int>(start[static_cast<size_t>(i)]);
  return f;
}

}  // namespace

const ViewFactorEstimate& onOnePattern(const ViewFactorEstimate& est, ViewFactorEstimate& storage) {
  if (samePattern(est.view_factors, est.standard_error)) return est;
  storage.view_factors = est.view_factors;
  storage.view_factors.makeCompressed();
  storage.standard_error = sigmaOnPattern(storage.view_factors, est.standard_error);
  return storage;
}

namespace {

}  // namespace

ReciprocityCorrection enforceReciprocity(const Eigen::VectorXd& area, const ViewFactorEstimate& est,
                                         const Eigen::VectorXd& rays) {
  // combinedPairs reads F and σ on one compressed pattern: a copy only when they differ.
  ViewFactorEstimate relaid;
  const ViewFactorEstimate* shared = &onOnePattern(est, relaid);
  std::vector<Pair> pairs = combinedPairs(area, *shared, rays);
  NodeTerms terms(area, est, rays);
  const Eigen::VectorXd mu =
      pinnedMultipliers(area, terms, freePairsOf(pairs), couplingsOf(pairs), [&](const Eigen::VectorXd& m) {
        bool changed = false;
        for (Pair& p : pairs)
          if (!p.pinned() && corrected(p, m) < 0) {
            p.g_hat = p.var = 0.0;
            changed = true;
          }
        return changed;
      });
  ReciprocityCorrection out;
  terms.corrected(mu, area, out);
  {  // swapped in: an assignment copies (Eigen 3.4), 0.38 GB at the stage's peak on the 6,144-node room
    RowSparse corrected = correctedRows(pairs, mu, area);
    out.view_factors.swap(corrected);
  }
  std::vector<Pair>().swap(pairs);  // before the report: 0.38 GB on the 6,144-node room
  reportCorrection(*shared, rays, out);  // σ on F's pattern (absent entries 0)
  return out;
}

}  // namespace radnet::geometry
