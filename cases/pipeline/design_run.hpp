#pragma once
// The design cases of a geometry case (hot/cold, BOL/EOL optics, dissipation levels), all
// on the one eigendecomposition of G: an optical set costs one k×k core per band and its
// exchange factors, a case its sweep, its band solves and its temperatures.
#include "cases/config/geometry_case.hpp"
#include "cases/pipeline/case_merge.hpp"
#include "cases/pipeline/results.hpp"
#include "geometry/rays/ray_caster.hpp"

#include <iosfwd>
#include <memory>
#include <optional>
#include <vector>

namespace radnet::cases {

/// What every design case shares.
struct DesignContext {
  const GeometryCase& c;
  const geometry::RayCaster& caster;
  const RadiativeNetwork& radiative;
  const solver::SolverSettings& solver;            ///< with the error budget's tolerance
  const solver::SparseRowMatrix& view_factor_stderr;       ///< σ_F (n×n), –
  const Eigen::VectorXd& lost_view_factor_stderr;  ///< σ of F_space + F_blocked (n), –
  const Eigen::VectorXd& area;                     ///< of the radiative nodes, m²
  /// Per optical set, the networks of a set that changes ρs or τ (null: the case's).
  std::vector<std::shared_ptr<const struct OwnOpticsNetwork>> own_networks = {};
  /// Parts that turn during the orbit: their configurations (null: a fixed geometry).
  class Articulated* articulated = nullptr;
};

/// An optical set that changes specular reflectance or transmittance: its F̃ traced with its
/// own optics, per band, on Ã = A κ of its own, and its own eigendecomposition (its G̃ is not
/// the case's; docs/solver.md, "Optical sets that change ρs or τ").
struct OwnOpticsNetwork {
  RadiativeNetwork radiative;
  solver::SparseRowMatrix view_factor_stderr;  ///< σ of its F̃ (n×n), –
  Eigen::VectorXd lost_view_factor_stderr;     ///< σ of its F̃_space + F̃_blocked (n), –
  Eigen::VectorXd area;                        ///< its IR network's areas Ã, m²
};

/// What an optical set is solved on: its own networks, or the case's.
struct SetNetworks {
  const RadiativeNetwork& radiative;
  const solver::SparseRowMatrix& view_factor_stderr;
  const Eigen::VectorXd& lost_view_factor_stderr;
  const Eigen::VectorXd& area;
};
SetNetworks networksOf(const DesignContext& ctx, int optics);

/// One design case's own results, kept apart for the optical samples.
struct CaseRun {
  std::optional<SweepResult> sweep;
  std::optional<ThermalSettings> settings;  ///< the case's thermal model (dissipations applied)
  std::optional<ThermalSolution> thermal;
};

/// The two band cores of one optical set: solar (ρ = 1 − α) and IR (ρ = 1 − ε).
struct BandCores {
  std::unique_ptr<solver::LowRankBandSolver> solar, ir;
};
BandCores bandCores(const RadiativeNetwork& radiative, const OpticalSet& set);

/// The base thermal model with the case's dissipation scale and per-node overrides.
ThermalSettings caseThermalSettings(const ThermalSettings& base, const DesignCase& d);

/// A sweep's positions and orbit cases with `absorbed_total` as the only load: what the
/// thermal solve reads.
SweepResult thermalForcing(const SweepResult& sweep, Eigen::MatrixXd absorbed_total);

/// Each row of (c×n) tables: a case's orbit minimum, time-weighted mean and maximum.
struct CaseTemperatures {
  Eigen::MatrixXd min, mean, max;  ///< K
};
/// Fills row k of `t` (sized c × n on first use) from case k's temperatures.
void setCaseRow(CaseTemperatures& t, int k, int cases, const ThermalSolution& thermal, const SweepResult* sweep);

/// Runs every design case, joins them into r.sweep and r.thermal, fills r.cases and keeps
/// each case's own results in `runs`. @throws NumericalError
void runDesignCases(const DesignContext& ctx, GeometryRunResult& r, std::vector<CaseRun>& runs, bool show_progress,
                    std::ostream& progress);

}  // namespace radnet::cases
