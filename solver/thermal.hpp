#pragma once
// Node temperatures from the radiative exchange factors, linear conductors, capacitances
// and the environmental loads. Heat balance of node i (W):
//   G_i(T, t) = Q_env,i(t) + Q_int,i + Σ_j K_ij (T_j − T_i)
//             + σ Σ_j GR_ij (T_j⁴ − T_i⁴) − σ GR_i,space (T_i⁴ − T_space⁴)
// Steady state: G(T) = 0 at each position (Newton with a backtracking line search).
// Transient: C dT/dt = G(T, t), variable-step BDF2 (L-stable: stiff small capacitances and
// zero-capacitance "arithmetic" nodes are fine), Newton at each step.
#include "solver/status.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <string>
#include <vector>

namespace radnet::solver {

struct ThermalNetwork {
  Eigen::MatrixXd gr;                      ///< radiative exchange factors GR (n×n), m²
  Eigen::VectorXd gr_space;                ///< GR to space, m²
  Eigen::SparseMatrix<double> conductors;  ///< K_ij (symmetric, zero diagonal), W/K
  Eigen::VectorXd capacitance;             ///< C_i, J/K (0: arithmetic node)
  Eigen::VectorXd dissipation;             ///< Q_int,i, W
  Eigen::VectorXd fixed_temperature;       ///< K, NaN where the node is free (boundary nodes otherwise)
  double space_temperature = 3.0;          ///< K
  /// @throws std::invalid_argument on inconsistent sizes or non-physical values
  void validate() const;
};

struct ThermalOptions {
  double tolerance_w = 1e-9;  ///< Newton stops when every |G_i| ≤ tolerance_w · (1 + scale of node i's terms)
  int max_newton_iterations = 100;
  double max_step_s = 10.0;  ///< transient substep
};

struct ThermalResult {
  Eigen::MatrixXd temperature;       ///< (n×P), K
  Eigen::MatrixXd temperature_rate;  ///< dT/dt at the same times (n×P), K/s; zero for steady states
  Status status = Status::Converged;
  std::string message;
  int newton_iterations = 0;    ///< total
  double max_residual_w = 0.0;  ///< largest |G_i| left, W
};

/// Heat balance G(T) of every node for environmental loads q_env (n), W.
Eigen::VectorXd heatBalance(const ThermalNetwork& net, const Eigen::VectorXd& temperature,
                            const Eigen::VectorXd& q_env);

/// Each node's heat balance split by kind, per node and position (n×P), W, positive into
/// the node. With the absorbed environmental loads (kept by the caller), they sum to zero
/// at every free node: what the Newton solve left is the imbalance.
struct HeatFlows {
  Eigen::MatrixXd emitted;      ///< IR exchange with space, σ GR_space (T_space⁴ − T⁴) (≤ 0 above T_space)
  Eigen::MatrixXd radiative;    ///< net IR exchange with the other nodes, σ Σ_j GR_ij (T_j⁴ − T_i⁴)
  Eigen::MatrixXd conducted;    ///< net conduction, Σ_j K_ij (T_j − T_i)
  Eigen::MatrixXd dissipation;  ///< internal dissipation Q_int
  Eigen::MatrixXd stored;       ///< −C dT/dt (zero in a steady state)
  Eigen::MatrixXd boundary;     ///< what a boundary condition supplies to hold a fixed node; 0 at free nodes
};

/// The heat flows of a solution: temperatures and rates from steadyStates or transient,
/// q_env (n×P, W) the absorbed environmental loads at the same times.
HeatFlows heatFlows(const ThermalNetwork& net, const ThermalResult& solution, const Eigen::MatrixXd& q_env);

/// Steady state at every column of q_env (n×P, W). Each solve starts from the previous answer.
ThermalResult steadyStates(const ThermalNetwork& net, const Eigen::MatrixXd& q_env, const ThermalOptions& opt = {});

/// Transient from `initial` (K) over `orbits` repetitions of a periodic load history given
/// at times_s (P, within one period, increasing) with values q_env (n×P, linear in between,
/// wrapping at `period_s`). Returns the temperatures at the P times of the last orbit.
ThermalResult transient(const ThermalNetwork& net, const std::vector<double>& times_s, const Eigen::MatrixXd& q_env,
                        double period_s, double orbits, const Eigen::VectorXd& initial, const ThermalOptions& opt = {});

}  // namespace radnet::solver
