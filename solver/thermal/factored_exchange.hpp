#pragma once
// GR of a thermal network held as the radiative solver factors it on a sparse network
// (solver/radiative/exchange.hpp): GR = D + W K Wᵀ, the direct exchange D sparse and exact,
// the reflected part in rank k. The thermal solver applies it as products, O(nnz(D) + n k)
// a product instead of n², so temperatures of a 100,000-node network never form GR
// (docs/solver.md, "Temperatures on a factored GR").
#include "solver/parallel.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCore>

namespace radnet::solver {

/// Below this many thermal nodes a factored GR is formed n × n for the thermal solver: the
/// dense LU is then as fast or faster (docs/factored-thermal-benchmark.md: a one-orbit
/// transient at 1,024 nodes 0.56 s dense against 0.74 s factored; at 2,025 nodes 3.4 s against
/// 1.6 s; steady states 1.3× and 2.1× faster factored).
inline constexpr long kFactoredThermalMinNodes = 1500;

struct FactoredExchange {
  Eigen::SparseMatrix<double, Eigen::RowMajor> direct;  ///< D (n×n), symmetric, ≥ 0, m²: the direct exchange and couplings given
  Eigen::MatrixXd basis;  ///< W (n×k), –: zero rows for nodes without geometry
  Eigen::MatrixXd core;   ///< K (k×k), symmetric, m²

  Eigen::Index size() const { return direct.rows(); }
  Eigen::Index rank() const { return basis.cols(); }
  /// GR x (n), m² × [x].
  Eigen::VectorXd times(const Eigen::VectorXd& x) const;
  /// Σ_j GR_ij (n), m².
  Eigen::VectorXd rowSum() const;
  /// GR_ii (n), m².
  Eigen::VectorXd diagonal() const;
  /// GR (n×n), m²: only where n² fits (small networks, the uncertainty's dense Jacobian).
  Eigen::MatrixXd dense() const;
  /// Σ_j GR_ij |x_j − x_i| (n): exact over D; over the reflected part R = W K Wᵀ (entries ≥ 0
  /// up to the rank's truncation) bounded by Cauchy–Schwarz,
  ///   Σ_j R_ij |x_j − x_i| ≤ √(Σ_j R_ij) · √(Σ_j R_ij (x_j − x_i)²),
  /// whose second sum is (R x²)_i − 2 x_i (R x)_i + x_i² (R 1)_i: three rank-k products. The
  /// bound is exact when every |x_j − x_i| is equal, and 0 where they all vanish (an
  /// isothermal enclosure), as the sum is.
  Eigen::VectorXd spread(const Eigen::VectorXd& x) const;
  /// R X for the reflected part alone (n×m), m² × [X].
  Eigen::MatrixXd reflectedTimes(const Eigen::Ref<const Eigen::MatrixXd>& x) const;
};

}  // namespace radnet::solver
