#pragma once
// Temperatures from the exchange factors and the thermal block: a steady state per
// position, or one transient per orbit case (both case forms).
#include "cases/config/thermal_settings.hpp"
#include "cases/pipeline/results.hpp"

#include <iosfwd>

namespace radnet::cases {

/// The solver's thermal network from the settings and a run's exchange factors (m²): the
/// radiative nodes' GR, padded with the lumped nodes, plus the user couplings and MLI.
solver::ThermalNetwork thermalNetwork(const ThermalSettings& settings, const solver::ExchangeFactors& exchange);

/// Temperatures (n×P; P = 1 without a sweep), K, with the sweep's absorbed loads, and the
/// heat flows of every node. @throws NumericalError when the heat balance does not converge
ThermalSolution runThermal(const ThermalSettings& settings, const solver::ExchangeFactors& exchange,
                           const SweepResult* sweep, StageTimings& timings, std::ostream& progress);

/// The heat flows of a solution and their imbalance; q_env (n×P, W) the absorbed loads.
HeatBalance heatBalance(const solver::ThermalNetwork& net, const solver::ThermalResult& solution,
                        const Eigen::MatrixXd& q_env);

}  // namespace radnet::cases
