#pragma once
// The step rules of the transients (transient.cpp): variable-step BDF2's coefficients and
// the step-length schedule towards an output time.
#include <algorithm>
#include <tuple>

namespace radnet::solver {

// Variable-step BDF2: y⁺ − a y + b y⁻ = h β f(y⁺), as (a, b, β) for the step ratio
// w = h / h_prev; the first step after a start or a discontinuity (h_prev = 0) is backward
// Euler (1, 0, 1).
inline std::tuple<double, double, double> bdf2Coefficients(double h, double h_prev) {
  if (!(h_prev > 0)) return {1.0, 0.0, 1.0};
  const double w = h / h_prev;
  return {(1 + w) * (1 + w) / (1 + 2 * w), w * w / (1 + 2 * w), (1 + w) / (1 + 2 * w)};
}

// The next step (s) towards a target `remaining` seconds away: the first is max_step/64
// (backward Euler's local error is O(h²)), then each at most doubles (BDF2 stays zero-stable
// for ratios below 1 + √2) up to max_step; no sliver of a last step.
inline double nextStep(double h_prev, double max_step, double remaining) {
  double h = h_prev > 0 ? std::min(max_step, 2.0 * h_prev) : max_step / 64.0;
  if (h >= remaining)
    h = remaining;
  else if (remaining - h < 0.25 * h)
    h = 0.5 * remaining;
  return h;
}

}  // namespace radnet::solver
