#pragma once
// The implicit solve shared by steady states and transient steps (internal to solver/):
// find T (and the powers u of the heaters held at their set point) with
//   C(T) ∘ (T − history) − hβ (G(T) + B u) = 0     a BDF2 step (steady state: C ≡ 0, hβ = 1)
//   T_sensor(k) − on_below(k) = 0                   each controlled heater k
// by Newton's method. Each node's row is divided by the size of what flows through it
// (balanceScale), so that the tolerance and the line search mean the same for a 1e-6 W/K
// strap and a 1e6 W/K bolted joint.
#include "solver/thermal/jacobian.hpp"
#include "solver/thermal/temperatures.hpp"

#include <Eigen/Dense>

#include <string>
#include <vector>

namespace radnet::solver::detail {

/// A factorised Jacobian kept between solves (the chord method): it serves while Newton
/// still converges fast with it, and is refactorised at the current iterate when it does
/// not. For a dense n-node network a factorisation costs O(n³), a solve with it O(n²); for a
/// factored GR a preconditioner's sparse LU, a solve some GMRES iterations (jacobian.hpp).
struct JacobianCache {
  JacobianSolver lu;
  Eigen::VectorXd gr_row_sum;  ///< Σ_j GR_ij of the network, kept with it (O(n²) to form)
  double hb = 0.0;     ///< the h β it was factorised for (a BDF2 step of another length needs another)
  bool valid = false;  ///< only for systems without controlled heaters
};

struct ImplicitSystem {
  const ThermalNetwork& net;
  Eigen::VectorXd q;        ///< applied powers (environment, dissipation, heaters that are on), W
  Eigen::VectorXd history;  ///< BDF2 history a T_n − b T_{n−1}, K (transient only)
  double hb = 1.0;          ///< h β, s (transient); 1 (steady)
  bool transient = false;
  std::vector<int> controlled;  ///< heaters (indices into net.heaters) holding their sensor at on_below
  JacobianCache* cache = nullptr;  ///< reused between solves when given
};

struct NewtonOutcome {
  Status status = Status::Converged;
  int iterations = 0;
  int factorisations = 0;   ///< Jacobian LUs computed
  double residual_w = 0.0;  ///< largest |G_i| left, W
  int worst_node = -1;      ///< not converged: the node whose balance is furthest from its tolerance
  std::string message;
};

/// Solves the system from the guess `t` (K) and `u` (W, one per controlled heater), in place.
NewtonOutcome solveImplicit(const ImplicitSystem& system, Eigen::VectorXd& t, Eigen::VectorXd& u,
                            const ThermalOptions& opt);

/// A transient's inputs: sizes, periods, steps, initial temperatures.
/// @throws std::invalid_argument saying which is wrong
/// @throws std::invalid_argument when the forcing's exchange states do not fit the network
void checkExchangeStates(const ThermalNetwork& net, const ThermalForcing& f);
void checkTransientInputs(const ThermalNetwork& net, const ThermalForcing& forcing, const Eigen::VectorXd& initial,
                          const ThermalOptions& opt);
/// A converged result with a non-finite temperature becomes Status::NonFinite.
void checkFinite(ThermalResult& result);

}  // namespace radnet::solver::detail
