#pragma once
// Node temperatures on a thermal network (solver/thermal/network.hpp).
// Steady state: G(T) = 0 at each position (Newton with a backtracking line search on the
// balance scaled node by node; thermostat heaters held at their set point where needed).
// Transient: C(T) dT/dt = G(T, t), variable-step BDF2 (L-stable: stiff small capacitances and
// zero-capacitance "arithmetic" nodes are fine), Newton at each step, heater switching and
// dissipation-table steps located inside the step.
#include "solver/status.hpp"
#include "solver/thermal/network.hpp"

#include <Eigen/Dense>

#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace radnet::solver {

struct ThermalOptions {
  double tolerance_w = 1e-9;  ///< Newton stops when every |G_i| ≤ tolerance_w · (scale of node i's terms)
  int max_newton_iterations = 100;
  double max_step_s = 10.0;           ///< transient substep
  double switch_tolerance_k = 1e-3;   ///< a heater switches within this of its set point, K
  bool reuse_jacobian = true;         ///< chord steps on a cached LU (false: a new LU every iteration)
  /// Called as each output is reached: (orbit, counted from 1, outputs done in it, outputs per
  /// orbit); steady states count as one orbit. A run's progress (a 100,002-node orbit takes
  /// minutes); it must not throw. Empty: not called.
  std::function<void(int orbit, int done, int outputs)> progress;
};

/// What drives the network: absorbed environment loads sampled at times within one period,
/// linear in between, the spacecraft's sunlit fraction there, and the periods with which
/// the loads and the dissipation tables repeat.
struct ThermalForcing {
  std::vector<double> times_s;          ///< P sample times, increasing, s
  Eigen::MatrixXd q_env;                ///< (n×P) absorbed environment loads, W
  std::vector<double> sunlit_fraction;  ///< P values in [0, 1]; empty: sunlit throughout
  double load_period_s = 0.0;           ///< the samples repeat with this period (the sweep's span); 0: held
  double schedule_period_s = 0.0;       ///< dissipation tables repeat with it (the orbit's period); 0: never
  /// The parts of q_env absorbed in the solar band (direct + albedo) and from the planet's IR
  /// (n×P, W), at the nominal optics; needed only when the network's optics follow temperature.
  Eigen::MatrixXd q_solar, q_ir;
  /// Parts that turn (an articulated wing): sample p is solved with GR exchange_states[exchange_state[p]],
  /// which holds from halfway after the previous sample to halfway before the next (a drive
  /// steps between samples); empty: the network's own GR throughout.
  std::shared_ptr<const std::vector<ExchangeUpdate>> exchange_states;
  std::vector<int> exchange_state;
  /// The state index at time t (the nearest sample, wrapping at load_period_s); −1 without states.
  int exchangeStateAt(double t_s) const;
  /// Loads at time t (s): linear between samples, wrapping at load_period_s.
  Eigen::VectorXd loadAt(double t_s) const { return sampleAt(q_env, t_s); }
  /// Any (n×P) matrix of the samples at time t the same way; empty for an empty one.
  Eigen::VectorXd sampleAt(const Eigen::MatrixXd& samples, double t_s) const;
  double sunlitAt(double t_s) const;
};

struct ThermalResult {
  Eigen::MatrixXd temperature;       ///< (n×P), K
  Eigen::MatrixXd temperature_rate;  ///< dT/dt at the same times (n×P), K/s; zero for steady states
  Eigen::MatrixXd rate_roundoff;     ///< how well dT/dt is resolved in floating point (n×P), K/s
  Eigen::MatrixXd dissipation;       ///< internal dissipation applied at those times (n×P), W
  Eigen::MatrixXd heater_power;      ///< (h×P), W: what each heater supplied there
  Eigen::VectorXd heater_duty;       ///< (h): time on over the last orbit (transient) or mean power / rated power (steady), –
  Status status = Status::Converged;
  std::string message;
  int newton_iterations = 0;    ///< total
  int factorisations = 0;       ///< Jacobian LU factorisations (O(n³) each; the chord steps between them cost O(n²))
  double max_residual_w = 0.0;  ///< largest |G_i| left, W
  int orbits = 0;               ///< transients: orbits integrated
  int heater_switches = 0;      ///< transients: switchings located inside a step
  double periodic_residual_k = std::numeric_limits<double>::quiet_NaN();  ///< periodic: last orbit-to-orbit change, K
  /// periodic: no periodic state exists because a thermostat cycles on its own period, not
  /// locked to the orbit (the change stopped decaying, within the dead band, switching every
  /// orbit); the last orbit is returned as Converged and `message` says so.
  bool heater_cycle_unlocked = false;
  /// periodic: orbits after which the history repeats; above 1 when a thermostat locked to
  /// several orbits (the last is returned, Converged; periodic_residual_k is then the largest
  /// difference from the other orbits of the period, and `message` says so).
  int orbits_per_period = 1;
  /// periodic, not converged: the nodes whose temperature history still changed most from the
  /// orbit before to the last (node index, K), largest first, at most five
  std::vector<std::pair<int, double>> worst_changes;
  int failed_node = -1;  ///< a Newton that did not converge: the node furthest from balance
  /// With optics that follow temperature: ε and α of every node at the output times (n×P),
  /// the loads applied there (q_env corrected for them, n×P, W) and how many GRs were formed.
  Eigen::MatrixXd emissivity, absorptivity, applied_loads;
  int exchange_updates = 0;
  /// The periodic state is not one orbit's: the caller should say so (message).
  bool notOneOrbitPeriodic() const { return heater_cycle_unlocked || orbits_per_period > 1; }
};

