#include "cases/output/summary.hpp"

#include "cases/pipeline/case_merge.hpp"

#include <array>
#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>

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

// The part of a run one design case makes: its orbit cases (rows of case_heater_duty
// without a sweep) and its positions (columns).
struct Span {
  int first_case = 0, end_case = 0;
  Eigen::Index begin = 0, count = 0;
};

Span caseSpan(const GeometryRunResult& r, int k) {
  const DesignCasesResult& c = r.cases;
  const auto at = [](const std::vector<int>& v, int i) { return v[static_cast<size_t>(i)]; };
  return {at(c.orbit_case_start, k), at(c.orbit_case_start, k + 1), at(c.position_start, k),
          at(c.position_start, k + 1) - at(c.position_start, k)};
}

void printSweepSummary(const std::vector<std::string>& names, const SweepResult& sw, const Span& span,
                       std::ostream& out) {
  const auto cols = [&](const Eigen::MatrixXd& m) { return m.middleCols(span.begin, span.count); };
  const Eigen::MatrixXd total = cols(sw.absorbed_total), solar = cols(sw.absorbed_solar),
                        albedo = cols(sw.absorbed_albedo), ir = cols(sw.absorbed_earth_ir);
  out << "orbit: " << span.count << " positions; absorbed environmental power per node, W "
      << "(solar + albedo + Earth IR):\n";
  out << std::left << std::setw(20) << "node" << std::right << std::setw(12) << "min" << std::setw(12) << "mean"
      << std::setw(12) << "max" << std::setw(12) << "solar max" << std::setw(12) << "albedo max" << std::setw(12)
      << "IR mean"
      << "\n";
  for (size_t k = 0; k < names.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    out << std::left << std::setw(20) << names[k] << std::right << std::setprecision(5) << std::setw(12)
        << total.row(i).minCoeff() << std::setw(12) << total.row(i).mean() << std::setw(12) << total.row(i).maxCoeff()
        << std::setw(12) << solar.row(i).maxCoeff() << std::setw(12) << albedo.row(i).maxCoeff() << std::setw(12)
        << ir.row(i).mean() << "\n";
  }
}

void printSweepQuality(const std::vector<std::string>& names, const SweepResult& sw, std::ostream& out) {
  out << "band residuals: solar " << sw.solar_residual << ", IR " << sw.ir_residual << "; solar energy balance error "
      << sw.energy_balance_error << "\n";
  const UncertaintySummary& u = sw.uncertainty;
  out << "uncertainty (1σ, of each node's orbit-maximum absorbed power): at most " << 100 * u.total << " %";
  if (u.worst_node >= 0) out << " (" << names[static_cast<size_t>(u.worst_node)] << ")";
  out << "; view factors " << 100 * u.view_factors << " %, loads " << 100 * u.loads << " %, truncation "
      << 100 * u.truncation << " %; accuracy asked " << 100 * u.accuracy << " %, " << u.nodes_over_budget
      << " node(s) over it\n";
}

// Orbit means of each node's heat flows, W, positive into the node, and each heater's duty.
void printHeatBalance(const ThermalSolution& thermal, const SweepResult* sweep, const Span& span, std::ostream& out) {
  const solver::HeatFlows& all = thermal.heat.flows;
  const Eigen::Index P = span.count;
  // Without a sweep the case's own output times (a transient without an orbit) weigh it.
  const std::vector<double> times =
      sweep ? thermal.times_s
            : std::vector<double>(thermal.times_s.begin() + span.begin, thermal.times_s.begin() + span.begin + P);
  const Eigen::VectorXd w = timeWeights(sweep, times, P, span.first_case, span.end_case);
  const auto cols = [&](const Eigen::MatrixXd& m) { return Eigen::MatrixXd(m.middleCols(span.begin, P)); };
  solver::HeatFlows f;
  for (auto member : {&solver::HeatFlows::emitted, &solver::HeatFlows::radiative, &solver::HeatFlows::conducted,
                      &solver::HeatFlows::dissipation, &solver::HeatFlows::heater, &solver::HeatFlows::stored,
                      &solver::HeatFlows::boundary})
    f.*member = cols(all.*member);
  Eigen::MatrixXd environment = Eigen::MatrixXd::Zero(f.stored.rows(), P);  // lumped nodes absorb nothing
  if (sweep) environment.topRows(sweep->absorbed_total.rows()) = cols(sweep->absorbed_total);
  out << "heat flows, W (" << (sweep ? "orbit mean" : P > 1 ? "mean over the run" : "steady state")
      << "; + into the node):\n"
      << std::left << std::setw(20) << "node" << std::right;
  for (const char* h :
       {"environment", "emitted", "radiative", "conducted", "dissipation", "heater", "stored", "boundary"})
    out << std::setw(12) << h;
  out << "\n";
  const std::array<const Eigen::MatrixXd*, 8> terms = {&environment,   &f.emitted, &f.radiative, &f.conducted,
                                                       &f.dissipation, &f.heater,  &f.stored,    &f.boundary};
  for (size_t k = 0; k < thermal.node_names.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    out << std::left << std::setw(20) << thermal.node_names[k] << std::right << std::setprecision(5);
    for (const Eigen::MatrixXd* m : terms) {
      const double v = m->row(i).dot(w);
      out << std::setw(12) << (std::abs(v) < 1e-12 * (1 + std::abs(environment.row(i).dot(w))) ? 0.0 : v);
    }
    out << "\n";
  }
  out << "heat balance: largest imbalance " << thermal.heat.max_imbalance_w << " W ("
      << thermal.heat.max_relative_imbalance << " of the largest term)\n";
  const Eigen::MatrixXd duty = thermal.case_heater_duty.middleRows(span.first_case, span.end_case - span.first_case);
  for (size_t k = 0; k < thermal.heater_names.size(); ++k) {
    const auto h = static_cast<Eigen::Index>(k);
    out << "heater " << thermal.heater_names[k] << ": duty " << std::setprecision(4) << 100.0 * duty.col(h).maxCoeff()
        << " %, mean power " << thermal.solve.heater_power.row(h).segment(span.begin, P).dot(w) << " W\n";
  }
}

