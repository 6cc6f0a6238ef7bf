#include "solver/thermal/periodic_state.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

namespace radnet::solver::detail {
namespace {

// A thermostat whose own on/off period does not divide the orbit's gives no periodic state: the
// orbit-to-orbit change wanders within the dead band instead of decaying. Told from a slow
// approach to a periodic state by three signs over the last orbits: the heaters switched in each
// of them, the change is within the widest dead band, and its largest value over the last
// quarter of the orbits is at least half that over the quarter before (a decay would halve it).
// A drift hidden under the wandering (a slow node far from its periodic state) shows in that
// node's orbit-mean temperature, which then moves the same way orbit after orbit, where a node
// driven by the unlocked cycle moves back and forth: any node drifting one way through the last
// half of the orbits by more than the tolerance rules the unlocked cycle out.
bool heaterCycleUnlocked(const ThermalNetwork& net, const std::vector<double>& residuals,
                         const std::vector<int>& switches, const std::vector<Eigen::VectorXd>& orbit_means,
                         double tolerance_k) {
  const long quarter = static_cast<long>(residuals.size() / 4);
  if (net.heaters.empty() || quarter < 2) return false;
  double widest_band_k = 0.0;
  for (const Heater& h : net.heaters) widest_band_k = std::max(widest_band_k, h.off_above_k - h.on_below_k);
  if (!std::all_of(switches.end() - quarter, switches.end(), [](int k) { return k > 0; })) return false;
  const auto last = residuals.end() - quarter, before = last - quarter;
  const double recent = *std::max_element(last, residuals.end()), earlier = *std::max_element(before, last);
  if (!(residuals.back() <= widest_band_k && recent >= 0.5 * earlier)) return false;
  const auto end = orbit_means.end();
  for (Eigen::Index i = 0; i < orbit_means.back().size(); ++i) {
    bool up = true, down = true;
    for (long k = 1; k < 2 * quarter; ++k) {
      const double step = end[-k][i] - end[-k - 1][i];
      up = up && step > 0, down = down && step < 0;
    }
    if ((up || down) && std::abs(end[-1][i] - end[-2 * quarter][i]) > tolerance_k) return false;
  }
  return true;
}

// A thermostat may lock to several orbits (on in one orbit of three): the history then repeats
// after m orbits, not after one. Sets res.orbits_per_period = m (2 … kMaxOrbitsPerPeriod) and
// the largest difference of the last orbit from the others of its period, as its residual.
bool lockedPeriod(const ThermalNetwork& net, ThermalResult& res, const std::deque<Eigen::MatrixXd>& history,
                  double tolerance_k) {
  if (net.heaters.empty() || res.heater_switches == 0) return false;
  for (size_t m = 2; m <= history.size(); ++m) {
    if ((res.temperature - history.end()[-static_cast<long>(m)]).cwiseAbs().maxCoeff() > tolerance_k) continue;
    res.orbits_per_period = static_cast<int>(m);
    double spread = 0.0;
    for (size_t k = 1; k < m; ++k)
      spread = std::max(spread, (res.temperature - history.end()[-static_cast<long>(k)]).cwiseAbs().maxCoeff());
    res.periodic_residual_k = spread;
    return true;
  }
  return false;
}

}  // namespace

bool PeriodicHistory::addOrbit(const ThermalNetwork& net, ThermalResult& res, int switches_in_orbit,
                               double tolerance_k) {
  switches.push_back(switches_in_orbit);
  orbit_means.push_back(res.temperature.rowwise().mean());
  bool repeats = false;
  if (!recent_.empty()) {
    // The largest change of any node's temperature history from one orbit to the next.
    last_change = (res.temperature - recent_.back()).cwiseAbs().rowwise().maxCoeff();
    res.periodic_residual_k = last_change.maxCoeff();
    residuals.push_back(res.periodic_residual_k);
    repeats = res.periodic_residual_k <= tolerance_k || lockedPeriod(net, res, recent_, tolerance_k);
  }
  recent_.push_back(res.temperature);
  if (recent_.size() > kMaxOrbitsPerPeriod) recent_.pop_front();
  return repeats;
}

void concludePeriodic(const ThermalNetwork& net, const PeriodicOptions& periodic, const PeriodicHistory& history,
                      ThermalResult& res) {
  const bool settled = res.periodic_residual_k <= periodic.tolerance_k;
  if (res.status != Status::Converged || settled) return;
  if (res.orbits_per_period > 1) {
    res.message = "the state repeats every " + std::to_string(res.orbits_per_period) +
                  " orbits, not every orbit (a thermostat cycle locked to " + std::to_string(res.orbits_per_period) +
                  " orbits): the last orbit is reported; the others of the period differ from it by up to " +
                  std::to_string(res.periodic_residual_k) + " K";
  } else if (heaterCycleUnlocked(net, history.residuals, history.switches, history.orbit_means,
                                 periodic.tolerance_k)) {
    res.heater_cycle_unlocked = true;
    res.message = "no periodic state: a thermostat cycles on its own period, not locked to the orbit (the "
                  "orbit-to-orbit change stopped decaying at " + std::to_string(res.periodic_residual_k) +
                  " K, within its dead band, after " + std::to_string(res.orbits) +
                  " orbits); the last orbit is reported";
  } else {
    res.status = Status::NotConverged;
    std::vector<int> order(static_cast<size_t>(history.last_change.size()));
    std::iota(order.begin(), order.end(), 0);
    const size_t shown = std::min<size_t>(5, order.size());
    std::partial_sort(order.begin(), order.begin() + static_cast<long>(shown), order.end(),
                      [&](int a, int b) { return history.last_change[a] > history.last_change[b]; });
    for (size_t k = 0; k < shown && history.last_change[order[k]] > 0; ++k)
      res.worst_changes.emplace_back(order[k], history.last_change[order[k]]);
    res.message = "the transient did not become periodic in " + std::to_string(res.orbits) +
                  " orbits: the last orbit still changed a temperature by " +
                  std::to_string(res.periodic_residual_k) + " K (periodic_tolerance " +
                  std::to_string(periodic.tolerance_k) + " K); raise max_orbits or check for a slow time constant" +
                  (res.heater_switches > 0 ? ", or a thermostat whose on/off cycle does not repeat with the orbit "
                                             "(a periodic_tolerance above its dead band)"
                                           : "");
  }
}

}  // namespace radnet::solver::detail
