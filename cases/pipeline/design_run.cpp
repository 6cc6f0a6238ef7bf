#include "cases/pipeline/design_run.hpp"

#include "cases/cluster/cluster.hpp"
#include "cases/pipeline/articulated.hpp"
#include "cases/pipeline/distributed.hpp"
#include "cases/pipeline/orbit_sweep.hpp"
#include "cases/pipeline/packing.hpp"
#include "cases/pipeline/radiative_network.hpp"
#include "cases/pipeline/thermal_run.hpp"
#include "solver/radiative/exchange.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <ostream>
#include <sstream>

namespace radnet::cases {
namespace {

const solver::ExchangeFactors& exchangeOf(const GeometryRunResult& r, int optics) {
  return optics == 0 ? *r.radiative.exchange : r.cases.optics_exchange[static_cast<size_t>(optics) - 1];
}

// An earlier case with the same orbits, attitude and environment up to S, a constant albedo
// and a uniform planet IR (the same load signature), whose irradiances case k scales instead
// of casting rays again; none when there is none or a factor would scale from zero. A planet
// IR that follows the Sun (day–night) is not proportional to S: it scales only at equal S.
struct LoadReuse {
  const SweepResult* from = nullptr;
  double direct = 1.0, albedo = 1.0, earth_ir = 1.0;
};
// The scales of a case's direct, albedo and planet IR loads that a reusing case multiplies.
std::array<double, 3> loadFactors(const OrbitSettings& o) {
  const orbits::EnvironmentOptions& e = o.environment;
  const double s = o.sweep.solar_constant_w_m2;
  return std::array<double, 3>{s, s * (e.albedo_by_latitude.empty() ? e.albedo : 1.0),
                               e.planet_ir.uniform() ? e.planet_ir.uniform_w_m2 : 1.0};
}

LoadReuse findReuse(const GeometryCase& c, int k, const std::vector<CaseRun>& runs) {
  const DesignCase& d = c.design_cases[static_cast<size_t>(k)];
  const auto factors = loadFactors;
  const auto day_night = [](const OrbitSettings& o) { return !o.environment.planet_ir.uniform(); };
  for (int j = 0; j < k; ++j) {
    const DesignCase& e = c.design_cases[static_cast<size_t>(j)];
    if (e.load_signature != d.load_signature || !runs[static_cast<size_t>(j)].sweep) continue;
    // Mirrors and windows carry part of the loads: only under the same ρs and τ.
    if (e.optics != d.optics && (c.optical_sets[static_cast<size_t>(e.optics)].own_specular ||
                                 c.optical_sets[static_cast<size_t>(d.optics)].own_specular))
      continue;
    const std::array<double, 3> from = factors(*e.orbit), to = factors(*d.orbit);
    if (!(from[0] > 0 && from[1] > 0 && from[2] > 0)) continue;
    if ((day_night(*e.orbit) || day_night(*d.orbit)) && from[0] != to[0]) continue;
    return {&*runs[static_cast<size_t>(j)].sweep, to[0] / from[0], to[1] / from[1], to[2] / from[2]};
  }
  return {};
}

// What the sky kernel's targets of case k's loads may lean on (orbits/loads.hpp,
// AbsorptanceRatios): each node's smallest α/ε and ε/α over every optical set (a later case
// may reuse the loads under other optics), none when optics are sampled or follow
// temperature; the cross terms weighted down by how much any case with the same load
// signature scales one load against another.
orbits::AbsorptanceRatios absorptanceRatios(const GeometryCase& c, int k) {
  orbits::AbsorptanceRatios r;
  const DesignCase& d = c.design_cases[static_cast<size_t>(k)];
  bool curves = false;
  for (const auto& [name, m] : c.materials) curves = curves || m.hasCurves();
  if (!curves && !c.optical_uncertainty && !c.optical_sets.empty()) {
    const Eigen::Index n = c.optical_sets[0].surface_absorptivity.size();
    r.min_alpha_over_epsilon = r.min_epsilon_over_alpha = Eigen::VectorXd::Constant(n, HUGE_VAL);
    for (const OpticalSet& set : c.optical_sets)
      for (Eigen::Index i = 0; i < n; ++i) {
        const double a = set.surface_absorptivity[i], e = set.surface_emissivity[i];
        // 0 where a value is 0 (no cross term: as if not known)
        r.min_alpha_over_epsilon[i] = std::min(r.min_alpha_over_epsilon[i], e > 0 ? a / e : 0.0);
        r.min_epsilon_over_alpha[i] = std::min(r.min_epsilon_over_alpha[i], a > 0 ? e / a : 0.0);
      }
  }
  const std::array<double, 3> from = loadFactors(*d.orbit);  // direct, albedo, IR
  for (const DesignCase& e : c.design_cases) {
    if (!e.orbit || e.load_signature != d.load_signature) continue;
    const std::array<double, 3> to = loadFactors(*e.orbit);
    if (!(from[0] > 0 && from[1] > 0 && from[2] > 0 && to[0] > 0 && to[1] > 0 && to[2] > 0)) continue;
    const double dr = to[0] / from[0], ar = to[1] / from[1], ir = to[2] / from[2];
    r.cross_weight = std::min({r.cross_weight, dr / ar, ir / ar, dr / ir, ar / ir});
  }
  return r;
}

// One design case's sweep on its optical set's cores (every rank: the loads are shared out
// within it).
void sweepCase(const DesignContext& ctx, int k, GeometryRunResult& r, std::vector<BandCores>& cores,
               std::vector<CaseRun>& runs, bool show_progress, std::ostream& progress) {
  CaseRun& run = runs[static_cast<size_t>(k)];
  const GeometryCase& c = ctx.c;
  const DesignCase& d = c.design_cases[static_cast<size_t>(k)];
  const OpticalSet& set = c.optical_sets[static_cast<size_t>(d.optics)];
  StageTimings& t = r.cases.timings[static_cast<size_t>(k)];
  if (c.design_cases.size() > 1)
    progress << "radnet: case " << k + 1 << "/" << c.design_cases.size() << " '" << d.name << "' (optics " << set.name
             << ")\n";
  if (!d.orbit) return;
  BandCores& bc = cores[static_cast<size_t>(d.optics)];
  if (!bc.solar) {
    StageTimer timer(t, Stage::BandSolves);
    bc = bandCores(networksOf(ctx, d.optics).radiative, set);
    r.cases.band_cores += 2;
  }
  // Turning parts: the loads are each configuration's own (a case could reuse them only at
  // the same angles); each position is solved in its configuration.
  const LoadReuse reuse = ctx.articulated ? LoadReuse{} : findReuse(c, k, runs);
  const SetNetworks nets = networksOf(ctx, d.optics);
  const orbits::AbsorptanceRatios absorptance = absorptanceRatios(c, k);
  run.sweep = runSweep({*d.orbit, ctx.caster, nets.radiative, *bc.solar, *bc.ir, ctx.solver, nets.view_factor_stderr,
                        reuse.from, reuse.direct, reuse.albedo, reuse.earth_ir, ctx.articulated, d.optics,
                        &nets.lost_view_factor_stderr, &absorptance},
                       t, show_progress, progress);
}

// The nodes whose ε or α follow temperature (materials with tables); null when no material
// has a table. GR for each new ε is a rank-|U| update of the case's own GR (the one
// eigendecomposition's, or the dense one), U the nodes with an ε table: O(n² |U|) a call.
std::shared_ptr<const solver::TemperatureOptics> temperatureOptics(const DesignContext& ctx, const OpticalSet& set,
                                                                   const Eigen::VectorXd& area,
                                                                   const solver::ExchangeFactors& nominal,
                                                                   const ThermalSettings& ts) {
  const GeometryCase& c = ctx.c;
  const Eigen::Index n = ts.nodeCount(), nr = set.emissivity.size();
  auto optics = std::make_shared<solver::TemperatureOptics>();
  optics->nominal_emissivity = optics->nominal_absorptivity = Eigen::VectorXd::Ones(n);
  // The surfaces' own ε, α: the tables give those; the network's ε̃ = ε/κ only inside GR.
  optics->nominal_emissivity.head(nr) = set.surface_emissivity;
  optics->nominal_absorptivity.head(nr) = set.surface_absorptivity;
  std::vector<int> varying;  // nodes whose ε changes
  for (Eigen::Index i = 0; i < nr; ++i) {
    const Material& m = c.materials.at(c.node_material[static_cast<size_t>(i)]);
    if (!m.hasCurves()) continue;
    optics->nodes.push_back(static_cast<int>(i));
    optics->emissivity.push_back(m.emissivity_curve);
    optics->absorptivity.push_back(m.absorptivity_curve);
    if (!m.emissivity_curve.warming.temperature_k.empty()) varying.push_back(static_cast<int>(i));
  }
  if (optics->nodes.empty()) return nullptr;
  auto update = std::make_shared<const solver::EmissivityUpdate>(nominal.dense(), set.emissivity, area, varying);
  // κ = 1 − ρs − τ of the IR band (1 where diffuse): a pure mirror (κ = 0) has ε = 0.
  const Eigen::VectorXd kappa = set.specular_ir.empty() ? Eigen::VectorXd::Ones(nr) : set.specular_ir.kappa();
  optics->exchange = [update, &ts, kappa, varying, network = set.emissivity](const Eigen::VectorXd& emissivity) {
    Eigen::VectorXd network_emissivity = network;  // the set's ε̃; the tables' nodes at ε(T)/κ
    for (int u : varying) network_emissivity[u] = kappa[u] > 0 ? std::min(1.0, emissivity[u] / kappa[u]) : 0.0;
    const solver::ExchangeFactors ex = (*update)(network_emissivity);
    if (ex.status != solver::Status::Converged)
      throw NumericalError(std::string("exchange factors for ε(T) ") + solver::toString(ex.status) + ": " + ex.message);
    return thermalExchange(ts, ex);
  };
  return optics;
}

// Design case k's temperatures, on the rank that owns the case.
ThermalOutcome solveCase(const DesignContext& ctx, int k, const GeometryRunResult& r, std::vector<CaseRun>& runs) {
  CaseRun& run = runs[static_cast<size_t>(k)];
  const DesignCase& d = ctx.c.design_cases[static_cast<size_t>(k)];
  const OpticalSet& set = ctx.c.optical_sets[static_cast<size_t>(d.optics)];
  const solver::ExchangeFactors& exchange = exchangeOf(r, d.optics);
  const SetNetworks nets = networksOf(ctx, d.optics);
  const double gr_truncation = exchange.from_pairs ? std::max(0.0, nets.radiative.pairs.probe_exchange_error) : 0.0;
  const ThermalErrorInputs errors{nets.view_factor_stderr, nets.lost_view_factor_stderr, set.emissivity, nets.area,
                                  gr_truncation};
  ThermalOutcome out;
  std::ostringstream log;
  std::vector<const solver::ExchangeFactors*> turned;  // parts that turn: each configuration's GR
  if (ctx.articulated && run.sweep)
    for (int j = 0; j < ctx.articulated->size(); ++j) turned.push_back(&ctx.articulated->exchange(j, d.optics, out.timings));
  try {
    out.thermal = runThermal(*run.settings, exchange, run.sweep ? &*run.sweep : nullptr, out.timings, log, &errors,
                             temperatureOptics(ctx, set, nets.area, exchange, *run.settings), turned);
  } catch (const NumericalError& e) {  // which design case failed, by name
    if (ctx.c.design_cases.size() < 2) throw;
    throw NumericalError("design case '" + d.name + "': " + e.what());
  }
  out.log = log.str();
  return out;
}

// Every case's temperatures: each MPI rank solves the cases it owns and hands them to the
// others; what each printed is printed in case order. The run's stage times get this
// rank's own thermal work (a case solved elsewhere adds 0 s here), each case its solver's.
void solveCases(const DesignContext& ctx, GeometryRunResult& r, std::vector<CaseRun>& runs, std::ostream& progress) {
  const GeometryCase& c = ctx.c;
  const int cases = static_cast<int>(c.design_cases.size());
  std::vector<ThermalOutcome> outcomes(static_cast<size_t>(cases));
  for (int k = 0; k < cases; ++k) {
    runs[static_cast<size_t>(k)].settings = caseThermalSettings(*c.thermal, c.design_cases[static_cast<size_t>(k)]);
    if (cluster::owns(k)) outcomes[static_cast<size_t>(k)] = solveCase(ctx, k, r, runs);
  }
  for (int k = 0; k < cases; ++k) {
    ThermalOutcome& o = outcomes[static_cast<size_t>(k)];
    const bool mine = cluster::owns(k);
    shareThermal(o, k % cluster::size());
    if (cases > 1)
      progress << "radnet: case " << k + 1 << "/" << cases << " '" << c.design_cases[static_cast<size_t>(k)].name
               << "': temperatures\n";
    progress << o.log;
    runs[static_cast<size_t>(k)].thermal = std::move(o.thermal);
    r.cases.timings[static_cast<size_t>(k)].addAll(o.timings);
    for (const auto& [stage, seconds] : o.timings.entries()) r.timings.add(stage, mine ? seconds : 0.0);
  }
}

// Every case's orbit statistics and, over the cases, each node's envelope and the case setting it.
void caseStatistics(const std::vector<CaseRun>& runs, DesignCasesResult& out) {
  if (runs.empty() || !runs.front().thermal) return;
  const int cases = static_cast<int>(runs.size());
  CaseTemperatures t;
  std::vector<double> weights;
  for (int k = 0; k < cases; ++k) {
    const CaseRun& run = runs[static_cast<size_t>(k)];
    const SweepResult* sweep = run.sweep ? &*run.sweep : nullptr;
    setCaseRow(t, k, cases, *run.thermal, sweep);
    const Eigen::VectorXd w = timeWeights(sweep, run.thermal->times_s, run.thermal->temperature().cols());
    weights.insert(weights.end(), w.data(), w.data() + w.size());
  }
  out.time_weight = Eigen::Map<const Eigen::VectorXd>(weights.data(), static_cast<Eigen::Index>(weights.size()));
  out.temperature_min = t.min;
  out.temperature_mean = t.mean;
  out.temperature_max = t.max;
  const Eigen::Index n = t.min.cols();
  out.envelope_min.resize(n);
  out.envelope_max.resize(n);
  out.envelope_min_case.resize(n);
  out.envelope_max_case.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::Index lo = 0, hi = 0;
    out.envelope_min[i] = t.min.col(i).minCoeff(&lo);
    out.envelope_max[i] = t.max.col(i).maxCoeff(&hi);
    out.envelope_min_case[i] = static_cast<int>(lo);
    out.envelope_max_case[i] = static_cast<int>(hi);
  }
}

}  // namespace

