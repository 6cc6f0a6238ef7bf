#pragma once
// The Oppenheim network of the IR band (docs/design.md, "The network"): emissive node voltages E_b = σT⁴,
// surface reflectance ρ = 1 − ε, radiative exchange factors GR (ESATAN's GR).
// Written without the textbook surface resistance (1 − ε)/(ε A), which breaks at ε = 1.
#include "solver/radiative/low_rank_solver.hpp"
#include "solver/radiative/network.hpp"

#include <Eigen/Dense>

#include <string>

namespace radnet::solver {

/// Radiative exchange factors of an IR band.
struct ExchangeFactors {
  Eigen::MatrixXd gr;        ///< GR (n×n), symmetric, m²: Q_ij = σ GR_ij (T_i⁴ − T_j⁴)
  Eigen::VectorXd gr_space;  ///< GR_i,space = ε_i A_i − Σ_j GR_ij, m²
  double asymmetry = 0.0;    ///< max |GR_ij − GR_ji| / max|GR| before symmetrising (round-off), –
  std::string method;        ///< "dense LU" or "direct + low-rank reflected (k = <rank>)"
  bool from_pairs = false;   ///< the reflections come from the rank-k pairs (not exact)
  Status status = Status::Converged;
  std::string message;
};

/// Exact GR = E G (I − S G)⁻¹ E, E = diag(ε), S = diag((1 − ε)/A), by one dense LU.
/// @param emissivity ε_i in [0, 1], –
ExchangeFactors exchangeFactorsDense(const Network& net, const Eigen::VectorXd& emissivity);

/// GR with the direct exchange exact and the reflected part in rank k: E G E + E V (C − Λ) Vᵀ E
/// (O(n² k) to form the n×n result).
/// @param ir_band solver built with reflectance 1 − ε
ExchangeFactors exchangeFactorsLowRank(const Network& net, const LowRankBandSolver& ir_band,
                                       const Eigen::VectorXd& emissivity);

/// Net radiative power gained by each node in the IR band, W (n×P):
/// Q_i = ε_i A_i (H_i + E_pIR,i − σT_i⁴), with M = ε∘σT⁴ + ρ∘E_pIR + S G M and H = A⁻¹ G M.
/// @param temperature_k          T (n×P), K, finite and ≥ 0
/// @param external_irradiance    E_pIR (n×P), W/m², e.g. planet IR; may be empty (zero)
/// @param refine_tolerance       as LowRankBandSolver::solve
BandSolution irNetPower(const Network& net, const LowRankBandSolver& ir_band, const Eigen::VectorXd& emissivity,
                        const Eigen::Ref<const Eigen::MatrixXd>& temperature_k,
                        const Eigen::Ref<const Eigen::MatrixXd>& external_irradiance, double refine_tolerance,
                        Eigen::MatrixXd& net_power_w);

}  // namespace radnet::solver
