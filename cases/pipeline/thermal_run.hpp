#pragma once
// Temperatures from the exchange factors and the thermal block: a steady state per
// position, or one transient per orbit case (both case forms).
#include "cases/config/thermal_settings.hpp"
#include "cases/pipeline/results.hpp"

#include <iosfwd>

namespace radnet::cases {

/// The solver's thermal network from the settings and a run's exchange factors (m²).
solver::ThermalNetwork thermalNetwork(const ThermalSettings& settings, const solver::ExchangeFactors& exchange);

/// Temperatures (n×P; P = 1 without a sweep), K, with the sweep's absorbed loads.
/// @throws NumericalError when the heat balance does not converge
solver::ThermalResult runThermal(const ThermalSettings& settings, const solver::ExchangeFactors& exchange,
                                 const SweepResult* sweep, StageTimings& timings, std::ostream& progress);

}  // namespace radnet::cases
