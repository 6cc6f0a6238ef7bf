// Steady states per position, with thermostat heaters held at their set point where needed.
#include "solver/thermal/temperatures.hpp"
#include "solver/thermal/newton.hpp"
#include "solver/thermal/optics.hpp"
#include "solver/units.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace radnet::solver {
namespace {

using units::kStefanBoltzmann;

// What a heater does in a steady state: nothing (its sensor is warm enough), hold its sensor
// at on_below with part of its power, or give all of it (the sensor still below on_below).
enum class HeaterMode { Off, Controlled, Saturated };

// Each node alone in radiative equilibrium with what it receives (floored at space).
Eigen::VectorXd startingGuess(const ThermalNetwork& net, const Eigen::VectorXd& q) {
  const Eigen::VectorXd emit = net.exchangeRowSum() + net.gr_space;
  Eigen::VectorXd t(q.size());
  for (Eigen::Index i = 0; i < t.size(); ++i) {
    t[i] = emit[i] > 0 ? std::pow(std::max(0.0, q[i]) / (kStefanBoltzmann * emit[i]) + std::pow(net.space_temperature, 4), 0.25)
                       : 293.15;
    t[i] = std::max(t[i], std::max(net.space_temperature, 1.0));
    if (net.isFixed(i)) t[i] = net.fixed_temperature[i];
  }
  return t;
}

// A sensor can be held at one set point only: two thermostats on one sensor (a primary and a
// backup) both Controlled would ask it to sit at two temperatures, or split one power two ways
// (a singular Jacobian). At equilibrium a heater whose set point is above the sensor's
// temperature gives all its power and one below gives none, so of those that would be
// Controlled together the highest set point (ties: the first listed) keeps control and the
// others wait Off; the backup takes over on a later round once the primary has saturated.
void oneControllerPerSensor(const std::vector<Heater>& heaters, std::vector<HeaterMode>& next,
                            Eigen::VectorXd& power) {
  for (size_t k = 0; k < heaters.size(); ++k) {
    if (next[k] != HeaterMode::Controlled) continue;
    for (size_t j = k + 1; j < heaters.size(); ++j) {
      if (next[j] != HeaterMode::Controlled || heaters[j].sensor != heaters[k].sensor) continue;
      const size_t loser = heaters[j].on_below_k > heaters[k].on_below_k ? k : j;
      next[loser] = HeaterMode::Off;
      power[static_cast<Eigen::Index>(loser)] = 0.0;
      if (loser == k) break;
    }
  }
}

// One position: Newton for the temperatures and the controlled heaters' powers, then the
// heaters' modes corrected until they agree with the answer (an active-set loop: at most a
// few rounds, since each heater moves at most Off → Controlled → Saturated and back, and a
// backup on a shared sensor waits Off until the primary saturates).
detail::NewtonOutcome solvePosition(const ThermalNetwork& net, const Eigen::VectorXd& q, std::vector<HeaterMode>& mode,
                                    Eigen::VectorXd& t, Eigen::VectorXd& power, const ThermalOptions& opt,
                                    detail::JacobianCache& cache) {
  const size_t H = net.heaters.size();
  constexpr double kSettle = 1e-6;  // K: a sensor this close to on_below is at it
  detail::NewtonOutcome total;
  for (size_t round = 0; round < 3 * H + 3; ++round) {  // a backup may wait a round per heater
    detail::ImplicitSystem sys{net, q, {}, 1.0, false, {}, &cache};
    Eigen::VectorXd u;
    std::vector<double> u0;
    for (size_t k = 0; k < H; ++k) {
      if (mode[k] == HeaterMode::Saturated) sys.q[net.heaters[k].node] += net.heaters[k].power_w;
      if (mode[k] == HeaterMode::Controlled) {
        sys.controlled.push_back(static_cast<int>(k));
        u0.push_back(std::clamp(power[static_cast<Eigen::Index>(k)], 0.0, net.heaters[k].power_w));
      }
    }
    u = Eigen::Map<Eigen::VectorXd>(u0.data(), static_cast<Eigen::Index>(u0.size()));
    detail::NewtonOutcome step = detail::solveImplicit(sys, t, u, opt);
    if (step.status != Status::Converged) {  // restart from the node-by-node guess before giving up
      t = startingGuess(net, sys.q);
      step = detail::solveImplicit(sys, t, u, opt);
    }
    total.iterations += step.iterations;
    total.factorisations += step.factorisations;
    total.residual_w = step.residual_w;
    if (step.status != Status::Converged) {
      step.iterations = total.iterations;
      step.factorisations = total.factorisations;
      return step;
    }
    std::vector<HeaterMode> next_mode = mode;
    for (size_t k = 0, c = 0; k < H; ++k) {
      const Heater& h = net.heaters[k];
      const double ts = t[h.sensor];
      HeaterMode& next = next_mode[k];
      if (mode[k] == HeaterMode::Controlled) {
        const double uk = u[static_cast<Eigen::Index>(c++)];
        next = uk < 0 ? HeaterMode::Off : uk > h.power_w ? HeaterMode::Saturated : HeaterMode::Controlled;
        power[static_cast<Eigen::Index>(k)] = std::clamp(uk, 0.0, h.power_w);
      } else if (mode[k] == HeaterMode::Off) {
        if (ts < h.on_below_k - kSettle) next = HeaterMode::Controlled;
        power[static_cast<Eigen::Index>(k)] = 0.0;
      } else {
        if (ts > h.on_below_k + kSettle) next = HeaterMode::Controlled;
        power[static_cast<Eigen::Index>(k)] = h.power_w;
      }
    }
    oneControllerPerSensor(net.heaters, next_mode, power);
    const bool changed = next_mode != mode;
    mode = next_mode;
    if (!changed) return total;
  }
  total.status = Status::NotConverged;
  total.message = "the heaters' set-point control did not settle";
  return total;
}

// One position whose optics follow temperature: successive substitution on ε and α with a
// new GR each round (on the one eigendecomposition), damped node by node: a node's step is
// halved whenever its mismatch ε(T(ε)) − ε changes sign. For a coating whose ε rises with T
// the mismatch falls as ε rises (more emission, colder, lower ε), so the halving brackets its
// one root like a bisection where plain substitution would jump between the branches of a
// steep table. `settled` is the optics at the previous position (the hysteresis memory).
detail::NewtonOutcome solveWithOptics(ThermalNetwork& local, const Eigen::VectorXd& q, const Eigen::VectorXd& q_solar,
                                      const Eigen::VectorXd& q_ir, const OpticsState& settled, OpticsState& state,
                                      std::vector<HeaterMode>& mode, Eigen::VectorXd& t, Eigen::VectorXd& power,
                                      const ThermalOptions& opt, detail::JacobianCache& cache) {
  const TemperatureOptics& optics = *local.optics;
  const Eigen::Index n = t.size();
  Eigen::VectorXd step_e = Eigen::VectorXd::Ones(n), step_a = Eigen::VectorXd::Ones(n);
  Eigen::VectorXd last_e = Eigen::VectorXd::Zero(n), last_a = Eigen::VectorXd::Zero(n);
  detail::NewtonOutcome total;
  constexpr int kMaxRounds = 400;
  for (int round = 0; round < kMaxRounds; ++round) {
    // A new GR: its row sums anew; the kept LU serves on while its chord steps converge.
    if (state.refreshExchange(local, 0.0)) cache.gr_row_sum.resize(0);
    const detail::NewtonOutcome out =
        solvePosition(local, q + state.loadCorrection(optics, q_solar, q_ir), mode, t, power, opt, cache);
    total.iterations += out.iterations;
    total.factorisations += out.factorisations;
    total.residual_w = out.residual_w;
    if (out.status != Status::Converged) return out;
    Eigen::VectorXd target_e, target_a;
    opticsAt(optics, settled, t, target_e, target_a);
    const Eigen::VectorXd miss_e = target_e - state.emissivity, miss_a = target_a - state.absorptivity;
    if (std::max(miss_e.cwiseAbs().maxCoeff(), miss_a.cwiseAbs().maxCoeff()) <= optics.steady_tolerance) return total;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (miss_e[i] * last_e[i] < 0) step_e[i] *= 0.5;
      if (miss_a[i] * last_a[i] < 0) step_a[i] *= 0.5;
    }
    state.emissivity += step_e.cwiseProduct(miss_e);
    state.absorptivity += step_a.cwiseProduct(miss_a);
    last_e = miss_e;
    last_a = miss_a;
  }
  total.status = Status::NotConverged;
  total.message = "the temperature-dependent optics did not settle in " + std::to_string(kMaxRounds) + " rounds";
  return total;
}

