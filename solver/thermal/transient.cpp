// Transients: variable-step BDF2 through the forcing's sample times, heater switching and
// dissipation-table steps located inside the step, orbit after orbit.
#include "solver/thermal/temperatures.hpp"
#include "solver/thermal/bdf2_steps.hpp"
#include "solver/thermal/newton.hpp"
#include "solver/thermal/optics.hpp"
#include "solver/thermal/periodic_state.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <tuple>

namespace radnet::solver {
namespace {

// The state between steps: the last two temperatures, the last step, the clock, which
// heaters are on, and what the last step applied.
struct TransientState {
  Eigen::VectorXd t_now, t_prev, rate;  // K, K, K/s
  Eigen::VectorXd rate_roundoff;        // K/s: how well `rate` is known in floating point
  double clock = 0.0, h_prev = 0.0;     // s
  std::vector<char> heater_on;
  Eigen::VectorXd dissipation;  // W, applied during the last step
  Eigen::VectorXd on_time;      // s each heater has been on since the window began
  double window_start = 0.0;    // s
};

class Integrator {
 public:
  Integrator(const ThermalNetwork& net, const ThermalForcing& f, const ThermalOptions& opt, ThermalResult& res)
      : moving_(fixedNetwork(net, f) ? ThermalNetwork{} : net), net_(fixedNetwork(net, f) ? net : moving_), f_(f),
        opt_(opt), res_(res) {
    holdBoundaries(0.0);
  }

  TransientState start(const Eigen::VectorXd& initial);
  // Marches to `target`, landing on every dissipation-table entry on the way. False when a
  // step failed (recorded in the result).
  bool marchTo(double target, TransientState& s);
  // One pass through the sample times of the period starting at `start`, recording there.
  bool marchPeriod(double start, TransientState& s);

 private:
  Eigen::VectorXd applied(const TransientState& s, double h, Eigen::VectorXd& dissipation) const;
  bool step(const TransientState& s, double h, Eigen::VectorXd& t_new, Eigen::VectorXd& dissipation);
  void accept(TransientState& s, double h, const Eigen::VectorXd& t_new, const Eigen::VectorXd& dissipation);
  int crossing(const TransientState& s, const Eigen::VectorXd& t_new, double& theta) const;
  bool switchInside(TransientState& s, double h, int k);
  void switchHeater(TransientState& s, int k);
  void switchCrossed(TransientState& s);
  std::vector<double> tableEntries(double from, double to) const;
  bool chattering(double from);
  void recordOptics(Eigen::Index p, const TransientState& s);

  // A heater switching this often between two outputs chatters: its dead band is too narrow
  // for its power against its sensor's capacity (a 1e-12 K band switches every 2e-11 s, and
  // the run would not end). Legitimate thermostats switch a few times an orbit.
  static constexpr int kMaxSwitchesPerOutput = 10000;
  std::vector<int> output_switches_;  // per heater, since the last output time

