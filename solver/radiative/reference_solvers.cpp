#include "solver/radiative/reference_solvers.hpp"

#include <Eigen/IterativeLinearSolvers>

#include <cmath>
#include <limits>

namespace radnet::solver {
namespace {

void checkSizes(const BandSystem& sys, const Eigen::VectorXd& mo) {
  const Eigen::Index n = sys.area.size();
  if (sys.conductance.rows() != n || sys.conductance.cols() != n || sys.reflectance.size() != n || mo.size() != n)
    throw std::invalid_argument("band system: G, A, ρ and M_o must all have n = " + std::to_string(n) + " rows");
}

// Tracks an iteration's update norm to decide convergence and divergence alike.
class Monitor {
 public:
  Monitor(const IterativeOptions& opt, double scale) : opt_(opt), scale_(scale > 0 ? scale : 1.0) {}
  // Returns true when the iteration should stop; sets the result's status.
  bool step(SolveResult& res, double update_norm, double solution_norm) {
    ++res.iterations;
    if (opt_.observer) opt_.observer(res.iterations, res.exitance);
    if (!std::isfinite(update_norm) || !std::isfinite(solution_norm)) {
      res.status = Status::NonFinite;
      res.message = "iterate became non-finite at iteration " + std::to_string(res.iterations);
      return true;
    }
    if (update_norm <= opt_.tolerance * std::max(solution_norm, std::numeric_limits<double>::min())) {
      res.status = Status::Converged;
      return true;
    }
    growing_ = update_norm > last_ ? growing_ + 1 : 0;
    last_ = update_norm;
    if (growing_ >= 8 || update_norm > 1e100 * scale_) {
      res.status = Status::Diverged;
      res.message = "update norm grew for " + std::to_string(growing_) + " iterations running (now " +
                    std::to_string(update_norm) + ") at iteration " + std::to_string(res.iterations);
      return true;
    }
    if (res.iterations >= opt_.max_iterations) {
      res.status = Status::NotConverged;
      res.message = "no convergence in " + std::to_string(res.iterations) + " iterations (relative update " +
                    std::to_string(update_norm / std::max(solution_norm, 1e-300)) + ")";
      return true;
    }
    return false;
  }

