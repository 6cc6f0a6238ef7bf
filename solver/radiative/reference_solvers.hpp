#pragma once
// Reference solvers of one band, M = M_o + S G M (Ashdown 2001, eq. 20), S = diag(ρ/A).
// They are the baselines for tests and for the speed-versus-error benchmark; the
// production path is LowRankBandSolver. All take a dense symmetric G.
#include "solver/radiative/eigenpairs.hpp"
#include "solver/status.hpp"

#include <Eigen/Dense>

#include <functional>
#include <string>

namespace radnet::solver {

/// The linear system of one band.
struct BandSystem {
  const Eigen::MatrixXd& conductance;  ///< G (n×n), symmetric, m²
  const Eigen::VectorXd& area;         ///< A (n), m²
  const Eigen::VectorXd& reflectance;  ///< ρ (n), –
};

struct IterativeOptions {
  /// Stop when ‖M⁽ʳ⁾ − M⁽ʳ⁻¹⁾‖₂ / ‖M⁽ʳ⁾‖₂ ≤ tolerance (Southwell: unshot power / emitted power).
  double tolerance = 1e-10;
  int max_iterations = 100000;
  /// Called after every iteration with (r, M⁽ʳ⁾), e.g. to record a convergence history.
  std::function<void(int, const Eigen::VectorXd&)> observer;
};

struct SolveResult {
  Eigen::VectorXd exitance;  ///< M, W/m²
  Status status = Status::Converged;
  int iterations = 0;
  std::string message;
};

/// Dense LU of (I − S G) (partial pivoting), O(n³).
SolveResult solveDenseLU(const BandSystem& sys, const Eigen::VectorXd& initial_exitance);

/// Jacobi iteration, eq. 20: the physical bounces of light.
SolveResult solveJacobi(const BandSystem& sys, const Eigen::VectorXd& initial_exitance,
                        const IterativeOptions& opt = {});

/// Gauss–Seidel sweeps over the nodes in order.
SolveResult solveGaussSeidel(const BandSystem& sys, const Eigen::VectorXd& initial_exitance,
                             const IterativeOptions& opt = {});

/// Southwell iteration (progressive radiosity, Ashdown §11): shoot the node with the
/// most unshot power A_i ΔM_i; one iteration = one shot (one column of G).
SolveResult solveSouthwell(const BandSystem& sys, const Eigen::VectorXd& initial_exitance,
                           const IterativeOptions& opt = {});

/// Conjugate gradients (Eigen, diagonal preconditioner) on the SPD form of eq. 12,
/// (A R⁻¹ − G) M = A R⁻¹ M_o. Needs ρ_i > 0 for every node.
/// @throws std::invalid_argument when some ρ_i ≤ 0
SolveResult solveConjugateGradient(const BandSystem& sys, const Eigen::VectorXd& initial_exitance,
                                   const IterativeOptions& opt = {});

/// The paper's eigenvector iteration (eqs. 35–37) with the first k pairs:
/// K⁽⁰⁾ = M_o, K⁽ʳ⁾ = Σ_i (K⁽ʳ⁻¹⁾·v_i) λ_i w_i with w_i = S v_i, M⁽ʳ⁾ = M⁽ʳ⁻¹⁾ + K⁽ʳ⁾.
/// Converges to the G'_k solution only when the spectral radius of S G'_k is below 1;
/// divergence (‖K‖ growing for 8 iterations running, or past 1e100 ‖M_o‖) is a status.
SolveResult solveEigenIteration(const EigenPairs& pairs, const Eigen::VectorXd& area,
                                const Eigen::VectorXd& reflectance, const Eigen::VectorXd& initial_exitance,
                                const IterativeOptions& opt = {});

}  // namespace radnet::solver