SetNetworks networksOf(const DesignContext& ctx, int optics) {
  const auto k = static_cast<size_t>(optics);
  if (k < ctx.own_networks.size() && ctx.own_networks[k]) {
    const OwnOpticsNetwork& own = *ctx.own_networks[k];
    return {own.radiative, own.view_factor_stderr, own.lost_view_factor_stderr, own.area};
  }
  return {ctx.radiative, ctx.view_factor_stderr, ctx.lost_view_factor_stderr, ctx.area};
}

BandCores bandCores(const RadiativeNetwork& radiative, const OpticalSet& set) {
  const Eigen::VectorXd one = Eigen::VectorXd::Ones(set.emissivity.size());
  BandCores cores;
  cores.solar =
      std::make_unique<solver::LowRankBandSolver>(radiative.solarNetwork(), radiative.pairs, one - set.absorptivity);
  cores.ir = std::make_unique<solver::LowRankBandSolver>(*radiative.network, radiative.pairs, one - set.emissivity);
  return cores;
}

ThermalSettings caseThermalSettings(const ThermalSettings& base, const DesignCase& d) {
  ThermalSettings ts = base;
  const double s = d.dissipation_scale;
  ts.dissipation *= s;
  for (solver::DissipationSchedule& schedule : ts.schedules) {
    schedule.sunlit_w *= s;
    schedule.eclipse_w *= s;
    for (double& p : schedule.power_w) p *= s;
  }
  // A per-node override is the node's whole dissipation: its schedules go.
  for (const auto& [node, watts] : d.dissipation) {
    ts.dissipation[node] = watts;
    ts.schedules.erase(std::remove_if(ts.schedules.begin(), ts.schedules.end(),
                                      [node = node](const solver::DissipationSchedule& q) { return q.node == node; }),
                       ts.schedules.end());
  }
  return ts;
}

