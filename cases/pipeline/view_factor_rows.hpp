#pragma once
// View-factor rows and the network built from them, shared by the geometry run and its
// articulated configurations (which recast the rows a turning part changes).
#include "cases/config/geometry_case.hpp"
#include "cases/pipeline/results.hpp"
#include "geometry/rays/ray_caster.hpp"
#include "geometry/rays/view_factors.hpp"
#include "geometry/reciprocity.hpp"
#include "solver/radiative/network.hpp"

#include <iosfwd>
#include <memory>
#include <vector>

namespace radnet::cases {

/// Casts the rows marked (empty: all) with the case's Monte Carlo settings; under MPI each
/// rank its share, joined on every rank (a row's rays depend only on the seed and the node:
/// the same F as one process). `shared` (shared_rows.hpp): each rank casts the marked rows
/// it holds and keeps them, the per-node vectors joined.
geometry::ViewFactorResult castRays(const GeometryCase& c, const geometry::RayCaster& caster, std::vector<char> rows,
                                   bool show_progress, std::ostream& progress, bool shared = false);

/// The case's exact-method options with `method: auto`'s plan (which rows go to rays: too
/// many blockers, or pairs dearer than the row's rays), its cap on F's entries left off (it
/// is agreed over MPI ranks; exactStage sets it).
geometry::ExactOptions plannedExactOptions(const GeometryCase& c);

/// Moves F, σ and the per-node vectors of `from` into `to` (swapped: no copy).
void moveEstimate(geometry::ViewFactorEstimate& from, geometry::ViewFactorEstimate& to);

/// F by the exact method into `estimate`, with the rows `auto` leaves to sampling cast as
/// rays; `rays` gets each row's variance weight, `r` the method's counts and timings.
/// `shared`: the rows this rank does not hold are dropped from the integrated F (and its
/// σ) before the sampled rows are cast, each rank its own. `errors_on_pattern`: σ may stay on
/// F's pattern (estimate.error_on_pattern) when no row is left to rays.
void exactStage(const GeometryCase& c, const geometry::RayCaster& caster, GeometryRunResult& r, Eigen::VectorXd& rays,
                bool show_progress, std::ostream& progress, geometry::ViewFactorEstimate& estimate, bool shared = false,
                bool errors_on_pattern = false);

/// The network from the corrected F, stored sparse or dense by the solver policy. The
/// correction's F is released once read (the network's G holds it; 2.4 GB at 2e8 entries).
/// A correction with held rows (its `transposed` set) makes a network of shared rows.
std::unique_ptr<solver::Network> buildNetwork(const GeometryCase& c, const Eigen::VectorXd& area,
                                              geometry::ReciprocityCorrection& correction);
inline std::unique_ptr<solver::Network> buildNetwork(const GeometryCase& c, const Eigen::VectorXd& area,
                                                     geometry::ReciprocityCorrection&& correction) {
  return buildNetwork(c, area, correction);
}

}  // namespace radnet::cases
