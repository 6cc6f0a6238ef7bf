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

/// The thermal model. Its nodes are the case's radiative nodes (geometry or network form,
/// in case order) followed by the lumped nodes of `thermal.lumped`, which have no
/// geometry: they exchange heat only through conductors and user radiative couplings.
struct ThermalSettings {
  std::vector<std::string> node_names;                      ///< every thermal node, radiative ones first
  int radiative_nodes = 0;                                  ///< how many of them come first with exchange factors
  Eigen::VectorXd capacitance;                              ///< J/K per node (0 when not given: arithmetic node)
  Eigen::VectorXd dissipation;                              ///< W
  Eigen::VectorXd fixed_temperature;                        ///< K, NaN for free nodes
  Eigen::VectorXd initial_temperature;                      ///< K, where a transient starts
  std::vector<Eigen::Triplet<double>> conductors;           ///< (i, j, W/K), both directions
  std::vector<Eigen::Triplet<double>> radiative_couplings;  ///< user GR and MLI (i, j, m²), both directions
  double space_temperature = 3.0;                           ///< K (cosmic background 2.7 K, rounded as ESATAN users do)
  std::optional<double> transient_orbits;                   ///< absent: steady state per position
  solver::ThermalOptions options;
  int nodeCount() const { return static_cast<int>(node_names.size()); }
  bool isLumped(int i) const { return i >= radiative_nodes; }
};

/// Parses `thermal:` against the case's radiative nodes; nullopt when absent.
/// @param names      the radiative nodes, in case order
/// @param area       their areas, m² (MLI couplings are A_outer ε*)
/// @param has_orbit  a transient needs an orbit (its period and loads)
std::optional<ThermalSettings> parseThermalSettings(const YamlDocument& doc, const std::vector<std::string>& names,
                                                    const Eigen::VectorXd& area, bool has_orbit);

}  // namespace radnet::cases
