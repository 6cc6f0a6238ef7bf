#include "solver/thermal.hpp"

#include "solver/network.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <tuple>

namespace radnet::solver {
namespace {

// ∂G/∂T (n×n, W/K): conduction Laplacian plus 4σT³ times the radiative coupling.
Eigen::MatrixXd jacobian(const ThermalNetwork& net, const Eigen::VectorXd& t) {
  Eigen::MatrixXd j = net.gr;
  j.diagonal() -= net.gr.rowwise().sum() + net.gr_space;
  j = kStefanBoltzmann * j * (4.0 * t.array().cube()).matrix().asDiagonal();
  for (int k = 0; k < net.conductors.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(net.conductors, k); it; ++it) {
      j(it.row(), it.col()) += it.value();
      j(it.row(), it.row()) -= it.value();
    }
  return j;
}

// The size of the terms of each node's balance, so that the tolerance is relative to what
// flows through the node.
Eigen::VectorXd balanceScale(const ThermalNetwork& net, const Eigen::VectorXd& t, const Eigen::VectorXd& q_env) {
  const Eigen::VectorXd t4 = t.array().square().square();
  Eigen::VectorXd s = q_env.cwiseAbs() + net.dissipation.cwiseAbs() +
                      kStefanBoltzmann * (net.gr.rowwise().sum() + net.gr_space).cwiseProduct(t4);
  for (int k = 0; k < net.conductors.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(net.conductors, k); it; ++it)
      s[it.row()] += std::abs(it.value()) * std::abs(t[it.row()]);
  return s.array() + 1.0;
}

bool isFixed(const ThermalNetwork& net, Eigen::Index i) { return !std::isnan(net.fixed_temperature[i]); }

// Newton on R(T) = c ∘ (T − T_prev_mix) − h β G(T) (transient) or −G(T) (steady, c = 0, hβ = 1).
// Fixed nodes keep their temperature. Backtracking keeps T > 0 and reduces |R|.
Status newton(const ThermalNetwork& net, Eigen::VectorXd& t, const Eigen::VectorXd& q_env,
              const Eigen::VectorXd& c_over, const Eigen::VectorXd& history, double hb, const ThermalOptions& opt,
              int& iterations, double& residual_w, std::string& message) {
  const Eigen::Index n = t.size();
  for (Eigen::Index i = 0; i < n; ++i)
    if (isFixed(net, i)) t[i] = net.fixed_temperature[i];
  auto resid = [&](const Eigen::VectorXd& x) {
    Eigen::VectorXd r = c_over.cwiseProduct(x - history) - hb * heatBalance(net, x, q_env);
    for (Eigen::Index i = 0; i < n; ++i)
      if (isFixed(net, i)) r[i] = 0.0;
    return r;
  };
  Eigen::VectorXd r = resid(t);
  for (int it = 0; it < opt.max_newton_iterations; ++it) {
    const Eigen::VectorXd scale = balanceScale(net, t, q_env);
    residual_w = (r.cwiseQuotient(scale)).cwiseAbs().maxCoeff();
    if (residual_w <= opt.tolerance_w) {
      residual_w = (r / std::max(hb, 1e-300)).cwiseAbs().maxCoeff();
      return Status::Converged;
    }
    Eigen::MatrixXd jm = -hb * jacobian(net, t);
    jm.diagonal() += c_over;
    for (Eigen::Index i = 0; i < n; ++i)
      if (isFixed(net, i)) {
        jm.row(i).setZero();
        jm(i, i) = 1.0;
      }
    Eigen::PartialPivLU<Eigen::MatrixXd> lu(jm);
    const Eigen::VectorXd step = lu.solve(-r);
    if (!step.allFinite()) {
      message = "thermal Newton: singular Jacobian (a node with no capacitance, conductor or radiative link?)";
      return Status::Singular;
    }
    double lambda = 1.0;
    // Keep every temperature positive: at most a 90 % drop per step.
    for (Eigen::Index i = 0; i < n; ++i)
      if (step[i] < 0) lambda = std::min(lambda, 0.9 * t[i] / -step[i]);
    const double r0 = r.norm();
    Eigen::VectorXd trial = t + lambda * step, rt = resid(trial);
    for (int back = 0; back < 30 && !(rt.norm() < (1 - 1e-4 * lambda) * r0); ++back) {
      lambda *= 0.5;
      trial = t + lambda * step;
      rt = resid(trial);
    }
    t = trial;
    r = rt;
    ++iterations;
  }
  message = "thermal Newton did not converge in " + std::to_string(opt.max_newton_iterations) + " iterations";
  return Status::NotConverged;
}

Eigen::VectorXd startingGuess(const ThermalNetwork& net, const Eigen::VectorXd& q_env) {
  // Each node alone in radiative equilibrium with what it receives (floored at space).
  const Eigen::VectorXd emit = net.gr.rowwise().sum() + net.gr_space;
  Eigen::VectorXd t(q_env.size());
  for (Eigen::Index i = 0; i < t.size(); ++i) {
    const double q = std::max(0.0, q_env[i] + net.dissipation[i]);
    t[i] = emit[i] > 0 ? std::pow(q / (kStefanBoltzmann * emit[i]) + std::pow(net.space_temperature, 4), 0.25) : 293.15;
    t[i] = std::max(t[i], std::max(net.space_temperature, 1.0));
    if (isFixed(net, i)) t[i] = net.fixed_temperature[i];
  }
  return t;
}

// Loads at time t (s): linear between the given positions, periodic with the orbit.
Eigen::VectorXd periodicLoad(const std::vector<double>& times, const Eigen::MatrixXd& q_env, double period, double t) {
  const size_t P = times.size();
  double tau = std::fmod(t, period);
  if (tau < times.front()) tau += period;
  auto it = std::upper_bound(times.begin(), times.end(), tau);
  const size_t hi = it == times.end() ? 0 : static_cast<size_t>(it - times.begin());
  const size_t lo = hi == 0 ? P - 1 : hi - 1;
  const double t_lo = times[lo], t_hi = hi == 0 ? times[0] + period : times[hi];
  const double w = t_hi > t_lo ? (tau - t_lo) / (t_hi - t_lo) : 0.0;
  return (1 - w) * q_env.col(static_cast<Eigen::Index>(lo)) + w * q_env.col(static_cast<Eigen::Index>(hi));
}

// The next time step (s) towards an output time `remaining` seconds away: the first is
// max_step/64, then each at most doubles up to max_step; no sliver of a last step.
double nextStep(double h_prev, double max_step, double remaining) {
  double h = h_prev > 0 ? std::min(max_step, 2.0 * h_prev) : max_step / 64.0;
  if (h >= remaining)
    h = remaining;
  else if (remaining - h < 0.25 * h)
    h = 0.5 * remaining;
  return h;
}

// Variable-step BDF2: y⁺ − a y + b y⁻ = h β f(y⁺), as (a, b, β) for the step ratio
// w = h / h_prev; the first step (h_prev = 0) is backward Euler (1, 0, 1).
std::tuple<double, double, double> bdf2Coefficients(double h, double h_prev) {
  if (!(h_prev > 0)) return {1.0, 0.0, 1.0};
  const double w = h / h_prev;
  return {(1 + w) * (1 + w) / (1 + 2 * w), w * w / (1 + 2 * w), (1 + w) / (1 + 2 * w)};
}

}  // namespace

void ThermalNetwork::validate() const {
  const Eigen::Index n = gr.rows();
  if (gr.cols() != n || gr_space.size() != n || capacitance.size() != n || dissipation.size() != n ||
      fixed_temperature.size() != n || conductors.rows() != n || conductors.cols() != n)
    throw std::invalid_argument("thermal network: every per-node array needs " + std::to_string(n) + " entries");
  if (!(std::isfinite(space_temperature) && space_temperature >= 0))
    throw std::invalid_argument("space temperature must be finite and >= 0 K");
  if ((capacitance.array() < 0).any() || !capacitance.allFinite())
    throw std::invalid_argument("capacitances must be finite and >= 0 J/K");
  for (Eigen::Index i = 0; i < n; ++i)
    if (!std::isnan(fixed_temperature[i]) && !(fixed_temperature[i] > 0 && std::isfinite(fixed_temperature[i])))
      throw std::invalid_argument("fixed temperatures must be finite and > 0 K");
}

Eigen::VectorXd heatBalance(const ThermalNetwork& net, const Eigen::VectorXd& t, const Eigen::VectorXd& q_env) {
  const Eigen::VectorXd t4 = t.array().square().square();
  Eigen::VectorXd g =
      q_env + net.dissipation + kStefanBoltzmann * (net.gr * t4 - net.gr.rowwise().sum().cwiseProduct(t4)) -
      kStefanBoltzmann * net.gr_space.cwiseProduct((t4.array() - std::pow(net.space_temperature, 4)).matrix());
  const Eigen::VectorXd kt = net.conductors * t;
  const Eigen::VectorXd krow = net.conductors * Eigen::VectorXd::Ones(t.size());
  return g + kt - krow.cwiseProduct(t);
}

HeatFlows heatFlows(const ThermalNetwork& net, const ThermalResult& solution, const Eigen::MatrixXd& q_env) {
  const Eigen::MatrixXd& t = solution.temperature;
  const Eigen::Index n = t.rows(), P = t.cols();
  if (q_env.rows() != n || q_env.cols() != P || solution.temperature_rate.rows() != n ||
      solution.temperature_rate.cols() != P || net.gr.rows() != n)
    throw std::invalid_argument("heat flows: temperatures, rates and loads need (n × P) entries");
  const Eigen::MatrixXd t4 = t.array().square().square().matrix();
  const Eigen::VectorXd gr_row = net.gr.rowwise().sum();
  const Eigen::VectorXd k_row = net.conductors * Eigen::VectorXd::Ones(n);
  HeatFlows f;
  f.emitted =
      -kStefanBoltzmann * (net.gr_space.asDiagonal() * (t4.array() - std::pow(net.space_temperature, 4)).matrix());
  f.radiative = kStefanBoltzmann * (net.gr * t4 - gr_row.asDiagonal() * t4);
  f.conducted = net.conductors * t - k_row.asDiagonal() * t;
  f.dissipation = net.dissipation.replicate(1, P);
  f.stored = -(net.capacitance.asDiagonal() * solution.temperature_rate);
  f.boundary = Eigen::MatrixXd::Zero(n, P);
  for (Eigen::Index i = 0; i < n; ++i)
    if (isFixed(net, i)) {  // its temperature does not move: it stores nothing, the boundary supplies the rest
      f.stored.row(i).setZero();
      f.boundary.row(i) =
          -(q_env.row(i) + f.emitted.row(i) + f.radiative.row(i) + f.conducted.row(i) + f.dissipation.row(i));
    }
  return f;
}

ThermalResult steadyStates(const ThermalNetwork& net, const Eigen::MatrixXd& q_env, const ThermalOptions& opt) {
  net.validate();
  ThermalResult res;
  const Eigen::Index n = q_env.rows();
  res.temperature.resize(n, q_env.cols());
  res.temperature_rate = Eigen::MatrixXd::Zero(n, q_env.cols());
  Eigen::VectorXd t = startingGuess(net, q_env.col(0));
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  for (Eigen::Index p = 0; p < q_env.cols(); ++p) {
    double residual = 0.0;
    Status s = newton(net, t, q_env.col(p), zero, zero, 1.0, opt, res.newton_iterations, residual, res.message);
    if (s != Status::Converged) {  // restart from the node-by-node guess before giving up
      t = startingGuess(net, q_env.col(p));
      s = newton(net, t, q_env.col(p), zero, zero, 1.0, opt, res.newton_iterations, residual, res.message);
    }
    if (s != Status::Converged) {
      res.status = s;
      res.message += " (steady state at position " + std::to_string(p) + ")";
      return res;
    }
    res.max_residual_w = std::max(res.max_residual_w, residual);
    res.temperature.col(p) = t;
  }
  return res;
}

ThermalResult transient(const ThermalNetwork& net, const std::vector<double>& times, const Eigen::MatrixXd& q_env,
                        double period, double orbits, const Eigen::VectorXd& initial, const ThermalOptions& opt) {
  net.validate();
  const Eigen::Index n = q_env.rows();
  const size_t P = times.size();
  if (P == 0 || static_cast<Eigen::Index>(P) != q_env.cols())
    throw std::invalid_argument("transient: one load column per time");
  if (!(period > 0 && orbits > 0 && opt.max_step_s > 0))
    throw std::invalid_argument("transient: period, orbits and step must be > 0");
  if (initial.size() != n || (initial.array() <= 0).any())
    throw std::invalid_argument("transient: initial temperatures must be > 0 K");
  // Output times: the P positions of the last orbit.
  const double last = (std::ceil(orbits) - 1) * period;
  std::vector<double> marks;
  for (double t : times) marks.push_back(last + t);
  ThermalResult res;
  res.temperature.resize(n, static_cast<Eigen::Index>(P));
  res.temperature_rate = Eigen::MatrixXd::Zero(n, static_cast<Eigen::Index>(P));
  Eigen::VectorXd t_prev = initial, t_now = initial, rate = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i)
    if (!std::isnan(net.fixed_temperature[i])) t_now[i] = t_prev[i] = net.fixed_temperature[i];
  double clock = 0.0, h_prev = 0.0;
  size_t next_mark = 0;
  while (next_mark < P) {
    // March to the next output time. The start is one backward-Euler step of max_step/64
    // (its local error is O(h²)), after which steps at most double (BDF2 stays zero-stable
    // for ratios below 1 + √2) up to max_step_s.
    const double target = marks[next_mark];
    while (target - clock > 1e-9 * std::max(1.0, std::abs(target))) {
      const double h = nextStep(h_prev, opt.max_step_s, target - clock);
      const auto [a, b, beta] = bdf2Coefficients(h, h_prev);
      const Eigen::VectorXd history = a * t_now - b * t_prev;
      Eigen::VectorXd guess = t_now;
      double residual = 0.0;
      const Status s = newton(net, guess, periodicLoad(times, q_env, period, clock + h), net.capacitance, history,
                              h * beta, opt, res.newton_iterations, residual, res.message);
      if (s != Status::Converged) {
        res.status = s;
        res.message += " (transient step at t = " + std::to_string(clock + h) + " s)";
        return res;
      }
      res.max_residual_w = std::max(res.max_residual_w, residual);
      rate = (guess - history) / (h * beta);  // the BDF2 derivative at the new time
      t_prev = t_now;
      t_now = guess;
      clock += h;
      h_prev = h;
    }
    res.temperature.col(static_cast<Eigen::Index>(next_mark)) = t_now;
    res.temperature_rate.col(static_cast<Eigen::Index>(next_mark)) = rate;
    ++next_mark;
  }
  if (!res.temperature.allFinite()) {
    res.status = Status::NonFinite;
    res.message = "transient temperatures are not finite";
  }
  return res;
}

}  // namespace radnet::solver
