// The forcing of a transient between its samples: linear interpolation, periodic or held.
#include "solver/thermal/temperatures.hpp"
#include "solver/thermal/newton.hpp"

#include <stdexcept>

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

Eigen::VectorXd ThermalForcing::sampleAt(const Eigen::MatrixXd& samples, double t) const {
  if (samples.size() == 0) return Eigen::VectorXd();
  const Bracket b = bracket(times_s, load_period_s, t);
  return (1 - b.w) * samples.col(b.lo) + b.w * samples.col(b.hi);
}

int ThermalForcing::exchangeStateAt(double t) const {
  if (!exchange_states || exchange_state.empty()) return -1;
  const Bracket b = bracket(times_s, load_period_s, t);
  return exchange_state[static_cast<size_t>(b.w < 0.5 ? b.lo : b.hi)];
}

double ThermalForcing::sunlitAt(double t) const {
  if (sunlit_fraction.empty()) return 1.0;
  const Bracket b = bracket(times_s, load_period_s, t);
  return (1 - b.w) * sunlit_fraction[static_cast<size_t>(b.lo)] + b.w * sunlit_fraction[static_cast<size_t>(b.hi)];
}

namespace detail {

void checkExchangeStates(const ThermalNetwork& net, const ThermalForcing& f) {
  if (!f.exchange_states) return;
  const auto& states = *f.exchange_states;
  if (f.exchange_state.size() != f.times_s.size())
    throw std::invalid_argument("thermal forcing: one exchange state per sample");
  for (int k : f.exchange_state)
    if (k < 0 || static_cast<size_t>(k) >= states.size())
      throw std::invalid_argument("thermal forcing: an exchange state index out of range");
  for (const ExchangeUpdate& u : states)
    if (u.gr.rows() != net.size() || u.gr.cols() != net.size() || u.gr_space.size() != net.size() ||
        !u.gr.allFinite() || !u.gr_space.allFinite())
      throw std::invalid_argument("thermal forcing: an exchange state's GR does not fit the network");
}

void checkTransientInputs(const ThermalNetwork& net, const ThermalForcing& f, const Eigen::VectorXd& initial,
                 const ThermalOptions& opt) {
  net.validate();
  const size_t P = f.times_s.size();
  if (P == 0 || static_cast<Eigen::Index>(P) != f.q_env.cols() || f.q_env.rows() != net.size() ||
      !(f.sunlit_fraction.empty() || f.sunlit_fraction.size() == P))
    throw std::invalid_argument("transient: one load column and sunlit fraction per time");
  checkExchangeStates(net, f);
  if (!(f.load_period_s >= 0 && opt.max_step_s > 0)) throw std::invalid_argument("transient: step must be > 0");
  if (f.load_period_s > 0 && !(f.times_s.back() <= f.load_period_s))
    throw std::invalid_argument("transient: sample times must lie within one load period");
  if (initial.size() != net.size() || !(initial.array() > 0).all() || !initial.allFinite())
    throw std::invalid_argument("transient: initial temperatures must be finite and > 0 K");
}

void checkFinite(ThermalResult& res) {
  if (res.status == Status::Converged && !res.temperature.allFinite()) {
    res.status = Status::NonFinite;
    res.message = "transient temperatures are not finite";
  }
}

}  // namespace detail

}  // namespace radnet::solver
