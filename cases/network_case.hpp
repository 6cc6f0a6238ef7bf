#pragma once
// The network-only case form: the user gives areas, reflectances and form factors from
// another tool (or a paper) and radnet solves the network. Schema in docs/case-files.md.
#include "cases/thermal_settings.hpp"
#include "cases/yaml_support.hpp"
#include "solver/eigenpairs.hpp"
#include "solver/network.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <optional>
#include <string>
#include <vector>

namespace radnet::cases {

/// The `solver:` block.
struct SolverSettings {
  int rank = 0;                  ///< explicit k (0: from the tolerance)
  double tolerance = 1e-10;      ///< relative residual target, and the a-priori truncation bound
  std::optional<bool> refine;    ///< default: refine when no explicit rank is given
  int max_rank = 200;            ///< cap on k chosen from a tolerance
  solver::EigenMethod method = solver::EigenMethod::Auto;
  bool refineEnabled() const { return refine.value_or(rank == 0); }
};

/// One `expect:` entry, checked by `radnet check`.
struct Expectation {
  /// exitance | irradiance | view_factor | space_view_factor | radiative_exchange | gr_space | eigenvalue |
  /// temperature (at position `index`, default 0) | orbit_mean_absorbed | orbit_max_absorbed_solar
  std::string quantity;
  std::string node;      ///< node name (or empty for eigenvalue)
  std::string to;        ///< second node for pair quantities
  int index = -1;        ///< eigenvalue index (0-based, by decreasing |λ|) or sweep position
  double value = 0.0;
  double tolerance = 0.0;  ///< absolute
  std::string where;       ///< file:line:column of the entry, for messages
};

struct NetworkCase {
  std::string name;
  std::string file;
  std::string yaml_text;
  std::vector<std::string> names;
  Eigen::VectorXd area;              ///< m²
  Eigen::VectorXd reflectance;       ///< –
  Eigen::VectorXd initial_exitance;  ///< W/m²
  std::optional<Eigen::VectorXd> emissivity;  ///< – (all nodes or none): enables GR output
  bool sparse = false;
  Eigen::MatrixXd view_factors;                  ///< dense form
  Eigen::SparseMatrix<double> view_factors_sparse;  ///< `view_factor_entries` form
  solver::NetworkTolerances tolerances;
  SolverSettings solver;
  std::optional<ThermalSettings> thermal;  ///< steady state with dissipations (needs emissivities)
  std::vector<Expectation> expectations;
  int network_line = 0, network_column = 0;  ///< position of `network:` for re-located errors

  /// Builds the validated network. @throws InputError (network errors re-located to the case)
  solver::Network buildNetwork() const;
};

/// True when the document is of the network-only form (has a `network:` key).
bool isNetworkCase(const YamlDocument& doc);

/// Parses and validates a network case. @throws InputError with file:line:column
NetworkCase loadNetworkCase(const YamlDocument& doc);

/// Parses the `solver:` block (shared with the geometry form).
SolverSettings parseSolverSettings(const YamlDocument& doc, const YAML::Node& node);

}  // namespace radnet::cases
