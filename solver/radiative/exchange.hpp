#pragma once
// The Oppenheim network of the IR band (docs/design.md, "The network"): emissive node voltages E_b = σT⁴,
// surface reflectance ρ = 1 − ε, radiative exchange factors GR (ESATAN's GR).
// Written without the textbook surface resistance (1 − ε)/(ε A), which breaks at ε = 1.
#include "solver/radiative/low_rank_solver.hpp"
#include "solver/radiative/network.hpp"

#include <Eigen/Dense>

#include <string>
#include <vector>

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

/// GR for emissivities that differ from a nominal set only on a few nodes U (those whose ε
/// follows temperature), by a rank-|U| update of the nominal GR instead of a new core:
/// with M = G (I − S G)⁻¹ (so GR = E M E) and S' = S + U D Uᵀ, D = diag(−Δε_u / A_u),
/// Woodbury gives M' = M + M_{:U} D (I − M_UU D)⁻¹ M_{U:}, and M_{:U} = E⁻¹ GR_{:U} / ε_U from
/// the nominal GR. So GR' = R GR R + W K Wᵀ, R = diag(ε'/ε), W = R GR_{:U} diag(1/ε_U),
/// K = D (I − M_UU D)⁻¹: O(n² |U|) a call, the n×n nominal GR kept. Exact for the nominal
/// GR's G (to round-off); nodes outside U keep their ε.
class EmissivityUpdate {
 public:
  /// @param nominal    GR at `emissivity` (n×n, symmetric), m²
  /// @param emissivity the nominal ε (n), > 0 on `nodes`
  /// @param area_m2    A (n)
  /// @param nodes      U: the nodes whose ε may change
  EmissivityUpdate(Eigen::MatrixXd nominal, Eigen::VectorXd emissivity, Eigen::VectorXd area_m2, std::vector<int> nodes);
  /// GR and GR_space at `emissivity` (n), equal to the nominal ε outside U.
  ExchangeFactors operator()(const Eigen::VectorXd& emissivity) const;

 private:
  Eigen::MatrixXd gr_;   ///< nominal GR, m²
  Eigen::VectorXd emissivity_, area_;
  std::vector<int> nodes_;
  Eigen::MatrixXd m_uu_;  ///< M_UU = GR_UU / (ε_u ε_v), m²
};

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
