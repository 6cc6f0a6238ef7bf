#pragma once
// The `solver:` block of a case: the network solve (rank, tolerance, refinement,
// eigensolver; both case forms) and, for geometry cases, how view factors are computed.
#include "cases/config/yaml_document.hpp"
#include "geometry/contour_view_factors.hpp"
#include "geometry/view_factors.hpp"
#include "solver/settings.hpp"

namespace radnet::cases {

enum class ViewFactorMethod { MonteCarlo, Contour };

/// Case-file spelling: "monte_carlo" or "contour".
const char* toString(ViewFactorMethod method);

/// `solver.view_factors` of a geometry case.
struct ViewFactorSettings {
  ViewFactorMethod method = ViewFactorMethod::MonteCarlo;
  geometry::ViewFactorOptions monte_carlo;  ///< rays, seed, target error, replicas, sampling
  geometry::ContourOptions contour;         ///< quadrature tolerance
};

/// Parses `solver:` (defaults when absent). `view_factors` is accepted here and read by
/// parseViewFactorSettings. @throws InputError with file:line:column
solver::SolverSettings parseSolverSettings(const YamlDocument& doc, const YAML::Node& node);

/// Parses `solver.view_factors` (defaults when absent).
ViewFactorSettings parseViewFactorSettings(const YamlDocument& doc, const YAML::Node& node);

}  // namespace radnet::cases
