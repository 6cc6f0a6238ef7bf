#pragma once
// `uncertainty:` each material's α and ε drawn at random, and shifted one at a time for
// the sensitivities, every variant on the run's one eigendecomposition: a variant costs two
// k×k cores, the exchange factors and the band solves and temperatures of every case.
#include "cases/pipeline/design_run.hpp"

#include <iosfwd>

namespace radnet::cases {

/// The finite-difference half step of the sensitivities: large enough that the
/// temperatures' solve tolerance (≪ 1e-3 K) does not show, small enough that T(α) is
/// linear over it to the percent.
inline constexpr double kSensitivityStep = 0.01;

/// A warning when more than this share of the sampled node values of α or ε is clipped: a
/// few percent is the physics (α 0.94 ± 0.03 cannot exceed 1), beyond that the sampled
/// distribution is no longer the normal one asked for.
inline constexpr double kClippedWarning = 0.05;

/// A sample's periodic transient settles to this many times the case's periodic_tolerance.
inline constexpr double kSamplePeriodicFactor = 10.0;

/// The optical sets with the α and ε of each of `materials` shifted by da[m] and de[m],
/// clipped to [0, 1].
std::vector<OpticalSet> shiftedSets(const GeometryCase& c, const std::vector<std::string>& materials,
                                    const Eigen::VectorXd& da, const Eigen::VectorXd& de);

/// Every case's orbit temperature statistics under `sets` (in place of the case's optical
/// sets), on the cases' loads as swept. `band_cores` counts the cores built.
/// @throws NumericalError when a band solve or a heat balance fails
CaseTemperatures caseTemperaturesUnder(const DesignContext& ctx, const std::vector<CaseRun>& runs,
                                       const std::vector<OpticalSet>& sets, int& band_cores);

/// The samples, their percentiles and the sensitivities (c.optical_uncertainty must be set).
OpticalUncertaintyResult sampleOpticalUncertainty(const DesignContext& ctx, const std::vector<CaseRun>& runs,
                                                  int& band_cores, bool show_progress, std::ostream& progress);

}  // namespace radnet::cases
