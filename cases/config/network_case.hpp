#pragma once
// The network-only case form: the user gives areas, reflectances and form factors from
// another tool (or a paper) and radnet solves the network. Schema in docs/case-files.md.
#include "cases/config/expectation.hpp"
#include "cases/config/output_settings.hpp"
#include "cases/config/thermal_settings.hpp"
#include "cases/config/yaml_document.hpp"
#include "solver/radiative/network.hpp"
#include "solver/radiative/settings.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <optional>
#include <string>
#include <vector>

namespace radnet::cases {

struct NetworkCase {
  std::string name;
  std::string file;
  std::string yaml_text;
  std::vector<std::string> names;
  Eigen::VectorXd area;                       ///< m²
  Eigen::VectorXd reflectance;                ///< –
  Eigen::VectorXd initial_exitance;           ///< W/m²
  std::optional<Eigen::VectorXd> emissivity;  ///< – (all nodes or none): enables GR output
  bool sparse = false;
  Eigen::MatrixXd view_factors;                     ///< dense form
  Eigen::SparseMatrix<double> view_factors_sparse;  ///< `view_factor_entries` form
  solver::NetworkTolerances tolerances;
  solver::SolverSettings solver;
  OutputSettings output;  ///< `output:` which matrices are also written densely
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

}  // namespace radnet::cases
