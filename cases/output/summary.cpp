#include "cases/output/summary.hpp"

#include "cases/output/node_table.hpp"
#include "cases/pipeline/case_merge.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>

namespace radnet::cases {
namespace {

// How the node tables of one summary are laid out.
struct Layout {
  NodeGroups groups;
  bool all = false;
  void print(const std::vector<std::string>& names, const std::vector<NodeColumn>& columns, std::ostream& out,
             int key_column = 0) const {
    NodeTableOptions o;
    o.all = all;
    o.key_column = key_column;
    printNodeTable(names, groups, columns, o, out);
  }
};

NodeColumn kelvin(const char* header, Eigen::VectorXd values, Aggregate a, int width = 10) {
  NodeColumn c{header, std::move(values), a};
  c.fixed = true;
  c.precision = 2;
  c.width = width;
  return c;
}

void printTimings(const StageTimings& timings, std::ostream& out) {
  out << "timings:";
  for (const auto& [stage, seconds] : timings.entries())
    out << " " << stageName(stage) << " " << std::setprecision(3) << seconds << " s;";
  out << "\n";
}

// Node min/mean/max of a (n × P) table, one row per node; ranked by the maximum. The mean is
// the time-weighted one `w` (P) of /solution/case_temperature_mean and radnet report.
void printNodeTemperatures(const std::vector<std::string>& names, const Eigen::MatrixXd& t, const Eigen::VectorXd& w,
                           const Layout& layout, std::ostream& out) {
  layout.print(names,
               {kelvin("min", t.rowwise().minCoeff(), Aggregate::Min), kelvin("mean", t * w, Aggregate::Mean),
                kelvin("max", t.rowwise().maxCoeff(), Aggregate::Max)},
               out, 2);
}

// The time weights of a run without an orbit: the trapezoid of its output times.
Eigen::VectorXd outputWeights(const ThermalSolution& t) { return timeWeights(nullptr, t.times_s, t.temperature().cols()); }

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

// The time weights of a design case's positions (its orbit means).
Eigen::VectorXd spanWeights(const SweepResult& sw, const Span& span) {
  std::vector<double> times;
  for (const auto& p : sw.positions) times.push_back(p.t_s);
  return timeWeights(&sw, times, span.count, span.first_case, span.end_case);
}

void printSweepSummary(const std::vector<std::string>& names, const SweepResult& sw, const Span& span,
                       const Layout& layout, std::ostream& out) {
  const auto cols = [&](const Eigen::MatrixXd& m) { return m.middleCols(span.begin, span.count); };
  const Eigen::MatrixXd total = cols(sw.absorbed_total);
  const Eigen::VectorXd w = spanWeights(sw, span);  // orbit means weighted by time, as everywhere
  out << "orbit: " << span.count << " positions; absorbed environmental power per node, W "
      << "(solar + albedo + Earth IR):\n";
  layout.print(names,
               {{"min", total.rowwise().minCoeff(), Aggregate::Sum},
                {"mean", total * w, Aggregate::Sum},
                {"max", total.rowwise().maxCoeff(), Aggregate::Sum},
                {"solar max", cols(sw.absorbed_solar).rowwise().maxCoeff(), Aggregate::Sum},
                {"albedo max", cols(sw.absorbed_albedo).rowwise().maxCoeff(), Aggregate::Sum},
                {"IR mean", cols(sw.absorbed_earth_ir) * w, Aggregate::Sum}},
               out, 1);
}

void printSweepQuality(const std::vector<std::string>& names, const SweepResult& sw, std::ostream& out) {
  out << "band residuals: solar " << sw.solar_residual << " (" << sw.solar_band_method << "), IR " << sw.ir_residual
      << " (" << sw.ir_band_method << "); solar energy balance error " << sw.energy_balance_error << "\n";
  const UncertaintySummary& u = sw.uncertainty;
  out << "uncertainty (1σ, of each node's orbit-maximum absorbed power): at most " << 100 * u.total << " %";
  if (u.worst_node >= 0) out << " (" << names[static_cast<size_t>(u.worst_node)] << ")";
  out << "; view factors " << 100 * u.view_factors << " %, loads " << 100 * u.loads << " %, truncation "
      << 100 * u.truncation << " %; accuracy asked " << 100 * u.accuracy << " %, " << u.nodes_over_budget
      << " node(s) over it\n";
}

// Orbit means of each node's heat flows, W, positive into the node, and each heater's duty.
void printHeatBalance(const ThermalSolution& thermal, const SweepResult* sweep, const Span& span, const Layout& layout,
                      std::ostream& out) {
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
      << "; + into the node):\n";
  const std::array<const char*, 8> headers = {"environment", "emitted", "radiative", "conducted",
                                              "dissipation", "heater",  "stored",    "boundary"};
  const std::array<const Eigen::MatrixXd*, 8> terms = {&environment,   &f.emitted, &f.radiative, &f.conducted,
                                                       &f.dissipation, &f.heater,  &f.stored,    &f.boundary};
  std::vector<NodeColumn> columns;
  for (size_t k = 0; k < terms.size(); ++k) columns.push_back({headers[k], *terms[k] * w, Aggregate::Sum});
  layout.print(thermal.node_names, columns, out, 0);
  const Eigen::MatrixXd duty = thermal.case_heater_duty.middleRows(span.first_case, span.end_case - span.first_case);
  for (size_t k = 0; k < thermal.heater_names.size(); ++k) {
    const auto h = static_cast<Eigen::Index>(k);
    // One definition: the mean power is the duty (time on, located to the switching) times the
    // heater's power; the table's heater column samples the power at the positions only.
    const double on = duty.col(h).maxCoeff();
    out << "heater " << thermal.heater_names[k] << ": duty " << std::setprecision(4) << 100.0 * on << " %, mean power "
        << on * (k < thermal.heater_rated_w.size() ? thermal.heater_rated_w[k] : 0.0) << " W\n";
  }
}

// Once per run (it is the run's largest over every case and position).
void printBalanceQuality(const ThermalSolution& thermal, std::ostream& out) {
  out << "heat balance: largest imbalance " << thermal.heat.max_imbalance_w << " W ("
      << thermal.heat.max_relative_imbalance << " of the largest term)\n";
}

std::string temperatureMode(const GeometryCase& c, const solver::ThermalResult& solve) {
  std::ostringstream m;
  if (c.thermal->periodic)
    m << "periodic transient, last of " << solve.orbits << " orbits, "
      << (solve.orbits_per_period > 1 ? "repeating every " + std::to_string(solve.orbits_per_period) +
                                            " orbits, differing from the others by "
          : solve.heater_cycle_unlocked ? "no period (a thermostat not locked to the orbit), change "
                                        : "orbit-to-orbit change ")
      << solve.periodic_residual_k << " K";
  else if (c.thermal->transient_orbits)
    m << "transient, last orbit";
  else if (c.thermal->duration_s)
    m << "transient without orbit over " << *c.thermal->duration_s << " s";
  else
    m << "steady state per position";
  return m.str();
}

// Per node, the hottest and the coldest over every design case, with the case.
void printEnvelope(const GeometryRunResult& r, const Layout& layout, std::ostream& out) {
  const DesignCasesResult& c = r.cases;
  out << "envelope over the design cases, K:\n";
  const auto caseNames = [&](const Eigen::VectorXi& index) {
    std::vector<std::string> names;
    for (Eigen::Index i = 0; i < index.size(); ++i) names.push_back(c.names[static_cast<size_t>(index[i])]);
    return names;
  };
  NodeColumn max_case{"case", {}, Aggregate::Max}, min_case{"case", {}, Aggregate::Min};
  max_case.text = caseNames(c.envelope_max_case), max_case.follows = 0, max_case.width = 16;
  min_case.text = caseNames(c.envelope_min_case), min_case.follows = 2, min_case.width = 16;
  layout.print(r.thermal->node_names,
               {kelvin("max", c.envelope_max, Aggregate::Max), max_case, kelvin("min", c.envelope_min, Aggregate::Min),
                min_case},
               out, 0);
}

void printOpticalUncertainty(const GeometryRunResult& r, const Layout& layout, std::ostream& out) {
  const OpticalUncertaintyResult& u = *r.optical_uncertainty;
  for (int k = 0; k < r.cases.caseCount(); ++k) {
    out << "optical uncertainty" << (r.cases.caseCount() > 1 ? " of case " + r.cases.names[static_cast<size_t>(k)] : "")
        << ", " << u.samples << " samples, K:\n";
    layout.print(r.thermal->node_names,
                 {kelvin("min 5 %", u.percentiles[0].row(k).transpose(), Aggregate::Min, 12),
                  kelvin("mean 50 %", u.percentiles[1].row(k).transpose(), Aggregate::Mean, 12),
                  kelvin("max 95 %", u.percentiles[2].row(k).transpose(), Aggregate::Max, 12)},
                 out, 2);
  }
}

std::string refinementNote(const solver::BandSolution& s, const solver::SolverSettings& settings, int rank) {
  if (s.method == "dense LU") return " (dense LU: predicted " + std::to_string(s.predicted_direct_s) + " s against " +
                                     std::to_string(s.predicted_refine_s) + " s of CG)";
  if (s.refined) return " (refined, " + std::to_string(s.refine_iterations) + " CG iterations)";
  if (settings.refineEnabled()) return " (rank-" + std::to_string(rank) + " solve already within the tolerance)";
  return " (eigenvector radiosity at rank " + std::to_string(rank) + ", not refined)";
}

}  // namespace

void printNetworkSummary(const NetworkCase& c, const NetworkRunResult& r, std::ostream& out, bool all_nodes) {
  const solver::Network& net = *r.radiative.network;
  const solver::EigenPairs& pairs = r.radiative.pairs;
  out << "case " << c.name << ": " << net.size() << " nodes\n";
  Layout layout{groupsByNamePrefix(net.names()), all_nodes};
  NodeColumn rho{"ρ", c.reflectance, Aggregate::Mean}, eps{"ε", {}, Aggregate::Mean};
  rho.width = 10, eps.width = 10;
  if (c.emissivity) eps.values = *c.emissivity;
  layout.print(net.names(),
               {{"area m²", net.area(), Aggregate::Sum}, rho, eps,
                {"M_o W/m²", c.initial_exitance, Aggregate::Mean, 5, false, 14},
                {"M W/m²", r.solution.exitance.col(0), Aggregate::Mean, 5, false, 14},
                {"H W/m²", r.solution.irradiance.col(0), Aggregate::Mean, 5, false, 14},
                {"F_space", net.spaceViewFactor(), Aggregate::Mean}},
               out, 4);
  out << "eigenpairs: rank " << pairs.rank() << " of " << net.size() << " (" << solver::toString(pairs.method)
      << ", " << pairs.rank_rule << "), largest dropped |λ| ≤ " << pairs.dropped_bound << " m²\n";
  out << "residual ‖M_o − (I − S G) M‖/‖M_o‖ with the full G: " << std::scientific << std::setprecision(3)
      << r.solution.max_residual << std::defaultfloat << refinementNote(r.solution, c.solver, pairs.rank()) << "\n";
  if (r.thermal) {
    const Layout thermal_layout{groupsByNamePrefix(r.thermal->node_names), all_nodes};
    out << "temperatures, K:\n";
    if (r.thermal->temperature().cols() == 1)
      thermal_layout.print(r.thermal->node_names, {kelvin("T", r.thermal->temperature().col(0), Aggregate::Max, 12)}, out);
    else  // a transient without orbit: its range over the run, not its first output
      printNodeTemperatures(r.thermal->node_names, r.thermal->temperature(), outputWeights(*r.thermal), thermal_layout, out);
    printHeatBalance(*r.thermal, nullptr, Span{0, 1, 0, r.thermal->temperature().cols()}, thermal_layout, out);
    printBalanceQuality(*r.thermal, out);
  }
  if (const auto& ex = r.radiative.exchange)
    out << "exchange factors GR (" << ex->method << "), Σ GR_space = " << ex->gr_space.sum() << " m²\n";
  printTimings(r.timings, out);
}

void printImportedSummary(const ImportedCase& c, const ImportRunResult& r, std::ostream& out, bool all_nodes) {
  const ThermalSolution& t = r.thermal;
  out << "case " << c.name << ": " << t.node_names.size() << " nodes imported from " << c.source << "\n";
  const Layout layout{groupsByNamePrefix(t.node_names), all_nodes};
  out << "temperatures, K:\n";
  if (t.temperature().cols() == 1)
    layout.print(t.node_names, {kelvin("T", t.temperature().col(0), Aggregate::Max, 12)}, out);
  else
    printNodeTemperatures(t.node_names, t.temperature(), outputWeights(t), layout, out);
  printHeatBalance(t, nullptr, Span{0, 1, 0, t.temperature().cols()}, layout, out);
  printBalanceQuality(t, out);
  printTimings(r.timings, out);
}

void printGeometrySummary(const GeometryCase& c, const GeometryRunResult& r, std::ostream& out, bool all_nodes) {
  const solver::Network& net = *r.radiative.network;
  const solver::ExchangeFactors& ex = *r.radiative.exchange;
  out << "case " << c.name << ": " << c.scene.faces().size() << " triangles, " << net.size() << " nodes\n";
  const Layout layout{groupsByPrimitive(c.scene, net.names()), all_nodes};
  const Layout thermal_layout{r.thermal ? groupsByPrimitive(c.scene, r.thermal->node_names) : NodeGroups{}, all_nodes};
  NodeColumn eps{"ε", c.surface_emissivity, Aggregate::Mean}, alpha{"α", c.surface_absorptivity, Aggregate::Mean};
  eps.width = alpha.width = 8;
  layout.print(net.names(),
               {{"area m²", r.radiative.surfaceArea(), Aggregate::Sum}, eps, alpha,
                {"F_space", net.spaceViewFactor(), Aggregate::Mean},
                {"GR_space", ex.gr_space, Aggregate::Sum},
                {"max σ(F)", r.row_stderr_max, Aggregate::Max}},
               out, 0);
  const int cases = r.cases.caseCount();
  if (cases > 1)
    out << "design cases: " << cases << " on " << r.cases.eigendecompositions << " eigendecomposition"
        << (r.cases.eigendecompositions == 1 ? "" : "s") << ", "
        << r.cases.band_cores << " band cores\n";
  if (r.thermal && cases > 1) printEnvelope(r, thermal_layout, out);
  for (int k = 0; k < cases; ++k) {
    const Span span = caseSpan(r, k);
    if (cases > 1)
      out << "case " << r.cases.names[static_cast<size_t>(k)] << " (optics " << r.cases.optics[static_cast<size_t>(k)]
          << ", dissipation × " << c.design_cases[static_cast<size_t>(k)].dissipation_scale << "):\n";
    if (r.sweep) printSweepSummary(net.names(), *r.sweep, span, layout, out);
    if (r.thermal) {
      out << "temperatures, K (" << temperatureMode(c, r.thermal->solve) << "):\n";
      const Eigen::VectorXd w = r.sweep ? spanWeights(*r.sweep, span) : outputWeights(*r.thermal);
      printNodeTemperatures(r.thermal->node_names, r.thermal->temperature().middleCols(span.begin, span.count), w,
                            thermal_layout, out);
      printHeatBalance(*r.thermal, r.sweep ? &*r.sweep : nullptr, span, thermal_layout, out);
    }
  }
  if (r.thermal) printBalanceQuality(*r.thermal, out);
  if (r.sweep) printSweepQuality(net.names(), *r.sweep, out);
  if (r.optical_uncertainty) printOpticalUncertainty(r, thermal_layout, out);
  out << "view factors: ";
  if (r.exact)
    out << r.exact->pairs_unoccluded + r.exact->pairs_occluded << " patch pairs exact ("
        << r.exact->pairs_occluded << " occluded), " << r.exact->sampled_rows << " rows by rays, ";
  out << r.total_rays << " rays, correction ≤ " << r.correction.max_change << " ("
      << r.correction.max_change_sigma << " σ); closure error " << r.correction.max_closure_error << "\n";
  if (r.articulation && !r.articulation->vertices.empty())
    out << "articulation: " << r.articulation->vertices.size() << " configurations on the one decomposition, "
        << r.articulation->recast_rows << " rows recomputed in each (" << r.articulation->integrated_rows
        << " integrated: " << r.articulation->pairs << " patch pairs; the others by rays: " << r.articulation->rays
        << " rays traced again), update ranks up to "
        << *std::max_element(r.articulation->update_rank.begin(), r.articulation->update_rank.end()) << "\n";
  const solver::EigenPairs& pairs = r.radiative.pairs;
  out << "eigenpairs: rank " << pairs.rank() << " (" << solver::toString(pairs.method) << ", " << pairs.rank_rule;
  if (pairs.probe_residual >= 0) out << "; probe residual " << pairs.probe_residual;
  if (pairs.probe_exchange_error >= 0) out << ", GR error " << pairs.probe_exchange_error;
  out << "); exchange factors: " << ex.method << "\n";
  printTimings(r.timings, out);
}

}  // namespace radnet::cases
