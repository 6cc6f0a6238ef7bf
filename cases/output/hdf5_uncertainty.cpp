// /uncertainty and the error budget's split in /report (docs/hdf5-layout.md).
#include "cases/output/hdf5_layout.hpp"

namespace radnet::cases {

void writeUncertainty(Hdf5Writer& h5, const GeometryCase& c, const GeometryRunResult& r, Eigen::Index n) {
  const solver::SolverSettings& s = r.solver;
  h5.attribute("/report", "accuracy", s.accuracy);
  h5.attribute("/report", "budget_solver_tolerance", s.rank > 0 ? 0.0 : s.tolerance);
  h5.attribute("/report", "budget_view_factor_target_error",
               c.view_factors.method == ViewFactorMethod::Exact ? 0.0 : c.view_factors.monte_carlo.target_error);
  if (!r.sweep) return;
  const SweepResult& sw = *r.sweep;
  const std::string meaning = "standard uncertainty (1 sigma) of the absorbed power /loads/solar + /loads/albedo + "
                              "/loads/earth_ir, by first-order propagation (docs/solver.md, Uncertainty)";
  h5.writeMatrix("/uncertainty/absorbed_power", padNodes(sw.absorbed_stderr, n).transpose(), "W");
  h5.attribute("/uncertainty/absorbed_power", "meaning", meaning);
  h5.writeMatrix("/uncertainty/absorbed_power_view_factors", padNodes(sw.absorbed_stderr_view_factors, n).transpose(),
                 "W");
  h5.writeMatrix("/uncertainty/absorbed_power_loads", padNodes(sw.absorbed_stderr_loads, n).transpose(), "W");
  h5.writeMatrix("/uncertainty/absorbed_power_truncation", padNodes(sw.absorbed_stderr_truncation, n).transpose(),
                 "W");
  h5.writeMatrix("/uncertainty/incident_solar", padNodes(sw.irradiance.direct_stderr, n).transpose(), "W/m^2");
  h5.writeMatrix("/uncertainty/incident_albedo", padNodes(sw.irradiance.albedo_stderr, n).transpose(), "W/m^2");
  h5.writeMatrix("/uncertainty/incident_earth_ir", padNodes(sw.irradiance.earth_ir_stderr, n).transpose(), "W/m^2");
  const orbits::EnvironmentOptions& env = c.design_cases.front().orbit->environment;
  h5.attribute("/report", "budget_load_relative_error", env.relative_error);
  h5.attribute("/report", "direct_solar_method", env.shadow_samples > 0 ? std::string("shadow rays")
                                                  : env.shadow_cell_m > 0 ? std::string("shadow grid")
                                                                           : std::string("exact clipping"));
  h5.attribute("/report", "shadow_grid_spacing_m", sw.irradiance.shadow_cell_m);
  h5.attribute("/report", "shadow_rays", static_cast<long long>(sw.irradiance.shadow_rays));
  h5.attribute("/report", "planet_rays", static_cast<long long>(sw.irradiance.planet_rays));
  h5.attribute("/report", "planet_load_method",
               std::string(sw.irradiance.planet_kernel ? "sky kernel" : "planet rays"));
  h5.attribute("/report", "sky_kernel_rays", static_cast<long long>(sw.irradiance.kernel_rays));
  h5.attribute("/report", "sky_kernel_fallback_node_positions", static_cast<long long>(sw.irradiance.kernel_fallbacks));
  const UncertaintySummary& u = sw.uncertainty;
  h5.attribute("/report", "absorbed_uncertainty_max_relative", u.total);
  h5.attribute("/report", "absorbed_uncertainty_view_factors_max_relative", u.view_factors);
  h5.attribute("/report", "absorbed_uncertainty_loads_max_relative", u.loads);
  h5.attribute("/report", "absorbed_uncertainty_truncation_max_relative", u.truncation);
  h5.attribute("/report", "nodes_over_budget", static_cast<long long>(u.nodes_over_budget));
  if (r.thermal && r.thermal->temperature_stderr.size()) {
    h5.writeMatrix("/uncertainty/temperature", r.thermal->temperature_stderr.transpose(), "K");
    h5.attribute("/uncertainty/temperature", "meaning",
                 std::string("standard uncertainty (1 sigma) of /solution/temperature from /uncertainty/"
                             "absorbed_power and the view factors' errors in the exchange between nodes, through "
                             "the heat balance's Jacobian"));
    h5.attribute("/uncertainty/temperature", "method", r.thermal->temperature_stderr_method);
  }
}

}  // namespace radnet::cases
