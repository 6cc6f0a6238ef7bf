#pragma once
// Production band solve: exact for the rank-k conductance G'_k = V Λ Vᵀ by the
// push-through identity (docs/design.md, "The network")
//     (I − S V Λ Vᵀ)⁻¹ = I + S V C Vᵀ,   C = Λ (I − Vᵀ S V Λ)⁻¹,
// so a reflectance set costs O(n k²) once, and each right-hand side O(n k). It replaces
// the paper's eigenvector iteration (Ashdown 2001, eqs. 35–37), which converges to the
// same G'_k solution only when the spectral radius of S G'_k is below 1.
#include "solver/radiative/eigenpairs.hpp"
#include "solver/radiative/network.hpp"
#include "solver/status.hpp"

#include <Eigen/Dense>

#include <string>

namespace radnet::solver {

/// Relative residual of the radiosity equation (eq. 3/20) per column with the FULL G:
/// ‖M_o − (I − S G) M‖₂ / ‖M_o‖₂ (absolute where M_o = 0).
/// @param gm  G M (n×P), W; passed in so that dense and sparse G share this code
Eigen::VectorXd relativeResidual(const Eigen::Ref<const Eigen::MatrixXd>& gm, const Eigen::VectorXd& area,
                                 const Eigen::VectorXd& reflectance, const Eigen::Ref<const Eigen::MatrixXd>& mo,
                                 const Eigen::Ref<const Eigen::MatrixXd>& m);

/// Result of a band solve for P right-hand sides (columns).
struct BandSolution {
  Eigen::MatrixXd exitance;    ///< M (n×P), W/m²
  Eigen::MatrixXd irradiance;  ///< H = A⁻¹ G M (n×P), W/m²; with G'_k when not refined
  Eigen::VectorXd residual;    ///< per column, relative, with the full G (see relativeResidual)
  Eigen::MatrixXd full_flux;   ///< G M with the full G (n×P), W: the residual's product, kept for reuse
  double max_residual = 0.0;
  int refine_iterations = 0;  ///< preconditioned CG iterations (0: low-rank answer kept)
  bool refined = false;       ///< brought to the tolerance (by CG or by the direct solve)
  /// How the answer was reached: "low-rank core" (kept), "low-rank core + CG", or "dense LU"
  /// (policy::bandSolveCost predicted it cheaper than CG to the tolerance).
  std::string method = "low-rank core";
  double predicted_refine_s = 0.0;  ///< the policy's prediction for CG to the tolerance, s (0: not asked)
  double predicted_direct_s = 0.0;  ///< ... and for dense LU of I − S G, s
  Status status = Status::Converged;
  std::string message;
};

/// How a band solve reaches its tolerance when the rank-k answer misses it.
enum class Refinement {
  Cheapest,          ///< CG or dense LU, by the policy's predicted cost (policy::bandSolveCost)
  ConjugateGradient  ///< always CG (benchmarks and tests of the CG path)
};

/// One band (solar: ρ = 1 − α; IR: ρ = 1 − ε) of one network, built on shared eigenpairs.
class LowRankBandSolver {
 public:
  /// @param reflectance ρ_i in [0, 1], –
  /// @throws NetworkError on a bad reflectance vector; a singular core is a status()
  LowRankBandSolver(const Network& net, const EigenPairs& pairs, Eigen::VectorXd reflectance);

  Status status() const { return status_; }
  const std::string& message() const { return message_; }
  int rank() const { return static_cast<int>(values_.size()); }
  const Eigen::VectorXd& reflectance() const { return rho_; }

  /// C = Λ (I − Vᵀ S V Λ)⁻¹ (k×k, symmetric), m².
  const Eigen::MatrixXd& core() const { return core_; }
  /// V (n×k), the eigenvectors the core is built on, –.
  const Eigen::MatrixXd& vectors() const { return vectors_; }
  /// Λ (k), the eigenvalues the core is built on, m².
  const Eigen::VectorXd& values() const { return values_; }

  /// G'(I − S G')⁻¹ X = V C Vᵀ X for a block X (n×P): the interreflected flux A H.
  Eigen::MatrixXd applyCore(const Eigen::Ref<const Eigen::MatrixXd>& x) const;

  /// Solves M = M_o + S G M for every column of M_o (n×P, W/m²).
  /// @param refine_tolerance  0: keep the exact-for-G'_k answer and report its residual;
  ///        > 0: refine with the full G (preconditioned CG, see docs/solver.md) until every
  ///        column's relative residual is at most this
  BandSolution solve(const Eigen::Ref<const Eigen::MatrixXd>& initial_exitance, double refine_tolerance = 0.0,
                     int max_refine_iterations = 500, Refinement how = Refinement::Cheapest) const;

 private:
  void refine(const Eigen::Ref<const Eigen::MatrixXd>& mo, BandSolution& sol, double tol, int max_iter) const;
  bool solveDirect(const Eigen::Ref<const Eigen::MatrixXd>& mo, BandSolution& sol) const;
  /// `b` empty: start from `start_residual` (b − K z for the z given) instead of forming it.
  int pcgRun(const Eigen::MatrixXd& b, const Eigen::MatrixXd& start_residual, Eigen::MatrixXd& z,
             const Eigen::VectorXd& scale, double tol, int max_iter, bool& low_rank_pc, bool& broke_down) const;
  Eigen::MatrixXd applyPreconditioner(const Eigen::Ref<const Eigen::MatrixXd>& r, bool low_rank) const;

  const Network& net_;
  Eigen::VectorXd rho_;
  Eigen::VectorXd sqrt_rho_;
  Eigen::VectorXd values_;
  Eigen::MatrixXd vectors_;
  Eigen::MatrixXd core_;
  Status status_ = Status::Converged;
  std::string message_;
};

}  // namespace radnet::solver
