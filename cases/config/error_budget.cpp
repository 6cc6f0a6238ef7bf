#include "cases/config/error_budget.hpp"

#include <algorithm>

namespace radnet::cases {

void applyErrorBudget(GeometryCase& c) {
  const double accuracy = c.solver.accuracy;
  for (DesignCase& d : c.design_cases)
    if (d.orbit) d.orbit->environment.relative_error = kLoadShare * accuracy;
  if (!c.view_factors.rays_pinned && c.view_factors.method != ViewFactorMethod::Exact)
    c.view_factors.monte_carlo.target_error = kViewFactorShare * accuracy;
  if (!c.view_factors.tolerance_pinned && c.view_factors.method != ViewFactorMethod::MonteCarlo) {
    c.view_factors.exact.relative_tolerance = kExactRelativeShare * accuracy;
    c.view_factors.exact.tolerance = kExactAbsoluteFraction * c.view_factors.exact.relative_tolerance;
  }
}

solver::SolverSettings budgetedSolverSettings(const solver::SolverSettings& settings, double max_view_factor_stderr) {
  solver::SolverSettings s = settings;
  if (s.rank > 0 || s.tolerance_given) return s;
  s.tolerance = std::clamp(kSolverNoiseFraction * max_view_factor_stderr, kSolverTightest, kSolverShare * s.accuracy);
  return s;
}

}  // namespace radnet::cases
