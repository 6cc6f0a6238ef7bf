#pragma once
// The orbit sweep of a geometry case: each orbit case swept and loaded, then all positions
// of all cases solved together, one solar and one IR band solve through the eigenpairs.
#include "cases/config/orbit_settings.hpp"
#include "cases/pipeline/results.hpp"
#include "geometry/ray_caster.hpp"
#include "solver/settings.hpp"

#include <iosfwd>

namespace radnet::cases {

/// What the sweep needs of the rest of the run.
struct SweepInputs {
  const OrbitSettings& orbit;
  const geometry::RayCaster& caster;
  const RadiativeNetwork& radiative;
  const Eigen::VectorXd& absorptivity;  ///< per node, solar band, –
  const Eigen::VectorXd& emissivity;    ///< per node, IR band, –
  const solver::SolverSettings& solver;
  const Eigen::MatrixXd& view_factor_stderr;  ///< σ_F (n×n), –; empty: exact view factors
};

/// @throws NumericalError when a band solve fails
SweepResult runSweep(const SweepInputs& in, StageTimings& timings, bool show_progress, std::ostream& progress);

}  // namespace radnet::cases
