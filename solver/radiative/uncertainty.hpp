#pragma once
// First-order propagation of independent errors to absorbed power and radiative exchange
// (docs/solver.md, "Uncertainty"; on to temperatures in solver/thermal/uncertainty.hpp). Sources: the view factors' standard errors σ_F (n×n),
// the external irradiances' sampling errors σ_E (n×P), and the rank-k truncation.
//
// One band, Q_i = α_i (A_i E_i + (A H)_i), A H = G M, M = (I − S G)⁻¹ ρ∘E. To first order
//   δ(A H) = (I − G S)⁻¹ δG M + B ρ δE,   (I − G S)⁻¹ = I + B S,   B = V C Vᵀ
// (the push-through core of the low-rank solver, exact for G'_k). With the entries of δG
// and δE independent, y = δG M has var y_i = A_i² Σ_j σ_F,ij² M_j², and
//   var (A H)_i = (1 + 2 B_ii s_i) var y_i + Σ_k B_ik² (s_k² var y_k + ρ_k² var E_k),
//   var Q_i = α_i² [A_i² var E_i + var (A H)_i + 2 A_i B_ii ρ_i var E_i].
// B∘B is applied by row blocks: O(n² (k + P)) time and O(n · block) memory, never n×n.
// Reciprocity makes δG_ij = δG_ji, a correlation this neglects; the test against
// high-ray references (tests/test_uncertainty.cpp) checks the coverage that results.
#include "solver/radiative/low_rank_solver.hpp"
#include "solver/radiative/network.hpp"

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include <algorithm>

namespace radnet::solver {

/// σ_F and other mostly-zero node × node matrices, by rows (F of a satellite is a few % non-zero).
using SparseRowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

/// The largest stored entry of a matrix of errors (≥ 0), 0 when it stores none.
inline double largestEntry(const SparseRowMatrix& m) {
  double largest = 0.0;
  for (Eigen::Index k = 0; k < m.outerSize(); ++k)
    for (SparseRowMatrix::InnerIterator it(m, k); it; ++it) largest = std::max(largest, it.value());
  return largest;
}

/// The largest entry of each of n rows (zeros for an empty matrix).
inline Eigen::VectorXd rowLargestEntries(const Eigen::Ref<const SparseRowMatrix>& m, Eigen::Index n) {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(n);
  for (Eigen::Index k = 0; k < m.outerSize() && k < n; ++k)
    for (Eigen::Ref<const SparseRowMatrix>::InnerIterator it(m, k); it; ++it) out[k] = std::max(out[k], it.value());
  return out;
}

/// The variance of one band's absorbed power per node and column, by source, W².
struct AbsorbedVariance {
  Eigen::MatrixXd view_factors;  ///< from σ_F
  Eigen::MatrixXd loads;         ///< from σ_E
};

/// @param band            the band's low-rank solver (its core C and the eigenvectors V)
/// @param view_factor_stderr σ_F (n×n), –; empty: no view-factor term
/// @param exitance        M (n×P) of the solution, W/m²
/// @param irradiance_stderr σ_E (n×P), W/m²
AbsorbedVariance absorbedVariance(const Network& net, const LowRankBandSolver& band,
                                  const SparseRowMatrix& view_factor_stderr, const Eigen::MatrixXd& exitance,
                                  const Eigen::MatrixXd& irradiance_stderr);

/// The truncation error of a rank-k answer, α ∘ |G M − A H| (n×P), W, with A H = G'_k M the
/// low-rank answer's: what refinement with the full G would change, to first order. Zero
/// when the band was refined.
/// @param full_flux G M with the full G (BandSolution::full_flux), W; @param irradiance H, W/m²
Eigen::MatrixXd truncationError(const Network& net, const LowRankBandSolver& band, const Eigen::MatrixXd& full_flux,
                                const Eigen::MatrixXd& irradiance, bool refined);

/// The variance of each node's radiative exchange from the view factors' errors, W² (n×P):
/// Σ_j (ε_i ε_j A_i σ_F,ij)² σ² (T_j⁴ − T_i⁴)² + (ε_i A_i σ_lost,i)² σ² (T_i⁴ − T_space⁴)²,
/// the first-order change of GR_ij = ε_i ε_j A_i F_ij + (reflections) by its direct term
/// (exact for black surfaces, low for shiny ones whose exchange runs mostly through
/// reflections), and of GR to space through F_space + F_blocked.
/// @param lost_stderr σ of F_space + F_blocked per node, –
/// @param temperature (n×P) K of the radiative nodes
Eigen::MatrixXd exchangeHeatVariance(const SparseRowMatrix& view_factor_stderr, const Eigen::VectorXd& lost_stderr,
                                     const Eigen::VectorXd& emissivity, const Eigen::VectorXd& area,
                                     const Eigen::MatrixXd& temperature, double space_temperature_k);

}  // namespace radnet::solver
