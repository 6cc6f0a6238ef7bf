#pragma once
// The `thermal:` block of a case (docs/case-files.md, "Thermal model"): geometric and lumped
// nodes with capacitances (constant or tables), dissipations (constant, by illumination or a
// time table), boundary temperatures, conductors (constant or tables), user radiative
// couplings and MLI, thermostat heaters, space temperature, and steady state or a transient.
#include "cases/config/yaml_document.hpp"
#include "solver/thermal/temperatures.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <optional>
#include <string>
#include <vector>

namespace radnet::cases {

/// The thermal model. Its nodes are the case's radiative nodes (geometry or network form,
/// in case order) followed by the lumped nodes of `thermal.lumped`, which have no
/// geometry: they exchange heat only through conductors and user radiative couplings.
struct ThermalSettings {
  std::vector<std::string> node_names;  ///< every thermal node, radiative ones first
  int radiative_nodes = 0;              ///< how many of them come first with exchange factors
  Eigen::VectorXd capacitance;          ///< J/K per node (0 when not given: arithmetic node)
  std::vector<std::pair<int, solver::TemperatureTable>> capacitance_tables;  ///< J/K against K
  Eigen::VectorXd dissipation;                                               ///< constant part, W
  std::vector<solver::DissipationSchedule> schedules;                        ///< by illumination or time table, W
  Eigen::VectorXd fixed_temperature;                                         ///< K, NaN for free nodes
  std::vector<solver::BoundarySchedule> boundary_schedules;                  ///< boundary nodes following a history (imported)
  Eigen::VectorXd initial_temperature;                                       ///< K, where a transient starts
  std::vector<Eigen::Triplet<double>> conductors;           ///< (i, j, W/K), both directions
  std::vector<solver::TabledConductor> tabled_conductors;   ///< W/K against the mean temperature
  std::vector<Eigen::Triplet<double>> radiative_couplings;  ///< user GR and MLI (i, j, m²), both directions
  std::vector<solver::Heater> heaters;
  double space_temperature = 3.0;                   ///< K (cosmic background 2.7 K, rounded as ESATAN users do)
  std::optional<double> transient_orbits;           ///< a transient over this many orbits
  std::optional<solver::PeriodicOptions> periodic;  ///< a transient integrated until it repeats
  std::optional<double> duration_s;                 ///< a transient without an orbit, s
  double output_step_s = 0.0;                       ///< its output interval, s
  std::vector<double> output_times_s;               ///< or its output times (an imported file's), s from the start
  solver::ThermalOptions options;
  std::vector<std::string> warnings;  ///< accepted but suspicious input, printed with the run's progress
  int nodeCount() const { return static_cast<int>(node_names.size()); }
  bool isLumped(int i) const { return i >= radiative_nodes; }
  bool isTransient() const { return transient_orbits || periodic || duration_s; }
};

/// Below it a temperature is legal (a cryogenic stage, a shroud) but far likelier °C written
/// for K: it is run, with a warning located at the value.
inline constexpr double kSuspiciousKelvin = 100.0;  // K

/// Appends "FILE:LINE:COLUMN: <what> <k> K is below 100 K; …" to `warnings` when k < 100 K.
void warnIfCelsius(const YamlDocument& doc, const YAML::Node& value, const std::string& what, double k,
                   std::vector<std::string>& warnings);

/// Parses `thermal:` against the case's radiative nodes; nullopt when absent.
/// @param names   the radiative nodes, in case order
/// @param area    their areas, m² (MLI couplings are A_outer ε*)
/// @param orbit_period_s  the shortest orbit period of the case's orbits (dissipation tables
///                        repeat each orbit and must fit in it); nullopt without an orbit
/// @param imported  a model read from another tool's file (names = its nodes): `thermal:` then
///                  adds lumped nodes, conductors, couplings and heaters to it and overrides
///                  the properties of the nodes it names; transient takes time_step only
std::optional<ThermalSettings> parseThermalSettings(const YamlDocument& doc, const std::vector<std::string>& names,
                                                    const Eigen::VectorXd& area, std::optional<double> orbit_period_s,
                                                    const ThermalSettings* imported = nullptr);

/// `{table: [[x, y], ...]}`: x strictly increasing within [x_lo, x_hi], y in [y_lo, y_hi].
/// @param what  names the entry and the units, e.g. "thermal.nodes.a.capacitance (K, J/K)"
void parseTable(const YamlDocument& doc, const YAML::Node& node, const std::string& what, double x_lo, double x_hi,
                double y_lo, double y_hi, std::vector<double>& x, std::vector<double>& y);

/// `heaters: [{name, node, power, on_below, off_above, sensor}]` into s.heaters.
void parseHeaters(const YamlDocument& doc, const YAML::Node& list, ThermalSettings& s);

}  // namespace radnet::cases