  // Optics that follow temperature (optics.hpp): optics_ the hysteresis memory at the last
  // accepted step, step_optics_ what the step in hand uses (at its predicted end, GR in moving_).
  OpticsState optics_, step_optics_;
  // Boundary nodes that follow a history are held at its value at each step's end, in a
  // copy of the network made only when there are some (or optics that change GR).
  void holdBoundaries(double t) {
    for (const BoundarySchedule& b : moving_.boundary_schedules) moving_.fixed_temperature[b.node] = b.at(t);
  }
  // Nothing in the network changes during the run: no held histories, no optics, no turning parts.
  static bool fixedNetwork(const ThermalNetwork& net, const ThermalForcing& f) {
    return net.boundary_schedules.empty() && !net.optics && !f.exchange_states;
  }
  // Turning parts: the GR of the arrangement at time t (ThermalForcing::exchangeStateAt).
  void turnParts(double t) {
    const int k = f_.exchangeStateAt(t);
    if (k < 0 || k == exchange_state_) return;
    const ExchangeUpdate& u = (*f_.exchange_states)[static_cast<size_t>(k)];
    moving_.gr = u.gr;
    moving_.gr_space = u.gr_space;
    exchange_state_ = k;
    cache_.gr_row_sum.resize(0);
    cache_.valid = false;  // the kept LU was another arrangement's
  }
  int exchange_state_ = -1;
  ThermalNetwork moving_;
  const ThermalNetwork& net_;
  const ThermalForcing& f_;
  const ThermalOptions& opt_;
  ThermalResult& res_;
  detail::JacobianCache cache_;  // one factorisation serves many steps (the chord method)
};

// Applied powers during the step (clock, clock + h]: loads and the sunlit fraction at its
// end (implicit), dissipation tables at its middle (a step never straddles a table entry:
// at an output time on an entry, the step's value is the one before it), heaters as they are.
Eigen::VectorXd Integrator::applied(const TransientState& s, double h, Eigen::VectorXd& dissipation) const {
  dissipation = dissipationAt(net_, s.clock + 0.5 * h, f_.sunlitAt(s.clock + h), f_.schedule_period_s, s.clock + h);
  Eigen::VectorXd q = f_.loadAt(s.clock + h) + dissipation;
  if (net_.optics)
    q += step_optics_.loadCorrection(*net_.optics, f_.sampleAt(f_.q_solar, s.clock + h), f_.sampleAt(f_.q_ir, s.clock + h));
  for (size_t k = 0; k < net_.heaters.size(); ++k)
    if (s.heater_on[k]) q[net_.heaters[k].node] += net_.heaters[k].power_w;
  return q;
}

bool Integrator::step(const TransientState& s, double h, Eigen::VectorXd& t_new, Eigen::VectorXd& dissipation) {
  holdBoundaries(s.clock + h);
  turnParts(s.clock + h);
  t_new = s.t_now + h * s.rate;  // the explicit prediction, when it stays physical
  if (!(t_new.array() > 0).all()) t_new = s.t_now;
  // A new GR: its row sums anew; the kept LU serves on while its chord steps converge.
  if (net_.optics && stepOptics(optics_, t_new, moving_, step_optics_)) cache_.gr_row_sum.resize(0);
  const auto [a, b, beta] = bdf2Coefficients(h, s.h_prev);
  const detail::ImplicitSystem sys{net_,      applied(s, h, dissipation), a * s.t_now - b * s.t_prev, h * beta, true,
                                   {},        &cache_};
  Eigen::VectorXd none;
  const detail::NewtonOutcome out = detail::solveImplicit(sys, t_new, none, opt_);
  res_.newton_iterations += out.iterations;
  res_.factorisations += out.factorisations;
  if (out.status != Status::Converged) {
    res_.status = out.status;
    res_.message = out.message + " (transient step at t = " + std::to_string(s.clock + h) + " s)";
    res_.failed_node = out.worst_node;
    return false;
  }
  res_.max_residual_w = std::max(res_.max_residual_w, out.residual_w);
  return true;
}

void Integrator::accept(TransientState& s, double h, const Eigen::VectorXd& t_new,
                        const Eigen::VectorXd& dissipation) {
  const auto [a, b, beta] = bdf2Coefficients(h, s.h_prev);
  const Eigen::VectorXd history = a * s.t_now - b * s.t_prev;
  s.rate = (t_new - history) / (h * beta);  // the BDF2 derivative at the new time
  s.rate_roundoff = 16 * std::numeric_limits<double>::epsilon() * (t_new.cwiseAbs() + history.cwiseAbs()) / (h * beta);
  for (size_t k = 0; k < net_.heaters.size(); ++k)
    if (s.heater_on[k]) s.on_time[static_cast<Eigen::Index>(k)] += h;
  s.t_prev = s.t_now;
  s.t_now = t_new;
  s.clock += h;
  s.h_prev = h;
  s.dissipation = dissipation;
  if (net_.optics) optics_.follow(*net_.optics, s.t_now);  // the memory moves with accepted steps only
}

// The heater whose sensor crossed its switching temperature first during the step to
// t_new, with θ (0 … 1) the linear estimate of where; −1 when none did.
int Integrator::crossing(const TransientState& s, const Eigen::VectorXd& t_new, double& theta) const {
  int first = -1;
  theta = 2.0;
  for (size_t k = 0; k < net_.heaters.size(); ++k) {
    const Heater& h = net_.heaters[k];
    const double threshold = s.heater_on[k] ? h.off_above_k : h.on_below_k;
    const double g0 = s.t_now[h.sensor] - threshold, g1 = t_new[h.sensor] - threshold;
    if (!(s.heater_on[k] ? g1 > 0 : g1 < 0)) continue;
    const double th = g0 != g1 ? std::clamp(g0 / (g0 - g1), 0.0, 1.0) : 1.0;
    if (th < theta) {
      theta = th;
      first = static_cast<int>(k);
    }
  }
  return first;
}

void Integrator::switchHeater(TransientState& s, int k) {
  s.heater_on[static_cast<size_t>(k)] = !s.heater_on[static_cast<size_t>(k)];
  s.h_prev = 0.0;  // the forcing jumps: restart BDF2 from backward Euler
  ++res_.heater_switches;
  if (output_switches_.size() != net_.heaters.size()) output_switches_.assign(net_.heaters.size(), 0);
  ++output_switches_[static_cast<size_t>(k)];
}

bool Integrator::chattering(double from) {
  for (size_t k = 0; k < output_switches_.size(); ++k) {
    if (output_switches_[k] <= kMaxSwitchesPerOutput) continue;
    const Heater& h = net_.heaters[k];
    res_.status = Status::NotConverged;
    std::ostringstream m;
    m << "heater '" << h.name << "' switched " << output_switches_[k] << " times between two outputs (from t = " << from
      << " s): its dead band, " << h.off_above_k - h.on_below_k << " K, is too narrow for " << h.power_w
      << " W against its sensor's heat capacity, and the transient would not end; widen the band (off_above − on_below)";
    res_.message = m.str();
    return true;
  }
  return false;
}

// Heaters whose sensor is already past their switching temperature (at the start, or
// within the switching tolerance after a located switch of another heater) switch now.
void Integrator::switchCrossed(TransientState& s) {
  for (size_t k = 0; k < net_.heaters.size(); ++k) {
    const Heater& h = net_.heaters[k];
    const double ts = s.t_now[h.sensor];
    if (s.heater_on[k] ? ts > h.off_above_k : ts < h.on_below_k) switchHeater(s, static_cast<int>(k));
  }
}

// Heater k's sensor crosses its threshold inside the step of h: find the time by the
// Illinois variant of regula falsi on the step length, re-solving the step each time, to
// switch_tolerance_k; take the step to there and switch.
bool Integrator::switchInside(TransientState& s, double h, int k) {
  const Heater& heater = net_.heaters[static_cast<size_t>(k)];
  const bool on = s.heater_on[static_cast<size_t>(k)];
  const double threshold = on ? heater.off_above_k : heater.on_below_k;
  const double tol = std::min(opt_.switch_tolerance_k, 0.1 * (heater.off_above_k - heater.on_below_k));
  auto crossed = [&](double g) { return on ? g > 0 : g < 0; };
  double lo = 0.0, hi = 1.0, g_lo = s.t_now[heater.sensor] - threshold;
  Eigen::VectorXd t_new, dissipation, t_hi, d_hi;
  if (!step(s, h, t_hi, d_hi)) return false;
  double g_hi = t_hi[heater.sensor] - threshold;
  int side = 0;
  for (int it = 0; it < 40 && std::abs(g_hi) > tol; ++it) {
    const double theta = std::clamp((lo * g_hi - hi * g_lo) / (g_hi - g_lo), lo + 1e-6 * (hi - lo), hi - 1e-6 * (hi - lo));
    if (!step(s, theta * h, t_new, dissipation)) return false;
    const double g = t_new[heater.sensor] - threshold;
    if (crossed(g)) {
      hi = theta, g_hi = g, t_hi = t_new, d_hi = dissipation;
      if (side == +1) g_lo *= 0.5;
      side = +1;
    } else {
      lo = theta, g_lo = g;
      if (side == -1) g_hi *= 0.5;
      side = -1;
      if (std::abs(g) <= tol) {  // close enough on the near side: switch here
        hi = theta, t_hi = t_new, d_hi = dissipation;
        break;
      }
    }
  }
  accept(s, hi * h, t_hi, d_hi);
  switchHeater(s, k);
  return true;
}

void Integrator::recordOptics(Eigen::Index p, const TransientState& s) {
  if (res_.emissivity.cols() != res_.temperature.cols())
    res_.emissivity = res_.absorptivity = res_.applied_loads = Eigen::MatrixXd::Zero(net_.size(), res_.temperature.cols());
  res_.emissivity.col(p) = step_optics_.emissivity_in_gr;  // what the step's GR and IR loads used
  res_.absorptivity.col(p) = step_optics_.absorptivity;
  res_.applied_loads.col(p) = f_.loadAt(s.clock) + step_optics_.loadCorrection(*net_.optics, f_.sampleAt(f_.q_solar, s.clock),
                                                                          f_.sampleAt(f_.q_ir, s.clock));
  res_.exchange_updates = step_optics_.exchange_updates;
}

std::vector<double> Integrator::tableEntries(double from, double to) const {
  std::vector<double> out;
  const double period = f_.schedule_period_s;
  for (const DissipationSchedule& sch : net_.schedules) {
    if (sch.kind != DissipationSchedule::Kind::Table) continue;
    const double first = period > 0 ? period * std::floor(from / period) : 0.0;
    for (double base = first; base <= to; base += period) {
      for (double e : sch.times_s)
        if (base + e > from && base + e <= to) out.push_back(base + e);
      if (!(period > 0)) break;
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

bool Integrator::marchTo(double target, TransientState& s) {
  const double from = s.clock;
  output_switches_.assign(net_.heaters.size(), 0);
  std::vector<double> stops = tableEntries(s.clock, target);
  const bool target_is_entry = !stops.empty() && stops.back() == target;
  if (!target_is_entry) stops.push_back(target);
  for (size_t k = 0; k < stops.size(); ++k) {
    const double stop = stops[k];
    while (stop - s.clock > 1e-9 * std::max(1.0, std::abs(stop))) {
      switchCrossed(s);
      const double h = nextStep(s.h_prev, opt_.max_step_s, stop - s.clock);
      Eigen::VectorXd t_new, dissipation;
      if (!step(s, h, t_new, dissipation)) return false;
      double theta = 0.0;
      const int heater = crossing(s, t_new, theta);
      if (heater < 0) {
        accept(s, h, t_new, dissipation);
      } else if (!switchInside(s, h, heater)) {
        return false;
      }
      if (chattering(from)) return false;
    }
    // The dissipation steps here: restart BDF2, whose two-step history would otherwise
    // carry the jump of dT/dt into an O(h) error.
    if (k + 1 < stops.size() || target_is_entry) s.h_prev = 0.0;
  }
  return true;
}

bool Integrator::marchPeriod(double start, TransientState& s) {
  const Eigen::Index P = static_cast<Eigen::Index>(f_.times_s.size());
  const Eigen::Index n = net_.size(), H = static_cast<Eigen::Index>(net_.heaters.size());
  res_.temperature.resize(n, P);
  res_.temperature_rate.resize(n, P);
  res_.rate_roundoff.resize(n, P);
  res_.dissipation.resize(n, P);
  res_.heater_power.resize(H, P);
  s.on_time.setZero();
  s.window_start = s.clock;
  for (Eigen::Index p = 0; p < P; ++p) {
    if (!marchTo(start + f_.times_s[static_cast<size_t>(p)], s)) return false;
    res_.temperature.col(p) = s.t_now;
    res_.temperature_rate.col(p) = s.rate;
    res_.rate_roundoff.col(p) = s.rate_roundoff;
    res_.dissipation.col(p) = s.dissipation;
    if (net_.optics) recordOptics(p, s);
    for (Eigen::Index k = 0; k < H; ++k)
      res_.heater_power(k, p) = s.heater_on[static_cast<size_t>(k)] ? net_.heaters[static_cast<size_t>(k)].power_w : 0.0;
    if (opt_.progress) opt_.progress(res_.orbits + 1, static_cast<int>(p + 1), static_cast<int>(P));
  }
  const double window = s.clock - s.window_start;
  res_.heater_duty = window > 0 ? Eigen::VectorXd(s.on_time / window) : Eigen::VectorXd(res_.heater_power.rowwise().mean());
  if (window <= 0)
    for (Eigen::Index k = 0; k < H; ++k) res_.heater_duty[k] /= net_.heaters[static_cast<size_t>(k)].power_w;
  return true;
}

// The starting state: boundary nodes at their temperature, heaters on where their sensor
// starts below on_below, and the arithmetic (zero-capacitance) nodes in balance with the
// others, so that the first output balances and BDF2 starts from a consistent state.
TransientState Integrator::start(const Eigen::VectorXd& initial) {
  const Eigen::Index n = net_.size();
  TransientState s;
  s.t_now = s.t_prev = initial;
  if (net_.optics) optics_.start(moving_, initial), step_optics_ = optics_;
  s.rate = s.rate_roundoff = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i)
    if (net_.isFixed(i)) s.t_now[i] = net_.fixed_temperature[i];
  for (const Heater& h : net_.heaters) s.heater_on.push_back(s.t_now[h.sensor] < h.on_below_k);
  s.on_time = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(net_.heaters.size()));
  Eigen::VectorXd dissipation;
  const Eigen::VectorXd q = applied(s, 0.0, dissipation);
  s.dissipation = dissipation;
  const Eigen::VectorXd c = capacitanceAt(net_, s.t_now);
  ThermalNetwork held = net_;  // capacitive nodes held at their initial temperature
  for (Eigen::Index i = 0; i < n; ++i)
    if (c[i] > 0) held.fixed_temperature[i] = s.t_now[i];
  Eigen::VectorXd t = s.t_now, none;
  if ((c.array() == 0).any() &&
      detail::solveImplicit({held, q, {}, 1.0, false, {}, nullptr}, t, none, opt_).status == Status::Converged)
    s.t_now = t;
  const Eigen::VectorXd g = netHeat(net_, s.t_now, q);
  for (Eigen::Index i = 0; i < n; ++i)
    if (c[i] > 0 && !net_.isFixed(i)) s.rate[i] = g[i] / c[i];
  s.t_prev = s.t_now;
  return s;
}

}  // namespace

ThermalResult transient(const ThermalNetwork& net, const ThermalForcing& forcing, double orbits,
                        const Eigen::VectorXd& initial, const ThermalOptions& opt) {
  detail::checkTransientInputs(net, forcing, initial, opt);
  if (!(orbits > 0 && std::isfinite(orbits))) throw std::invalid_argument("transient: orbits must be > 0");
  ThermalResult res;
  Integrator integrator(net, forcing, opt, res);
  TransientState state = integrator.start(initial);
  const int count = forcing.load_period_s > 0 ? static_cast<int>(std::ceil(orbits)) : 1;
  for (int k = 0; k < count; ++k) {
    if (!integrator.marchPeriod(k * forcing.load_period_s, state)) return res;
    res.orbits = k + 1;
  }
  detail::checkFinite(res);
  return res;
}

ThermalResult transient(const ThermalNetwork& net, const std::vector<double>& times, const Eigen::MatrixXd& q_env,
                        double period, double orbits, const Eigen::VectorXd& initial, const ThermalOptions& opt) {
  if (!(period > 0)) throw std::invalid_argument("transient: the period must be > 0 s");
  return transient(net, ThermalForcing{times, q_env, {}, period, period}, orbits, initial, opt);
}

ThermalResult periodicTransient(const ThermalNetwork& net, const ThermalForcing& forcing,
                                const Eigen::VectorXd& initial, const PeriodicOptions& periodic,
                                const ThermalOptions& opt) {
  detail::checkTransientInputs(net, forcing, initial, opt);
  if (!(forcing.load_period_s > 0)) throw std::invalid_argument("periodic transient: needs a load period");
  if (!(periodic.tolerance_k > 0) || periodic.max_orbits < 2)
    throw std::invalid_argument("periodic transient: tolerance must be > 0 K and max_orbits at least 2");
  ThermalResult res;
  Integrator integrator(net, forcing, opt, res);
  TransientState state = integrator.start(initial);
  detail::PeriodicHistory history;
  for (int orbit = 0; orbit < periodic.max_orbits; ++orbit) {
    const int switches_before = res.heater_switches;
    if (!integrator.marchPeriod(orbit * forcing.load_period_s, state)) return res;
    res.orbits = orbit + 1;
    if (history.addOrbit(net, res, res.heater_switches - switches_before, periodic.tolerance_k)) break;
  }
  detail::concludePeriodic(net, periodic, history, res);
  detail::checkFinite(res);
  return res;
}

}  // namespace radnet::solver