 private:
  const IterativeOptions& opt_;
  double scale_;
  double last_ = std::numeric_limits<double>::infinity();
  int growing_ = 0;
};

}  // namespace

SolveResult solveDenseLU(const BandSystem& sys, const Eigen::VectorXd& mo) {
  checkSizes(sys, mo);
  const Eigen::Index n = mo.size();
  const Eigen::VectorXd s = sys.reflectance.cwiseQuotient(sys.area);
  const Eigen::MatrixXd m = Eigen::MatrixXd::Identity(n, n) - s.asDiagonal() * sys.conductance;
  Eigen::FullPivLU<Eigen::MatrixXd> lu(m);
  SolveResult res;
  if (!lu.isInvertible()) {
    res.status = Status::Singular;
    res.message = "I − S G is singular (a lossless closed cavity?)";
    return res;
  }
  res.exitance = lu.solve(mo);
  res.iterations = 1;
  if (!res.exitance.allFinite()) {
    res.status = Status::NonFinite;
    res.message = "LU solution is not finite";
  }
  return res;
}

SolveResult solveJacobi(const BandSystem& sys, const Eigen::VectorXd& mo, const IterativeOptions& opt) {
  checkSizes(sys, mo);
  const Eigen::VectorXd s = sys.reflectance.cwiseQuotient(sys.area);
  SolveResult res;
  res.exitance = mo;  // M⁽⁰⁾ = M_o
  Monitor mon(opt, mo.norm());
  for (;;) {
    Eigen::VectorXd next = mo + s.cwiseProduct(sys.conductance * res.exitance);  // eq. 20
    const double update = (next - res.exitance).norm();
    res.exitance.swap(next);
    if (mon.step(res, update, res.exitance.norm())) return res;
  }
}

SolveResult solveGaussSeidel(const BandSystem& sys, const Eigen::VectorXd& mo, const IterativeOptions& opt) {
  checkSizes(sys, mo);
  const Eigen::Index n = mo.size();
  const Eigen::VectorXd s = sys.reflectance.cwiseQuotient(sys.area);
  SolveResult res;
  res.exitance = mo;
  Monitor mon(opt, mo.norm());
  for (;;) {
    double update2 = 0.0;
    for (Eigen::Index i = 0; i < n; ++i) {
      // Row i of (I − S G) M = M_o, solved for M_i; G_ii ≠ 0 for concave nodes.
      const double off = sys.conductance.col(i).dot(res.exitance) - sys.conductance(i, i) * res.exitance[i];
      const double diag = 1.0 - s[i] * sys.conductance(i, i);
      const double value = (mo[i] + s[i] * off) / diag;
      update2 += (value - res.exitance[i]) * (value - res.exitance[i]);
      res.exitance[i] = value;
    }
    if (mon.step(res, std::sqrt(update2), res.exitance.norm())) return res;
  }
}

SolveResult solveSouthwell(const BandSystem& sys, const Eigen::VectorXd& mo, const IterativeOptions& opt) {
  checkSizes(sys, mo);
  const Eigen::VectorXd s = sys.reflectance.cwiseQuotient(sys.area);
  SolveResult res;
  res.exitance = mo;
  Eigen::VectorXd unshot = mo;  // ΔM: exitance not yet distributed
  const double emitted = sys.area.cwiseProduct(mo.cwiseAbs()).sum();
  if (emitted == 0.0) return res;
  for (;;) {
    Eigen::Index k = 0;
    sys.area.cwiseProduct(unshot.cwiseAbs()).maxCoeff(&k);
    const double shot = unshot[k];
    unshot[k] = 0.0;
    // Node j receives A_k ΔM_k F_kj = G_kj ΔM_k and reflects ρ_j/A_j of it.
    const Eigen::VectorXd gained = s.cwiseProduct(sys.conductance.col(k)) * shot;
    res.exitance += gained;
    unshot += gained;
    const double remaining = sys.area.cwiseProduct(unshot.cwiseAbs()).sum();
    ++res.iterations;
    if (opt.observer) opt.observer(res.iterations, res.exitance);
    if (!std::isfinite(remaining)) {
      res.status = Status::NonFinite;
      res.message = "unshot power became non-finite";
      return res;
    }
    if (remaining <= opt.tolerance * emitted) return res;
    if (res.iterations >= opt.max_iterations) {
      res.status = Status::NotConverged;
      res.message = "unshot power still " + std::to_string(remaining / emitted) + " of the emitted after " +
                    std::to_string(res.iterations) + " shots";
      return res;
    }
  }
}

SolveResult solveConjugateGradient(const BandSystem& sys, const Eigen::VectorXd& mo, const IterativeOptions& opt) {
  checkSizes(sys, mo);
  if ((sys.reflectance.array() <= 0).any())
    throw std::invalid_argument("conjugate gradients on A R⁻¹ − G needs every reflectance > 0");
  const Eigen::VectorXd a_over_rho = sys.area.cwiseQuotient(sys.reflectance);
  Eigen::MatrixXd k = -sys.conductance;  // eq. 12: A R⁻¹ (I − R F) = A R⁻¹ − G, SPD
  k.diagonal() += a_over_rho;
  Eigen::ConjugateGradient<Eigen::MatrixXd, Eigen::Lower | Eigen::Upper> cg;
  cg.setTolerance(opt.tolerance);
  cg.setMaxIterations(opt.max_iterations);
  cg.compute(k);
  SolveResult res;
  res.exitance = cg.solveWithGuess(a_over_rho.cwiseProduct(mo), mo);
  res.iterations = static_cast<int>(cg.iterations());
  if (cg.info() != Eigen::Success) {
    res.status = Status::NotConverged;
    res.message = "CG stopped after " + std::to_string(res.iterations) + " iterations at relative residual " +
                  std::to_string(cg.error());
  }
  if (!res.exitance.allFinite()) {
    res.status = Status::NonFinite;
    res.message = "CG iterate is not finite";
  }
  return res;
}

SolveResult solveEigenIteration(const EigenPairs& pairs, const Eigen::VectorXd& area,
                                const Eigen::VectorXd& reflectance, const Eigen::VectorXd& mo,
                                const IterativeOptions& opt) {
  if (pairs.vectors.rows() != mo.size() || area.size() != mo.size() || reflectance.size() != mo.size())
    throw std::invalid_argument("eigen iteration: sizes of V, A, ρ and M_o differ");
  const Eigen::VectorXd s = reflectance.cwiseQuotient(area);
  const Eigen::MatrixXd w = s.asDiagonal() * pairs.vectors;  // w_i = S v_i
  SolveResult res;
  res.exitance = mo;          // M⁽⁰⁾ = M_o
  Eigen::VectorXd kvec = mo;  // K⁽⁰⁾ = M_o, eq. 35
  Monitor mon(opt, mo.norm());
  for (;;) {
    const Eigen::VectorXd coeff = pairs.values.cwiseProduct(pairs.vectors.transpose() * kvec);  // (K·v_i) λ_i
    kvec = w * coeff;                                                                           // eq. 36
    res.exitance += kvec;                                                                       // eq. 37
    if (mon.step(res, kvec.norm(), res.exitance.norm())) return res;
  }
}

}  // namespace radnet::solver
