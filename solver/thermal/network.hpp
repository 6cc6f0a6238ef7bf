#pragma once
// The thermal network that temperatures are solved on (docs/design.md, "Temperatures"):
// radiative exchange factors GR, conductors (constant or tabulated against temperature),
// capacitances (constant or tabulated), dissipations (constant or scheduled in time),
// thermostat heaters and boundary nodes. Heat balance of node i (W):
//   G_i(T, t) = Q_env,i(t) + Q_int,i(t) + Q_heater,i(t) + Σ_j K_ij(T̄_ij) (T_j − T_i)
//             + σ Σ_j GR_ij (T_j⁴ − T_i⁴) − σ GR_i,space (T_i⁴ − T_space⁴),   T̄_ij = (T_i + T_j)/2.
#include "solver/thermal/factored_exchange.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace radnet::solver {

/// A property tabulated against temperature: linear between points, held at the end values
/// beyond the first and last point (ESATAN's and Thermal Desktop's default for tables).
struct TemperatureTable {
  std::vector<double> temperature_k;  ///< strictly increasing, K
  std::vector<double> value;          ///< the property at each temperature
  double at(double t_k) const;
  /// d value / dT at t_k (the segment's slope; 0 beyond the ends).
  double slope(double t_k) const;
  /// @throws std::invalid_argument naming `what` unless there is at least one point, the
  /// temperatures are finite, positive and increasing, and the values finite and ≥ 0
  void validate(const std::string& what) const;
};

/// Part of a node's internal dissipation that changes in time, W (on top of the constant one).
struct DissipationSchedule {
  enum class Kind {
    Illumination,  ///< eclipse_w + f (sunlit_w − eclipse_w), f the spacecraft's sunlit fraction
    Table,         ///< power_w[k] from times_s[k] until the next entry, repeating every period
    Interpolated   ///< linear between the entries, held beyond them, never repeating (a load history read from another tool)
  };
  int node = -1;
  Kind kind = Kind::Illumination;
  double sunlit_w = 0.0, eclipse_w = 0.0;
  std::vector<double> times_s;  ///< increasing, the first 0: seconds into the period
  std::vector<double> power_w;
  /// @param t_s  seconds since the start of the run
  /// @param sunlit_fraction  0 … 1
  /// @param period_s  the table repeats with this period (the orbit's); 0: it does not repeat
  double at(double t_s, double sunlit_fraction, double period_s) const;
};

/// A boundary node whose held temperature follows a history (an imported file's): linear
/// between the entries, held beyond them, never repeating.
struct BoundarySchedule {
  int node = -1;
  std::vector<double> times_s;        ///< increasing, s from the start
  std::vector<double> temperature_k;  ///< K
  double at(double t_s) const;
};

/// Linear interpolation in (x, y), held at the end values beyond them; x increasing.
double interpolateHeld(const std::vector<double>& x, const std::vector<double>& y, double at);

/// An on/off thermostat with hysteresis: on when its sensor falls below on_below_k, off
/// when it rises above off_above_k (a dead band, so it cannot chatter).
struct Heater {
  std::string name;
  int node = -1;    ///< where the power goes
  int sensor = -1;  ///< whose temperature switches it (often `node`)
  double power_w = 0.0, on_below_k = 0.0, off_above_k = 0.0;
};

/// A conductor whose conductance (W/K) is tabulated against the mean of its two nodes'
/// temperatures (K).
struct TabledConductor {
  int i = -1, j = -1;
  TemperatureTable conductance;
};

struct TemperatureOptics;  // solver/thermal/optics.hpp

/// GR (n×n) and GR to space (n), m², of the whole thermal network: for an emissivity vector
/// (optics that follow temperature) or for one arrangement of turning parts.
struct ExchangeUpdate {
  Eigen::MatrixXd gr;
  Eigen::VectorXd gr_space;
};

struct ThermalNetwork {
  Eigen::MatrixXd gr;                      ///< radiative exchange factors GR (n×n), m²; empty when factored
  /// GR held factored instead of `gr` (a large sparse network: D + W K Wᵀ): never formed n × n,
  /// applied as products and solved with by a Krylov method (solver/thermal/jacobian.hpp).
  /// Optics that follow temperature and turning parts need `gr` dense.
  std::shared_ptr<const FactoredExchange> gr_factored;
  Eigen::VectorXd gr_space;                ///< GR to space, m²
  Eigen::SparseMatrix<double> conductors;  ///< constant K_ij (symmetric, zero diagonal), W/K
  std::vector<TabledConductor> tabled_conductors;
  Eigen::VectorXd capacitance;  ///< C_i, J/K (0: arithmetic node)
  std::vector<std::pair<int, TemperatureTable>> capacitance_tables;  ///< C_i(T) in place of capacitance[i], J/K
  Eigen::VectorXd dissipation;                                       ///< constant Q_int,i, W
  std::vector<DissipationSchedule> schedules;                        ///< added to the constant dissipation
  std::vector<Heater> heaters;
  Eigen::VectorXd fixed_temperature;  ///< K, NaN where the node is free (boundary nodes otherwise)
  std::vector<BoundarySchedule> boundary_schedules;  ///< in a transient, these boundary nodes follow a history
  double space_temperature = 3.0;     ///< K
  /// Nodes whose ε or α follow their temperature (null: none); gr and gr_space are then the
  /// nominal ε's, and the solvers form new ones as the optics move.
  std::shared_ptr<const TemperatureOptics> optics;