std::string temperatureMode(const GeometryCase& c, const solver::ThermalResult& solve) {
  std::ostringstream m;
  if (c.thermal->periodic)
    m << "periodic transient, last of " << solve.orbits << " orbits, orbit-to-orbit change " << solve.periodic_residual_k
      << " K";
  else if (c.thermal->transient_orbits)
    m << "transient, last orbit";
  else if (c.thermal->duration_s)
    m << "transient without orbit over " << *c.thermal->duration_s << " s";
  else
    m << "steady state per position";
  return m.str();
}

// Per node, the hottest and the coldest over every design case, with the case.
void printEnvelope(const GeometryRunResult& r, std::ostream& out) {
  const DesignCasesResult& c = r.cases;
  out << "envelope over the design cases, K:\n"
      << std::left << std::setw(20) << "node" << std::right << std::setw(10) << "max" << "  " << std::left
      << std::setw(14) << "case" << std::right << std::setw(10) << "min" << "  " << std::left << std::setw(14) << "case"
      << "\n";
  for (size_t k = 0; k < r.thermal->node_names.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    out << std::left << std::setw(20) << r.thermal->node_names[k] << std::right << std::fixed << std::setprecision(2)
        << std::setw(10) << c.envelope_max[i] << "  " << std::left << std::setw(14)
        << c.names[static_cast<size_t>(c.envelope_max_case[i])] << std::right << std::setw(10) << c.envelope_min[i]
        << "  " << std::left << std::setw(14) << c.names[static_cast<size_t>(c.envelope_min_case[i])]
        << std::defaultfloat << std::right << "\n";
  }
}

void printOpticalUncertainty(const GeometryRunResult& r, std::ostream& out) {
  const OpticalUncertaintyResult& u = *r.optical_uncertainty;
  const auto& names = r.thermal->node_names;
  for (int k = 0; k < r.cases.caseCount(); ++k) {
    out << "optical uncertainty" << (r.cases.caseCount() > 1 ? " of case " + r.cases.names[static_cast<size_t>(k)] : "")
        << ", " << u.samples << " samples, K:\n"
        << std::left << std::setw(20) << "node" << std::right << std::setw(12) << "min 5 %" << std::setw(12)
        << "mean 50 %" << std::setw(12) << "max 95 %" << "\n";
    for (size_t j = 0; j < names.size(); ++j) {
      const auto i = static_cast<Eigen::Index>(j);
      out << std::left << std::setw(20) << names[j] << std::right << std::fixed << std::setprecision(2)
          << std::setw(12) << u.percentiles[0](k, i) << std::setw(12) << u.percentiles[1](k, i) << std::setw(12)
          << u.percentiles[2](k, i) << std::defaultfloat << "\n";
    }
  }
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
    printHeatBalance(*r.thermal, nullptr, Span{0, 1, 0, r.thermal->temperature().cols()}, out);
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
  const int cases = r.cases.caseCount();
  if (cases > 1)
    out << "design cases: " << cases << " on " << r.cases.eigendecompositions << " eigendecomposition, "
        << r.cases.band_cores << " band cores\n";
  if (r.thermal && cases > 1) printEnvelope(r, out);
  for (int k = 0; k < cases; ++k) {
    const Span span = caseSpan(r, k);
    if (cases > 1)
      out << "case " << r.cases.names[static_cast<size_t>(k)] << " (optics " << r.cases.optics[static_cast<size_t>(k)]
          << ", dissipation × " << c.design_cases[static_cast<size_t>(k)].dissipation_scale << "):\n";
    if (r.sweep) printSweepSummary(net.names(), *r.sweep, span, out);
    if (r.thermal) {
      out << "temperatures, K (" << temperatureMode(c, r.thermal->solve) << "):\n";
      printNodeTemperatures(r.thermal->node_names, r.thermal->temperature().middleCols(span.begin, span.count), out);
      printHeatBalance(*r.thermal, r.sweep ? &*r.sweep : nullptr, span, out);
    }
  }
  if (r.sweep) printSweepQuality(net.names(), *r.sweep, out);
  if (r.optical_uncertainty) printOpticalUncertainty(r, out);
  out << "view factors: ";
  if (r.exact)
    out << r.exact->pairs_unoccluded + r.exact->pairs_occluded << " patch pairs exact ("
        << r.exact->pairs_occluded << " occluded), " << r.exact->sampled_rows << " rows by rays, ";
  out << r.total_rays << " rays, correction ≤ " << r.correction.max_change << " ("
      << r.correction.max_change_sigma << " σ); closure error " << r.correction.max_closure_error << "\n";
  out << "eigenpairs: rank " << r.radiative.pairs.rank() << " (" << solver::toString(r.radiative.pairs.method)
      << "); exchange factors: " << ex.method << "\n";
  printTimings(r.timings, out);
}

}  // namespace radnet::cases
