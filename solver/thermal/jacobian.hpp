#pragma once
// The implicit system's Jacobian at one iterate, ready to solve with (internal to solver/;
// the system is newton.hpp's). Two forms, one answer:
// - GR dense: J (n + a square) formed and LU-factorised, O(n³) once, O(n²) a solve;
// - GR factored (D + W K Wᵀ): J = S + U Vᵀ, S sparse (conductors, capacitances, GR's direct
//   part, the diagonal, heaters, boundary rows) and U Vᵀ the reflected part's rank-k term
//   −hβ 4σ W K Wᵀ diag(T³). Never formed: GMRES (Saad & Schultz 1986; Eigen's
//   implementation) on products with S and with U, Vᵀ, left-preconditioned by the sparse LU of
//   S's conductive skeleton (conductors, heaters, boundary rows and J's whole diagonal), which
//   is what a fine FE mesh makes stiff; the radiative off-diagonals are GMRES's to resolve.
//   O(nnz(D) + n k) a product, so a 100,000-node network's step needs no n² anything.
#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <memory>

namespace radnet::solver::detail {

struct ImplicitSystem;
class FactoredJacobian;

class JacobianSolver {
 public:
  JacobianSolver() = default;
  /// J of `system` at temperatures t (n) with `controlled` heaters' powers as unknowns.
  JacobianSolver(const ImplicitSystem& system, const Eigen::VectorXd& t, Eigen::Index controlled);
  /// J⁻¹ b; not finite when J is singular (dense) or the iteration broke down (factored).
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

 private:
  std::shared_ptr<const Eigen::PartialPivLU<Eigen::MatrixXd>> lu_;
  std::shared_ptr<const FactoredJacobian> factored_;
};

/// GMRES's stopping rule: the preconditioned residual reduced by this factor. A Newton step
/// solved this far is as good as an exact one (its error is far below the next step's).
inline constexpr double kJacobianRelativeResidual = 1e-10;
/// At most this many GMRES iterations a solve, restarted every kJacobianRestart.
inline constexpr int kJacobianMaxIterations = 2000;
inline constexpr int kJacobianRestart = 60;

}  // namespace radnet::solver::detail
