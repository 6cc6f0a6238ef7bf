#include "cases/pipeline/thermal_run.hpp"

#include "cases/config/errors.hpp"

#include <array>
#include <cmath>
#include <ostream>

namespace radnet::cases {
namespace {

// One transient per orbit case, each periodic over its own swept orbit(s).
solver::ThermalResult transientPerCase(const ThermalSettings& ts, const solver::ThermalNetwork& net,
                                       const SweepResult& sw, const Eigen::MatrixXd& q_env) {
  const Eigen::Index n = net.gr.rows();
  solver::ThermalResult result;
  result.temperature.resize(n, q_env.cols());
  result.temperature_rate.resize(n, q_env.cols());
  for (int k = 0; k < sw.caseCount(); ++k) {
    const int begin = sw.case_start[static_cast<size_t>(k)];
    const int count = sw.case_start[static_cast<size_t>(k) + 1] - begin;
    std::vector<double> times;
    for (int p = begin; p < begin + count; ++p) times.push_back(sw.positions[static_cast<size_t>(p)].t_s);
    solver::ThermalResult part =
        solver::transient(net, times, q_env.middleCols(begin, count), sw.case_sweep_s[static_cast<size_t>(k)],
                          *ts.transient_orbits, ts.initial_temperature, ts.options);
    result.newton_iterations += part.newton_iterations;
    result.max_residual_w = std::max(result.max_residual_w, part.max_residual_w);
    if (part.status != solver::Status::Converged) {
      result.status = part.status;
      result.message = part.message + " (orbit case " + std::to_string(k + 1) + ")";
      break;
    }
    result.temperature.middleCols(begin, count) = part.temperature;
    result.temperature_rate.middleCols(begin, count) = part.temperature_rate;
  }
  return result;
}

}  // namespace

solver::ThermalNetwork thermalNetwork(const ThermalSettings& ts, const solver::ExchangeFactors& exchange) {
  const Eigen::Index n = ts.nodeCount(), nr = exchange.gr.rows();
  solver::ThermalNetwork net;
  net.gr = Eigen::MatrixXd::Zero(n, n);
  net.gr.topLeftCorner(nr, nr) = exchange.gr;
  for (const auto& c : ts.radiative_couplings) net.gr(c.row(), c.col()) += c.value();
  net.gr_space = Eigen::VectorXd::Zero(n);
  net.gr_space.head(nr) = exchange.gr_space;
  net.conductors.resize(n, n);
  net.conductors.setFromTriplets(ts.conductors.begin(), ts.conductors.end());
  net.capacitance = ts.capacitance;
  net.dissipation = ts.dissipation;
  net.fixed_temperature = ts.fixed_temperature;
  net.space_temperature = ts.space_temperature;
  return net;
}

HeatBalance heatBalance(const solver::ThermalNetwork& net, const solver::ThermalResult& solution,
                        const Eigen::MatrixXd& q_env) {
  HeatBalance b;
  b.flows = solver::heatFlows(net, solution, q_env);
  const solver::HeatFlows& f = b.flows;
  const std::array<const Eigen::MatrixXd*, 7> terms = {&q_env,         &f.emitted, &f.radiative, &f.conducted,
                                                       &f.dissipation, &f.stored,  &f.boundary};
  for (Eigen::Index p = 0; p < q_env.cols(); ++p)
    for (Eigen::Index i = 0; i < q_env.rows(); ++i) {
      double sum = 0.0, largest = 0.0;
      for (const Eigen::MatrixXd* m : terms) {
        sum += (*m)(i, p);
        largest = std::max(largest, std::abs((*m)(i, p)));
      }
      b.max_imbalance_w = std::max(b.max_imbalance_w, std::abs(sum));
      if (largest > 0) b.max_relative_imbalance = std::max(b.max_relative_imbalance, std::abs(sum) / largest);
    }
  return b;
}

ThermalSolution runThermal(const ThermalSettings& ts, const solver::ExchangeFactors& exchange, const SweepResult* sweep,
                           StageTimings& timings, std::ostream& progress) {
  const solver::ThermalNetwork net = thermalNetwork(ts, exchange);
  // Lumped nodes absorb nothing from the environment.
  Eigen::MatrixXd q_env = Eigen::MatrixXd::Zero(ts.nodeCount(), sweep ? sweep->absorbed_total.cols() : 1);
  if (sweep) q_env.topRows(ts.radiative_nodes) = sweep->absorbed_total;
  StageTimer timer(timings, Stage::Thermal);
  ThermalSolution out;
  out.node_names = ts.node_names;
  out.radiative_nodes = ts.radiative_nodes;
  if (ts.transient_orbits)
    out.solve = transientPerCase(ts, net, *sweep, q_env);
  else
    out.solve = solver::steadyStates(net, q_env, ts.options);
  timer.stop();
  const solver::ThermalResult& result = out.solve;
  if (result.status != solver::Status::Converged)
    throw NumericalError(std::string("temperatures ") + solver::toString(result.status) + ": " + result.message);
  out.heat = heatBalance(net, result, q_env);
  progress << "radnet: temperatures (" << (ts.transient_orbits ? "transient" : "steady state per position") << "), "
           << result.newton_iterations << " Newton iterations, largest heat-balance residual " << result.max_residual_w
           << " W; heat flows balance to " << out.heat.max_relative_imbalance << " of the largest term\n";
  return out;
}

}  // namespace radnet::cases
