// The forcing of a transient between its samples: linear interpolation, periodic or held.
#include "solver/thermal/temperatures.hpp"

#include <algorithm>
#include <cmath>

namespace radnet::solver {

namespace {

// Where time t falls among the samples: the samples before and after it and the weight of
// the later one, wrapping at `period` (0: held before the first and after the last sample).
struct Bracket {
  Eigen::Index lo = 0, hi = 0;
  double w = 0.0;
};

Bracket bracket(const std::vector<double>& times, double period, double t) {
  const size_t P = times.size();
  double tau = period > 0 ? t - period * std::floor(t / period) : t;
  if (period > 0 && tau < times.front()) tau += period;
  const auto it = std::upper_bound(times.begin(), times.end(), tau);
  if (!(period > 0)) {
    if (it == times.begin()) return {0, 0, 0.0};
    if (it == times.end()) return {static_cast<Eigen::Index>(P) - 1, static_cast<Eigen::Index>(P) - 1, 0.0};
  }
  const size_t hi = it == times.end() ? 0 : static_cast<size_t>(it - times.begin());
  const size_t lo = hi == 0 ? P - 1 : hi - 1;
  const double t_lo = times[lo], t_hi = hi == 0 ? times[0] + period : times[hi];
  return {static_cast<Eigen::Index>(lo), static_cast<Eigen::Index>(hi), t_hi > t_lo ? (tau - t_lo) / (t_hi - t_lo) : 0.0};
}

}  // namespace

Eigen::VectorXd ThermalForcing::loadAt(double t) const {
  const Bracket b = bracket(times_s, load_period_s, t);
  return (1 - b.w) * q_env.col(b.lo) + b.w * q_env.col(b.hi);
}

double ThermalForcing::sunlitAt(double t) const {
  if (sunlit_fraction.empty()) return 1.0;
  const Bracket b = bracket(times_s, load_period_s, t);
  return (1 - b.w) * sunlit_fraction[static_cast<size_t>(b.lo)] + b.w * sunlit_fraction[static_cast<size_t>(b.hi)];
}

}  // namespace radnet::solver
