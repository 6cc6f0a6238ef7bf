#include "cases/output/summary.hpp"

#include <iomanip>
#include <ostream>

namespace radnet::cases {
namespace {

void printTimings(const StageTimings& timings, std::ostream& out) {
  out << "timings:";
  for (const auto& [stage, seconds] : timings.entries())
    out << " " << stageName(stage) << " " << std::setprecision(3) << seconds << " s;";
  out << "\n";
}

// Node min/mean/max of a (n × P) table, one row per node.
void printNodeTemperatures(const std::vector<std::string>& names, const Eigen::MatrixXd& t, std::ostream& out) {
  out << std::left << std::setw(20) << "node" << std::right << std::setw(10) << "min" << std::setw(10) << "mean"
      << std::setw(10) << "max"
      << "\n";
  for (size_t i = 0; i < names.size(); ++i) {
    const auto row = t.row(static_cast<Eigen::Index>(i));
    out << std::left << std::setw(20) << names[i] << std::right << std::fixed << std::setprecision(2) << std::setw(10)
        << row.minCoeff() << std::setw(10) << row.mean() << std::setw(10) << row.maxCoeff() << std::defaultfloat
        << "\n";
  }
}

void printSweepSummary(const std::vector<std::string>& names, const SweepResult& sw, std::ostream& out) {
  out << "orbit: " << sw.positions.size() << " positions; absorbed environmental power per node, W "
      << "(solar + albedo + Earth IR):\n";
  out << std::left << std::setw(20) << "node" << std::right << std::setw(12) << "min" << std::setw(12) << "mean"
      << std::setw(12) << "max" << std::setw(12) << "solar max" << std::setw(12) << "albedo max" << std::setw(12)
      << "IR mean"
      << "\n";
  for (size_t k = 0; k < names.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    out << std::left << std::setw(20) << names[k] << std::right << std::setprecision(5) << std::setw(12)
        << sw.absorbed_total.row(i).minCoeff() << std::setw(12) << sw.absorbed_total.row(i).mean() << std::setw(12)
        << sw.absorbed_total.row(i).maxCoeff() << std::setw(12) << sw.absorbed_solar.row(i).maxCoeff() << std::setw(12)
        << sw.absorbed_albedo.row(i).maxCoeff() << std::setw(12) << sw.absorbed_earth_ir.row(i).mean() << "\n";
  }
  out << "band residuals: solar " << sw.solar_residual << ", IR " << sw.ir_residual << "; solar energy balance error "
      << sw.energy_balance_error << "\n";
}

// Orbit means of each node's heat flows, W, positive into the node.
void printHeatBalance(const std::vector<std::string>& names, const HeatBalance& heat, const SweepResult* sweep,
                      std::ostream& out) {
  const solver::HeatFlows& f = heat.flows;
  const Eigen::Index P = f.stored.cols();
  const Eigen::VectorXd none = Eigen::VectorXd::Zero(f.stored.rows());
  Eigen::VectorXd environment = none;  // lumped nodes absorb nothing
  if (sweep) environment.head(sweep->absorbed_total.rows()) = sweep->absorbed_total.rowwise().mean();
  out << "heat flows, W (mean over " << P << " position(s); + into the node):\n"
      << std::left << std::setw(20) << "node" << std::right;
  for (const char* h : {"environment", "emitted", "radiative", "conducted", "dissipation", "stored", "boundary"})
    out << std::setw(12) << h;
  out << "\n";
  for (size_t k = 0; k < names.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    out << std::left << std::setw(20) << names[k] << std::right << std::setprecision(5);
    for (double v : {environment[i], f.emitted.row(i).mean(), f.radiative.row(i).mean(), f.conducted.row(i).mean(),
                     f.dissipation.row(i).mean(), f.stored.row(i).mean(), f.boundary.row(i).mean()})
      out << std::setw(12) << (v == 0.0 ? 0.0 : v);  // no "-0"
    out << "\n";
  }
  out << "heat balance: largest imbalance " << heat.max_imbalance_w << " W (" << heat.max_relative_imbalance
      << " of the largest term)\n";
}

std::string refinementNote(const solver::BandSolution& s, const solver::SolverSettings& settings, int rank) {
  if (s.refined) return " (refined, " + std::to_string(s.refine_iterations) + " CG iterations)";
  if (settings.refineEnabled()) return " (rank-" + std::to_string(rank) + " solve already within the tolerance)";
  return " (eigenvector radiosity at rank " + std::to_string(rank) + ", not refined)";
}

}  // namespace

void printNetworkSummary(const NetworkCase& c, const NetworkRunResult& r, std::ostream& out) {
  const solver::Network& net = *r.radiative.network;
  const solver::EigenPairs& pairs = r.radiative.pairs;
  out << "case " << c.name << ": " << net.size() << " nodes\n";
  out << std::left << std::setw(16) << "node" << std::right << std::setw(12) << "area m²" << std::setw(10) << "ρ"
      << std::setw(10) << "ε" << std::setw(14) << "M_o W/m²" << std::setw(14) << "M W/m²" << std::setw(14) << "H W/m²"
      << std::setw(12) << "F_space"
      << "\n";
  for (int i = 0; i < net.size(); ++i) {
    out << std::left << std::setw(16) << net.names()[static_cast<size_t>(i)] << std::right << std::setprecision(5)
        << std::setw(12) << net.area()[i] << std::setw(10) << c.reflectance[i] << std::setw(10);
    if (c.emissivity)
      out << (*c.emissivity)[i];
    else
      out << "-";
    out << std::setw(14) << c.initial_exitance[i] << std::setw(14) << r.solution.exitance(i, 0) << std::setw(14)
        << r.solution.irradiance(i, 0) << std::setw(12) << net.spaceViewFactor()[i] << "\n";
  }
  out << "eigenpairs: rank " << pairs.rank() << " of " << net.size() << " (" << solver::toString(pairs.method)
      << "), largest dropped |λ| ≤ " << pairs.dropped_bound << " m²\n";
  out << "residual ‖M_o − (I − S G) M‖/‖M_o‖ with the full G: " << std::scientific << std::setprecision(3)
      << r.solution.max_residual << std::defaultfloat << refinementNote(r.solution, c.solver, pairs.rank()) << "\n";
  if (r.thermal) {
    const auto& names = r.thermal->node_names;
    for (size_t i = 0; i < names.size(); ++i)
      out << "temperature " << names[i] << ": " << std::fixed << std::setprecision(3)
          << r.thermal->temperature()(static_cast<Eigen::Index>(i), 0) << std::defaultfloat << " K\n";
    printHeatBalance(names, r.thermal->heat, nullptr, out);
  }
  if (const auto& ex = r.radiative.exchange)
    out << "exchange factors GR (" << ex->method << "), Σ GR_space = " << ex->gr_space.sum() << " m²\n";
  printTimings(r.timings, out);
}

void printGeometrySummary(const GeometryCase& c, const GeometryRunResult& r, std::ostream& out) {
  const solver::Network& net = *r.radiative.network;
  const solver::ExchangeFactors& ex = *r.radiative.exchange;
  out << "case " << c.name << ": " << c.scene.faces().size() << " triangles, " << net.size() << " nodes\n";
  out << std::left << std::setw(20) << "node" << std::right << std::setw(12) << "area m²" << std::setw(8) << "ε"
      << std::setw(8) << "α" << std::setw(12) << "F_space" << std::setw(12) << "GR_space" << std::setw(12) << "max σ(F)"
      << "\n";
  for (int i = 0; i < net.size(); ++i) {
    out << std::left << std::setw(20) << net.names()[static_cast<size_t>(i)] << std::right << std::setprecision(5)
        << std::setw(12) << net.area()[i] << std::setw(8) << c.emissivity[i] << std::setw(8) << c.absorptivity[i]
        << std::setw(12) << net.spaceViewFactor()[i] << std::setw(12) << ex.gr_space[i] << std::setw(12)
        << (r.view_factor_stderr.cols() ? r.view_factor_stderr.row(i).maxCoeff() : 0.0) << "\n";
  }
  if (r.sweep) printSweepSummary(net.names(), *r.sweep, out);
  if (r.thermal) {
    const solver::ThermalResult& solve = r.thermal->solve;
    out << "temperatures, K (";
    if (c.thermal->periodic)
      out << "periodic transient, last of " << solve.orbits << " orbits, orbit-to-orbit change "
          << solve.periodic_residual_k << " K";
    else if (c.thermal->transient_orbits)
      out << "transient, last orbit";
    else
      out << "steady state per position";
    out << "):\n";
    printNodeTemperatures(r.thermal->node_names, r.thermal->temperature(), out);
    printHeatBalance(r.thermal->node_names, r.thermal->heat, r.sweep ? &*r.sweep : nullptr, out);
  }
  out << "view factors: " << r.total_rays << " rays, correction ≤ " << r.correction.max_change << " ("
      << r.correction.max_change_sigma << " σ); closure error " << r.correction.max_closure_error << "\n";
  out << "eigenpairs: rank " << r.radiative.pairs.rank() << " (" << solver::toString(r.radiative.pairs.method)
      << "); exchange factors: " << ex.method << "\n";
  printTimings(r.timings, out);
}

}  // namespace radnet::cases
