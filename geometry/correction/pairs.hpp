#pragma once
// What the two whole-matrix reciprocity corrections share (correction/reciprocity.cpp: the pairs in a
// list; reciprocity_in_place.cpp: the pairs read from F and σ where they lie): a pair's
// combined estimate, the walk over a symmetric pattern, the closure multipliers with their
// pinning, and each entry's move in the report. Internal to geometry/.
#include "geometry/reciprocity.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

namespace radnet::geometry::detail {

using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// 24 B (15.7 M of them on a 6,144-node room): a pair pinned at zero keeps ĝ = v = 0, as
// every estimate's variance is floored at one ray's (> 0).
struct Pair {
  int i, j;      // i <= j
  double g_hat;  // combined estimate of g_ij, m²
  double var;    // its variance, m⁴; 0: pinned at zero
  bool pinned() const { return var == 0.0; }
};

// Above this many entries of K the multipliers come from conjugate gradients, not a
// sparse LDLᵀ (whose fill-in on dense patterns costs n³/3: 6 of 8 s on a 1,536-node room).
inline constexpr Eigen::Index kDirectSolveEntries = 200000;

// One ray's worth of variance, (A_i / N_i)², m⁴: the floor under every estimate of row i.
inline double rayFloorVariance(const Eigen::VectorXd& area, const Eigen::VectorXd& rays, int i) {
  return std::pow(area[i] / std::max(1.0, rays[i]), 2);
}

// Every row's floor, rayFloorVariance(area, rays, i), formed once for combinedPair.
inline Eigen::VectorXd rayFloorVariances(const Eigen::VectorXd& area, const Eigen::VectorXd& rays) {
  Eigen::VectorXd floor(area.size());
  for (Eigen::Index i = 0; i < area.size(); ++i) floor[i] = rayFloorVariance(area, rays, static_cast<int>(i));
  return floor;
}

// Pair (i, j ≥ i) from its two directional estimates, x = A_i F_ij with variance (A_i σ_ij)²
// floored at one ray's worth (`floor`, rayFloorVariances: a division less per side and pass),
// combined by inverse variance; F and σ share one compressed pattern, so an entry's σ sits
// at its index in F. k_ji < 0: F_ji is absent, and the other side's zero counts with one
// ray's variance. Bit for bit whichever correction calls it (σ in double or, on F's pattern,
// float: the same numbers).
template <class Error>
Pair combinedPair(const Eigen::VectorXd& area, const Eigen::VectorXd& floor, const double* value, const Error* error,
                  int i, int j, int k_ij, int k_ji) {
  auto variance = [&](int row, int k) { return std::max(std::pow(area[row] * double(error[k]), 2), floor[row]); };
  const double v = variance(i, k_ij);
  double num = area[i] * value[k_ij] / v, den = 1.0 / v;
  if (j != i) {
    if (k_ji >= 0) {
      const double vj = variance(j, k_ji);
      num += area[j] * value[k_ji] / vj;
      den += 1.0 / vj;
    } else {
      den += 1.0 / floor[j];
    }
  }
  return {i, j, num / den, 1.0 / den};
}

// A pair's corrected conductance g_ij = ĝ_ij + v_ij (μ_i + μ_j) (0 when pinned), m².
inline double corrected(const Pair& p, const Eigen::VectorXd& mu) {
  return p.g_hat + p.var * (p.i == p.j ? mu[p.i] : mu[p.i] + mu[p.j]);
}

// Whether σ is stored on F's compressed pattern, entry for entry (as combinedPairs reads it).
inline bool samePattern(const RowSparse& f, const RowSparse& sigma) {
  return f.isCompressed() && sigma.isCompressed() && f.rows() == sigma.rows() && f.nonZeros() == sigma.nonZeros() &&
         std::equal(f.outerIndexPtr(), f.outerIndexPtr() + f.outerSize() + 1, sigma.outerIndexPtr()) &&
         std::equal(f.innerIndexPtr(), f.innerIndexPtr() + f.nonZeros(), sigma.innerIndexPtr());
}

// Calls visit(i, j, k_ij, k_ji) for every pair of a compressed pattern in which each F_ij
// has its F_ji (the exact method's), rows in increasing i, then j ≥ i (k_ji = k_ij on the
// diagonal): the order of combinedPairs. False, having stopped, at an entry without partner.
template <class Visit>
bool forEachSymmetricPair(const RowSparse& f, Visit&& visit) {
  const int n = static_cast<int>(f.rows());
  const int* outer = f.outerIndexPtr();
  const int* inner = f.innerIndexPtr();
  std::vector<int> cursor(outer, outer + n);  // each row's next lower entry not yet visited
  for (int i = 0; i < n; ++i) {
    const int first = cursor[static_cast<size_t>(i)];
    if (first < outer[i + 1] && inner[first] < i) return false;  // F_ij, j < i, whose F_ji row j lacked
    for (int k = first; k < outer[i + 1]; ++k) {
      const int j = inner[k];
      if (j == i) {
        visit(i, i, k, k);
        continue;
      }
      int& c = cursor[static_cast<size_t>(j)];
      if (c >= outer[j + 1] || inner[c] != i) return false;
      visit(i, j, k, c++);
    }
  }
  return true;
}

// Jacobi-preconditioned conjugate gradients on K μ = rhs from μ = 0, stopping as Eigen's
// ConjugateGradient does (‖rhs − K μ‖ ≤ kMultiplierTolerance ‖rhs‖). K = diag(d) + Σ v_ij
// (e_i e_jᵀ + e_j e_iᵀ) over the couplings, never formed: on a 6,144-node room it would hold
// 15.7 M of them (0.19 GB beside F and σ). couplings(b, B, fn(i, j, v)) visits block b of
// B; the product sums each block apart, on all cores, then the blocks in order (the same
// bits for any thread count).
inline constexpr double kMultiplierTolerance = 1e-13;
inline constexpr double kClosureTolerance = 1e-14;  // of a row's area: F's closure, –
inline constexpr int kMultiplierMaxIterations = 2000;
inline constexpr int kCouplingBlocks = 8;

template <class Couplings>
bool conjugateGradients(const Couplings& couplings, const Eigen::VectorXd& d, const Eigen::VectorXd& rhs,
                        const Eigen::VectorXd& area, Eigen::VectorXd& mu) {
  const Eigen::Index n = rhs.size();
  mu = Eigen::VectorXd::Zero(n);
  const double threshold = kMultiplierTolerance * kMultiplierTolerance * rhs.squaredNorm();
  if (threshold == 0) return true;
  std::vector<Eigen::VectorXd> partial(kCouplingBlocks, Eigen::VectorXd(n));
  auto product = [&](const Eigen::VectorXd& x, Eigen::VectorXd& y) {
    solver::parallelFor(kCouplingBlocks, [&](long long b) {
      Eigen::VectorXd& part = partial[static_cast<size_t>(b)];
      part.setZero();
      // Row i's own sum is kept in a register while its couplings come (they come row by
      // row): added through memory, each term waited on the store of the one before.
      int row = -1;
      double row_sum = 0.0;
      couplings(static_cast<int>(b), kCouplingBlocks, [&](int i, int j, double v) {
        if (i != row) {
          if (row >= 0) part[row] += row_sum;
          row = i, row_sum = 0.0;
        }
        row_sum += v * x[j];
        part[j] += v * x[i];
      });
      if (row >= 0) part[row] += row_sum;
    });
    y = d.cwiseProduct(x);
    for (const Eigen::VectorXd& part : partial) y += part;
  };
  Eigen::VectorXd r = rhs, z = r.cwiseQuotient(d), p = z, kp(n);
  double rz = r.dot(z);
  for (int it = 0; it < kMultiplierMaxIterations; ++it) {
    product(p, kp);
    const double alpha = rz / p.dot(kp);
    mu += alpha * p;
    r -= alpha * kp;
    // r is each row's closure error in conductance (m²): every row closed to kClosureTolerance
    // of its area is as closed as F's rounding leaves it (a room's 21 products were 17).
    if (r.squaredNorm() < threshold || (r.cwiseAbs().array() <= kClosureTolerance * area.array()).all())
      return mu.allFinite();
    z = r.cwiseQuotient(d);
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  return false;
}

// The free pairs' sums per coupling block: each row's Σ ĝ and Σ v, and the off-diagonal
// entries. add() is the one place they are summed, so a correction that forms them while
// visiting the pairs for its own reasons (the in-place one, as it reads their variances)
// hands closureMultipliers the same bits it would form itself.
struct PairSums {
  /// A block's count on a cache line of its own (counted on all cores at once).
  struct alignas(64) Count {
    Eigen::Index value = 0;
  };
  std::vector<Eigen::VectorXd> rhs_part, diag_part;
  std::vector<Count> off_part;
  explicit PairSums(Eigen::Index n)
      : rhs_part(kCouplingBlocks, Eigen::VectorXd::Zero(n)), diag_part(kCouplingBlocks, Eigen::VectorXd::Zero(n)),
        off_part(kCouplingBlocks) {}
  void add(size_t block, const Pair& p) {
    Eigen::VectorXd &r = rhs_part[block], &d = diag_part[block];
    r[p.i] += p.g_hat;
    d[p.i] += p.var;
    if (p.i != p.j) {
      r[p.j] += p.g_hat;
      d[p.j] += p.var;
      off_part[block].value += 2;
    }
  }
};

// The Lagrange multipliers μ of the closure constraints: K μ = c − (row sums of the
// estimates), K = Σ v over each row's terms (diagonal) and v_ij off it. Pinned pairs are
// fixed at zero (their estimate leaves the right-hand side). free_pairs(b, B, fn(const Pair&))
// visits block b of B of the pairs not pinned; couplings(b, B, fn(i, j, v)) the same pairs
// off the diagonal, by the same blocks. The blocks' sums are formed on all cores, each apart,
// then added in block order (the same bits for any thread count; a pass over the 15.7 M pairs
// of a 6,144-node room was 0.38 s on one core, per round of pinning). `known`: the first
// round's sums, formed already (PairSums).
template <class FreePairs, class Couplings>
Eigen::VectorXd closureMultipliers(const FreePairs& free_pairs, const Couplings& couplings,
                                   const Eigen::VectorXd& free_rhs, const Eigen::VectorXd& free_variance,
                                   const Eigen::VectorXd& area, const PairSums* known = nullptr) {
  const Eigen::Index n = free_rhs.size();
  std::optional<PairSums> formed;
  if (!known) {
    formed.emplace(n);
    solver::parallelFor(kCouplingBlocks, [&](long long block) {
      free_pairs(static_cast<int>(block), kCouplingBlocks, [&](const Pair& p) { formed->add(size_t(block), p); });
    });
  }
  const PairSums& sums = known ? *known : *formed;
  const std::vector<Eigen::VectorXd>&rhs_part = sums.rhs_part, &diag_part = sums.diag_part;
  Eigen::VectorXd rhs = free_rhs, diag = free_variance;
  Eigen::Index off_diagonal = 0;
  for (size_t b = 0; b < rhs_part.size(); ++b) rhs -= rhs_part[b], diag += diag_part[b], off_diagonal += sums.off_part[b].value;
  for (Eigen::Index i = 0; i < n; ++i)
    if (!(diag[i] > 0)) diag[i] = 1.0;  // isolated rows: μ = 0
  Eigen::VectorXd mu = Eigen::VectorXd::Zero(n);
  // A dense pattern (every cell of a closed room sees the others): the factor fills in to n²
  // and costs n³/3; K is diagonally dominant (each diagonal holds its row's variances), so
  // Jacobi-preconditioned conjugate gradients converge in tens of products.
  if (off_diagonal + n > kDirectSolveEntries && conjugateGradients(couplings, diag, rhs, area, mu)) return mu;
  std::vector<Eigen::Triplet<double>> k;
  for (int b = 0; b < kCouplingBlocks; ++b)
    couplings(b, kCouplingBlocks, [&](int i, int j, double v) {
      k.emplace_back(i, j, v);
      k.emplace_back(j, i, v);
    });
  for (Eigen::Index i = 0; i < n; ++i) k.emplace_back(i, i, diag[i]);
  Eigen::SparseMatrix<double> km(n, n);
  km.setFromTriplets(k.begin(), k.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(km);
  if (ldlt.info() == Eigen::Success) mu = ldlt.solve(rhs);
  if (ldlt.info() != Eigen::Success || !mu.allFinite()) {
    // Singular (e.g. a bipartite network with every row fixed): least squares instead.
    Eigen::LeastSquaresConjugateGradient<Eigen::SparseMatrix<double>> lscg(km);
    mu = lscg.solve(rhs);
  }
  return mu;
}

// The space and blocked conductances, free per node with variances from their own errors.
struct NodeTerms {
  Eigen::VectorXd g_space, g_blocked, v_space, v_blocked;

  NodeTerms(const Eigen::VectorXd& area, const ViewFactorEstimate& est, const Eigen::VectorXd& rays)
      : g_space(area.cwiseProduct(est.space)), g_blocked(area.cwiseProduct(est.blocked)) {
    const Eigen::Index n = area.size();
    v_space.resize(n), v_blocked.resize(n);
    for (int i = 0; i < n; ++i) {
      const double floor_var = rayFloorVariance(area, rays, i);
      v_space[i] = est.space[i] > 0 ? std::max(std::pow(area[i] * est.space_error[i], 2), floor_var) : 0.0;
      v_blocked[i] = est.blocked[i] > 0 ? std::max(std::pow(area[i] * est.blocked_error[i], 2), floor_var) : 0.0;
    }
  }
  // A term driven below zero is pinned there (clamping it afterwards would leave the row's
  // closure to nothing: a closed enclosure's row summed over 1 by its quadrature error).
  bool pinNegative(const Eigen::VectorXd& mu) {
    bool changed = false;
    for (Eigen::Index i = 0; i < mu.size(); ++i)
      for (auto [g_term, v_term] : {std::pair{&g_space, &v_space}, std::pair{&g_blocked, &v_blocked}})
        if ((*v_term)[i] > 0 && (*g_term)[i] + (*v_term)[i] * mu[i] < 0) {
          (*g_term)[i] = (*v_term)[i] = 0.0;
          changed = true;
        }
    return changed;
  }
  void corrected(const Eigen::VectorXd& mu, const Eigen::VectorXd& area, ReciprocityCorrection& out) const {
    out.space = (g_space + v_space.cwiseProduct(mu)).cwiseMax(0.0).cwiseQuotient(area);
    out.blocked = (g_blocked + v_blocked.cwiseProduct(mu)).cwiseMax(0.0).cwiseQuotient(area);
  }
};

// The multipliers with entries driven negative pinned to zero and solved again (at most 20
// rounds); pin_pairs(μ) pins the pairs' and says whether any was.
template <class FreePairs, class Couplings, class PinPairs>
Eigen::VectorXd pinnedMultipliers(const Eigen::VectorXd& area, NodeTerms& terms, const FreePairs& free_pairs,
                                  const Couplings& couplings, const PinPairs& pin_pairs,
                                  const PairSums* first_sums = nullptr) {
  Eigen::VectorXd mu = Eigen::VectorXd::Zero(area.size());
  for (int pass = 0; pass < 20; ++pass) {
    mu = closureMultipliers(free_pairs, couplings, area - terms.g_space - terms.g_blocked,
                            terms.v_space + terms.v_blocked, area, pass == 0 ? first_sums : nullptr);
    const bool pairs_pinned = pin_pairs(mu);
    if (!terms.pinNegative(mu) && !pairs_pinned) break;
  }
  return mu;
}

// One corrected entry's move from its estimate, into the report: the largest move (the first
// in row order among equal ones) and the most standard errors.
inline void noteChange(int i, int j, double after, double before, double sigma, double rays_i, ReciprocityCorrection& out) {
  const double change = std::abs(after - before);
  // A cast row's σ comes from its own hits: an entry that drew no hit says σ = 0 whatever
  // its size, one that drew one hit σ = its value. Measured against the binomial σ at the
  // larger of the two values (what N rays scatter an entry of that size by), floored at
  // one ray. An integrated row (N = 1 / tolerance) is measured generously this way, but
  // its entries barely move: where it and a cast row disagree, the cast entry moves.
  const double n_rays = std::max(1.0, rays_i), p = std::min(1.0, std::max(after, before));
  const bool earlier = out.worst_from < 0 || i < out.worst_from || (i == out.worst_from && j < out.worst_to);
  if (change > out.max_change || (change == out.max_change && change > 0 && earlier)) {
    out.max_change = change;
    out.worst_from = i;
    out.worst_to = j;
  }
  // s is at least max(σ, 1/N): a move under the most standard errors so far by that bound
  // (with a margin past rounding) cannot raise it, and its square root and divisions are
  // skipped (most entries of a correction barely move: 0.1 s of the 6,144-node room's
  // overwrite). The same maximum as always computing it.
  const double s_floor = std::max(sigma, 1.0 / n_rays);
  if (change <= out.max_change_sigma * s_floor * (1.0 - 1e-12)) return;
  const double s = std::max({sigma, std::sqrt(p * (1.0 - p) / n_rays), 1.0 / n_rays});
  out.max_change_sigma = std::max(out.max_change_sigma, change / s);
}

// A part's report (noteChange's, over some of the entries) into `out`: the larger move, the
// first in row order among equal ones, as if every entry had been noted into `out` itself.
inline void mergeChange(const ReciprocityCorrection& part, ReciprocityCorrection& out) {
  const bool earlier = out.worst_from < 0 || part.worst_from < out.worst_from ||
                       (part.worst_from == out.worst_from && part.worst_to < out.worst_to);
  if (part.worst_from >= 0 && (part.max_change > out.max_change || (part.max_change == out.max_change && earlier))) {
    out.max_change = part.max_change;
    out.worst_from = part.worst_from;
    out.worst_to = part.worst_to;
  }
  out.max_change_sigma = std::max(out.max_change_sigma, part.max_change_sigma);
}

inline double largestClosureError(const ReciprocityCorrection& out) {
  double worst = 0.0;
  for (Eigen::Index i = 0; i < out.view_factors.outerSize(); ++i)
    worst = std::max(worst, std::abs(out.view_factors.row(i).sum() + out.space[i] + out.blocked[i] - 1.0));
  return worst;
}

}  // namespace radnet::geometry::detail
