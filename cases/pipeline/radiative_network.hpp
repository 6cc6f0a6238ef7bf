#pragma once
// The stages both case forms share once they have a network: the one eigendecomposition
// of G and the exchange factors, by the solver policy (solver/radiative/policy.hpp).
#include "cases/pipeline/results.hpp"
#include "solver/radiative/settings.hpp"

#include <iosfwd>

namespace radnet::cases {

/// The eigenpairs serving both bands; `max_reflectance` per node is the larger of the
/// two bands' ρ, `emissivities` every optical set's ε (the rank's GR check).
/// @throws NumericalError when the eigensolver fails
solver::EigenPairs decomposeNetwork(const solver::Network& net, const Eigen::VectorXd& max_reflectance,
                                    const std::vector<Eigen::VectorXd>& emissivities,
                                    const solver::SolverSettings& settings, StageTimings& timings);

/// A warning when the rank cap stopped the decomposition before the probes met the
/// tolerance the rank-k answers are used at (GR from the pairs, or unrefined band solves),
/// or when an explicit rank leaves GR less accurate than the error budget's solver share; ""
/// otherwise.
std::string rankWarning(const solver::EigenPairs& pairs, const solver::SolverSettings& settings);

/// Every warning the decomposition gives: `auto`'s dense fallback after Lanczos failed, and
/// rankWarning's.
std::vector<std::string> decompositionWarnings(const solver::EigenPairs& pairs, const solver::SolverSettings& settings);

/// GR and GR to space. @throws NumericalError when they cannot be formed (e.g. a lossless closed cavity)
solver::ExchangeFactors exchangeFactors(const RadiativeNetwork& radiative, const Eigen::VectorXd& emissivity,
                                        const solver::SolverSettings& settings, StageTimings& timings);

}  // namespace radnet::cases
