#include "cases/pipeline/thermal_run.hpp"

#include "cases/config/errors.hpp"
#include "cases/pipeline/progress.hpp"
#include "solver/radiative/uncertainty.hpp"
#include "solver/thermal/uncertainty.hpp"
#include "solver/units.hpp"

#include <array>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <ostream>

namespace radnet::cases {
namespace {

// The forcing of orbit case k: its positions' loads and sunlit fractions, repeating over the
// case's sweep, dissipation tables over its orbit period.
solver::ThermalForcing caseForcing(const SweepResult& sw, const Eigen::MatrixXd& q_env, int k, bool optics,
                                   const std::shared_ptr<const std::vector<solver::ExchangeUpdate>>& turned) {
  const int begin = sw.case_start[static_cast<size_t>(k)], end = sw.case_start[static_cast<size_t>(k) + 1];
  solver::ThermalForcing f;
  if (turned) {  // parts that turn: each position's arrangement
    f.exchange_states = turned;
    f.exchange_state.assign(sw.configuration.begin() + begin, sw.configuration.begin() + end);
  }
  for (int p = begin; p < end; ++p) {
    f.times_s.push_back(sw.positions[static_cast<size_t>(p)].t_s);
    f.sunlit_fraction.push_back(sw.positions[static_cast<size_t>(p)].sunlit_fraction);
  }
  f.q_env = q_env.middleCols(begin, end - begin);
  if (optics) {  // the bands' parts, which follow α(T) and ε(T)
    f.q_solar = f.q_ir = Eigen::MatrixXd::Zero(q_env.rows(), end - begin);
    const Eigen::Index nr = sw.absorbed_solar.rows();
    f.q_solar.topRows(nr) = (sw.absorbed_solar + sw.absorbed_albedo).middleCols(begin, end - begin);
    f.q_ir.topRows(nr) = sw.absorbed_earth_ir.middleCols(begin, end - begin);
  }
  f.load_period_s = sw.case_sweep_s[static_cast<size_t>(k)];
  f.schedule_period_s = sw.case_period_s[static_cast<size_t>(k)];
  return f;
}

// Which orbit case failed, by its name, and the nodes still changing most there.
std::string failureWhere(const ThermalSettings& ts, const SweepResult& sw, int k, const solver::ThermalResult& part) {
  std::ostringstream s;
  s << " (orbit case " << k + 1;
  if (static_cast<size_t>(k) < sw.case_labels.size() && !sw.case_labels[static_cast<size_t>(k)].empty())
    s << " '" << sw.case_labels[static_cast<size_t>(k)] << "'";
  s << ")";
  if (part.failed_node >= 0 && static_cast<size_t>(part.failed_node) < ts.node_names.size())
    s << "; furthest from balance: node '" << ts.node_names[static_cast<size_t>(part.failed_node)] << "'";
  for (size_t j = 0; j < part.worst_changes.size(); ++j)
    s << (j ? ", " : "; still changing most: ") << ts.node_names[static_cast<size_t>(part.worst_changes[j].first)]
      << " " << std::setprecision(3) << part.worst_changes[j].second << " K";
  return s.str();
}

// One transient per orbit case, each periodic over its own swept orbit(s); or one steady
// state per position. Each case's heater duty is kept.
solver::ThermalResult solvePerCase(const ThermalSettings& ts, const solver::ThermalNetwork& net, const SweepResult& sw,
                                   const Eigen::MatrixXd& q_env, Eigen::MatrixXd& case_duty,
                                   const std::shared_ptr<const std::vector<solver::ExchangeUpdate>>& turned,
                                   const solver::ThermalOptions& opt) {
  const Eigen::Index n = net.size(), P = q_env.cols(), H = static_cast<Eigen::Index>(net.heaters.size());
  solver::ThermalResult result;
  result.temperature.resize(n, P);
  result.temperature_rate.resize(n, P);
  result.rate_roundoff.resize(n, P);
  result.dissipation.resize(n, P);
  result.heater_power.resize(H, P);
  case_duty.resize(sw.caseCount(), H);
  for (int k = 0; k < sw.caseCount(); ++k) {
    const solver::ThermalForcing f = caseForcing(sw, q_env, k, net.optics != nullptr, turned);
    const solver::ThermalResult part =
        ts.periodic ? solver::periodicTransient(net, f, ts.initial_temperature, *ts.periodic, opt)
        : ts.transient_orbits ? solver::transient(net, f, *ts.transient_orbits, ts.initial_temperature, opt)
                              : solver::steadyStates(net, f, opt);
    result.newton_iterations += part.newton_iterations;
    result.heater_switches += part.heater_switches;
    result.factorisations += part.factorisations;
    result.max_residual_w = std::max(result.max_residual_w, part.max_residual_w);
    result.orbits = std::max(result.orbits, part.orbits);  // the slowest orbit case
    if (ts.periodic)
      result.periodic_residual_k =
          k == 0 ? part.periodic_residual_k : std::max(result.periodic_residual_k, part.periodic_residual_k);
    if (part.status != solver::Status::Converged) {
      result.status = part.status;
      result.message = part.message + failureWhere(ts, sw, k, part);
      break;
    }
    if (part.notOneOrbitPeriodic()) {
      result.heater_cycle_unlocked = result.heater_cycle_unlocked || part.heater_cycle_unlocked;
      result.orbits_per_period = std::max(result.orbits_per_period, part.orbits_per_period);
      result.message += (result.message.empty() ? "" : "; ") + part.message + failureWhere(ts, sw, k, part);
    }
    const int begin = sw.case_start[static_cast<size_t>(k)];
    const Eigen::Index count = part.temperature.cols();
    result.temperature.middleCols(begin, count) = part.temperature;
    result.temperature_rate.middleCols(begin, count) = part.temperature_rate;
    result.rate_roundoff.middleCols(begin, count) = part.rate_roundoff;
    result.dissipation.middleCols(begin, count) = part.dissipation;
    result.heater_power.middleCols(begin, count) = part.heater_power;
    if (net.optics) {
      if (k == 0) result.emissivity = result.absorptivity = result.applied_loads = Eigen::MatrixXd::Zero(n, P);
      result.emissivity.middleCols(begin, count) = part.emissivity;
      result.absorptivity.middleCols(begin, count) = part.absorptivity;
      result.applied_loads.middleCols(begin, count) = part.applied_loads;
      result.exchange_updates += part.exchange_updates;
    }
    case_duty.row(k) = part.heater_duty.transpose();
  }
  // The duty that sizes a heater: the largest of any case.
  result.heater_duty = H > 0 ? Eigen::VectorXd(case_duty.colwise().maxCoeff().transpose()) : Eigen::VectorXd();
  return result;
}

// Without an orbit: a steady state (no environment loads), or a transient over `duration`
// with outputs every output_step.
solver::ThermalResult solveWithoutOrbit(const ThermalSettings& ts, const solver::ThermalNetwork& net,
                                        std::vector<double>& times, const solver::ThermalOptions& opt) {
  solver::ThermalForcing f;
  if (!ts.output_times_s.empty()) {
    f.times_s = ts.output_times_s;
  } else if (ts.duration_s) {
    const long steps = std::lround(std::ceil(*ts.duration_s / ts.output_step_s - 1e-9));
    for (long k = 0; k <= steps; ++k) f.times_s.push_back(std::min(*ts.duration_s, k * ts.output_step_s));
  } else {
    f.times_s.push_back(0.0);
  }
  times = f.times_s;
  f.q_env = Eigen::MatrixXd::Zero(net.size(), static_cast<Eigen::Index>(f.times_s.size()));
  return ts.duration_s ? solver::transient(net, f, 1.0, ts.initial_temperature, opt)
                       : solver::steadyStates(net, f, opt);
}

std::string modeName(const ThermalSettings& ts) {
  return ts.periodic ? "periodic transient"
         : ts.transient_orbits ? "transient"
         : ts.duration_s ? "transient without orbit"
                         : "steady";
}

// A temperature the network does not fix is an error naming the nodes, never the initial guess.
void checkDetermined(const ThermalSettings& ts, const solver::ThermalNetwork& net) {
  const std::vector<int> loose = solver::undeterminedNodes(net, ts.isTransient());
  if (loose.empty()) return;
  std::string names;
  for (size_t k = 0; k < loose.size() && k < 8; ++k)
    names += (k ? ", '" : "'") + ts.node_names[static_cast<size_t>(loose[k])] + "'";
  if (loose.size() > 8) names += " and " + std::to_string(loose.size() - 8) + " more";
  throw NumericalError("temperatures undetermined: node(s) " + names +
                       " have no radiative or conductive path to space or to a boundary node" +
                       (ts.isTransient() ? " and no capacitance" : "") +
                       ", so nothing fixes their temperature: a sealed enclosure or a node with emissivity 0 "
                       "needs a conductor to the structure (or a shell), or a boundary node");
}

// GR from the pairs: the probes bound |ΔGR x|_i by e ε_i A_i max x, so with x = σT⁴ node i's
// net exchange (GR σT⁴)_i − (GR 1)_i σT_i⁴ moves by at most e ε_i A_i σ (max_j T_j⁴ + T_i⁴).
// That bound is taken as one standard deviation of the heat balance (docs/solver.md).
void addExchangeTruncation(const ThermalErrorInputs& in, const Eigen::Ref<const Eigen::MatrixXd>& t,
                           Eigen::MatrixXd& var_q) {
  if (!(in.exchange_truncation > 0)) return;
  for (Eigen::Index p = 0; p < t.cols(); ++p) {
    const double t4_max = t.col(p).array().pow(4).maxCoeff();
    for (Eigen::Index i = 0; i < t.rows(); ++i) {
      const double bound = in.exchange_truncation * in.emissivity[i] * in.area[i] * solver::kStefanBoltzmann *
                           (t4_max + std::pow(t(i, p), 4));
      var_q(i, p) += bound * bound;
    }
  }
}

// σ_T from the absorbed power's uncertainty and the view factors' errors in the exchange
// between the radiative nodes (lumped nodes: no environment, no view factors).
void temperatureUncertainty(const solver::ThermalNetwork& net, const SweepResult& sw, const ThermalErrorInputs& in,
                            int radiative_nodes, ThermalSolution& out) {
  const Eigen::MatrixXd& t = out.solve.temperature;
  Eigen::MatrixXd var_q = Eigen::MatrixXd::Zero(t.rows(), t.cols());
  var_q.topRows(radiative_nodes) =
      sw.absorbed_stderr.array().square().matrix() +
      solver::exchangeHeatVariance(in.view_factor_stderr, in.lost_view_factor_stderr, in.emissivity, in.area,
                                   t.topRows(radiative_nodes), net.space_temperature);
  addExchangeTruncation(in, t.topRows(radiative_nodes), var_q);
  solver::TemperaturePropagation used;
  out.temperature_stderr = solver::temperatureStderr(net, t, var_q, sw.case_start, used);
  if (!out.temperature_stderr.allFinite()) {  // a near-singular Jacobian: say so, write nothing
    out.temperature_stderr.resize(0, 0);
    out.temperature_stderr_method = "not computed: the heat balance's Jacobian is singular";
    return;
  }
  out.temperature_stderr_method =
      used == solver::TemperaturePropagation::PerPosition
          ? "first order, the heat balance's Jacobian at each position"
      : used == solver::TemperaturePropagation::PerSpan
          ? "first order, the heat balance's Jacobian at each orbit case's mean temperatures"
          : "first order, the Jacobian's diagonal only (large network): coupling to neighbours left out, an "
            "underestimate";
}

}  // namespace

HeatBalance heatBalance(const solver::ThermalNetwork& net, const solver::ThermalResult& solution,
                        const Eigen::MatrixXd& q_env, const std::vector<const solver::ExchangeUpdate*>& exchange_per_position) {
  HeatBalance b;
  b.flows = solver::heatFlows(net, solution, q_env, exchange_per_position);
  const solver::HeatFlows& f = b.flows;
  const std::array<const Eigen::MatrixXd*, 8> terms = {&q_env,         &f.emitted, &f.radiative, &f.conducted,
                                                       &f.dissipation, &f.heater,  &f.stored,    &f.boundary};
  for (Eigen::Index p = 0; p < q_env.cols(); ++p) {
    // A node that exchanges almost nothing (a lumped node without dissipation) is measured
    // against kRelativeFloor of the position's largest term, not against its own near-zero.
    constexpr double kRelativeFloor = 1e-6;
    double position_largest = 0.0;
    for (const Eigen::MatrixXd* m : terms) position_largest = std::max(position_largest, m->col(p).cwiseAbs().maxCoeff());
    for (Eigen::Index i = 0; i < q_env.rows(); ++i) {
      double sum = 0.0, largest = kRelativeFloor * position_largest;
      for (const Eigen::MatrixXd* m : terms) {
        sum += (*m)(i, p);
        largest = std::max(largest, std::abs((*m)(i, p)));
      }
      // What floating point cannot resolve (HeatFlows::roundoff) is not counted as imbalance.
      const double beyond = std::max(0.0, std::abs(sum) - f.roundoff(i, p));
      b.max_imbalance_w = std::max(b.max_imbalance_w, beyond);
      if (largest > 0) b.max_relative_imbalance = std::max(b.max_relative_imbalance, beyond / largest);
    }
  }
  return b;
}

namespace {

// No spacecraft material survives 4000 K (graphite sublimes near 3900 K, tungsten melts at
// 3695 K): a node above it means a dissipation in mW written as W, a capacitance in kJ/K, a
// node cut off from every sink. The run is kept (the numbers are what the model says), but
// not silently: a warning names the hottest node, its temperature and when.
constexpr double kHottestMaterial = 4000.0;  // K

void warnImplausibleTemperatures(const ThermalSolution& out, std::ostream& progress) {
  const Eigen::MatrixXd& t = out.solve.temperature;
  if (t.size() == 0) return;
  Eigen::Index node = 0, column = 0;
  const double hottest = t.maxCoeff(&node, &column);
  if (!(hottest > kHottestMaterial)) return;
  progress << "radnet: warning: thermal: node '" << out.node_names[static_cast<size_t>(node)] << "' reaches "
           << hottest << " K";
  if (static_cast<size_t>(column) < out.times_s.size()) progress << " at t = " << out.times_s[static_cast<size_t>(column)] << " s";
  progress << ", above what any material survives (" << kHottestMaterial
           << " K): check its dissipation (W), capacitance (J/K) and links to the rest of the model\n";
}

// With ε(T), α(T): the heat balance takes the loads at each node's own optics, and the
// solution keeps their ratio to the sweep's nominal ones (for /solution/heat).
void useOwnOptics(const solver::TemperatureOptics& optics, ThermalSolution& out, Eigen::MatrixXd& q_env) {
  const solver::ThermalResult& result = out.solve;
  if (result.applied_loads.size() == 0) return;
  q_env = result.applied_loads;
  out.solar_load_scale = optics.nominal_absorptivity.cwiseInverse().asDiagonal() * result.absorptivity;
  out.ir_load_scale = optics.nominal_emissivity.cwiseInverse().asDiagonal() * result.emissivity;
}

// Parts that turn: each configuration's GR of the whole thermal network, and each position's.
struct TurnedExchange {
  std::shared_ptr<std::vector<solver::ExchangeUpdate>> states;  ///< null: no turning parts
  std::vector<const solver::ExchangeUpdate*> per_position;
};
TurnedExchange turnedExchange(const ThermalSettings& ts, const std::vector<const solver::ExchangeFactors*>& turned,
                              const SweepResult* sweep) {
  TurnedExchange out;
  if (turned.empty() || !sweep) return out;
  out.states = std::make_shared<std::vector<solver::ExchangeUpdate>>();
  for (const solver::ExchangeFactors* ex : turned) out.states->push_back(thermalExchange(ts, *ex));
  for (int k : sweep->configuration) out.per_position.push_back(&(*out.states)[static_cast<size_t>(k)]);
  return out;
}

// The run's line on the temperatures: mode, orbits, heaters, the Newton's work and the balance.
void reportThermal(const ThermalSettings& ts, const solver::ThermalNetwork& net, const ThermalSolution& out,
                   std::ostream& progress) {
  const solver::ThermalResult& result = out.solve;
  progress << "radnet: temperatures (" << out.mode;
  if (ts.periodic && result.notOneOrbitPeriodic())
    progress << ", " << result.orbits << " orbits, a change of " << result.periodic_residual_k
             << " K left by a thermostat cycle " << (result.heater_cycle_unlocked ? "not locked to the orbit"
                                                   : "repeating over several orbits");
  else if (ts.periodic)
    progress << ", " << result.orbits << " orbits to a change below " << ts.periodic->tolerance_k << " K";
  if (!ts.heaters.empty()) progress << ", " << result.heater_switches << " heater switchings";
  if (net.optics) progress << ", " << result.exchange_updates << " GRs for ε(T) on the one eigendecomposition";
  progress << "), " << result.newton_iterations << " Newton iterations (" << result.factorisations
           << (net.gr_factored ? " Jacobians; GR factored, rank " + std::to_string(net.gr_factored->rank()) +
                                     ", steps by GMRES"
                               : std::string(" Jacobian factorisations"))
           << "), largest heat-balance residual "
           << result.max_residual_w << " W; heat flows balance to " << out.heat.max_relative_imbalance
           << " of the largest term\n";
}

}  // namespace

ThermalSolution runThermal(const ThermalSettings& ts, const solver::ExchangeFactors& exchange, const SweepResult* sweep,
                           StageTimings& timings, std::ostream& progress, const ThermalErrorInputs* errors,
                           std::shared_ptr<const solver::TemperatureOptics> optics,
                           const std::vector<const solver::ExchangeFactors*>& turned) {
  for (const std::string& w : ts.warnings) progress << "radnet: warning: " << w << "\n";
  const TurnedExchange states = turnedExchange(ts, turned, sweep);
  // Optics that follow temperature and turning parts re-form GR densely, and a small network
  // is solved faster dense; otherwise a factored GR stays factored.
  const bool keep_factored = !optics && turned.empty() && ts.nodeCount() >= solver::kFactoredThermalMinNodes;
  solver::ThermalNetwork net = thermalNetwork(ts, exchange, keep_factored);
  net.optics = std::move(optics);
  checkDetermined(ts, net);
  StageTimer timer(timings, Stage::Thermal);
  solver::ThermalOptions options = ts.options;
  options.progress = thermalProgress(progress);
  ThermalSolution out{ts.node_names, ts.radiative_nodes, {}, modeName(ts)};
  for (const solver::Heater& h : ts.heaters) out.heater_names.push_back(h.name), out.heater_rated_w.push_back(h.power_w);
  // Lumped nodes absorb nothing from the environment.
  Eigen::MatrixXd q_env;
  if (sweep) {
    q_env = Eigen::MatrixXd::Zero(ts.nodeCount(), sweep->absorbed_total.cols());
    q_env.topRows(ts.radiative_nodes) = sweep->absorbed_total;
    for (const auto& p : sweep->positions) out.times_s.push_back(p.t_s);
    out.solve = solvePerCase(ts, net, *sweep, q_env, out.case_heater_duty, states.states, options);
  } else {
    out.solve = solveWithoutOrbit(ts, net, out.times_s, options);
    q_env = Eigen::MatrixXd::Zero(ts.nodeCount(), static_cast<Eigen::Index>(out.times_s.size()));
    out.case_heater_duty = out.solve.heater_duty.transpose();
  }
  timer.stop();
  const solver::ThermalResult& result = out.solve;
  if (result.status != solver::Status::Converged) {
    std::string where;  // a sweep's failure says its case and node already (failureWhere)
    if (!sweep && result.failed_node >= 0)
      where = "; furthest from balance: node '" + ts.node_names[static_cast<size_t>(result.failed_node)] + "'";
    throw NumericalError(std::string("temperatures ") + solver::toString(result.status) + ": " + result.message + where);
  }
  if (result.notOneOrbitPeriodic()) progress << "radnet: warning: temperatures: " << result.message << "\n";
  if (net.optics) useOwnOptics(*net.optics, out, q_env);
  out.heat = heatBalance(net, result, q_env, states.per_position);
  warnImplausibleTemperatures(out, progress);
  if (sweep && errors) {
    StageTimer t_unc(timings, Stage::Uncertainty);
    temperatureUncertainty(net, *sweep, *errors, ts.radiative_nodes, out);
    if (out.temperature_stderr.size() == 0)
      progress << "radnet: warning: temperature uncertainty " << out.temperature_stderr_method
               << "; /uncertainty/temperature is not written\n";
  }
  reportThermal(ts, net, out, progress);
  return out;
}

}  // namespace radnet::cases