SweepResult thermalForcing(const SweepResult& sweep, Eigen::MatrixXd absorbed_total) {
  SweepResult f;
  f.positions = sweep.positions;
  f.case_start = sweep.case_start;
  f.case_labels = sweep.case_labels;
  f.case_period_s = sweep.case_period_s;
  f.case_sweep_s = sweep.case_sweep_s;
  f.absorbed_total = std::move(absorbed_total);
  return f;
}

void setCaseRow(CaseTemperatures& t, int k, int cases, const ThermalSolution& thermal, const SweepResult* sweep) {
  const Eigen::MatrixXd& temperature = thermal.temperature();
  if (t.min.size() == 0)
    for (Eigen::MatrixXd* m : {&t.min, &t.mean, &t.max}) m->setZero(cases, temperature.rows());
  const OrbitStatistics s = orbitStatistics(temperature, timeWeights(sweep, thermal.times_s, temperature.cols()));
  t.min.row(k) = s.min.transpose();
  t.mean.row(k) = s.mean.transpose();
  t.max.row(k) = s.max.transpose();
}

void runDesignCases(const DesignContext& ctx, GeometryRunResult& r, std::vector<CaseRun>& runs, bool show_progress,
                    std::ostream& progress) {
  const GeometryCase& c = ctx.c;
  DesignCasesResult& out = r.cases;
  for (size_t k = 0; k < c.optical_sets.size(); ++k) {
    out.optics_names.push_back(c.optical_sets[k].name);
    if (k > 0)
      out.optics_exchange.push_back(exchangeFactors(networksOf(ctx, static_cast<int>(k)).radiative,
                                                    c.optical_sets[k].emissivity, ctx.solver, r.timings));
  }
  std::vector<BandCores> cores(c.optical_sets.size());
  runs.assign(c.design_cases.size(), CaseRun{});  // sized once: earlier cases' references stay valid
  out.timings.assign(c.design_cases.size(), StageTimings{});
  for (size_t k = 0; k < c.design_cases.size(); ++k) {
    out.names.push_back(c.design_cases[k].name);
    out.optics.push_back(c.optical_sets[static_cast<size_t>(c.design_cases[k].optics)].name);
    sweepCase(ctx, static_cast<int>(k), r, cores, runs, show_progress, progress);
  }
  for (const StageTimings& t : out.timings) r.timings.addAll(t);
  if (c.thermal) solveCases(ctx, r, runs, progress);
  out.orbit_case_start = {0};
  out.position_start = {0};
  for (size_t k = 0; k < runs.size(); ++k) {
    const CaseRun& run = runs[k];
    if (run.sweep) {
      if (!r.sweep) r.sweep = *run.sweep; else appendSweep(*r.sweep, *run.sweep);
    }
    if (run.thermal) {
      if (!r.thermal) r.thermal = *run.thermal; else appendThermal(*r.thermal, *run.thermal);
    }
    out.orbit_case_start.push_back(r.sweep ? r.sweep->caseCount() : static_cast<int>(k) + 1);
    out.position_start.push_back(r.sweep ? static_cast<int>(r.sweep->positions.size())
                                 : r.thermal ? static_cast<int>(r.thermal->times_s.size()) : 0);
  }
  if (r.sweep) summarizeUncertainty(*r.sweep, ctx.solver.accuracy, progress);
  caseStatistics(runs, out);
}

}  // namespace radnet::cases
