#include "solver/thermal_newton.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace radnet::solver::detail {
namespace {

// The residual (n + a) of the system at (t, u), the size of what flows through each row
// and the round-off of evaluating it.
struct Residual {
  Eigen::VectorXd r, scale, noise;
};

Residual residual(const ImplicitSystem& s, const Eigen::VectorXd& t, const Eigen::VectorXd& u) {
  const ThermalNetwork& net = s.net;
  const Eigen::Index n = t.size(), a = u.size();
  Eigen::VectorXd q = s.q;
  for (Eigen::Index k = 0; k < a; ++k) q[net.heaters[static_cast<size_t>(s.controlled[static_cast<size_t>(k)])].node] += u[k];
  Residual out{Eigen::VectorXd(n + a), Eigen::VectorXd(n + a), Eigen::VectorXd::Zero(n + a)};
  out.r.head(n) = -s.hb * netHeat(net, t, q);
  out.scale.head(n) = s.hb * balanceScale(net, t, q);
  out.noise.head(n) = s.hb * balanceRoundOff(net, t);
  if (s.transient) {
    // Stored heat C (T − history), and its round-off (the difference of two temperatures).
    constexpr double kRoundOff = 16 * std::numeric_limits<double>::epsilon();
    const Eigen::VectorXd c = capacitanceAt(net, t);
    out.r.head(n) += c.cwiseProduct(t - s.history);
    out.scale.head(n) += c.cwiseProduct((t - s.history).cwiseAbs());
    out.noise.head(n) += kRoundOff * c.cwiseProduct(t.cwiseAbs() + s.history.cwiseAbs());
  }
  out.scale.head(n).array() += 1e-30 * s.hb;  // W: a node through which nothing flows
  for (Eigen::Index k = 0; k < a; ++k) {
    const Heater& h = net.heaters[static_cast<size_t>(s.controlled[static_cast<size_t>(k)])];
    out.r[n + k] = t[h.sensor] - h.on_below_k;
    out.scale[n + k] = 1.0;  // K
  }
  for (Eigen::Index i = 0; i < n; ++i)
    if (net.isFixed(i)) out.r[i] = 0.0;
  return out;
}

Eigen::MatrixXd jacobian(const ImplicitSystem& s, const Eigen::VectorXd& t, Eigen::Index a) {
  const ThermalNetwork& net = s.net;
  const Eigen::Index n = t.size();
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(n + a, n + a);
  j.topLeftCorner(n, n) = -s.hb * netHeatJacobian(net, t);
  if (s.transient)
    j.topLeftCorner(n, n).diagonal() +=
        capacitanceAt(net, t) + capacitanceSlope(net, t).cwiseProduct(t - s.history);
  for (Eigen::Index k = 0; k < a; ++k) {
    const Heater& h = net.heaters[static_cast<size_t>(s.controlled[static_cast<size_t>(k)])];
    j(h.node, n + k) = -s.hb;
    j(n + k, h.sensor) = 1.0;
  }
  for (Eigen::Index i = 0; i < n; ++i)
    if (net.isFixed(i)) {
      j.row(i).setZero();
      j(i, i) = 1.0;
    }
  return j;
}

// Each row's residual in units of its tolerance: converged when every one is ≤ 1, i.e.
// |r_i| ≤ tol · (what flows through i) + (the round-off of evaluating it).
Eigen::VectorXd weights(const Residual& res, double tol) { return (tol * res.scale + res.noise).cwiseInverse(); }
double worst(const Residual& res, double tol) { return res.r.cwiseProduct(weights(res, tol)).cwiseAbs().maxCoeff(); }

}  // namespace

NewtonOutcome solveImplicit(const ImplicitSystem& s, Eigen::VectorXd& t, Eigen::VectorXd& u,
                            const ThermalOptions& opt) {
  const Eigen::Index n = t.size(), a = u.size();
  for (Eigen::Index i = 0; i < n; ++i)
    if (s.net.isFixed(i)) t[i] = s.net.fixed_temperature[i];
  NewtonOutcome out;
  Residual res = residual(s, t, u);
  for (int it = 0;; ++it) {
    if (worst(res, opt.tolerance_w) <= 1.0) {
      out.residual_w = res.r.head(n).cwiseAbs().maxCoeff() / s.hb;
      return out;
    }
    if (it == opt.max_newton_iterations) break;
    Eigen::VectorXd step = Eigen::PartialPivLU<Eigen::MatrixXd>(jacobian(s, t, a)).solve(-res.r);
    if (!step.allFinite()) {
      out.status = Status::Singular;
      out.message = "thermal Newton: singular Jacobian (a node with no capacitance, conductor or radiative link?)";
      return out;
    }
    // Keep every temperature positive: at most a 90 % drop per step. Then backtrack on the
    // scaled residual (its scale frozen at this iterate, so the merit does not move with λ).
    double lambda = 1.0;
    for (Eigen::Index i = 0; i < n; ++i)
      if (step[i] < 0) lambda = std::min(lambda, 0.9 * t[i] / -step[i]);
    const Eigen::VectorXd w = weights(res, opt.tolerance_w);
    const double merit0 = res.r.cwiseProduct(w).norm();
    Eigen::VectorXd t_try = t + lambda * step.head(n), u_try = u + lambda * step.tail(a);
    Residual trial = residual(s, t_try, u_try);
    for (int back = 0; back < 30 && worst(trial, opt.tolerance_w) > 1.0 &&
                       !(trial.r.cwiseProduct(w).norm() < (1 - 1e-4 * lambda) * merit0);
         ++back) {
      lambda *= 0.5;
      t_try = t + lambda * step.head(n);
      u_try = u + lambda * step.tail(a);
      trial = residual(s, t_try, u_try);
    }
    t = t_try;
    u = u_try;
    res = trial;
    ++out.iterations;
  }
  out.status = Status::NotConverged;
  out.message = "thermal Newton did not converge in " + std::to_string(opt.max_newton_iterations) +
                " iterations (largest heat-balance residual " + std::to_string(worst(res, opt.tolerance_w)) +
                " times its tolerance)";
  return out;
}

}  // namespace radnet::solver::detail
