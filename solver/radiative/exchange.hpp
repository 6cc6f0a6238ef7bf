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

/// Radiative exchange factors of an IR band, dense or factored. Factored (the low-rank
/// method on a sparse network): GR = D + W K Wᵀ with the direct exchange D = E G E sparse
/// (exact, nnz(G) entries) and the reflected part from the rank-k pairs, W = E V (n×k),
/// K = C − Λ (k×k): O(nnz + n k) memory instead of n², and n² only where a consumer asks
/// for the dense matrix (the thermal solver, a design case's ε update, an output below
/// kDenseOutputMaxNodes).
struct ExchangeFactors {
  Eigen::MatrixXd gr;        ///< GR (n×n), symmetric, m²: Q_ij = σ GR_ij (T_i⁴ − T_j⁴); empty when factored
  Eigen::VectorXd gr_space;  ///< GR_i,space = ε_i A_i − Σ_j GR_ij, m²
  /// The factors (set by exchangeFactorsLowRank, dense or not; `direct` only when factored).
  Eigen::SparseMatrix<double, Eigen::RowMajor> direct;  ///< D = E G E (n×n, sparse), m²
  Eigen::MatrixXd basis;         ///< W = E V (n×k), –
  Eigen::MatrixXd core;          ///< K = C − Λ (k×k), symmetric, m²
  /// `direct`'s rows shared out as the network's (RowShare): the held rows only; entry, rows
  /// and apply are then collectives (every process asks the same).
  RowShare share;
  double asymmetry = 0.0;    ///< max |GR_ij − GR_ji| / max|GR| before symmetrising (round-off), –
  std::string method;        ///< "dense LU" or "direct + low-rank reflected (k = <rank>)"
  bool from_pairs = false;   ///< the reflections come from the rank-k pairs (not exact)
  Status status = Status::Converged;
  std::string message;

  /// n, the number of nodes.
  Eigen::Index size() const { return gr.size() ? gr.rows() : direct.rows(); }
  /// True when GR is held as the factors only (no n × n matrix in memory).
  bool factored() const { return gr.size() == 0 && direct.rows() > 0; }
  /// GR_ij, m² (O(k) when factored).
  double entry(Eigen::Index i, Eigen::Index j) const;
  /// GR (n×n) into `out` (n×n), m²: a copy, or formed from the factors (O(n² k)).
  void denseInto(Eigen::Ref<Eigen::MatrixXd> out) const;
  /// GR (n×n), m², as denseInto.
  Eigen::MatrixXd dense() const;
  /// Rows first … first + count − 1 of GR (count × n), m², without forming the rest.
  Eigen::MatrixXd rows(Eigen::Index first, Eigen::Index count) const;
  /// Y = GR X, m² (X: n×m), without forming GR.
  Eigen::MatrixXd apply(const Eigen::Ref<const Eigen::MatrixXd>& x) const;
};

/// The smallest reflectance ρ = 1 − ε of every node for which exchangeFactorsDense takes the
/// symmetric Cholesky form (n³ flops) instead of the LU (about 4.7 n³).
inline constexpr double kSymmetricExchangeMinReflectance = 1e-3;

/// Exact GR = E G (I − S G)⁻¹ E, E = diag(ε), S = diag((1 − ε)/A): by Cholesky of the symmetric
/// S⁻¹ − G when every ρ ≥ kSymmetricExchangeMinReflectance, else by one dense LU (docs/solver.md).
/// @param emissivity ε_i in [0, 1], –
ExchangeFactors exchangeFactorsDense(const Network& net, const Eigen::VectorXd& emissivity);

/// GR with the direct exchange exact and the reflected part in rank k: E G E + E V (C − Λ) Vᵀ E.
/// Factored on a sparse network (O(nnz + n k)); on a dense one also formed densely (O(n² k)).
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
