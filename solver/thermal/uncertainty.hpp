#pragma once
// First-order propagation of independent errors in each node's heat input to its
// temperature (docs/solver.md, "Uncertainty"): δT = −J⁻¹ δQ through the heat balance's
// Jacobian. The heat inputs' variances come from solver/radiative/uncertainty.hpp.
#include "solver/thermal/network.hpp"

#include <Eigen/Dense>

#include <vector>

namespace radnet::solver {

/// How temperatureStderr propagated: per position, once per span, or diagonal.
enum class TemperaturePropagation { PerPosition, PerSpan, Diagonal };

/// The networks sizes up to which each propagation is used.
inline constexpr Eigen::Index kTemperaturePerPositionMaxNodes = 300;
inline constexpr Eigen::Index kTemperaturePerSpanMaxNodes = 3000;

/// Standard uncertainty of the temperatures (n×P), K, from independent errors of each
/// node's heat input (variance var_q, n×P, W²): δT = −J⁻¹ δQ with J = ∂G/∂T of the heat
/// balance, so var T_i = Σ_k (J⁻¹)_ik² var Q_k over the free nodes (boundary nodes: 0).
/// J is evaluated at each position's temperatures (n ≤ kTemperaturePerPositionMaxNodes), at
/// the mean temperatures of each span [span_start[s], span_start[s+1]) (n ≤
/// kTemperaturePerSpanMaxNodes), or only its diagonal is kept (beyond: an underestimate,
/// since the spread of a node's error to its neighbours is left out). For a transient this
/// is the quasi-static response: right for the persistent part of the errors (the view
/// factors'), an upper bound for errors that change from position to position.
Eigen::MatrixXd temperatureStderr(const ThermalNetwork& net, const Eigen::MatrixXd& temperature,
                                  const Eigen::MatrixXd& var_q, const std::vector<int>& span_start,
                                  TemperaturePropagation& used);

}  // namespace radnet::solver
