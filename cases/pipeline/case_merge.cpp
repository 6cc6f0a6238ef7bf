#include "cases/pipeline/case_merge.hpp"

#include <array>

#include <algorithm>
#include <cmath>

namespace radnet::cases {
namespace {

// Columns of `b` after those of `a` (an empty `a` takes `b`).
void appendCols(Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.size() == 0) {
    a = b;
    return;
  }
  if (b.size() == 0) return;
  Eigen::MatrixXd joined(a.rows(), a.cols() + b.cols());
  joined << a, b;
  a = std::move(joined);
}

// What `part`'s loads cast, added to `all`'s.
void addLoadCounts(orbits::EnvironmentLoads& all, const orbits::EnvironmentLoads& part) {
  all.planet_casts += part.planet_casts;
  all.planet_rays += part.planet_rays;
  all.planet_kernel = all.planet_kernel || part.planet_kernel;
  all.kernel_rays += part.kernel_rays;
  all.kernel_fallbacks += part.kernel_fallbacks;
  all.shadow_rays += part.shadow_rays;
  all.shadow_cell_m = std::max(all.shadow_cell_m, part.shadow_cell_m);
  all.seconds += part.seconds;
}

}  // namespace

void appendLoads(orbits::EnvironmentLoads& all, const orbits::EnvironmentLoads& part) {
  for (auto member : {&orbits::EnvironmentLoads::direct, &orbits::EnvironmentLoads::albedo,
                      &orbits::EnvironmentLoads::earth_ir, &orbits::EnvironmentLoads::earth_view_factor,
                      &orbits::EnvironmentLoads::direct_stderr, &orbits::EnvironmentLoads::albedo_stderr,
                      &orbits::EnvironmentLoads::earth_ir_stderr})
    appendCols(all.*member, part.*member);
  addLoadCounts(all, part);
}

namespace {

constexpr std::array<Eigen::MatrixXd orbits::EnvironmentLoads::*, 7> kLoadMatrices = {
    &orbits::EnvironmentLoads::direct,        &orbits::EnvironmentLoads::albedo,
    &orbits::EnvironmentLoads::earth_ir,      &orbits::EnvironmentLoads::earth_view_factor,
    &orbits::EnvironmentLoads::direct_stderr, &orbits::EnvironmentLoads::albedo_stderr,
    &orbits::EnvironmentLoads::earth_ir_stderr};
constexpr std::array<Eigen::MatrixXd SweepResult::*, 9> kBandMatrices = {
    &SweepResult::absorbed_solar,  &SweepResult::absorbed_albedo,
    &SweepResult::absorbed_earth_ir, &SweepResult::absorbed_total,
    &SweepResult::exitance_solar,  &SweepResult::absorbed_stderr,
    &SweepResult::absorbed_stderr_view_factors, &SweepResult::absorbed_stderr_loads,
    &SweepResult::absorbed_stderr_truncation};

void placeColumns(Eigen::MatrixXd& all, const Eigen::MatrixXd& part, const std::vector<int>& columns, Eigen::Index P) {
  if (part.size() == 0) return;
  if (all.cols() != P || all.rows() != part.rows()) all = Eigen::MatrixXd::Zero(part.rows(), P);
  for (size_t j = 0; j < columns.size(); ++j) all.col(columns[j]) = part.col(static_cast<Eigen::Index>(j));
}

void joinMethod(std::string& joined, const std::string& method) {
  if (joined.empty()) joined = method;
  else if (!method.empty() && joined.find(method) == std::string::npos) joined += ", " + method;
}

}  // namespace

void placeLoads(orbits::EnvironmentLoads& all, const orbits::EnvironmentLoads& part, const std::vector<int>& columns,
                Eigen::Index positions) {
  for (auto member : kLoadMatrices) placeColumns(all.*member, part.*member, columns, positions);
  addLoadCounts(all, part);
}

void addLoads(orbits::EnvironmentLoads& all, const orbits::EnvironmentLoads& part) {
  for (auto member : kLoadMatrices) {
    const Eigen::MatrixXd& m = part.*member;
    if (m.size() == 0) continue;
    Eigen::MatrixXd& a = all.*member;
    if (a.size() == 0) a = Eigen::MatrixXd::Zero(m.rows(), m.cols());
    a += m;  // disjoint parts: a sum of zeros and values, exact
  }
  addLoadCounts(all, part);
}

