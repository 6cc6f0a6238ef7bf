#include "geometry/reciprocity.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <map>

namespace radnet::geometry {
namespace {

struct Pair {
  int i, j;      // i <= j
  double g_hat;  // combined estimate of g_ij, m²
  double var;    // its variance, m⁴
  bool pinned = false;
};

using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// One ray's worth of variance, (A_i / N_i)², m⁴: the floor under every estimate of row i.
double rayFloorVariance(const Eigen::VectorXd& area, const Eigen::VectorXd& rays, int i) {
  return std::pow(area[i] / std::max(1.0, rays[i]), 2);
}

// Both directional estimates of each pair, x = A_i F_ij with variance (A_i σ_ij)² floored
// at one ray's worth, combined by inverse variance.
std::vector<Pair> combinedPairs(const Eigen::VectorXd& area, const ViewFactorEstimate& est,
                                const Eigen::VectorXd& rays) {
  const int n = static_cast<int>(area.size());
  std::map<std::pair<int, int>, std::pair<double, double>> sums;  // (i,j) → (Σ x/v, Σ 1/v)
  for (int i = 0; i < n; ++i) {
    const double floor_var = rayFloorVariance(area, rays, i);
    // F and σ share one sparsity pattern (both come from the same tallies): walk them together.
    RowSparse::InnerIterator es(est.standard_error, i);
    for (RowSparse::InnerIterator it(est.view_factors, i); it; ++it) {
      const int j = static_cast<int>(it.col());
      while (es && es.col() < j) ++es;
      const double s = (es && es.col() == j) ? es.value() : 0.0;
      const double v = std::max(std::pow(area[i] * s, 2), floor_var);
      auto& acc = sums[{std::min(i, j), std::max(i, j)}];
      acc.first += area[i] * it.value() / v;
      acc.second += 1.0 / v;
    }
  }
  // A pair seen from one side only: the other side saw zero rays, an estimate of 0 with
  // one ray's variance.
  std::vector<Pair> pairs;
  for (const auto& [key, acc] : sums) {
    auto [i, j] = key;
    double num = acc.first, den = acc.second;
    if (i != j) {
      const bool has_ij = est.view_factors.coeff(i, j) != 0.0, has_ji = est.view_factors.coeff(j, i) != 0.0;
      if (!has_ij) den += 1.0 / rayFloorVariance(area, rays, i);
      if (!has_ji) den += 1.0 / rayFloorVariance(area, rays, j);
    }
    pairs.push_back({i, j, num / den, 1.0 / den});
  }
  return pairs;
}

// The Lagrange multipliers μ of the closure constraints: K μ = c − (row sums of the
// estimates), K = Σ v over each row's terms (diagonal) and v_ij off it. Pinned pairs are
// fixed at zero.
Eigen::VectorXd closureMultipliers(const std::vector<Pair>& pairs, const Eigen::VectorXd& free_rhs,
                                   const Eigen::VectorXd& free_variance) {
  const Eigen::Index n = free_rhs.size();
  Eigen::VectorXd rhs = free_rhs;
  std::vector<Eigen::Triplet<double>> k;
  Eigen::VectorXd diag = free_variance;
  for (const Pair& p : pairs) {
    rhs[p.i] -= p.g_hat;
    if (p.i != p.j) rhs[p.j] -= p.g_hat;
    if (p.pinned) continue;
    if (p.i == p.j) {
      diag[p.i] += p.var;
    } else {
      diag[p.i] += p.var;
      diag[p.j] += p.var;
      k.emplace_back(p.i, p.j, p.var);
      k.emplace_back(p.j, p.i, p.var);
    }
  }
  // Pinned entries are fixed at zero: their estimate leaves the right-hand side.
  for (const Pair& p : pairs)
    if (p.pinned) {
      rhs[p.i] += p.g_hat;
      if (p.i != p.j) rhs[p.j] += p.g_hat;
    }
  for (Eigen::Index i = 0; i < n; ++i) k.emplace_back(i, i, diag[i] > 0 ? diag[i] : 1.0);  // isolated rows: μ = 0
  Eigen::SparseMatrix<double> km(n, n);
  km.setFromTriplets(k.begin(), k.end());
  Eigen::VectorXd mu = Eigen::VectorXd::Zero(n);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(km);
  if (ldlt.info() == Eigen::Success) mu = ldlt.solve(rhs);
  if (ldlt.info() != Eigen::Success || !mu.allFinite()) {
    // Singular (e.g. a bipartite network with every row fixed): least squares instead.
    Eigen::LeastSquaresConjugateGradient<Eigen::SparseMatrix<double>> lscg(km);
    mu = lscg.solve(rhs);
  }
  return mu;
}

// How far each entry moved, in view-factor units and in standard errors, and the closure.
void reportChanges(const ViewFactorEstimate& est, const Eigen::VectorXd& rays, ReciprocityCorrection& out) {
  const int n = static_cast<int>(rays.size());
  for (int i = 0; i < n; ++i) {
    for (RowSparse::InnerIterator it(out.view_factors, i); it; ++it) {
      const int j = static_cast<int>(it.col());
      const double change = std::abs(it.value() - est.view_factors.coeff(i, j));
      const double s = std::max(est.standard_error.coeff(i, j), 1.0 / std::max(1.0, rays[i]));
      if (change > out.max_change) {
        out.max_change = change;
        out.worst_from = i;
        out.worst_to = j;
      }
      out.max_change_sigma = std::max(out.max_change_sigma, change / s);
    }
    const double closure = out.view_factors.row(i).sum() + out.space[i] + out.blocked[i] - 1.0;
    out.max_closure_error = std::max(out.max_closure_error, std::abs(closure));
  }
}

}  // namespace

ReciprocityCorrection enforceReciprocity(const Eigen::VectorXd& area, const ViewFactorEstimate& est,
                                         const Eigen::VectorXd& rays) {
  const int n = static_cast<int>(area.size());
  std::vector<Pair> pairs = combinedPairs(area, est, rays);
  // Space and blocked conductances: free per node, variance from their own errors.
  Eigen::VectorXd g_space = area.cwiseProduct(est.space), g_blocked = area.cwiseProduct(est.blocked);
  Eigen::VectorXd v_space(n), v_blocked(n);
  for (int i = 0; i < n; ++i) {
    const double floor_var = rayFloorVariance(area, rays, i);
    v_space[i] = est.space[i] > 0 ? std::max(std::pow(area[i] * est.space_error[i], 2), floor_var) : 0.0;
    v_blocked[i] = est.blocked[i] > 0 ? std::max(std::pow(area[i] * est.blocked_error[i], 2), floor_var) : 0.0;
  }
  // Entries driven negative are pinned to zero and the multipliers solved again.
  std::vector<double> g(pairs.size());
  Eigen::VectorXd mu = Eigen::VectorXd::Zero(n);
  for (int pass = 0; pass < 20; ++pass) {
    mu = closureMultipliers(pairs, area - g_space - g_blocked, v_space + v_blocked);
    bool changed = false;
    for (size_t q = 0; q < pairs.size(); ++q) {
      Pair& p = pairs[q];
      if (p.pinned) {
        g[q] = 0.0;
        continue;
      }
      g[q] = p.g_hat + p.var * (p.i == p.j ? mu[p.i] : mu[p.i] + mu[p.j]);
      if (g[q] < 0) {
        p.pinned = true;
        changed = true;
      }
    }
    if (!changed) break;
  }
  ReciprocityCorrection out;
  out.space = (g_space + v_space.cwiseProduct(mu)).cwiseMax(0.0).cwiseQuotient(area);
  out.blocked = (g_blocked + v_blocked.cwiseProduct(mu)).cwiseMax(0.0).cwiseQuotient(area);
  std::vector<Eigen::Triplet<double>> t;
  for (size_t q = 0; q < pairs.size(); ++q) {
    const Pair& p = pairs[q];
    if (g[q] <= 0) continue;
    t.emplace_back(p.i, p.j, g[q] / area[p.i]);
    if (p.i != p.j) t.emplace_back(p.j, p.i, g[q] / area[p.j]);
  }
  out.view_factors.resize(n, n);
  out.view_factors.setFromTriplets(t.begin(), t.end());
  reportChanges(est, rays, out);
  return out;
}

}  // namespace radnet::geometry
