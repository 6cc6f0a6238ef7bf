#include "cases/pipeline/orbit_sweep.hpp"

#include "cases/cluster/cluster.hpp"
#include "cases/config/errors.hpp"
#include "cases/pipeline/case_merge.hpp"
#include "cases/pipeline/distributed.hpp"
#include "cases/pipeline/progress.hpp"
#include "cases/pipeline/articulated.hpp"
#include "geometry/irradiance/sky_kernel.hpp"
#include "solver/radiative/uncertainty.hpp"

#include <map>
#include <ostream>

namespace radnet::cases {
namespace {

// The relative residual a band on a network of its own (not the decomposed G̃) is solved to
// when the case keeps rank-k answers (refine tolerance 0).
constexpr double kOwnNetworkTolerance = 1e-8;

// The refinement tolerance of a band solve on `band`: the case's, or, on a network the
// decomposition does not describe (the solar band's own), at least kOwnNetworkTolerance: the
// core only preconditions it.
double bandTolerance(const RadiativeNetwork& radiative, const solver::Network& band, double tol) {
  return &band == radiative.network.get() ? tol : (tol > 0 ? tol : kOwnNetworkTolerance);
}

// One band for all positions at once: M_o = ρ ∘ E (n×cols); the solution and the absorbed
// power (1 − ρ) A (E + H), W.
struct BandOutcome {
  solver::BandSolution solution;
  Eigen::MatrixXd absorbed;
};

BandOutcome solveBand(const solver::LowRankBandSolver& band, const solver::Network& net,
                      const Eigen::MatrixXd& irradiance, double refine_tol, const char* name) {
  BandOutcome out;
  const Eigen::VectorXd& rho = band.reflectance();
  out.solution = band.solve(rho.asDiagonal() * irradiance, refine_tol);
  const solver::BandSolution& sol = out.solution;
  if (sol.status != solver::Status::Converged)
    throw NumericalError(std::string(name) + " band solve " + solver::toString(sol.status) + ": " + sol.message);
  const Eigen::VectorXd absorptance = Eigen::VectorXd::Ones(net.size()) - rho;
  out.absorbed = absorptance.cwiseProduct(net.area()).asDiagonal() * (irradiance + sol.irradiance);
  return out;
}

// Orbit case k's irradiances from the earlier case in.reuse, scaled: direct ∝ S, albedo
// ∝ S a, Earth IR ∝ OLR, each σ with it (the rays, shadows and view factors are the same).
orbits::EnvironmentLoads scaledLoads(const SweepInputs& in, int k) {
  const SweepResult& from = *in.reuse;
  const int begin = from.case_start[static_cast<size_t>(k)], count = from.case_start[static_cast<size_t>(k) + 1] - begin;
  const orbits::EnvironmentLoads& e = from.irradiance;
  orbits::EnvironmentLoads out;
  out.direct = in.direct_ratio * e.direct.middleCols(begin, count);
  out.direct_stderr = in.direct_ratio * e.direct_stderr.middleCols(begin, count);
  out.albedo = in.albedo_ratio * e.albedo.middleCols(begin, count);
  out.albedo_stderr = in.albedo_ratio * e.albedo_stderr.middleCols(begin, count);
  out.earth_ir = in.earth_ir_ratio * e.earth_ir.middleCols(begin, count);
  out.earth_ir_stderr = in.earth_ir_ratio * e.earth_ir_stderr.middleCols(begin, count);
  out.earth_view_factor = e.earth_view_factor.middleCols(begin, count);
  out.shadow_cell_m = e.shadow_cell_m;
  return out;
}

// Sweeps and loads each orbit case (an epoch × beta combination) on its own, then joins
// the positions of all cases into one (n × P) set of irradiances.
// What the loads stage cast, for the progress log.
void describeLoads(const orbits::EnvironmentLoads& loads, int positions, std::ostream& progress) {
  progress << "radnet: loads: ";
  if (loads.planet_kernel)
    progress << "sky kernel of " << loads.kernel_rays << " rays (cast once for " << positions << " positions), "
             << loads.planet_rays << " planet rays for " << loads.kernel_fallbacks
             << " node-positions over the error target, ";
  else
    progress << loads.planet_rays << " planet rays (cast " << loads.planet_casts << " time(s) for " << positions
             << " positions), ";
  progress << loads.shadow_rays << " shadow rays";
  if (loads.shadow_cell_m > 0) progress << " (grid spacing " << loads.shadow_cell_m * 1e3 << " mm)";
  progress << "\n";
}

// Orbit case `orbit`'s loads at `positions` on one caster (under MPI each rank its sun
// positions and planet nodes, then joined).
// `sun` and `planet` (empty: all) restrict the positions whose direct load and the nodes
// whose planet loads are computed; the rest stay 0.
orbits::EnvironmentLoads loadPositions(const SweepInputs& in, const geometry::RayCaster& caster,
                                       const orbits::Orbit& orbit, const std::vector<orbits::SweepPosition>& positions,
                                       geometry::SkyKernel& sky_kernel, bool show_progress, std::ostream& progress,
                                       std::vector<char> sun = {}, std::vector<char> planet = {}) {
  const OrbitSettings& o = in.orbit;
  const Eigen::VectorXd& area = in.radiative.surfaceArea();  // irradiance per m² of the surfaces themselves
  orbits::EnvironmentOptions env = o.environment;
  env.solar_specular = in.radiative.solar_specular;
  env.ir_specular = in.radiative.ir_specular;
  env.sky_kernel_cache = &sky_kernel;
  if (in.absorptance) env.absorptance = *in.absorptance;
  // Each node's blocked share from the view factors (1 − F_space: every other node and
  // inactive surface), where they are this caster's geometric ones: not with mirrors or
  // windows (the network's F̃ is then E^s κ) nor turning parts (each configuration's own).
  if (in.lost_view_factor_stderr && in.lost_view_factor_stderr->size() == area.size() && !in.articulated &&
      in.radiative.surface_area.size() == 0) {
    env.blocked_share = (1.0 - in.radiative.network->spaceViewFactor().array()).matrix();
    env.blocked_share_stderr = *in.lost_view_factor_stderr;
  }
  // Turning parts: a configuration holds a few positions; where the planet stays put in the
  // body frame (nadir) their planet rays are cast once, cheaper than a sky kernel of the
  // configuration's own. Where it moves, rays would be cast again at every position, for the
  // rows that stay put as for the turning ones: auto keeps its choice, the kernel (the
  // 2,006-node tracking wings flown inertial: 617 M planet rays and 59 s of loads against the
  // kernels' 5.9 M rays and 1.0 s).
  if (in.articulated && env.planet_method == orbits::EnvironmentOptions::PlanetMethod::Auto &&
      orbits::earthFixedInBody(o.attitude))
    env.planet_method = orbits::EnvironmentOptions::PlanetMethod::Rays;
  if (show_progress) env.progress = progressBar(progress, "orbit loads", "positions");
  if (cluster::distributed()) {  // each rank its share of what is asked
    const std::vector<char> owned_positions = cluster::ownedMask(static_cast<long long>(positions.size()));
    const std::vector<char> owned_nodes = cluster::ownedMask(area.size());
    if (sun.empty()) sun = owned_positions;
    else for (size_t p = 0; p < sun.size(); ++p) sun[p] = sun[p] && owned_positions[p];
    if (planet.empty()) planet = owned_nodes;
    else for (size_t i = 0; i < planet.size(); ++i) planet[i] = planet[i] && owned_nodes[i];
  }
  env.sun_positions = std::move(sun);
  env.planet_nodes = std::move(planet);
  orbits::EnvironmentLoads loads = orbits::environmentLoads(caster, area, positions, orbits::earthFixedInBody(o.attitude),
                                                            orbit.body().equatorial_radius_m, env);
  joinLoads(loads);
  return loads;
}

// The positions of one orbit case with turning parts: each configuration's positions loaded
// on its own caster, placed back in order.
orbits::EnvironmentLoads articulatedLoads(const SweepInputs& in, const orbits::Orbit& orbit,
                                          const std::vector<orbits::SweepPosition>& positions,
                                          const std::vector<int>& config, std::map<int, geometry::SkyKernel>& kernels,
                                          std::ostream& progress) {
  std::map<int, std::vector<int>> columns;
  for (size_t p = 0; p < config.size(); ++p) columns[config[p]].push_back(static_cast<int>(p));
  // A node whose row no turn changes (its triangles face away from every swept volume) sees
  // the planet the same in every configuration: its planet loads once, on the base geometry;
  // each configuration's the turning rows' and its positions' direct sunlight.
  const std::vector<char>& turning = in.articulated->rows();
  std::vector<char> still(turning.size());
  for (size_t i = 0; i < turning.size(); ++i) still[i] = !turning[i];
  orbits::EnvironmentLoads loads;
  for (const auto& [k, cols] : columns) {
    std::vector<orbits::SweepPosition> some;
    for (int p : cols) some.push_back(positions[static_cast<size_t>(p)]);
    const orbits::EnvironmentLoads part =
        loadPositions(in, *in.articulated->at(k).caster, orbit, some, kernels[k], false, progress, {}, turning);
    placeLoads(loads, part, cols, static_cast<Eigen::Index>(positions.size()));
  }
  addLoads(loads, loadPositions(in, *in.articulated->at(0).caster, orbit, positions, kernels[-1], false, progress,
                                std::vector<char>(positions.size(), 0), still));
  return loads;
}

// Sweeps and loads each orbit case (an epoch × beta combination) on its own, then joins
// the positions of all cases into one (n × P) set of irradiances.
void sweepAndLoad(const SweepInputs& in, SweepResult& sw, StageTimings& timings, bool show_progress,
                  std::ostream& progress) {
  const OrbitSettings& o = in.orbit;
  std::vector<orbits::EnvironmentLoads> parts;
  geometry::SkyKernel sky_kernel;  // one per geometry: every orbit case's planet loads
  std::map<int, geometry::SkyKernel> configuration_kernels;  // turning parts: one per configuration
  for (size_t k = 0; k < o.cases.size(); ++k) {
    const orbits::Orbit& orbit = *o.cases[k].orbit;
    StageTimer t_orbit(timings, Stage::Orbit);
    const std::vector<orbits::SweepPosition> positions = orbits::sweepOrbit(orbit, o.attitude, o.sweep);
    t_orbit.stop();
    int events = 0;
    for (const auto& p : positions) events += p.event;
    progress << "radnet: orbit " << k + 1 << "/" << o.cases.size() << " (" << o.description << ", " << o.cases[k].label
             << "), nodal period " << orbit.nodalPeriod() << " s, " << positions.size() << " positions (" << events
             << " eclipse entries/exits inserted)\n";
    std::vector<int> config;
    if (in.articulated) {
      Eigen::MatrixXd angles;
      config = in.articulated->configure(positions, angles, timings, progress);
      Eigen::MatrixXd joined(sw.articulation_angle.rows() + angles.rows(), angles.cols());
      if (sw.articulation_angle.rows()) joined.topRows(sw.articulation_angle.rows()) = sw.articulation_angle;
      joined.bottomRows(angles.rows()) = angles;
      sw.articulation_angle = std::move(joined);
      sw.configuration.insert(sw.configuration.end(), config.begin(), config.end());
    }
    StageTimer t_loads(timings, Stage::EnvironmentLoads);
    if (in.reuse)
      parts.push_back(scaledLoads(in, static_cast<int>(k)));
    else if (in.articulated)
      parts.push_back(articulatedLoads(in, orbit, positions, config, configuration_kernels, progress));
    else
      parts.push_back(loadPositions(in, in.caster, orbit, positions, sky_kernel, show_progress, progress));
    sw.case_start.push_back(static_cast<int>(sw.positions.size()));
    sw.case_labels.push_back(o.cases[k].label);
    sw.central_body = orbit.body().name;
    sw.planet_ir_model = o.environment.planet_ir.describe();
    sw.case_period_s.push_back(orbit.nodalPeriod());
    sw.case_sweep_s.push_back(orbit.nodalPeriod() * o.sweep.orbits);
    sw.positions.insert(sw.positions.end(), positions.begin(), positions.end());
  }
  const int P = static_cast<int>(sw.positions.size());
  sw.case_start.push_back(P);
  for (const orbits::EnvironmentLoads& part : parts) appendLoads(sw.irradiance, part);
  if (in.reuse) {
    progress << "radnet: loads: the irradiances of an earlier case with the same orbit and attitude, times "
             << in.direct_ratio << " (direct), " << in.albedo_ratio << " (albedo), " << in.earth_ir_ratio
             << " (planet IR): no rays cast\n";
    return;
  }
  describeLoads(sw.irradiance, P, progress);
}

// Energy balance of the solar band: what arrives = what is absorbed + what leaves to
// space or to inactive sides; the largest relative error over the positions.
double solarEnergyBalanceError(const solver::Network& net, const SweepResult& sw) {
  const Eigen::VectorXd& area = net.area();
  const Eigen::VectorXd lost = area.cwiseProduct(net.spaceViewFactor() + net.blockedFraction());
  double worst = 0.0;
  for (Eigen::Index p = 0; p < sw.absorbed_solar.cols(); ++p) {
    const double in = area.dot(sw.irradiance.direct.col(p) + sw.irradiance.albedo.col(p));
    if (in <= 0) continue;
    const double out =
        sw.absorbed_solar.col(p).sum() + sw.absorbed_albedo.col(p).sum() + lost.dot(sw.exitance_solar.col(p));
    worst = std::max(worst, std::abs(in - out) / in);
  }
  return worst;
}

// The uncertainty of the absorbed power: the view-factor terms of the two bands added
// (one δF moves both), the loads' and truncation terms in quadrature (independent).
void absorbedUncertainty(const SweepInputs& in, const solver::LowRankBandSolver& solar,
                         const solver::LowRankBandSolver& ir, const BandOutcome& solar_band,
                         const BandOutcome& ir_band, SweepResult& sw) {
  const solver::Network& net = *in.radiative.network;
  const int P = static_cast<int>(sw.positions.size());
  const orbits::EnvironmentLoads& e = sw.irradiance;
  const Eigen::MatrixXd solar_sigma =
      (e.direct_stderr.array().square() + e.albedo_stderr.array().square()).sqrt().matrix();
  const solver::Network& solar_net = in.radiative.solarNetwork();
  const solver::AbsorbedVariance vs =
      solver::absorbedVariance(solar_net, solar, in.view_factor_stderr, sw.exitance_solar, solar_sigma);
  const solver::AbsorbedVariance vi =
      solver::absorbedVariance(net, ir, in.view_factor_stderr, ir_band.solution.exitance, e.earth_ir_stderr);
  const solver::BandSolution& s = solar_band.solution;
  const Eigen::MatrixXd solar_h = s.irradiance.leftCols(P) + s.irradiance.rightCols(P);
  const Eigen::MatrixXd solar_gm = s.full_flux.leftCols(P) + s.full_flux.rightCols(P);
  sw.absorbed_stderr_truncation =
      solver::truncationError(solar_net, solar, solar_gm, solar_h, s.refined) +
      solver::truncationError(net, ir, ir_band.solution.full_flux, ir_band.solution.irradiance,
                              ir_band.solution.refined);
  sw.absorbed_stderr_view_factors = vs.view_factors.cwiseSqrt() + vi.view_factors.cwiseSqrt();
  sw.absorbed_stderr_loads = (vs.loads + vi.loads).cwiseSqrt();
  sw.absorbed_stderr = (sw.absorbed_stderr_view_factors.array().square() + sw.absorbed_stderr_loads.array().square() +
                        sw.absorbed_stderr_truncation.array().square())
                           .sqrt()
                           .matrix();
}

// Both bands' solves of the sweep's irradiances on the inputs' network and cores, and the
// absorbed power's uncertainty.
void solveBands(const SweepInputs& in, SweepResult& sw, StageTimings& timings) {
  const int P = static_cast<int>(sw.positions.size());
  const solver::Network& net = *in.radiative.network;
  const int n = net.size();
  StageTimer t_bands(timings, Stage::BandSolves);
  const double tol = in.solver.refineTolerance();
  const solver::LowRankBandSolver& solar = in.solar;
  const solver::LowRankBandSolver& ir = in.ir;
  const solver::Network& solar_net = in.radiative.solarNetwork();
  // Solar band (ρ = 1 − α): direct and albedo as 2P right-hand sides of one solve. A solar
  // network of its own (specular optics apart from the IR band's) is always solved to the
  // tolerance: the core of the one decomposition only preconditions it.
  Eigen::MatrixXd ext(n, 2 * P);
  ext << sw.irradiance.direct, sw.irradiance.albedo;
  const double solar_tol = bandTolerance(in.radiative, solar_net, tol);
  const BandOutcome solar_band = solveBand(solar, solar_net, ext, solar_tol, "solar");
  sw.absorbed_solar = solar_band.absorbed.leftCols(P);
  sw.absorbed_albedo = solar_band.absorbed.rightCols(P);
  sw.exitance_solar = solar_band.solution.exitance.leftCols(P) + solar_band.solution.exitance.rightCols(P);
  sw.solar_residual = solar_band.solution.max_residual;
  sw.solar_refine_iterations = solar_band.solution.refine_iterations;
  sw.solar_band_method = solar_band.solution.method;
  sw.energy_balance_error = solarEnergyBalanceError(solar_net, sw);
  // IR band (ρ = 1 − ε): the planet's IR, interreflected.
  const BandOutcome ir_band = solveBand(ir, net, sw.irradiance.earth_ir, bandTolerance(in.radiative, net, tol), "IR");
  sw.absorbed_earth_ir = ir_band.absorbed;
  sw.ir_residual = ir_band.solution.max_residual;
  sw.ir_refine_iterations = ir_band.solution.refine_iterations;
  sw.ir_band_method = ir_band.solution.method;
  t_bands.stop();
  sw.absorbed_total = sw.absorbed_solar + sw.absorbed_albedo + sw.absorbed_earth_ir;
  StageTimer t_unc(timings, Stage::Uncertainty);
  absorbedUncertainty(in, solar, ir, solar_band, ir_band, sw);
  // The network's solar radiosity is M̃ = J / κ: report the surfaces' own diffuse exitance J.
  if (in.radiative.kappa_solar.size()) sw.exitance_solar = in.radiative.kappa_solar.asDiagonal() * sw.exitance_solar;
}

// Turning parts: each configuration's positions solved on its own network and cores.
void solveArticulatedBands(const SweepInputs& in, SweepResult& sw, StageTimings& timings) {
  std::map<int, std::vector<int>> columns;
  for (size_t p = 0; p < sw.configuration.size(); ++p) columns[sw.configuration[p]].push_back(static_cast<int>(p));
  for (const auto& [k, cols] : columns) {
    const Configuration& conf = in.articulated->at(k);
    const BandCores& cores = in.articulated->cores(k, in.optics, timings);
    const SweepInputs at{in.orbit, *conf.caster, *conf.radiative, *cores.solar, *cores.ir, in.solver,
                         conf.view_factor_stderr};
    SweepResult part;
    for (int p : cols) part.positions.push_back(sw.positions[static_cast<size_t>(p)]);
    part.irradiance = loadColumns(sw.irradiance, cols);
    solveBands(at, part, timings);
    placeBands(sw, part, cols);
  }
}

}  // namespace

SweepResult runSweep(const SweepInputs& in, StageTimings& timings, bool show_progress, std::ostream& progress) {
  SweepResult sw;
  sweepAndLoad(in, sw, timings, show_progress, progress);
  if (in.articulated) solveArticulatedBands(in, sw, timings);
  else solveBands(in, sw, timings);
  return sw;
}

Eigen::MatrixXd absorbedPower(const solver::LowRankBandSolver& solar, const solver::LowRankBandSolver& ir,
                              const RadiativeNetwork& radiative, const orbits::EnvironmentLoads& irradiance,
                              double refine_tolerance) {
  const solver::Network& net = *radiative.network;
  const solver::Network& solar_net = radiative.solarNetwork();
  const Eigen::Index P = irradiance.direct.cols();
  Eigen::MatrixXd ext(net.size(), 2 * P);
  ext << irradiance.direct, irradiance.albedo;
  const Eigen::MatrixXd sun =
      solveBand(solar, solar_net, ext, bandTolerance(radiative, solar_net, refine_tolerance), "solar").absorbed;
  return sun.leftCols(P) + sun.rightCols(P) +
         solveBand(ir, net, irradiance.earth_ir, bandTolerance(radiative, net, refine_tolerance), "IR").absorbed;
}

void summarizeUncertainty(SweepResult& sw, double accuracy, std::ostream& progress) {
  UncertaintySummary& u = sw.uncertainty;
  u = UncertaintySummary{};
  u.accuracy = accuracy;
  for (Eigen::Index i = 0; i < sw.absorbed_total.rows(); ++i) {
    const double scale = sw.absorbed_total.row(i).cwiseAbs().maxCoeff();
    if (!(scale > 0)) continue;
    const double total = sw.absorbed_stderr.row(i).maxCoeff() / scale;
    if (total > u.total) {
      u.total = total;
      u.worst_node = static_cast<int>(i);
    }
    u.view_factors = std::max(u.view_factors, sw.absorbed_stderr_view_factors.row(i).maxCoeff() / scale);
    u.loads = std::max(u.loads, sw.absorbed_stderr_loads.row(i).maxCoeff() / scale);
    u.truncation = std::max(u.truncation, sw.absorbed_stderr_truncation.row(i).maxCoeff() / scale);
    u.nodes_over_budget += total > u.accuracy;
  }
  if (u.nodes_over_budget > 0)
    progress << "radnet: warning: the absorbed power of " << u.nodes_over_budget << " node(s) is uncertain by more "
             << "than solver.accuracy " << u.accuracy << " of its orbit maximum (at most " << u.total << ": view "
             << "factors " << u.view_factors << ", loads " << u.loads << ", truncation " << u.truncation
             << "); /uncertainty/absorbed_power has it per node and position\n";
}

}  // namespace radnet::cases