/// Heat balance G(T) of every node for environmental loads q_env (n) and the constant
/// dissipation, W.
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
  Eigen::MatrixXd heater;       ///< heater power
  Eigen::MatrixXd stored;       ///< −C dT/dt (zero in a steady state)
  Eigen::MatrixXd boundary;     ///< what a boundary condition supplies to hold a fixed node; 0 at free nodes
  /// What floating point resolves of each node's balance (n×P), W: C × the rate's round-off
  /// (a 1e6 J/K node over a 10 s step resolves 1e-8 W, no better), conductors' differences,
  /// and 16 ε of the terms' sum. An imbalance within it is no imbalance.
  Eigen::MatrixXd roundoff;
};

/// The heat flows of a solution: temperatures, rates, dissipations and heater powers from
/// steadyStates or a transient, q_env (n×P, W) the absorbed environmental loads at the same times.
/// @param exchange_per_position  parts that turn: each position's GR (null entries, or empty: the network's)
HeatFlows heatFlows(const ThermalNetwork& net, const ThermalResult& solution, const Eigen::MatrixXd& q_env,
                    const std::vector<const ExchangeUpdate*>& exchange_per_position = {});

/// Steady state at every sample of `forcing` (each solve starts from the previous answer).
/// Heaters: each supplies what holds its sensor at on_below (0 … its power); duty is the
/// mean of power / rated power over the samples.
ThermalResult steadyStates(const ThermalNetwork& net, const ThermalForcing& forcing, const ThermalOptions& opt = {});
/// Steady states for loads q_env (n×P, W) alone (sunlit, the constant dissipation).
ThermalResult steadyStates(const ThermalNetwork& net, const Eigen::MatrixXd& q_env, const ThermalOptions& opt = {});

/// Transient from `initial` (K) over `orbits` repetitions of the forcing's load period.
/// Returns the temperatures at its sample times in the last repetition. With a load period of
/// 0, one pass through the sample times (a transient without an orbit).
ThermalResult transient(const ThermalNetwork& net, const ThermalForcing& forcing, double orbits,
                        const Eigen::VectorXd& initial, const ThermalOptions& opt = {});
/// The same for loads q_env at times_s repeating every period_s, constant dissipation.
ThermalResult transient(const ThermalNetwork& net, const std::vector<double>& times_s, const Eigen::MatrixXd& q_env,
                        double period_s, double orbits, const Eigen::VectorXd& initial, const ThermalOptions& opt = {});

/// When a transient is periodic: integrate orbit after orbit until the largest change of any
/// node's temperature at the P positions between consecutive orbits is at most tolerance_k.
struct PeriodicOptions {
  double tolerance_k = 0.01;  ///< K
  int max_orbits = 50;
};

/// Transient from `initial` (K) over as many load periods as it takes to become periodic (see
/// PeriodicOptions); returns the last orbit, with `orbits` and `periodic_residual_k`. Not
/// periodic within max_orbits: Status::NotConverged, saying by how much.
ThermalResult periodicTransient(const ThermalNetwork& net, const ThermalForcing& forcing,
                                const Eigen::VectorXd& initial, const PeriodicOptions& periodic,
                                const ThermalOptions& opt = {});

}  // namespace radnet::solver
