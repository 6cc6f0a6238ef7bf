#include "solver/thermal/newton.hpp"

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

// With `frozen`, the scale and round-off are taken from there instead of evaluated anew
// (the O(n²) part of a residual that a chord step does not need to repeat).
Residual residual(const ImplicitSystem& s, const Eigen::VectorXd& t, const Eigen::VectorXd& u,
                  const Residual* frozen = nullptr) {
  const ThermalNetwork& net = s.net;
  const Eigen::Index n = t.size(), a = u.size();
  Eigen::VectorXd q = s.q;
  for (Eigen::Index k = 0; k < a; ++k) q[net.heaters[static_cast<size_t>(s.controlled[static_cast<size_t>(k)])].node] += u[k];
  Residual out{Eigen::VectorXd(n + a), Eigen::VectorXd(n + a), Eigen::VectorXd::Zero(n + a)};
  const Eigen::VectorXd* gr_row = s.cache && s.cache->gr_row_sum.size() == n ? &s.cache->gr_row_sum : nullptr;
  out.r.head(n) = -s.hb * netHeat(net, t, q, gr_row);
  if (frozen) {
    out.scale = frozen->scale;
    out.noise = frozen->noise;
  } else {
    out.scale.head(n) = s.hb * balanceScale(net, t, q);
    out.noise.head(n) = s.hb * balanceRoundOff(net, t, gr_row);
  }
  if (s.transient) {
    // Stored heat C (T − history), and its round-off (the difference of two temperatures).
    constexpr double kRoundOff = 16 * std::numeric_limits<double>::epsilon();
    const Eigen::VectorXd c = capacitanceAt(net, t);
    out.r.head(n) += c.cwiseProduct(t - s.history);
    if (!frozen) {
      out.scale.head(n) += c.cwiseProduct((t - s.history).cwiseAbs());
      out.noise.head(n) += kRoundOff * c.cwiseProduct(t.cwiseAbs() + s.history.cwiseAbs());
    }
  }
  if (!frozen) out.scale.head(n).array() += 1e-30 * s.hb;  // W: a node through which nothing flows
  for (Eigen::Index k = 0; k < a; ++k) {
    const Heater& h = net.heaters[static_cast<size_t>(s.controlled[static_cast<size_t>(k)])];
    out.r[n + k] = t[h.sensor] - h.on_below_k;
    out.scale[n + k] = 1.0;  // K
  }
  for (Eigen::Index i = 0; i < n; ++i)
    if (net.isFixed(i)) out.r[i] = 0.0;
  return out;
}

// Each row's residual in units of its tolerance: converged when every one is ≤ 1, i.e.
// |r_i| ≤ tol · (what flows through i) + (the round-off of evaluating it).
Eigen::VectorXd weights(const Residual& res, double tol) { return (tol * res.scale + res.noise).cwiseInverse(); }
double worst(const Residual& res, double tol) { return res.r.cwiseProduct(weights(res, tol)).cwiseAbs().maxCoeff(); }

}  // namespace

