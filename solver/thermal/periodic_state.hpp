#pragma once
// What a periodic transient has seen orbit after orbit, and what it concludes when the history
// does not repeat after one orbit: a thermostat locked onto several orbits, one not locked to
// the orbit at all (no periodic state exists), or a transient that has not settled yet
// (docs/solver.md, "Periodic transients").
#include "solver/thermal/network.hpp"
#include "solver/thermal/temperatures.hpp"

#include <Eigen/Dense>

#include <deque>
#include <vector>

namespace radnet::solver::detail {

/// The most orbits a thermostat's cycle may be locked onto and still be recognised.
inline constexpr size_t kMaxOrbitsPerPeriod = 8;

class PeriodicHistory {
 public:
  /// Records the orbit just integrated (res.temperature) with the heater switchings it had;
  /// sets res.periodic_residual_k (and res.orbits_per_period for a locked cycle). True when
  /// the history repeats: after one orbit, or after m = 2 … kMaxOrbitsPerPeriod.
  bool addOrbit(const ThermalNetwork& net, ThermalResult& res, int switches, double tolerance_k);

  std::vector<double> residuals;              ///< orbit-to-orbit change after orbits 2, 3, …, K
  std::vector<int> switches;                  ///< heater switchings within each orbit
  std::vector<Eigen::VectorXd> orbit_means;   ///< each node's mean over the positions of each orbit, K
  Eigen::VectorXd last_change;                ///< each node's largest change from the orbit before to the last, K

 private:
  std::deque<Eigen::MatrixXd> recent_;        ///< the last orbits' temperatures, newest last
};

/// After the last orbit: the message and status for a locked cycle (Converged, m orbits), an
/// unlocked one (Converged, heater_cycle_unlocked) or neither (NotConverged unless settled).
void concludePeriodic(const ThermalNetwork& net, const PeriodicOptions& periodic, const PeriodicHistory& history,
                      ThermalResult& res);

}  // namespace radnet::solver::detail
