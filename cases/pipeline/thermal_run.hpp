#pragma once
// Temperatures from the exchange factors and the thermal block: a steady state per
// position, or one transient per orbit case (both case forms).
#include "cases/config/thermal_settings.hpp"
#include "cases/pipeline/results.hpp"

#include "solver/thermal/optics.hpp"

#include <iosfwd>
#include <memory>

namespace radnet::cases {

/// GR (n×n) and GR to space of the whole thermal network for a run's exchange factors: the
/// radiative nodes' GR padded with the lumped nodes, plus the user couplings, m².
solver::ExchangeUpdate thermalExchange(const ThermalSettings& settings, const solver::ExchangeFactors& exchange);

/// The solver's thermal network from the settings and a run's exchange factors (m²): the
/// radiative nodes' GR, padded with the lumped nodes, plus the user couplings and MLI.
/// With `keep_factored` and factored exchange factors, GR stays factored (the direct part
/// sparse, with the couplings; the basis padded with zero rows): no n × n matrix at all.
solver::ThermalNetwork thermalNetwork(const ThermalSettings& settings, const solver::ExchangeFactors& exchange,
                                      bool keep_factored = false);

/// What the temperatures' uncertainty needs of a geometry case beyond the sweep.
struct ThermalErrorInputs {
  const solver::SparseRowMatrix& view_factor_stderr;  ///< σ_F (n_r×n_r), –
  const Eigen::VectorXd& lost_view_factor_stderr;  ///< σ of F_space + F_blocked (n_r), –
  const Eigen::VectorXd& emissivity;          ///< of the radiative nodes, –
  const Eigen::VectorXd& area;                ///< of the radiative nodes, m²
  /// GR formed from the pairs: the probes' largest error of GR x relative to ε_i A_i max x
  /// (EigenPairs::probe_exchange_error); 0 when GR is exact.
  double exchange_truncation = 0.0;
};

/// Temperatures (n×P; P = 1 without a sweep), K, with the sweep's absorbed loads, and the
/// heat flows of every node; with a sweep and `errors`, their standard uncertainty too. With
/// `optics`, the nodes' ε(T) and α(T) are followed (GR re-formed on the one eigendecomposition).
/// With `turned` (parts that turn), position p is solved with GR turned[sweep->configuration[p]].
/// @throws NumericalError when the heat balance does not converge
ThermalSolution runThermal(const ThermalSettings& settings, const solver::ExchangeFactors& exchange,
                           const SweepResult* sweep, StageTimings& timings, std::ostream& progress,
                           const ThermalErrorInputs* errors = nullptr,
                           std::shared_ptr<const solver::TemperatureOptics> optics = nullptr,
                           const std::vector<const solver::ExchangeFactors*>& turned = {});

/// The heat flows of a solution and their imbalance; q_env (n×P, W) the absorbed loads.
HeatBalance heatBalance(const solver::ThermalNetwork& net, const solver::ThermalResult& solution,
                        const Eigen::MatrixXd& q_env,
                        const std::vector<const solver::ExchangeUpdate*>& exchange_per_position = {});

}  // namespace radnet::cases
