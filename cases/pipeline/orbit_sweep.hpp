#pragma once
// The orbit sweep of a geometry case: each orbit case swept and loaded, then all positions
// of all cases solved together, one solar and one IR band solve through the eigenpairs.
#include "cases/config/orbit_settings.hpp"
#include "cases/pipeline/results.hpp"
#include "geometry/rays/ray_caster.hpp"
#include "solver/radiative/settings.hpp"

#include <iosfwd>

namespace radnet::cases {

/// What the sweep needs of the rest of the run.
struct SweepInputs {
  const OrbitSettings& orbit;
  const geometry::RayCaster& caster;
  const RadiativeNetwork& radiative;
  const solver::LowRankBandSolver& solar;  ///< the solar band's core (ρ = 1 − α of the case's optics)
  const solver::LowRankBandSolver& ir;     ///< the IR band's core (ρ = 1 − ε)
  const solver::SolverSettings& solver;
  const solver::SparseRowMatrix& view_factor_stderr;  ///< σ_F (n×n), –; empty: exact view factors
  /// An earlier design case with the same orbits, attitude and environment but for the
  /// solar constant, a constant albedo and the Earth IR: its irradiances are reused,
  /// multiplied by these ratios, instead of casting the rays again.
  const SweepResult* reuse = nullptr;
  double direct_ratio = 1.0, albedo_ratio = 1.0, earth_ir_ratio = 1.0;
  /// Parts that turn during the orbit: each position is loaded and solved in its own
  /// configuration (caster, network, cores of optical set `optics`); null: a fixed geometry.
  class Articulated* articulated = nullptr;
  int optics = 0;
  /// σ of F_space + F_blocked per node (null: not known): with the network's F_space, what
  /// the view factors tell the sky kernel of each node's blocked share (orbits/sky_loads.hpp).
  const Eigen::VectorXd* lost_view_factor_stderr = nullptr;
  /// Each node's smallest α/ε and ε/α over the optical sets these loads serve (null: not
  /// known): the sky kernel's targets lean on the absorbed power with them (orbits/loads.hpp).
  const orbits::AbsorptanceRatios* absorptance = nullptr;
};

/// @throws NumericalError when a band solve fails
SweepResult runSweep(const SweepInputs& in, StageTimings& timings, bool show_progress, std::ostream& progress);

/// The absorbed power (n×P), W, of the irradiances under the two bands' cores: solar,
/// albedo and Earth IR, each interreflected. @throws NumericalError when a band solve fails
Eigen::MatrixXd absorbedPower(const solver::LowRankBandSolver& solar, const solver::LowRankBandSolver& ir,
                              const RadiativeNetwork& radiative, const orbits::EnvironmentLoads& irradiance,
                              double refine_tolerance);

/// Fills sw.uncertainty from its absorbed power and σ's; a warning when nodes are over budget.
void summarizeUncertainty(SweepResult& sw, double accuracy, std::ostream& progress);

}  // namespace radnet::cases
