#pragma once
// The error budget (docs/solver.md, "Error budget"): one `solver.accuracy` (relative, on
// each node's absorbed power) split into what each stage may spend. A count the case pins
// (rays, planet_rays, shadow_samples, shadow_cell, rank, tolerance) is left as given; the
// run then reports the uncertainty that results, whatever it is.
#include "cases/config/geometry_case.hpp"

namespace radnet::cases {

/// Each environment load's sampling σ, relative to its scale (the node's area times the
/// flux for direct Sun; see geometry::PlanetRayOptions for the planet's).
inline constexpr double kLoadShare = 0.5;
/// The absolute σ of each view-factor entry cast by rays (F ≤ 1 and a node's absorbed
/// power is Σ_j F_ij M_j, so an entry's σ is roughly its relative share).
inline constexpr double kViewFactorShare = 0.1;
/// Each exactly integrated pair's error relative to its value (F ≥ 0 and a node's absorbed
/// power is a positive sum over its row, so a relative error bounds the row's), and the
/// absolute floor per entry as a fraction of it (pairs that barely see each other).
inline constexpr double kExactRelativeShare = kViewFactorShare;
inline constexpr double kExactAbsoluteFraction = 1e-3;
/// The band solves refine to this fraction of the largest view-factor σ (refining below
/// the view factors' own noise buys nothing) ...
inline constexpr double kSolverNoiseFraction = 0.1;
/// ... within [kSolverTightest, kSolverShare × accuracy]: exact view factors get a solve
/// to round-off, and noisy ones never a solve looser than a tenth of the budget.
inline constexpr double kSolverShare = 0.1;
inline constexpr double kSolverTightest = 1e-10;

/// Sets the shares the case left open: the loads' relative error, the view-factor target
/// error of ray-cast rows and the exact method's targets per pair.
void applyErrorBudget(GeometryCase& c);

/// The solver settings of a run once the view factors are known: their tolerance follows
/// the largest view-factor σ unless the case gave a rank or a tolerance.
solver::SolverSettings budgetedSolverSettings(const solver::SolverSettings& settings, double max_view_factor_stderr);

}  // namespace radnet::cases