// Position p's optics and the loads at them, into the result.
void recordOptics(const OpticsState& state, const Eigen::VectorXd& loads,
                  Eigen::Index p, ThermalResult& res) {
  if (res.emissivity.cols() != res.temperature.cols())
    res.emissivity = res.absorptivity = res.applied_loads = Eigen::MatrixXd::Zero(loads.size(), res.temperature.cols());
  res.emissivity.col(p) = state.emissivity;
  res.absorptivity.col(p) = state.absorptivity;
  res.applied_loads.col(p) = loads;
  res.exchange_updates = state.exchange_updates;
}

// Parts that turn: position p's GR into the network, the kept factorisation dropped.
void turnParts(const ThermalForcing& forcing, size_t p, ThermalNetwork& net, detail::JacobianCache& cache) {
  const ExchangeUpdate& u = (*forcing.exchange_states)[static_cast<size_t>(forcing.exchange_state[p])];
  net.gr = u.gr;
  net.gr_space = u.gr_space;
  cache = detail::JacobianCache{};
}

}  // namespace

ThermalResult steadyStates(const ThermalNetwork& net_in, const ThermalForcing& forcing, const ThermalOptions& opt) {
  // Optics that follow temperature or turning parts change GR: a copy of the network holds it.
  ThermalNetwork with_optics = net_in.optics || forcing.exchange_states ? net_in : ThermalNetwork{};
  const ThermalNetwork& net = net_in.optics || forcing.exchange_states ? with_optics : net_in;
  net.validate();
  const Eigen::Index n = net.size(), P = forcing.q_env.cols(), H = static_cast<Eigen::Index>(net.heaters.size());
  if (forcing.q_env.rows() != n || P == 0 || static_cast<Eigen::Index>(forcing.times_s.size()) != P ||
      !(forcing.sunlit_fraction.empty() || static_cast<Eigen::Index>(forcing.sunlit_fraction.size()) == P))
    throw std::invalid_argument("steady states: one load column, time and sunlit fraction per position");
  detail::checkExchangeStates(net, forcing);
  ThermalResult res;
  res.temperature.resize(n, P);
  res.temperature_rate = res.rate_roundoff = Eigen::MatrixXd::Zero(n, P);
  res.dissipation.resize(n, P);
  res.heater_power.resize(H, P);
  std::vector<HeaterMode> mode(static_cast<size_t>(H), HeaterMode::Off);
  Eigen::VectorXd power = Eigen::VectorXd::Zero(H);
  Eigen::VectorXd t;
  detail::JacobianCache cache;  // one factorisation serves many positions
  OpticsState settled, state;
  for (Eigen::Index p = 0; p < P; ++p) {
    const size_t ps = static_cast<size_t>(p);
    const double sunlit = forcing.sunlit_fraction.empty() ? 1.0 : forcing.sunlit_fraction[ps];
    res.dissipation.col(p) = dissipationAt(net, forcing.times_s[ps], sunlit, forcing.schedule_period_s);
    const Eigen::VectorXd q = forcing.q_env.col(p) + res.dissipation.col(p);
    if (forcing.exchange_states) turnParts(forcing, ps, with_optics, cache);
    if (p == 0) t = startingGuess(net, q);
    if (p == 0 && net.optics) settled.start(with_optics, t);  // the warming branch at the first guess
    state = settled;
    const Eigen::VectorXd q_solar = forcing.q_solar.size() ? forcing.q_solar.col(p) : Eigen::VectorXd();
    const Eigen::VectorXd q_ir = forcing.q_ir.size() ? forcing.q_ir.col(p) : Eigen::VectorXd();
    const detail::NewtonOutcome s =
        net.optics ? solveWithOptics(with_optics, q, q_solar, q_ir, settled, state, mode, t, power, opt, cache)
                   : solvePosition(net, q, mode, t, power, opt, cache);
    res.newton_iterations += s.iterations;
    res.factorisations += s.factorisations;
    if (s.status != Status::Converged) {
      res.status = s.status;
      res.message = s.message + " (steady state at position " + std::to_string(p) + ")";
      res.failed_node = s.worst_node;
      return res;
    }
    res.max_residual_w = std::max(res.max_residual_w, s.residual_w);
    res.temperature.col(p) = t;
    if (net.optics) {
      settled = state;
      recordOptics(state, forcing.q_env.col(p) + state.loadCorrection(*net.optics, q_solar, q_ir), p, res);
    }
    res.heater_power.col(p) = power;
    if (opt.progress) opt.progress(1, static_cast<int>(p + 1), static_cast<int>(P));
  }
  res.heater_duty = Eigen::VectorXd::Zero(H);
  for (Eigen::Index k = 0; k < H; ++k)
    res.heater_duty[k] = res.heater_power.row(k).mean() / net.heaters[static_cast<size_t>(k)].power_w;
  if (!res.temperature.allFinite()) {
    res.status = Status::NonFinite;
    res.message = "steady temperatures are not finite";
  }
  return res;
}

ThermalResult steadyStates(const ThermalNetwork& net, const Eigen::MatrixXd& q_env, const ThermalOptions& opt) {
  ThermalForcing forcing;
  forcing.q_env = q_env;
  for (Eigen::Index p = 0; p < q_env.cols(); ++p) forcing.times_s.push_back(static_cast<double>(p));
  return steadyStates(net, forcing, opt);
}

}  // namespace radnet::solver
