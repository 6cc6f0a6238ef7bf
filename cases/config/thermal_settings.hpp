#pragma once
// The `thermal:` block of a case: capacitances, dissipations, boundary temperatures,
// linear conductors, space temperature, and steady state or a transient.
#include "cases/config/yaml_document.hpp"
#include "solver/thermal.hpp"

#include <Eigen/Dense>

#include <optional>
#include <string>
#include <vector>

namespace radnet::cases {

struct ThermalSettings {
  Eigen::VectorXd capacitance;                     ///< J/K per node (0 when not given: arithmetic node)
  Eigen::VectorXd dissipation;                     ///< W
  Eigen::VectorXd fixed_temperature;               ///< K, NaN for free nodes
  std::vector<Eigen::Triplet<double>> conductors;  ///< (i, j, W/K), both directions
  double initial_temperature = 293.15;             ///< K
  double space_temperature = 3.0;                  ///< K (cosmic background 2.7 K, rounded as ESATAN users do)
  std::optional<double> transient_orbits;          ///< absent: steady state per position
  solver::ThermalOptions options;
};

/// Parses `thermal:` against the case's node names; nullopt when absent.
/// @param has_orbit a transient needs an orbit (its period and loads)
std::optional<ThermalSettings> parseThermalSettings(const YamlDocument& doc, const std::vector<std::string>& nodes,
                                                    bool has_orbit);

}  // namespace radnet::cases
