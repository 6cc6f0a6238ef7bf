#pragma once
// The `solver:` block of a case: the network solve (rank, tolerance, refinement,
// eigensolver; both case forms) and, for geometry cases, how view factors are computed.
#include "cases/config/yaml_document.hpp"
#include "geometry/exact/view_factors.hpp"
#include "geometry/rays/view_factors.hpp"
#include "solver/radiative/settings.hpp"

namespace radnet::cases {

/// Auto: exact for pairs with few blockers, ray casting for the rows of the rest; Exact:
/// every pair deterministic; MonteCarlo: every row by ray casting.
enum class ViewFactorMethod { Auto, Exact, MonteCarlo };

/// Case-file spelling: "auto", "exact" or "monte_carlo".
const char* toString(ViewFactorMethod method);

/// `solver.view_factors` of a geometry case.
struct ViewFactorSettings {
  ViewFactorMethod method = ViewFactorMethod::Auto;
  geometry::ViewFactorOptions monte_carlo;  ///< rays, seed, target error, replicas, sampling
  geometry::ExactOptions exact;             ///< tolerance; max_blockers (auto only)
  bool rays_pinned = false;                 ///< the case gave rays or target_error (the budget leaves them)
  bool tolerance_pinned = false;            ///< the case gave tolerance (the budget leaves the exact targets)
};

/// Parses `solver:` (defaults when absent). `view_factors` is accepted here and read by
/// parseViewFactorSettings. @throws InputError with file:line:column
solver::SolverSettings parseSolverSettings(const YamlDocument& doc, const YAML::Node& node);

/// Parses `solver.view_factors` (defaults when absent).
ViewFactorSettings parseViewFactorSettings(const YamlDocument& doc, const YAML::Node& node);

}  // namespace radnet::cases