namespace {

// Backtracking along `step` from (t, u): at most a 90 % drop of any temperature, then halving
// until the weighted residual (weights frozen at this iterate, so the merit does not move
// with λ) decreases by Armijo's rule, or the trial has converged.
Residual lineSearch(const ImplicitSystem& s, const Residual& res, const Eigen::VectorXd& step, double tol,
                    Eigen::VectorXd& t, Eigen::VectorXd& u) {
  const Eigen::Index n = t.size(), a = u.size();
  double lambda = 1.0;
  for (Eigen::Index i = 0; i < n; ++i)
    if (step[i] < 0) lambda = std::min(lambda, 0.9 * t[i] / -step[i]);
  const Eigen::VectorXd w = weights(res, tol);
  const double merit0 = res.r.cwiseProduct(w).norm();
  Eigen::VectorXd t_try = t + lambda * step.head(n), u_try = u + lambda * step.tail(a);
  Residual trial = residual(s, t_try, u_try);
  for (int back = 0; back < 30 && worst(trial, tol) > 1.0 &&
                     !(trial.r.cwiseProduct(w).norm() < (1 - 1e-4 * lambda) * merit0);
       ++back) {
    lambda *= 0.5;
    t_try = t + lambda * step.head(n);
    u_try = u + lambda * step.tail(a);
    trial = residual(s, t_try, u_try);
  }
  t = t_try;
  u = u_try;
  return trial;
}

// A chord step with the cached factorisation, kept only when it at least halves the
// weighted residual (or converges) and keeps every temperature positive.
bool chordStep(const ImplicitSystem& s, Residual& res, double tol, Eigen::VectorXd& t) {
  const Eigen::VectorXd step = s.cache->lu.solve(-res.r);
  const Eigen::VectorXd t_try = t + step;
  if (!step.allFinite() || !(t_try.array() > 0).all()) return false;
  const Eigen::VectorXd none;
  Residual trial = residual(s, t_try, none, &res);  // scale and round-off as at the last full evaluation
  const Eigen::VectorXd w = weights(res, tol);
  if (worst(trial, tol) > 1.0 && !(trial.r.cwiseProduct(w).norm() < 0.5 * res.r.cwiseProduct(w).norm()))
    return false;
  t = t_try;
  res = std::move(trial);
  return true;
}

}  // namespace

NewtonOutcome solveImplicit(const ImplicitSystem& s, Eigen::VectorXd& t, Eigen::VectorXd& u,
                            const ThermalOptions& opt) {
  const Eigen::Index n = t.size(), a = u.size();
  for (Eigen::Index i = 0; i < n; ++i)
    if (s.net.isFixed(i)) t[i] = s.net.fixed_temperature[i];
  if (s.cache && s.cache->gr_row_sum.size() != n) s.cache->gr_row_sum = s.net.exchangeRowSum();
  JacobianCache* cache = a == 0 && opt.reuse_jacobian ? s.cache : nullptr;
  NewtonOutcome out;
  Residual res = residual(s, t, u);
  for (int it = 0;; ++it) {
    if (worst(res, opt.tolerance_w) <= 1.0) {
      out.residual_w = res.r.head(n).cwiseAbs().maxCoeff() / s.hb;
      return out;
    }
    if (it == opt.max_newton_iterations) break;
    ++out.iterations;
    // The cached factorisation serves steps of a similar length (its convergence is checked).
    if (cache && cache->valid && std::abs(s.hb / cache->hb - 1.0) < 0.5 && chordStep(s, res, opt.tolerance_w, t))
      continue;
    // A full Newton step at this iterate (its factorisation kept for the chord steps after).
    JacobianSolver lu(s, t, a);
    ++out.factorisations;
    const Eigen::VectorXd step = lu.solve(-res.r);
    if (!step.allFinite()) {
      const bool overflow = !res.r.allFinite();
      out.status = overflow ? Status::NonFinite : Status::Singular;
      out.message = overflow ? "thermal Newton: the heat balance is not finite (a power, conductance or temperature "
                               "beyond what doubles hold?)"
                             : "thermal Newton: singular Jacobian (a node with no capacitance, conductor or "
                               "radiative link?)";
      return out;
    }
    if (cache) {
      cache->lu = std::move(lu);
      cache->hb = s.hb;
      cache->valid = true;
    }
    res = lineSearch(s, res, step, opt.tolerance_w, t, u);
  }
  out.status = Status::NotConverged;
  res.r.cwiseProduct(weights(res, opt.tolerance_w)).cwiseAbs().maxCoeff(&out.worst_node);
  out.message = "thermal Newton did not converge in " + std::to_string(opt.max_newton_iterations) +
                " iterations (largest heat-balance residual " + std::to_string(worst(res, opt.tolerance_w)) +
                " times its tolerance)";
  return out;
}

}  // namespace radnet::solver::detail