orbits::EnvironmentLoads loadColumns(const orbits::EnvironmentLoads& all, const std::vector<int>& columns) {
  orbits::EnvironmentLoads out;
  for (auto member : kLoadMatrices) {
    const Eigen::MatrixXd& m = all.*member;
    if (m.size() == 0) continue;
    Eigen::MatrixXd& o = out.*member;
    o.resize(m.rows(), static_cast<Eigen::Index>(columns.size()));
    for (size_t j = 0; j < columns.size(); ++j) o.col(static_cast<Eigen::Index>(j)) = m.col(columns[j]);
  }
  return out;
}

void placeBands(SweepResult& all, const SweepResult& part, const std::vector<int>& columns) {
  const Eigen::Index P = static_cast<Eigen::Index>(all.positions.size());
  for (auto member : kBandMatrices) placeColumns(all.*member, part.*member, columns, P);
  all.solar_residual = std::max(all.solar_residual, part.solar_residual);
  all.ir_residual = std::max(all.ir_residual, part.ir_residual);
  all.solar_refine_iterations = std::max(all.solar_refine_iterations, part.solar_refine_iterations);
  all.ir_refine_iterations = std::max(all.ir_refine_iterations, part.ir_refine_iterations);
  all.energy_balance_error = std::max(all.energy_balance_error, part.energy_balance_error);
  joinMethod(all.solar_band_method, part.solar_band_method);
  joinMethod(all.ir_band_method, part.ir_band_method);
}

void appendSweep(SweepResult& all, const SweepResult& part) {
  const int offset = static_cast<int>(all.positions.size());
  if (!all.case_start.empty()) all.case_start.pop_back();
  for (int start : part.case_start) all.case_start.push_back(start + offset);
  all.positions.insert(all.positions.end(), part.positions.begin(), part.positions.end());
  all.case_labels.insert(all.case_labels.end(), part.case_labels.begin(), part.case_labels.end());
  all.case_period_s.insert(all.case_period_s.end(), part.case_period_s.begin(), part.case_period_s.end());
  all.case_sweep_s.insert(all.case_sweep_s.end(), part.case_sweep_s.begin(), part.case_sweep_s.end());
  appendLoads(all.irradiance, part.irradiance);
  for (auto member : {&SweepResult::absorbed_solar, &SweepResult::absorbed_albedo, &SweepResult::absorbed_earth_ir,
                      &SweepResult::absorbed_total, &SweepResult::exitance_solar, &SweepResult::absorbed_stderr,
                      &SweepResult::absorbed_stderr_view_factors, &SweepResult::absorbed_stderr_loads,
                      &SweepResult::absorbed_stderr_truncation})
    appendCols(all.*member, part.*member);
  if (part.articulation_angle.size() && all.articulation_angle.size() == 0) {
    all.articulation_angle = part.articulation_angle;
    all.configuration = part.configuration;
  } else if (part.articulation_angle.size()) {
    Eigen::MatrixXd angles(all.articulation_angle.rows() + part.articulation_angle.rows(), part.articulation_angle.cols());
    angles << all.articulation_angle, part.articulation_angle;
    all.articulation_angle = std::move(angles);
    all.configuration.insert(all.configuration.end(), part.configuration.begin(), part.configuration.end());
  }
  all.solar_residual = std::max(all.solar_residual, part.solar_residual);
  all.ir_residual = std::max(all.ir_residual, part.ir_residual);
  all.solar_refine_iterations = std::max(all.solar_refine_iterations, part.solar_refine_iterations);
  all.ir_refine_iterations = std::max(all.ir_refine_iterations, part.ir_refine_iterations);
  if (offset == 0) all.central_body = part.central_body, all.planet_ir_model = part.planet_ir_model;
  for (auto member : {&SweepResult::solar_band_method, &SweepResult::ir_band_method, &SweepResult::central_body,
                      &SweepResult::planet_ir_model}) {
    std::string& joined = all.*member;
    const std::string& method = part.*member;
    if (joined.empty()) joined = method;
    else if (!method.empty() && (", " + joined + ", ").find(", " + method + ", ") == std::string::npos)
      joined += ", " + method;
  }
  all.energy_balance_error = std::max(all.energy_balance_error, part.energy_balance_error);
}