  Eigen::Index size() const { return gr_factored ? gr_factored->size() : gr.rows(); }
  bool isFixed(Eigen::Index i) const;
  /// GR x (n), m² × [x], from whichever form GR is held in.
  Eigen::VectorXd exchangeTimes(const Eigen::VectorXd& x) const;
  /// Σ_j GR_ij (n), m².
  Eigen::VectorXd exchangeRowSum() const;
  /// GR (n×n), m²: `gr`, or formed from the factors (where n² fits).
  Eigen::MatrixXd exchangeDense() const;
  /// @throws std::invalid_argument on inconsistent sizes, indices or non-physical values
  void validate() const;
};

/// Capacitances at temperatures t (n), J/K, and their derivatives dC/dT, J/K².
Eigen::VectorXd capacitanceAt(const ThermalNetwork& net, const Eigen::VectorXd& t);
Eigen::VectorXd capacitanceSlope(const ThermalNetwork& net, const Eigen::VectorXd& t);

/// Scheduled plus constant dissipation of every node at time t_s, W.
/// @param interpolated_at_s  where Interpolated schedules are taken instead (a transient step's
///                           end, like the environment loads: a ramp evaluated at the step's
///                           middle would lag by half a step); NaN: at t_s
Eigen::VectorXd dissipationAt(const ThermalNetwork& net, double t_s, double sunlit_fraction, double period_s,
                              double interpolated_at_s = std::numeric_limits<double>::quiet_NaN());

/// Heat balance G(T) of every node, W, for applied powers q (environment + dissipation +
/// heaters) (n), W.
/// @param gr_row_sum  Σ_j GR_ij when the caller keeps it (an O(n²) sum a Newton loop need not repeat)
Eigen::VectorXd netHeat(const ThermalNetwork& net, const Eigen::VectorXd& t, const Eigen::VectorXd& q,
                        const Eigen::VectorXd* gr_row_sum = nullptr);
/// Net conduction into every node, Σ_j K_ij(T̄) (T_j − T_i), W.
Eigen::VectorXd conductedHeat(const ThermalNetwork& net, const Eigen::VectorXd& t);
/// ∂G/∂T (n×n), W/K (a factored GR formed: where n² fits).
Eigen::MatrixXd netHeatJacobian(const ThermalNetwork& net, const Eigen::VectorXd& t);
/// ∂(conducted heat)/∂T entry by entry, W/K, as add(row, column, value) (repeated entries
/// sum): constant conductors K_ij, and tabulated ones with their slopes
/// (q = K(T̄)(T_j − T_i) into i: ∂q/∂T_i = −K + ½ K' (T_j − T_i), ∂q/∂T_j = K + ½ K' (T_j − T_i)).
/// The one source of these entries for the dense Jacobian, its diagonal and the factored one.
template <class Add>
void conductionJacobianEntries(const ThermalNetwork& net, const Eigen::VectorXd& t, const Add& add) {
  for (int k = 0; k < net.conductors.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(net.conductors, k); it; ++it) {
      if (it.row() == it.col()) continue;  // K_ii would add and take away the same
      add(it.row(), it.col(), it.value());
      add(it.row(), it.row(), -it.value());
    }
  for (const TabledConductor& c : net.tabled_conductors) {
    const double mean = 0.5 * (t[c.i] + t[c.j]), k = c.conductance.at(mean);
    const double d = 0.5 * c.conductance.slope(mean) * (t[c.j] - t[c.i]);
    add(c.i, c.i, -k + d);
    add(c.i, c.j, k + d);
    add(c.j, c.i, k - d);
    add(c.j, c.j, -k - d);
  }
}
/// The diagonal of ∂G/∂T (n), W/K, without forming the rest.
Eigen::VectorXd netHeatJacobianDiagonal(const ThermalNetwork& net, const Eigen::VectorXd& t);
/// The size of what flows through each node at t (sum of |net terms|: powers, exchange with
/// each node and with space, conduction), W: the scale of its balance, so that a tolerance
/// means the same for a 1e-6 W/K strap, a 1e6 W/K joint and a node near the space temperature.
Eigen::VectorXd balanceScale(const ThermalNetwork& net, const Eigen::VectorXd& t, const Eigen::VectorXd& q);
/// The round-off of evaluating each node's balance at t, W (differences of nearly equal
/// temperatures and of their fourth powers): a balance within it is as solved as it can be.
/// @param gr_row_sum  Σ_j GR_ij when the caller keeps it (as netHeat)
Eigen::VectorXd balanceRoundOff(const ThermalNetwork& net, const Eigen::VectorXd& t,
                                const Eigen::VectorXd* gr_row_sum = nullptr);

/// Nodes whose temperature the network does not determine: those of a connected group
/// (through GR, conductors and couplings) with no path to space or to a boundary node and,
/// when `transient`, no capacitance either. Empty when every temperature is determined.
std::vector<int> undeterminedNodes(const ThermalNetwork& net, bool transient);

}  // namespace radnet::solver
