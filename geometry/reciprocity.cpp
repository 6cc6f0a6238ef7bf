#include "geometry/reciprocity.hpp"

#include <Eigen/SparseCholesky>
#include <Eigen/IterativeLinearSolvers>

#include <algorithm>
#include <cmath>
#include <map>

namespace radnet::geometry {
namespace {

struct Pair {
  int i, j;        // i <= j
  double g_hat;    // combined estimate of g_ij, m²
  double var;      // its variance, m⁴
  bool pinned = false;
};

}  // namespace

ReciprocityCorrection enforceReciprocity(const Eigen::VectorXd& area,
                                         const Eigen::SparseMatrix<double, Eigen::RowMajor>& f,
                                         const Eigen::SparseMatrix<double, Eigen::RowMajor>& sigma,
                                         const Eigen::VectorXd& space, const Eigen::VectorXd& space_sigma,
                                         const Eigen::VectorXd& blocked, const Eigen::VectorXd& blocked_sigma,
                                         const Eigen::VectorXd& rays) {
  const int n = static_cast<int>(area.size());
  // Both directional estimates of each pair, x = A_i F_ij with variance (A_i σ_ij)² floored
  // at one ray's worth (A_i / N_i)².
  std::map<std::pair<int, int>, std::pair<double, double>> sums;  // (i,j) → (Σ x/v, Σ 1/v)
  for (int i = 0; i < n; ++i) {
    const double floor_var = std::pow(area[i] / std::max(1.0, rays[i]), 2);
    // F and σ share one sparsity pattern (both come from the same tallies): walk them together.
    Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator es(sigma, i);
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(f, i); it; ++it) {
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
      const bool has_ij = f.coeff(i, j) != 0.0, has_ji = f.coeff(j, i) != 0.0;
      if (!has_ij) den += 1.0 / std::pow(area[i] / std::max(1.0, rays[i]), 2);
      if (!has_ji) den += 1.0 / std::pow(area[j] / std::max(1.0, rays[j]), 2);
    }
    pairs.push_back({i, j, num / den, 1.0 / den});
  }
  // Space and blocked conductances: free per node, variance from their own errors.
  Eigen::VectorXd g_space = area.cwiseProduct(space), g_blocked = area.cwiseProduct(blocked);
  Eigen::VectorXd v_space(n), v_blocked(n);
  for (int i = 0; i < n; ++i) {
    const double floor_var = std::pow(area[i] / std::max(1.0, rays[i]), 2);
    v_space[i] = space[i] > 0 ? std::max(std::pow(area[i] * space_sigma[i], 2), floor_var) : 0.0;
    v_blocked[i] = blocked[i] > 0 ? std::max(std::pow(area[i] * blocked_sigma[i], 2), floor_var) : 0.0;
  }

  std::vector<double> g(pairs.size());
  Eigen::VectorXd mu = Eigen::VectorXd::Zero(n);
  for (int pass = 0; pass < 20; ++pass) {
    // K μ = c − (row sums of the estimates), K = Σ v over each row's terms (diagonal) and v_ij off it.
    Eigen::VectorXd rhs = area - g_space - g_blocked;
    std::vector<Eigen::Triplet<double>> k;
    Eigen::VectorXd diag = v_space + v_blocked;
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
    for (int i = 0; i < n; ++i) k.emplace_back(i, i, diag[i] > 0 ? diag[i] : 1.0);  // isolated rows: μ = 0
    Eigen::SparseMatrix<double> km(n, n);
    km.setFromTriplets(k.begin(), k.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(km);
    if (ldlt.info() == Eigen::Success) mu = ldlt.solve(rhs);
    if (ldlt.info() != Eigen::Success || !mu.allFinite()) {
      // Singular (e.g. a bipartite network with every row fixed): least squares instead.
      Eigen::LeastSquaresConjugateGradient<Eigen::SparseMatrix<double>> lscg(km);
      mu = lscg.solve(rhs);
    }
    bool changed = false;
    for (size_t q = 0; q < pairs.size(); ++q) {
      Pair& p = pairs[q];
      if (p.pinned) { g[q] = 0.0; continue; }
      g[q] = p.g_hat + p.var * (p.i == p.j ? mu[p.i] : mu[p.i] + mu[p.j]);
      if (g[q] < 0) { p.pinned = true; changed = true; }
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
  // Report how far each entry moved, in view-factor units and in standard errors.
  for (int i = 0; i < n; ++i) {
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(out.view_factors, i); it; ++it) {
      const int j = static_cast<int>(it.col());
      const double change = std::abs(it.value() - f.coeff(i, j));
      const double s = std::max(sigma.coeff(i, j), 1.0 / std::max(1.0, rays[i]));
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
  return out;
}

}  // namespace radnet::geometry