void appendThermal(ThermalSolution& all, const ThermalSolution& part) {
  solver::ThermalResult& s = all.solve;
  const solver::ThermalResult& p = part.solve;
  for (auto member : {&solver::ThermalResult::temperature, &solver::ThermalResult::temperature_rate,
                      &solver::ThermalResult::rate_roundoff, &solver::ThermalResult::dissipation,
                      &solver::ThermalResult::heater_power, &solver::ThermalResult::emissivity,
                      &solver::ThermalResult::absorptivity, &solver::ThermalResult::applied_loads})
    appendCols(s.*member, p.*member);
  s.exchange_updates += p.exchange_updates;
  for (auto member : {&ThermalSolution::solar_load_scale, &ThermalSolution::ir_load_scale})
    appendCols(all.*member, part.*member);
  if (s.heater_duty.size() == p.heater_duty.size()) s.heater_duty = s.heater_duty.cwiseMax(p.heater_duty);
  s.newton_iterations += p.newton_iterations;
  s.factorisations += p.factorisations;
  s.heater_switches += p.heater_switches;
  s.max_residual_w = std::max(s.max_residual_w, p.max_residual_w);
  s.orbits = std::max(s.orbits, p.orbits);
  if (!std::isnan(p.periodic_residual_k))
    s.periodic_residual_k = std::isnan(s.periodic_residual_k) ? p.periodic_residual_k
                                                              : std::max(s.periodic_residual_k, p.periodic_residual_k);
  all.times_s.insert(all.times_s.end(), part.times_s.begin(), part.times_s.end());
  Eigen::MatrixXd duty(all.case_heater_duty.rows() + part.case_heater_duty.rows(), part.case_heater_duty.cols());
  duty << all.case_heater_duty, part.case_heater_duty;
  all.case_heater_duty = std::move(duty);
  solver::HeatFlows& f = all.heat.flows;
  for (auto member : {&solver::HeatFlows::emitted, &solver::HeatFlows::radiative, &solver::HeatFlows::conducted,
                      &solver::HeatFlows::dissipation, &solver::HeatFlows::heater, &solver::HeatFlows::stored,
                      &solver::HeatFlows::boundary, &solver::HeatFlows::roundoff})
    appendCols(f.*member, part.heat.flows.*member);
  all.heat.max_imbalance_w = std::max(all.heat.max_imbalance_w, part.heat.max_imbalance_w);
  all.heat.max_relative_imbalance = std::max(all.heat.max_relative_imbalance, part.heat.max_relative_imbalance);
  // One case without σ_T (a singular Jacobian) leaves the joined run without it: never a partial table.
  if (all.temperature_stderr.size() && part.temperature_stderr.size()) {
    appendCols(all.temperature_stderr, part.temperature_stderr);
  } else {
    all.temperature_stderr.resize(0, 0);
    if (part.temperature_stderr.size() == 0) all.temperature_stderr_method = part.temperature_stderr_method;
  }
}

Eigen::VectorXd timeWeights(const SweepResult* sweep, const std::vector<double>& times, Eigen::Index P,
                            int first_case, int end_case) {
  Eigen::VectorXd w = Eigen::VectorXd::Constant(P, 1.0 / static_cast<double>(P));
  if (sweep) {
    if (end_case < 0) end_case = sweep->caseCount();
    const int offset = sweep->case_start[static_cast<size_t>(first_case)];
    double total = 0;
    for (int k = first_case; k < end_case; ++k) {
      const int b = sweep->case_start[static_cast<size_t>(k)], e = sweep->case_start[static_cast<size_t>(k) + 1];
      const double span = sweep->case_sweep_s[static_cast<size_t>(k)];
      for (int p = b; p < e; ++p) {
        const double prev = p > b ? times[static_cast<size_t>(p - 1)] : times[static_cast<size_t>(e - 1)] - span;
        const double next = p + 1 < e ? times[static_cast<size_t>(p + 1)] : times[static_cast<size_t>(b)] + span;
        w[p - offset] = 0.5 * (next - prev);
      }
      total += span;
    }
    return w / total;
  }
  if (P > 1 && static_cast<Eigen::Index>(times.size()) == P) {
    for (Eigen::Index p = 0; p < P; ++p) {
      const size_t q = static_cast<size_t>(p);
      w[p] = 0.5 * ((p + 1 < P ? times[q + 1] : times[q]) - (p > 0 ? times[q - 1] : times[q]));
    }
    w /= w.sum();
  }
  return w;
}

OrbitStatistics orbitStatistics(const Eigen::MatrixXd& t, const Eigen::VectorXd& w) {
  return {t.rowwise().minCoeff(), t * w, t.rowwise().maxCoeff()};
}

}  // namespace radnet::cases
