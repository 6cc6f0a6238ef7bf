#include "cases/output/hdf5_layout.hpp"

#include "cases/cluster/cluster.hpp"
#include "cases/output/hdf5_matrices.hpp"

#include "solver/units.hpp"

#include <cmath>
#include <map>
#include <ctime>

namespace radnet::cases {

void writeMeta(Hdf5Writer& h5, const std::string& case_name, const std::string& case_yaml,
               const IncludedFiles& included) {
  const std::time_t t = std::time(nullptr);
  char created[32];
  std::strftime(created, sizeof created, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  h5.attribute("/meta", "program", std::string("radnet"));
  h5.attribute("/meta", "version", std::string(RADNET_VERSION));
  h5.attribute("/meta", "case_name", case_name);
  h5.attribute("/meta", "created_utc", std::string(created));
  h5.writeText("/meta/case_yaml", case_yaml);
  for (size_t k = 0; k < included.size(); ++k) {  // the included files, so a result carries all its input
    const std::string path = "/meta/included/" + std::to_string(k);
    h5.writeText(path, included[k].second);
    h5.attribute(path, "file", included[k].first);
  }
}

Eigen::Index nodeCount(const RadiativeNetwork& radiative, const std::optional<ThermalSolution>& thermal) {
  return thermal ? static_cast<Eigen::Index>(thermal->node_names.size()) : radiative.network->size();
}

Eigen::MatrixXd padNodes(const Eigen::MatrixXd& values, Eigen::Index rows) {
  if (values.rows() == rows) return values;
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(rows, values.cols());
  out.topRows(values.rows()) = values;
  return out;
}

void writeNodes(Hdf5Writer& h5, const RadiativeNetwork& radiative, const std::optional<ThermalSolution>& thermal) {
  const solver::Network& net = *radiative.network;
  const Eigen::Index n = nodeCount(radiative, thermal);
  h5.writeStrings("/nodes/name", thermal ? thermal->node_names : net.names());
  h5.writeVector("/nodes/area", padNodes(radiative.surfaceArea(), n).col(0), "m^2");
  std::vector<bool> lumped(static_cast<size_t>(n), false);
  for (Eigen::Index i = net.size(); i < n; ++i) lumped[static_cast<size_t>(i)] = true;
  h5.writeBooleans("/nodes/lumped", lumped);
}

void writeRadiativeNetwork(Hdf5Writer& h5, const RadiativeNetwork& radiative, const OutputSettings& output) {
  const solver::Network& net = *radiative.network;
  const bool dense = output.denseMatrices(net.size(), !net.isSparse());
  CsrPattern g_pattern;
  if (!net.share().whole()) {
    // Rows shared out over MPI ranks: G, F and GR's direct part by writeSharedMatrices.
  } else if (net.isSparse()) {  // F = A⁻¹ G and G written from G's own arrays, never copied or formed densely; one pattern
    const Eigen::Map<const SparseRows> g = rowsOfSymmetric(net.sparseConductance());
    writeNetworkMatrix(h5, "conductance", g, "m^2", dense);
    g_pattern = CsrPattern("/network/sparse/conductance", g);
    writeNetworkMatrix(h5, "view_factors", g, "1", dense, net.area().cwiseInverse(), g_pattern);
  } else {
    // F = A⁻¹ G row by row as it is written: no n × n copy of G or F (2 × 288 MiB at 6,144 nodes).
    writeDenseNetworkMatrix(h5, "view_factors", net.heldDenseConductance(), "1", dense, net.area().cwiseInverse());
    writeDenseNetworkMatrix(h5, "conductance", net.heldDenseConductance(), "m^2", dense);
  }
  h5.writeVector("/network/space_view_factor", net.spaceViewFactor(), "1");
  h5.attribute("/network", "reciprocity_max_view_factor_change", net.reciprocity().max_view_factor_change);
  h5.attribute("/network", "closure_max_row_overshoot", net.reciprocity().max_row_overshoot);
  if (const auto& ex = radiative.exchange)  // GR's direct part E G E has G's pattern (checked)
    writeExchange(h5, "/network/", *ex, output.denseExchange(net.size(), !ex->factored()), g_pattern);
  const solver::EigenPairs& pairs = radiative.pairs;
  h5.writeVector("/eigen/values", pairs.values, "m^2");
  h5.writeMatrix("/eigen/vectors", pairs.vectors, "1");
  h5.attribute("/eigen", "rank", static_cast<long long>(pairs.rank()));
  h5.attribute("/eigen", "tolerance", pairs.tolerance);
  h5.attribute("/eigen", "method", std::string(solver::toString(pairs.method)));
  h5.attribute("/eigen", "largest_dropped_eigenvalue_bound", pairs.dropped_bound);
  h5.attribute("/eigen", "rank_rule", pairs.rank_rule);
  if (pairs.probe_residual >= 0) h5.attribute("/eigen", "probe_residual", pairs.probe_residual);
  if (pairs.probe_exchange_error >= 0) h5.attribute("/eigen", "probe_exchange_error", pairs.probe_exchange_error);
}

void writeGeometry(Hdf5Writer& h5, const geometry::Scene& scene, const geometry::SeamReport& seams,
                   const Eigen::VectorXi& triangle_node) {
  h5.writeMatrix("/geometry/vertices", scene.vertexMatrix(), "m");
  h5.writeIntegers("/geometry/triangles", scene.triangleMatrix(), "1");
  // triangle_node: the node a triangle belongs to (its front side's, or its back side's
  // when only the back is active); the per-side maps keep −1 for an inactive side.
  h5.writeIntegers("/geometry/triangle_node", triangle_node, "1");
  h5.writeIntegers("/geometry/triangle_front_node", scene.frontNodes(), "1");
  h5.writeIntegers("/geometry/triangle_back_node", scene.backNodes(), "1");
  // Seams closed between curved primitives (geometry/scene/seams.hpp): what it cost the areas.
  h5.attribute("/geometry", "seam_vertices_moved", static_cast<long long>(seams.vertices_moved));
  h5.attribute("/geometry", "seam_largest_move_m", seams.largest_move_m);
  h5.attribute("/geometry", "seam_largest_area_change", seams.largest_area_change);
}

namespace {

void writeRawMatrices(Hdf5Writer& h5, const Eigen::SparseMatrix<double, Eigen::RowMajor>& raw_f, const CsrRef& sigma,
                      bool dense) {
  writeNetworkMatrix(h5, "view_factors_raw", raw_f, "1", dense);
  // σ is estimated entry by entry with the raw F: the same pattern (checked).
  writeNetworkMatrix(h5, "view_factor_stderr", sigma, "1", dense, {}, CsrPattern("/network/sparse/view_factors_raw", raw_f));
}

}  // namespace

void writeRawViewFactors(Hdf5Writer& h5, const geometry::ViewFactorEstimate& raw, bool dense) {
  if (raw.upper_exchange) {
    // Each pair held once: F laid out for the file, then σ over its values (one n × n
    // pattern beside the pairs, not two), the CSR's indices F's.
    Eigen::SparseMatrix<double, Eigen::RowMajor> full =
        geometry::viewFactorsFromUpper(raw.exchange_upper, raw.upper_area);
    writeNetworkMatrix(h5, "view_factors_raw", full, "1", dense);
    const CsrPattern pattern("/network/sparse/view_factors_raw", full);  // the pattern stays as σ is laid over it
    geometry::errorsOverUpperLayout(full, raw.exchange_upper, raw.upper_area, raw.exchange_error_upper.data());
    writeNetworkMatrix(h5, "view_factor_stderr", full, "1", dense, {}, pattern);
    return;
  }
  if (!raw.errors_on_pattern) return writeRawMatrices(h5, raw.view_factors, raw.standard_error, dense);
  // σ in single precision on F's own pattern: its indices are F's (linked, not written twice).
  writeNetworkMatrix(h5, "view_factors_raw", raw.view_factors, "1", dense);
  writeFloatNetworkMatrix(h5, "view_factor_stderr", geometry::errorsOnPattern(raw), "1", dense,
                          CsrPattern("/network/sparse/view_factors_raw", raw.view_factors));
}

void writeViewFactorEstimate(Hdf5Writer& h5, const GeometryRunResult& r, ViewFactorMethod method,
                             const OutputSettings& output) {
  const bool dense = output.denseMatrices(r.radiative.network->size(), !r.radiative.network->isSparse());
  // Else written during the run, or by writeSharedMatrices (rows shared out).
  if (!r.raw_estimate_written && r.radiative.network->share().whole())
    writeRawMatrices(h5, r.raw_view_factors, r.view_factor_stderr, dense);
  h5.writeVector("/network/blocked_view_factor", r.radiative.network->blockedFraction(), "1");
  h5.attribute("/network", "correction_max_change", r.correction.max_change);
  h5.attribute("/network", "correction_max_change_sigma", r.correction.max_change_sigma);
  h5.attribute("/network", "method", std::string(toString(method)));
  h5.attribute("/network", "rays_total", static_cast<long long>(r.total_rays));
  if (r.exact) {
    h5.attribute("/network", "exact_patches", static_cast<long long>(r.exact->patches));
    h5.attribute("/network", "exact_pairs_unoccluded", static_cast<long long>(r.exact->pairs_unoccluded));
    h5.attribute("/network", "exact_pairs_occluded", static_cast<long long>(r.exact->pairs_occluded));
    h5.attribute("/network", "exact_pairs_hidden", static_cast<long long>(r.exact->pairs_hidden));
    h5.attribute("/network", "rows_sampled", static_cast<long long>(r.exact->sampled_rows));
    h5.attribute("/network", "exact_pairs_by_quadrature", static_cast<long long>(r.exact->pairs_by_quadrature));
    // auto's cost model against the stage's measured time (time_view_factors_s)
    if (r.exact->predicted_seconds > 0)
      h5.attribute("/report", "time_view_factors_predicted_s", r.exact->predicted_seconds);
  }
  h5.attribute("/report", "view_factor_error", r.row_stderr_max.size() ? r.row_stderr_max.maxCoeff() : 0.0);
  h5.attribute("/report", "rays_per_second", r.rays_per_second);
}

namespace {

// /orbit: the positions of every orbit case, one after another.
void writeOrbit(Hdf5Writer& h5, const SweepResult& sw) {
  const int P = static_cast<int>(sw.positions.size());
  Eigen::VectorXd time(P), sunlit(P), beta(P), flux(P), event(P);
  Eigen::MatrixXd sun(P, 3), earth(P, 3), position(P, 3), velocity(P, 3), elements(P, 6);
  for (int p = 0; p < P; ++p) {
    const auto& q = sw.positions[static_cast<size_t>(p)];
    position.row(p) = q.position_eci_m.transpose();
    velocity.row(p) = q.velocity_eci_m_s.transpose();
    const orbits::KeplerElements& el = q.elements;
    elements.row(p) << el.semi_major_axis_m, el.eccentricity, units::radToDeg(el.inclination_rad),
        units::radToDeg(el.raan_rad), units::radToDeg(el.arg_perigee_rad), units::radToDeg(el.true_anomaly_rad);
    time[p] = q.t_s;
    sunlit[p] = q.sunlit_fraction;
    beta[p] = units::radToDeg(q.beta_rad);
    flux[p] = q.solar_flux_w_m2;
    event[p] = q.event ? 1.0 : 0.0;
    sun.row(p) = q.sun_body.transpose();
    earth.row(p) = q.planet_body.transpose();
  }
  h5.writeVector("/orbit/time", time, "s");
  h5.writeMatrix("/orbit/position_eci", position, "m");
  h5.writeMatrix("/orbit/velocity_eci", velocity, "m/s");
  h5.writeVector("/orbit/semi_major_axis", elements.col(0), "m");
  h5.writeVector("/orbit/eccentricity", elements.col(1), "1");
  h5.writeVector("/orbit/inclination", elements.col(2), "deg");
  h5.writeVector("/orbit/raan", elements.col(3), "deg");
  h5.writeVector("/orbit/arg_perigee", elements.col(4), "deg");
  h5.writeVector("/orbit/true_anomaly", elements.col(5), "deg");
  h5.attribute("/orbit/semi_major_axis", "kind",
               std::string("the propagator's elements at each position (two-body + secular J2): the osculating "
                           "elements of position_eci/velocity_eci for mu = n^2 a^3, n the J2-corrected mean motion"));
  h5.writeMatrix("/orbit/sun_body", sun, "1");
  h5.writeMatrix("/orbit/earth_body", earth, "1");
  h5.writeVector("/orbit/sunlit_fraction", sunlit, "1");
  h5.writeVector("/orbit/beta", beta, "deg");
  h5.writeVector("/orbit/solar_flux", flux, "W/m^2");
  h5.writeVector("/orbit/eclipse_event", event, "1");
  h5.attribute("/orbit", "body", sw.central_body);
  h5.attribute("/orbit", "planet_ir", sw.planet_ir_model);
  Eigen::VectorXi case_of(P);
  for (int k = 0; k < sw.caseCount(); ++k)
    case_of
        .segment(sw.case_start[static_cast<size_t>(k)],
                 sw.case_start[static_cast<size_t>(k) + 1] - sw.case_start[static_cast<size_t>(k)])
        .setConstant(k);
  h5.writeIntegers("/orbit/case", case_of, "1");
  h5.writeStrings("/orbit/case_label", sw.case_labels);
  h5.writeVector("/orbit/period", Eigen::Map<const Eigen::VectorXd>(sw.case_period_s.data(), sw.caseCount()), "s");
  h5.attribute("/orbit/period", "kind",
               std::string("nodal: ascending node to ascending node with the secular J2 rates; each case's sweep "
                           "spans whole nodal periods"));
}

}  // namespace

void writeSweep(Hdf5Writer& h5, const SweepResult& sw, Eigen::Index n) {
  writeOrbit(h5, sw);
  // Positions × nodes (P, n), as docs/hdf5-layout.md lays them out.
  h5.writeMatrix("/loads/solar", padNodes(sw.absorbed_solar, n).transpose(), "W");
  h5.writeMatrix("/loads/albedo", padNodes(sw.absorbed_albedo, n).transpose(), "W");
  h5.writeMatrix("/loads/earth_ir", padNodes(sw.absorbed_earth_ir, n).transpose(), "W");
  h5.writeMatrix("/loads/earth_view_factor", padNodes(sw.irradiance.earth_view_factor, n).transpose(), "1");
  h5.writeMatrix("/loads/incident_solar", padNodes(sw.irradiance.direct, n).transpose(), "W/m^2");
  h5.writeMatrix("/loads/incident_albedo", padNodes(sw.irradiance.albedo, n).transpose(), "W/m^2");
  h5.writeMatrix("/loads/incident_earth_ir", padNodes(sw.irradiance.earth_ir, n).transpose(), "W/m^2");
  h5.writeMatrix("/solution/exitance_solar", padNodes(sw.exitance_solar, n).transpose(), "W/m^2");
  h5.attribute("/report", "solar_band_residual", sw.solar_residual);
  h5.attribute("/report", "truncation_residual", std::max(sw.solar_residual, sw.ir_residual));
  h5.attribute("/report", "ir_band_residual", sw.ir_residual);
  h5.attribute("/report", "solar_band_method", sw.solar_band_method);
  h5.attribute("/report", "ir_band_method", sw.ir_band_method);
  h5.attribute("/report", "solar_refine_iterations", static_cast<long long>(sw.solar_refine_iterations));
  h5.attribute("/report", "ir_refine_iterations", static_cast<long long>(sw.ir_refine_iterations));
  h5.attribute("/report", "solar_energy_balance_error", sw.energy_balance_error);
  h5.attribute("/report", "planet_ray_casts", static_cast<long long>(sw.irradiance.planet_casts));
}

namespace {

void writeHeaters(Hdf5Writer& h5, const ThermalSolution& thermal, const ThermalSettings& settings) {
  const Eigen::Index H = static_cast<Eigen::Index>(settings.heaters.size());
  if (H == 0) return;
  std::vector<std::string> nodes, sensors;
  for (const solver::Heater& h : settings.heaters) {
    nodes.push_back(settings.node_names[static_cast<size_t>(h.node)]);
    sensors.push_back(settings.node_names[static_cast<size_t>(h.sensor)]);
  }
  h5.writeStrings("/heaters/name", thermal.heater_names);
  h5.writeStrings("/heaters/node", nodes);
  h5.writeStrings("/heaters/sensor", sensors);
  Eigen::VectorXd rated(H), on_below(H), off_above(H);
  for (Eigen::Index k = 0; k < H; ++k) {
    const solver::Heater& h = settings.heaters[static_cast<size_t>(k)];
    rated[k] = h.power_w, on_below[k] = h.on_below_k, off_above[k] = h.off_above_k;
  }
  h5.writeVector("/heaters/rated_power", rated, "W");
  h5.writeVector("/heaters/on_below", on_below, "K");
  h5.writeVector("/heaters/off_above", off_above, "K");
  h5.writeMatrix("/heaters/power", thermal.solve.heater_power.transpose(), "W");
  h5.writeVector("/heaters/duty", thermal.solve.heater_duty, "1");
  h5.attribute("/heaters/duty", "meaning",
               std::string(settings.isTransient() ? "fraction of the last orbit (or of the run) the heater is on; the "
                                                    "largest over orbit cases"
                                                  : "mean power over the positions / rated power; the largest over "
                                                    "orbit cases"));
  h5.writeMatrix("/heaters/case_duty", thermal.case_heater_duty, "1");
}

}  // namespace

namespace {

// Pairs i < j of symmetric triplets given in both directions, duplicates summed.
std::map<std::pair<int, int>, double> upperPairs(const std::vector<Eigen::Triplet<double>>& both_directions) {
  std::map<std::pair<int, int>, double> pairs;
  for (const auto& t : both_directions)
    if (t.row() < t.col()) pairs[{t.row(), t.col()}] += t.value();
  return pairs;
}

// /thermal: what the couplings of the thermal model are, for export to other tools
// (cases/output/export.cpp): conductors at every position's temperatures (tabled ones
// at the mean of their nodes'), user couplings and MLI as GR, boundary temperatures.
void writeThermalModel(Hdf5Writer& h5, const ThermalSolution& thermal, const ThermalSettings& settings) {
  const auto constant = upperPairs(settings.conductors);
  std::map<std::pair<int, int>, size_t> column;
  for (const auto& [ij, g] : constant) column.emplace(ij, column.size());
  for (const auto& t : settings.tabled_conductors)
    column.emplace(std::pair{std::min(t.i, t.j), std::max(t.i, t.j)}, column.size());
  const Eigen::MatrixXd& temperature = thermal.temperature();  // (n × P)
  Eigen::MatrixXi nodes(static_cast<Eigen::Index>(column.size()), 2);
  Eigen::MatrixXd conductance = Eigen::MatrixXd::Zero(temperature.cols(), nodes.rows());
  for (const auto& [ij, k] : column) nodes.row(static_cast<Eigen::Index>(k)) << ij.first, ij.second;
  for (const auto& [ij, g] : constant) conductance.col(static_cast<Eigen::Index>(column[ij])).array() += g;
  for (const auto& t : settings.tabled_conductors) {
    const auto k = static_cast<Eigen::Index>(column[{std::min(t.i, t.j), std::max(t.i, t.j)}]);
    for (Eigen::Index p = 0; p < temperature.cols(); ++p)
      conductance(p, k) += t.conductance.at(0.5 * (temperature(t.i, p) + temperature(t.j, p)));
  }
  h5.writeIntegers("/thermal/conductor_nodes", nodes, "1");
  h5.writeMatrix("/thermal/conductance", conductance, "W/K");
  const auto couplings = upperPairs(settings.radiative_couplings);
  Eigen::MatrixXi coupling_nodes(static_cast<Eigen::Index>(couplings.size()), 2);
  Eigen::VectorXd coupling_gr(coupling_nodes.rows());
  Eigen::Index k = 0;
  for (const auto& [ij, gr] : couplings) {
    coupling_nodes.row(k) << ij.first, ij.second;
    coupling_gr[k++] = gr;
  }
  h5.writeIntegers("/thermal/coupling_nodes", coupling_nodes, "1");
  h5.writeVector("/thermal/coupling_gr", coupling_gr, "m^2");
  // No NaN in a result: free nodes are 0 K here (below every allowed temperature) and 0 in
  // the mask that says which nodes are held.
  const Eigen::Index n = settings.fixed_temperature.size();
  Eigen::VectorXi held(n);
  for (Eigen::Index i = 0; i < n; ++i) held[i] = std::isnan(settings.fixed_temperature[i]) ? 0 : 1;
  h5.writeVector("/thermal/fixed_temperature", (held.array() == 1).select(settings.fixed_temperature, 0.0), "K");
  h5.writeIntegers("/thermal/fixed", held, "1");
  h5.attribute("/thermal", "space_temperature", settings.space_temperature);
}

}  // namespace

void writeTemperatures(Hdf5Writer& h5, const ThermalSolution& thermal, const ThermalSettings& settings,
                       const SweepResult* sweep) {
  writeThermalModel(h5, thermal, settings);
  h5.writeMatrix("/solution/temperature", thermal.temperature().transpose(), "K");
  h5.attribute("/solution/temperature", "mode", std::string(settings.isTransient() ? "transient" : "steady"));
  h5.attribute("/solution/temperature", "kind", thermal.mode);
  if (settings.isTransient()) h5.attribute("/solution/temperature", "orbits", static_cast<long long>(thermal.solve.orbits));
  if (settings.periodic) {
    h5.attribute("/solution/temperature", "periodic_residual", thermal.solve.periodic_residual_k);
    h5.attribute("/solution/temperature", "periodic_tolerance", settings.periodic->tolerance_k);
    // 1 normally; m > 1 for a thermostat locked to m orbits; 0 when no period exists (a
    // thermostat not locked to the orbit): docs/solver.md, "Periodic transients".
    h5.attribute("/solution/temperature", "orbits_per_period",
                 static_cast<long long>(thermal.solve.heater_cycle_unlocked ? 0 : thermal.solve.orbits_per_period));
  }
  if (!sweep)
    h5.writeVector("/solution/time",
                   Eigen::Map<const Eigen::VectorXd>(thermal.times_s.data(), static_cast<Eigen::Index>(thermal.times_s.size())),
                   "s");
  h5.attribute("/report", "thermal_max_residual_w", thermal.solve.max_residual_w);
  solver::ThermalNetwork capacities;
  capacities.capacitance = settings.capacitance;
  capacities.capacitance_tables = settings.capacitance_tables;
  h5.writeVector("/nodes/capacitance", solver::capacitanceAt(capacities, settings.initial_temperature), "J/K");
  h5.attribute("/nodes/capacitance", "at", std::string("the initial temperature (for nodes with a table)"));
  h5.writeVector("/nodes/dissipation", settings.dissipation, "W");
  h5.attribute("/nodes/dissipation", "meaning",
               std::string("the constant part; /solution/heat/dissipation holds schedules over time"));
  writeHeaters(h5, thermal, settings);
  const HeatBalance& heat = thermal.heat;
  const solver::HeatFlows& f = heat.flows;
  const Eigen::MatrixXd none = Eigen::MatrixXd::Zero(f.stored.rows(), f.stored.cols());
  // Positions × nodes (P, n), positive into the node.
  const Eigen::Index n = none.rows();
  // With ε(T), α(T): each node's loads at its own optics (the sweep's are at the nominal ones).
  const auto scaled = [&](const Eigen::MatrixXd& m, const Eigen::MatrixXd& scale) -> Eigen::MatrixXd {
    if (!sweep) return none;
    return scale.size() ? Eigen::MatrixXd(padNodes(m, n).cwiseProduct(scale)) : padNodes(m, n);
  };
  h5.writeMatrix("/solution/heat/solar", scaled(sweep ? sweep->absorbed_solar : none, thermal.solar_load_scale).transpose(), "W");
  h5.writeMatrix("/solution/heat/albedo", scaled(sweep ? sweep->absorbed_albedo : none, thermal.solar_load_scale).transpose(), "W");
  h5.writeMatrix("/solution/heat/earth_ir", scaled(sweep ? sweep->absorbed_earth_ir : none, thermal.ir_load_scale).transpose(), "W");
  if (thermal.solve.emissivity.size() > 0) {
    h5.writeMatrix("/solution/emissivity", thermal.solve.emissivity.transpose(), "1");
    h5.writeMatrix("/solution/absorptivity", thermal.solve.absorptivity.transpose(), "1");
    h5.attribute("/solution/emissivity", "meaning",
                 std::string("each node's IR emissivity at each output time (materials with a table against "
                             "temperature follow it; the others are constant)"));
    h5.attribute("/report", "exchange_updates", static_cast<long long>(thermal.solve.exchange_updates));
  }
  h5.writeMatrix("/solution/heat/emitted", f.emitted.transpose(), "W");
  h5.writeMatrix("/solution/heat/radiative", f.radiative.transpose(), "W");
  h5.writeMatrix("/solution/heat/conducted", f.conducted.transpose(), "W");
  h5.writeMatrix("/solution/heat/dissipation", f.dissipation.transpose(), "W");
  h5.writeMatrix("/solution/heat/heater", f.heater.transpose(), "W");
  h5.writeMatrix("/solution/heat/stored", f.stored.transpose(), "W");
  h5.writeMatrix("/solution/heat/boundary", f.boundary.transpose(), "W");
  h5.attribute("/report", "heat_balance_max_imbalance_w", heat.max_imbalance_w);
  h5.attribute("/report", "heat_balance_max_relative_imbalance", heat.max_relative_imbalance);
}

void writeTimings(Hdf5Writer& h5, const StageTimings& timings) {
  // Under MPI the times are the slowest rank's per stage (cases/pipeline/distributed.hpp).
  for (const auto& [stage, seconds] : timings.entries())
    h5.attribute("/report", "time_" + std::string(stageName(stage)) + "_s", seconds);
  h5.attribute("/report", "mpi_ranks", static_cast<long long>(cluster::size()));
}

}  // namespace radnet::cases
