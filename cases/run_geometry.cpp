#include "cases/run_geometry.hpp"

#include "cases/errors.hpp"
#include "cases/xdmf.hpp"

#include <filesystem>
#include <functional>

#include <iomanip>
#include <ostream>

namespace radnet::cases {
namespace {

// A progress line on stderr, redrawn in place about 50 times per stage.
std::function<void(int, int)> progressBar(std::ostream& out, const char* stage, const char* unit) {
  return [&out, stage, unit](int done, int total) {
    if (done == total || done % std::max(1, total / 50) == 0)
      out << "\rradnet: " << stage << " " << std::setw(3) << (100 * done / total) << " % (" << done << "/" << total
          << " " << unit << ")" << (done == total ? "\n" : "") << std::flush;
  };
}

// One band for all positions at once: M_o = ρ ∘ E (n×cols); returns the solution and
// the absorbed power (1 − ρ) A (E + H), W.
solver::BandSolution solveBand(const solver::Network& net, const solver::EigenPairs& pairs, const Eigen::VectorXd& rho,
                               const Eigen::MatrixXd& irradiance, double refine_tol, const char* band,
                               Eigen::MatrixXd& absorbed) {
  const solver::LowRankBandSolver solver(net, pairs, rho);
  solver::BandSolution sol = solver.solve(rho.asDiagonal() * irradiance, refine_tol);
  if (sol.status != solver::Status::Converged)
    throw NumericalError(std::string(band) + " band solve " + solver::toString(sol.status) + ": " + sol.message);
  const Eigen::VectorXd absorptance = Eigen::VectorXd::Ones(net.size()) - rho;
  absorbed = absorptance.cwiseProduct(net.area()).asDiagonal() * (irradiance + sol.irradiance);
  return sol;
}

void runSweep(const GeometryCase& c, const geometry::RayCaster& caster, const Eigen::VectorXd& area,
              GeometryRunResult& r, bool show_progress, std::ostream& progress) {
  const OrbitSettings& o = *c.orbit;
  GeometryRunResult::Sweep sw;
  const int n = static_cast<int>(area.size());
  // Each orbit case (an epoch × beta combination) is swept and loaded on its own, then all
  // positions join the band solves as one matrix.
  std::vector<orbits::EnvironmentLoads> parts;
  for (size_t k = 0; k < o.cases.size(); ++k) {
    const orbits::Orbit& orbit = *o.cases[k].orbit;
    StageTimer t_orbit;
    const std::vector<orbits::SweepPosition> positions = orbits::sweepOrbit(orbit, o.attitude, o.sweep);
    r.timings_s.emplace_back("orbit", t_orbit.seconds());
    int events = 0;
    for (const auto& p : positions) events += p.event;
    progress << "radnet: orbit " << k + 1 << "/" << o.cases.size() << " (" << o.description << ", "
             << o.cases[k].label << "), period " << orbit.period() << " s, " << positions.size() << " positions ("
             << events << " eclipse entries/exits inserted)\n";
    StageTimer t_loads;
    orbits::EnvironmentOptions env = o.environment;
    if (show_progress) env.progress = progressBar(progress, "orbit loads", "positions");
    parts.push_back(orbits::environmentLoads(caster, area, positions, orbits::earthFixedInBody(o.attitude),
                                             orbit.earth().equatorial_radius_m, env));
    r.timings_s.emplace_back("environment_loads", t_loads.seconds());
    sw.case_start.push_back(static_cast<int>(sw.positions.size()));
    sw.positions.insert(sw.positions.end(), positions.begin(), positions.end());
  }
  const int P = static_cast<int>(sw.positions.size());
  sw.case_start.push_back(P);
  for (const auto& oc : o.cases) sw.case_labels.push_back(oc.label);
  auto join = [&](auto member) {
    Eigen::MatrixXd all(n, P);
    for (size_t k = 0; k < parts.size(); ++k)
      all.middleCols(sw.case_start[k], sw.case_start[k + 1] - sw.case_start[k]) = parts[k].*member;
    return all;
  };
  sw.irradiance.direct = join(&orbits::EnvironmentLoads::direct);
  sw.irradiance.albedo = join(&orbits::EnvironmentLoads::albedo);
  sw.irradiance.earth_ir = join(&orbits::EnvironmentLoads::earth_ir);
  sw.irradiance.earth_view_factor = join(&orbits::EnvironmentLoads::earth_view_factor);
  for (const auto& part : parts) {
    sw.irradiance.planet_casts += part.planet_casts;
    sw.irradiance.shadow_rays += part.shadow_rays;
    sw.irradiance.seconds += part.seconds;
  }
  progress << "radnet: loads: planet rays cast " << sw.irradiance.planet_casts << " time(s) for " << P << " positions\n";

  // Solar band (ρ = 1 − α): direct and albedo as 2P right-hand sides of one solve.
  StageTimer t_bands;
  const double tol = c.solver.refineEnabled() ? c.solver.tolerance : 0.0;
  const solver::Network& net = *r.network;
  Eigen::MatrixXd ext(n, 2 * P);
  ext << sw.irradiance.direct, sw.irradiance.albedo;
  Eigen::MatrixXd absorbed;
  const Eigen::VectorXd rho_solar = Eigen::VectorXd::Ones(n) - c.absorptivity;
  const solver::BandSolution solar = solveBand(net, r.pairs, rho_solar, ext, tol, "solar", absorbed);
  sw.absorbed_solar = absorbed.leftCols(P);
  sw.absorbed_albedo = absorbed.rightCols(P);
  sw.exitance_solar = solar.exitance.leftCols(P) + solar.exitance.rightCols(P);
  sw.solar_residual = solar.max_residual;
  sw.solar_refine_iterations = solar.refine_iterations;
  // Energy balance: what arrives = what is absorbed + what leaves to space or inactive sides.
  const Eigen::VectorXd lost = area.cwiseProduct(net.spaceViewFactor() + net.blockedFraction());
  for (int p = 0; p < P; ++p) {
    const double in = area.dot(sw.irradiance.direct.col(p) + sw.irradiance.albedo.col(p));
    if (in <= 0) continue;
    const double out = sw.absorbed_solar.col(p).sum() + sw.absorbed_albedo.col(p).sum() +
                       lost.dot(sw.exitance_solar.col(p));
    sw.energy_balance_error = std::max(sw.energy_balance_error, std::abs(in - out) / in);
  }
  // IR band (ρ = 1 − ε): the planet's IR, interreflected.
  const solver::BandSolution ir =
      solveBand(net, r.pairs, Eigen::VectorXd::Ones(n) - c.emissivity, sw.irradiance.earth_ir, tol, "IR", absorbed);
  sw.absorbed_earth_ir = absorbed;
  sw.ir_residual = ir.max_residual;
  sw.ir_refine_iterations = ir.refine_iterations;
  r.timings_s.emplace_back("band_solves", t_bands.seconds());
  r.sweep = std::move(sw);
}

void runThermal(const GeometryCase& c, GeometryRunResult& r, std::ostream& progress) {
  const ThermalSettings& ts = *c.thermal;
  const int n = r.network->size();
  const solver::ThermalNetwork net = thermalNetwork(ts, r.exchange.gr, r.exchange.gr_space);
  const Eigen::MatrixXd q_env = r.sweep ? Eigen::MatrixXd(r.sweep->absorbed_solar + r.sweep->absorbed_albedo +
                                                          r.sweep->absorbed_earth_ir)
                                        : Eigen::MatrixXd::Zero(n, 1);
  StageTimer t_thermal;
  if (ts.transient_orbits) {
    // One transient per orbit case, each periodic over its own swept orbit(s).
    const auto& sw = *r.sweep;
    r.thermal = solver::ThermalResult{};
    r.thermal->temperature.resize(n, q_env.cols());
    for (size_t k = 0; k + 1 < sw.case_start.size(); ++k) {
      const int begin = sw.case_start[k], count = sw.case_start[k + 1] - begin;
      std::vector<double> times;
      for (int p = begin; p < begin + count; ++p) times.push_back(sw.positions[static_cast<size_t>(p)].t_s);
      const double period = c.orbit->cases[k].orbit->period() * c.orbit->sweep.orbits;
      solver::ThermalResult part = solver::transient(net, times, q_env.middleCols(begin, count), period,
                                                     *ts.transient_orbits,
                                                     Eigen::VectorXd::Constant(n, ts.initial_temperature), ts.options);
      r.thermal->newton_iterations += part.newton_iterations;
      r.thermal->max_residual_w = std::max(r.thermal->max_residual_w, part.max_residual_w);
      if (part.status != solver::Status::Converged) {
        r.thermal->status = part.status;
        r.thermal->message = part.message + " (orbit case " + std::to_string(k + 1) + ")";
        break;
      }
      r.thermal->temperature.middleCols(begin, count) = part.temperature;
    }
  } else {
    r.thermal = solver::steadyStates(net, q_env, ts.options);
  }
  r.timings_s.emplace_back("thermal", t_thermal.seconds());
  if (r.thermal->status != solver::Status::Converged)
    throw NumericalError(std::string("temperatures ") + solver::toString(r.thermal->status) + ": " + r.thermal->message);
  progress << "radnet: temperatures (" << (ts.transient_orbits ? "transient" : "steady state per position") << "), "
           << r.thermal->newton_iterations << " Newton iterations, largest heat-balance residual "
           << r.thermal->max_residual_w << " W\n";
}

}  // namespace

GeometryRunResult runGeometryCase(const GeometryCase& c, bool show_progress, std::ostream& progress) {
  GeometryRunResult r;
  const geometry::Scene& scene = c.scene;
  const int n = static_cast<int>(scene.nodes().size());
  for (const auto& w : scene.warnings()) progress << "radnet: warning: " << w << "\n";
  progress << "radnet: scene of " << scene.faces().size() << " triangles, " << n << " nodes\n";
  StageTimer t_tree;
  const geometry::RayCaster caster(scene);
  r.timings_s.emplace_back("aabb_tree", t_tree.seconds());

  Eigen::VectorXd area(n), rays(n);
  for (int i = 0; i < n; ++i) area[i] = scene.nodes()[static_cast<size_t>(i)].area_m2;
  StageTimer t_vf;
  if (c.method == ViewFactorMethod::MonteCarlo) {
    geometry::ViewFactorOptions opt = c.view_factors;
    if (show_progress) opt.progress = progressBar(progress, "view factors", "nodes");
    const geometry::ViewFactorResult vf = geometry::computeViewFactors(caster, opt);
    r.raw_view_factors = vf.denseViewFactors();
    r.view_factor_stderr = vf.denseStandardError();
    for (int i = 0; i < n; ++i) rays[i] = double(vf.rays[static_cast<size_t>(i)]);
    r.total_rays = vf.total_rays;
    r.rays_per_second = vf.seconds > 0 ? double(vf.total_rays) / vf.seconds : 0.0;
    r.correction = geometry::enforceReciprocity(area, vf.view_factors, vf.standard_error, vf.space, vf.space_error,
                                                vf.blocked, vf.blocked_error, rays);
  } else {
    const geometry::ContourResult det = geometry::contourViewFactors(caster, c.contour);
    r.raw_view_factors = det.view_factors;
    r.view_factor_stderr = det.error_estimate;
    // Quadrature: a resolution of 1e6 "rays" makes the variance floor negligible.
    rays.setConstant(1e6);
    const Eigen::SparseMatrix<double, Eigen::RowMajor> f = det.view_factors.sparseView(), e = det.error_estimate.sparseView();
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
    r.correction = geometry::enforceReciprocity(area, f, e, det.space, zero, zero, zero, rays);
  }
  r.timings_s.emplace_back("view_factors", t_vf.seconds());
  progress << "radnet: view factors: " << r.total_rays << " rays"
           << (r.rays_per_second > 0 ? " (" + std::to_string(static_cast<long long>(r.rays_per_second)) + " rays/s)" : "")
           << ", reciprocity/closure correction moved F by at most " << r.correction.max_change << " ("
           << r.correction.max_change_sigma << " σ)\n";

  StageTimer t_net;
  // The correction makes A F symmetric and the rows closed; the network re-checks both.
  const solver::NetworkTolerances tol{1e-9, 1e-9};
  std::vector<std::string> names;
  for (const auto& node : scene.nodes()) names.push_back(node.name);
  const double density = double(r.correction.view_factors.nonZeros()) / (double(n) * n);
  const Eigen::SparseMatrix<double> fcol = r.correction.view_factors;
  r.network = density < 0.25 ? std::make_unique<solver::Network>(names, area, fcol, r.correction.blocked, tol)
                             : std::make_unique<solver::Network>(names, area, Eigen::MatrixXd(fcol),
                                                                 r.correction.blocked, tol);
  r.timings_s.emplace_back("network", t_net.seconds());

  StageTimer t_eig;
  const Eigen::VectorXd rho_max =
      (Eigen::VectorXd::Ones(n) - c.emissivity).cwiseMax(Eigen::VectorXd::Ones(n) - c.absorptivity);
  r.pairs = decomposeForBands(*r.network, rho_max, c.solver.rank, c.solver.tolerance, c.solver.max_rank,
                              c.solver.method);
  r.timings_s.emplace_back("eigendecomposition", t_eig.seconds());
  if (r.pairs.status != solver::Status::Converged)
    throw NumericalError(std::string("eigendecomposition of G ") + solver::toString(r.pairs.status) + ": " +
                         r.pairs.message);

  StageTimer t_gr;
  r.exchange = computeExchangeFactors(*r.network, r.pairs, c.emissivity, c.solver.refineEnabled(), r.exchange_method);
  r.timings_s.emplace_back("exchange_factors", t_gr.seconds());
  if (c.orbit) runSweep(c, caster, area, r, show_progress, progress);
  if (c.thermal) runThermal(c, r, progress);
  return r;
}

namespace {

// Per-triangle copies of node values for the XDMF sidecar: a triangle shows its front
// node (or its back node when only the back is active).
std::vector<XdmfAttribute> writeCellValues(Hdf5Writer& h5, const GeometryCase& c, const GeometryRunResult& r) {
  const Eigen::VectorXi front = c.scene.frontNodes(), back = c.scene.backNodes();
  const Eigen::Index nt = front.size();
  Eigen::VectorXi shown(nt);
  for (Eigen::Index t = 0; t < nt; ++t) shown[t] = front[t] >= 0 ? front[t] : back[t];
  std::vector<XdmfAttribute> attrs = {{"node", "/geometry/triangle_node", false, true}};
  auto spread = [&](const Eigen::MatrixXd& node_by_position) {  // (n×P) → (P×nt)
    Eigen::MatrixXd cells(node_by_position.cols(), nt);
    for (Eigen::Index t = 0; t < nt; ++t) cells.col(t) = node_by_position.row(shown[t]).transpose();
    return cells;
  };
  const Eigen::MatrixXd area_node = r.network->area();
  h5.writeVector("/xdmf/node_area", spread(area_node).row(0).transpose(), "m^2");
  attrs.push_back({"node area [m^2]", "/xdmf/node_area", false});
  if (r.sweep) {
    const auto& sw = *r.sweep;
    const Eigen::MatrixXd flux = r.network->area().cwiseInverse().asDiagonal() *
                                 (sw.absorbed_solar + sw.absorbed_albedo + sw.absorbed_earth_ir);
    h5.writeMatrix("/xdmf/absorbed_flux", spread(flux), "W/m^2");
    h5.writeMatrix("/xdmf/exitance_solar", spread(sw.exitance_solar), "W/m^2");
    attrs.push_back({"absorbed environmental flux [W/m^2]", "/xdmf/absorbed_flux", true});
    attrs.push_back({"solar exitance [W/m^2]", "/xdmf/exitance_solar", true});
  }
  if (r.thermal && r.sweep) {
    h5.writeMatrix("/xdmf/temperature", spread(r.thermal->temperature), "K");
    attrs.push_back({"temperature [K]", "/xdmf/temperature", true});
  } else if (r.thermal) {
    h5.writeVector("/xdmf/temperature", spread(r.thermal->temperature).row(0).transpose(), "K");
    attrs.push_back({"temperature [K]", "/xdmf/temperature", false});
  }
  return attrs;
}

void writeSweep(Hdf5Writer& h5, const GeometryRunResult::Sweep& sw) {  // positions of every orbit case
  const int P = static_cast<int>(sw.positions.size());
  Eigen::VectorXd time(P), sunlit(P), beta(P), flux(P), event(P);
  Eigen::MatrixXd sun(P, 3), earth(P, 3);
  for (int p = 0; p < P; ++p) {
    const auto& q = sw.positions[static_cast<size_t>(p)];
    time[p] = q.t_s;
    sunlit[p] = q.sunlit_fraction;
    beta[p] = q.beta_rad * 180.0 / M_PI;
    flux[p] = q.solar_flux_w_m2;
    event[p] = q.event ? 1.0 : 0.0;
    sun.row(p) = q.sun_body.transpose();
    earth.row(p) = q.earth_body.transpose();
  }
  h5.writeVector("/orbit/time", time, "s");
  h5.writeMatrix("/orbit/sun_body", sun, "1");
  h5.writeMatrix("/orbit/earth_body", earth, "1");
  h5.writeVector("/orbit/sunlit_fraction", sunlit, "1");
  h5.writeVector("/orbit/beta", beta, "deg");
  h5.writeVector("/orbit/solar_flux", flux, "W/m^2");
  h5.writeVector("/orbit/eclipse_event", event, "1");
  Eigen::VectorXi case_of(P);
  for (size_t k = 0; k + 1 < sw.case_start.size(); ++k)
    case_of.segment(sw.case_start[k], sw.case_start[k + 1] - sw.case_start[k]).setConstant(static_cast<int>(k));
  h5.writeIntegers("/orbit/case", case_of, "1");
  h5.writeStrings("/orbit/case_label", sw.case_labels);
  // Positions × nodes, as DESIGN.md §3 lays out (P, n).
  h5.writeMatrix("/loads/solar", sw.absorbed_solar.transpose(), "W");
  h5.writeMatrix("/loads/albedo", sw.absorbed_albedo.transpose(), "W");
  h5.writeMatrix("/loads/earth_ir", sw.absorbed_earth_ir.transpose(), "W");
  h5.writeMatrix("/loads/earth_view_factor", sw.irradiance.earth_view_factor.transpose(), "1");
  h5.writeMatrix("/loads/incident_solar", sw.irradiance.direct.transpose(), "W/m^2");
  h5.writeMatrix("/loads/incident_albedo", sw.irradiance.albedo.transpose(), "W/m^2");
  h5.writeMatrix("/loads/incident_earth_ir", sw.irradiance.earth_ir.transpose(), "W/m^2");
  h5.writeMatrix("/solution/exitance_solar", sw.exitance_solar.transpose(), "W/m^2");
  h5.attribute("/report", "solar_band_residual", sw.solar_residual);
  h5.attribute("/report", "truncation_residual", std::max(sw.solar_residual, sw.ir_residual));
  h5.attribute("/report", "ir_band_residual", sw.ir_residual);
  h5.attribute("/report", "solar_energy_balance_error", sw.energy_balance_error);
  h5.attribute("/report", "planet_ray_casts", static_cast<long long>(sw.irradiance.planet_casts));
}

}  // namespace

void writeGeometryResult(const GeometryCase& c, const GeometryRunResult& r, const std::string& path) {
  Hdf5Writer h5(path);
  writeMeta(h5, c.name, c.yaml_text);
  for (size_t k = 0; k < c.included.size(); ++k) {  // the included files, so a result carries all its input
    const std::string path = "/meta/included/" + std::to_string(k);
    h5.writeText(path, c.included[k].second);
    h5.attribute(path, "file", c.included[k].first);
  }
  writeNetwork(h5, *r.network);
  h5.writeVector("/nodes/emissivity", c.emissivity, "1");
  h5.writeVector("/nodes/absorptivity", c.absorptivity, "1");
  h5.writeStrings("/nodes/material", c.node_material);
  h5.writeMatrix("/geometry/vertices", c.scene.vertexMatrix(), "m");
  h5.writeIntegers("/geometry/triangles", c.scene.triangleMatrix(), "1");
  // triangle_node: the node a triangle belongs to (its front side's, or its back side's
  // when only the back is active); the per-side maps keep −1 for an inactive side.
  const Eigen::VectorXi front = c.scene.frontNodes(), back = c.scene.backNodes();
  h5.writeIntegers("/geometry/triangle_node", front.binaryExpr(back, [](int f, int b) { return f >= 0 ? f : b; }), "1");
  h5.writeIntegers("/geometry/triangle_front_node", front, "1");
  h5.writeIntegers("/geometry/triangle_back_node", back, "1");
  h5.writeMatrix("/network/view_factor_stderr", r.view_factor_stderr, "1");
  h5.writeMatrix("/network/view_factors_raw", r.raw_view_factors, "1");
  h5.writeVector("/network/blocked_view_factor", r.network->blockedFraction(), "1");
  h5.attribute("/network", "correction_max_change", r.correction.max_change);
  h5.attribute("/network", "correction_max_change_sigma", r.correction.max_change_sigma);
  h5.attribute("/network", "method", std::string(c.method == ViewFactorMethod::MonteCarlo ? "monte_carlo" : "contour"));
  h5.attribute("/network", "rays_total", static_cast<long long>(r.total_rays));
  writeExchange(h5, r.exchange, r.exchange_method);
  writeEigen(h5, r.pairs);
  if (r.sweep) writeSweep(h5, *r.sweep);
  if (r.thermal) {
    h5.writeMatrix("/solution/temperature", r.thermal->temperature.transpose(), "K");
    h5.attribute("/solution/temperature", "mode", std::string(c.thermal->transient_orbits ? "transient" : "steady"));
    h5.attribute("/report", "thermal_max_residual_w", r.thermal->max_residual_w);
    h5.writeVector("/nodes/capacitance", c.thermal->capacitance, "J/K");
    h5.writeVector("/nodes/dissipation", c.thermal->dissipation, "W");
  }
  const std::vector<XdmfAttribute> cell_values = writeCellValues(h5, c, r);
  writeTimings(h5, r.timings_s);
  h5.attribute("/report", "view_factor_error", r.view_factor_stderr.size() ? r.view_factor_stderr.maxCoeff() : 0.0);
  h5.attribute("/report", "rays_per_second", r.rays_per_second);
  // The ParaView sidecar next to the HDF5 file (same stem, .xmf), renamed after the HDF5.
  std::vector<double> times;
  if (r.sweep)
    for (const auto& p : r.sweep->positions) times.push_back(p.t_s);
  const std::filesystem::path h5_path(path);
  const std::string xmf = (h5_path.parent_path() / h5_path.stem()).string() + ".xmf";
  const std::string text = xdmfText(h5_path.filename().string(), static_cast<long>(c.scene.vertexMatrix().rows()),
                                    static_cast<long>(c.scene.faces().size()), times, cell_values);
  h5.commit();
  writeTextAtomically(xmf, text);
}

void printGeometrySummary(const GeometryCase& c, const GeometryRunResult& r, std::ostream& out) {
  const solver::Network& net = *r.network;
  out << "case " << c.name << ": " << c.scene.faces().size() << " triangles, " << net.size() << " nodes\n";
  out << std::left << std::setw(20) << "node" << std::right << std::setw(12) << "area m²" << std::setw(8) << "ε"
      << std::setw(8) << "α" << std::setw(12) << "F_space" << std::setw(12) << "GR_space" << std::setw(12)
      << "max σ(F)" << "\n";
  for (int i = 0; i < net.size(); ++i) {
    out << std::left << std::setw(20) << net.names()[static_cast<size_t>(i)] << std::right << std::setprecision(5)
        << std::setw(12) << net.area()[i] << std::setw(8) << c.emissivity[i] << std::setw(8) << c.absorptivity[i]
        << std::setw(12) << net.spaceViewFactor()[i] << std::setw(12) << r.exchange.gr_space[i] << std::setw(12)
        << (r.view_factor_stderr.cols() ? r.view_factor_stderr.row(i).maxCoeff() : 0.0) << "\n";
  }
  if (r.sweep) {
    const auto& sw = *r.sweep;
    const Eigen::MatrixXd total = sw.absorbed_solar + sw.absorbed_albedo + sw.absorbed_earth_ir;
    out << "orbit: " << sw.positions.size() << " positions; absorbed environmental power per node, W "
        << "(solar + albedo + Earth IR):\n";
    out << std::left << std::setw(20) << "node" << std::right << std::setw(12) << "min" << std::setw(12) << "mean"
        << std::setw(12) << "max" << std::setw(12) << "solar max" << std::setw(12) << "albedo max" << std::setw(12)
        << "IR mean" << "\n";
    for (int i = 0; i < net.size(); ++i)
      out << std::left << std::setw(20) << net.names()[static_cast<size_t>(i)] << std::right << std::setprecision(5)
          << std::setw(12) << total.row(i).minCoeff() << std::setw(12) << total.row(i).mean() << std::setw(12)
          << total.row(i).maxCoeff() << std::setw(12) << sw.absorbed_solar.row(i).maxCoeff() << std::setw(12)
          << sw.absorbed_albedo.row(i).maxCoeff() << std::setw(12) << sw.absorbed_earth_ir.row(i).mean() << "\n";
    out << "band residuals: solar " << sw.solar_residual << ", IR " << sw.ir_residual
        << "; solar energy balance error " << sw.energy_balance_error << "\n";
  }
  if (r.thermal) {
    const Eigen::MatrixXd& t = r.thermal->temperature;
    out << "temperatures, K (" << (c.thermal->transient_orbits ? "transient, last orbit" : "steady state per position")
        << "):\n" << std::left << std::setw(20) << "node" << std::right << std::setw(10) << "min" << std::setw(10)
        << "mean" << std::setw(10) << "max" << "\n";
    for (int i = 0; i < net.size(); ++i)
      out << std::left << std::setw(20) << net.names()[static_cast<size_t>(i)] << std::right << std::fixed
          << std::setprecision(2) << std::setw(10) << t.row(i).minCoeff() << std::setw(10) << t.row(i).mean()
          << std::setw(10) << t.row(i).maxCoeff() << std::defaultfloat << "\n";
  }
  out << "view factors: " << r.total_rays << " rays, correction ≤ " << r.correction.max_change << " ("
      << r.correction.max_change_sigma << " σ); closure error " << r.correction.max_closure_error << "\n";
  out << "eigenpairs: rank " << r.pairs.rank() << " (" << solver::toString(r.pairs.method) << "); exchange factors: "
      << r.exchange_method << "\n";
  out << "timings:";
  for (const auto& [stage, seconds] : r.timings_s) out << " " << stage << " " << std::setprecision(3) << seconds << " s;";
  out << "\n";
}

std::optional<double> lookupGeometryResult(const GeometryRunResult& r, const Expectation& x) {
  const solver::Network& net = *r.network;
  const int i = x.node.empty() ? -1 : net.indexOf(x.node);
  const int j = x.to.empty() ? -1 : net.indexOf(x.to);
  if (x.quantity == "view_factor") return net.conductance(i, j) / net.area()[i];
  if (x.quantity == "space_view_factor") return net.spaceViewFactor()[i];
  if (x.quantity == "radiative_exchange") return r.exchange.gr(i, j);
  if (x.quantity == "gr_space") return r.exchange.gr_space[i];
  if (x.quantity == "eigenvalue" && x.index < r.pairs.rank()) return r.pairs.values[x.index];
  if (x.quantity == "temperature" && r.thermal) {
    const int p = std::max(0, x.index);
    if (p >= r.thermal->temperature.cols()) return std::nullopt;
    return r.thermal->temperature(i, p);
  }
  if (r.sweep && x.quantity == "orbit_mean_absorbed")
    return (r.sweep->absorbed_solar + r.sweep->absorbed_albedo + r.sweep->absorbed_earth_ir).row(i).mean();
  if (r.sweep && x.quantity == "orbit_max_absorbed_solar") return r.sweep->absorbed_solar.row(i).maxCoeff();
  return std::nullopt;
}

}  // namespace radnet::cases
