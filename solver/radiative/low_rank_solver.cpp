#include "solver/radiative/low_rank_solver.hpp"

#include "solver/radiative/policy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace radnet::solver {

Eigen::VectorXd relativeResidual(const Eigen::Ref<const Eigen::MatrixXd>& gm, const Eigen::VectorXd& area,
                                 const Eigen::VectorXd& reflectance, const Eigen::Ref<const Eigen::MatrixXd>& mo,
                                 const Eigen::Ref<const Eigen::MatrixXd>& m) {
  const Eigen::VectorXd s = reflectance.cwiseQuotient(area);
  const Eigen::MatrixXd r = mo - m + s.asDiagonal() * gm;
  Eigen::VectorXd out(mo.cols());
  for (Eigen::Index c = 0; c < mo.cols(); ++c) {
    const double scale = mo.col(c).norm();
    out[c] = scale > 0 ? r.col(c).norm() / scale : r.col(c).norm();
  }
  return out;
}

LowRankBandSolver::LowRankBandSolver(const Network& net, const EigenPairs& pairs, Eigen::VectorXd reflectance)
    : net_(net), rho_(std::move(reflectance)), values_(pairs.values), vectors_(pairs.vectors) {
  checkRange(net, rho_, "reflectance", 0.0, 1.0);
  if (pairs.status != Status::Converged || vectors_.rows() != net.size()) {
    status_ = pairs.status == Status::Converged ? Status::Singular : pairs.status;
    message_ = "no usable eigenpairs: " +
               (pairs.message.empty() ? "vectors of " + std::to_string(vectors_.rows()) + " rows" : pairs.message);
    return;
  }
  sqrt_rho_ = rho_.cwiseSqrt();
  if (pairs.rank() == 0) {  // G'_0 = 0 (no exchange worth a pair): H' = 0, refinement sees the full G
    core_.resize(0, 0);
    return;
  }
  const Eigen::VectorXd s = rho_.cwiseQuotient(net.area());
  // W = Vᵀ S V (k×k) costs O(n k²); then C = (I − Λ W)⁻¹ Λ = Λ (I − W Λ)⁻¹ (push-through).
  // As (S^½ V)ᵀ (S^½ V): one symmetric rank-k update, half the products of a general one.
  const int k = rank();
  const Eigen::MatrixXd sv = s.cwiseSqrt().asDiagonal() * vectors_;
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(k, k);
  w.selfadjointView<Eigen::Lower>().rankUpdate(sv.transpose());
  w.triangularView<Eigen::StrictlyUpper>() = w.transpose();
  const Eigen::MatrixXd lhs = Eigen::MatrixXd::Identity(k, k) - values_.asDiagonal() * w;
  Eigen::FullPivLU<Eigen::MatrixXd> lu(lhs);
  // I − Λ W is singular when S G'_k has the eigenvalue 1 (a closed, lossless cavity).
  lu.setThreshold(1e-13);
  if (!lu.isInvertible()) {
    status_ = Status::Singular;
    message_ = "I − Λ Vᵀ S V is singular: the network has no loss (closed cavity with ρ = 1?)";
    return;
  }
  core_ = lu.solve(Eigen::MatrixXd(values_.asDiagonal()));
  core_ = (0.5 * (core_ + core_.transpose())).eval();  // symmetric in exact arithmetic; eval: no aliasing
  if (!core_.allFinite()) {
    status_ = Status::NonFinite;
    message_ = "low-rank core C is not finite";
  }
}

Eigen::MatrixXd LowRankBandSolver::applyCore(const Eigen::Ref<const Eigen::MatrixXd>& x) const {
  // Three thin products, O(n k P): never the n×n matrix V C Vᵀ.
  return vectors_ * (core_ * (vectors_.transpose() * x));
}

BandSolution LowRankBandSolver::solve(const Eigen::Ref<const Eigen::MatrixXd>& mo, double refine_tolerance,
                                      int max_refine_iterations, Refinement how) const {
  BandSolution sol;
  if (mo.rows() != net_.size()) throw std::invalid_argument("initial exitance must have one row per node");
  if (!mo.allFinite()) throw std::invalid_argument("initial exitance contains a non-finite value");
  if (status_ != Status::Converged) {
    sol.status = status_;
    sol.message = message_;
    return sol;
  }
  // A H' = G' M' = V C Vᵀ M_o and M' = M_o + ρ ∘ H' (exact for G'_k).
  sol.irradiance = net_.area().cwiseInverse().asDiagonal() * applyCore(mo);
  sol.exitance = mo + rho_.asDiagonal() * sol.irradiance;
  sol.full_flux = net_.applyConductance(sol.exitance);
  sol.residual = relativeResidual(sol.full_flux, net_.area(), rho_, mo, sol.exitance);
  sol.max_residual = sol.residual.size() ? sol.residual.maxCoeff() : 0.0;
  if (refine_tolerance > 0 && sol.max_residual > refine_tolerance) {
    // The cheaper way to the tolerance, by predicted cost (policy.hpp): CG from the rank-k
    // answer, or one dense LU of I − S G when CG would need many products with G.
    const policy::BandSolveCost cost =
        policy::bandSolveCost(net_, rank(), mo.cols(), sol.max_residual, refine_tolerance);
    sol.predicted_refine_s = cost.refine_s;
    sol.predicted_direct_s = cost.direct_s;
    const bool direct = how == Refinement::Cheapest && cost.direct();
    const bool solved = direct && solveDirect(mo, sol) && sol.max_residual <= refine_tolerance;
    if (!solved) refine(mo, sol, refine_tolerance, max_refine_iterations);  // from the LU's answer, if any
  }
  if (!sol.exitance.allFinite() || !sol.irradiance.allFinite()) {
    sol.status = Status::NonFinite;
    sol.message = "band solution is not finite";
  }
  return sol;
}

Eigen::MatrixXd LowRankBandSolver::applyPreconditioner(const Eigen::Ref<const Eigen::MatrixXd>& r,
                                                       bool low_rank) const {
  // P = A⁻¹ + A⁻¹ R^½ V C Vᵀ R^½ A⁻¹ = (A − R^½ G'_k R^½)⁻¹ by the same identity as the core.
  const Eigen::VectorXd inv_area = net_.area().cwiseInverse();
  Eigen::MatrixXd y = inv_area.asDiagonal() * r;
  if (!low_rank) return y;
  const Eigen::MatrixXd t = sqrt_rho_.asDiagonal() * y;
  return y + inv_area.asDiagonal() * (sqrt_rho_.asDiagonal() * applyCore(t));
}

// Refinement with the full G. The symmetric form of eq. 20 without dividing by ρ:
// with z = R^½ H (so M = M_o + R^½ z),
//     (A − R^½ G R^½) z = R^½ G M_o,
// which is SPD when the spectral radius of S G is below 1, and valid for ρ = 0 nodes
// (their z is 0). Batched conjugate gradients, one GEMM with G per iteration for all
// columns, preconditioned by the low-rank inverse (A − R^½ G'_k R^½)⁻¹. If truncation
// made that preconditioner indefinite (dropped negative λ), CG falls back to the
// diagonal preconditioner A⁻¹ and says so in the message. The M-form residual is
// A⁻¹ R^½ (b − K z), so each column stops on the same criterion that is reported.
// One run of block preconditioned CG on K z = b (K = A − R^½ G R^½) from the current z,
// until the recurrence residual of every column meets `tol`, `max_iter` total iterations
// pass, the preconditioner turns indefinite (then low_rank_pc is cleared) or K proves
// indefinite (`broke_down`). Returns the iterations done.
int LowRankBandSolver::pcgRun(const Eigen::MatrixXd& b, const Eigen::MatrixXd& start_residual, Eigen::MatrixXd& z,
                              const Eigen::VectorXd& scale, double tol, int max_iter, bool& low_rank_pc,
                              bool& broke_down) const {
  const Eigen::VectorXd& area = net_.area();
  const Eigen::VectorXd r_weight = area.cwiseInverse().cwiseProduct(sqrt_rho_);
  const Eigen::Index cols = z.cols();
  auto applyK = [&](const Eigen::MatrixXd& x) -> Eigen::MatrixXd {
    return area.asDiagonal() * x - sqrt_rho_.asDiagonal() * net_.applyConductance(sqrt_rho_.asDiagonal() * x);
  };
  auto converged = [&](const Eigen::MatrixXd& res) {
    const Eigen::VectorXd rel = (r_weight.asDiagonal() * res).colwise().norm().transpose().cwiseQuotient(scale);
    return (rel.array() <= tol).all();
  };
  Eigen::MatrixXd r = b.size() != 0 ? Eigen::MatrixXd(b - applyK(z)) : start_residual;
  Eigen::MatrixXd y = applyPreconditioner(r, low_rank_pc);
  Eigen::VectorXd rz = (r.cwiseProduct(y)).colwise().sum().transpose();
  if (low_rank_pc && (rz.array() < 0).any()) {  // indefinite preconditioner: use the diagonal one
    low_rank_pc = false;
    y = applyPreconditioner(r, false);
    rz = (r.cwiseProduct(y)).colwise().sum().transpose();
  }
  Eigen::MatrixXd p = y;
  int done_iterations = 0;
  bool done = converged(r);
  while (!done && done_iterations < max_iter) {
    const Eigen::MatrixXd q = applyK(p);
    const Eigen::VectorXd pq = (p.cwiseProduct(q)).colwise().sum().transpose();
    Eigen::VectorXd alpha = Eigen::VectorXd::Zero(cols);
    for (Eigen::Index c = 0; c < cols; ++c) {
      if (rz[c] == 0.0) continue;  // column already exact
      if (!(pq[c] > 0.0)) {
        broke_down = true;
        return done_iterations;
      }
      alpha[c] = rz[c] / pq[c];
    }
    z += p * alpha.asDiagonal();
    r -= q * alpha.asDiagonal();
    ++done_iterations;
    done = converged(r);
    if (done) break;
    y = applyPreconditioner(r, low_rank_pc);
    const Eigen::VectorXd rz_new = (r.cwiseProduct(y)).colwise().sum().transpose();
    if (low_rank_pc && (rz_new.array() < 0).any()) {  // restart with A⁻¹
      low_rank_pc = false;
      break;
    }
    Eigen::VectorXd beta = Eigen::VectorXd::Zero(cols);
    for (Eigen::Index c = 0; c < cols; ++c) beta[c] = rz[c] > 0 ? rz_new[c] / rz[c] : 0.0;
    p = y + p * beta.asDiagonal();
    rz = rz_new;
    if (!z.allFinite()) break;
  }
  return done_iterations;
}

// M = (I − S G)⁻¹ M_o by dense LU; false (sol untouched) when I − S G is numerically
// singular, and CG then says what it can.
bool LowRankBandSolver::solveDirect(const Eigen::Ref<const Eigen::MatrixXd>& mo, BandSolution& sol) const {
  const Eigen::VectorXd s = rho_.cwiseQuotient(net_.area());
  Eigen::MatrixXd lhs = -(s.asDiagonal() * net_.denseConductance());
  lhs.diagonal().array() += 1.0;
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(lhs);
  if (!(lu.rcond() > 1e-14)) return false;
  Eigen::MatrixXd m = lu.solve(mo);
  if (!m.allFinite()) return false;
  sol.exitance = std::move(m);
  sol.full_flux = net_.applyConductance(sol.exitance);
  sol.irradiance = net_.area().cwiseInverse().asDiagonal() * sol.full_flux;
  sol.residual = relativeResidual(sol.full_flux, net_.area(), rho_, mo, sol.exitance);
  sol.max_residual = sol.residual.size() ? sol.residual.maxCoeff() : 0.0;
  sol.refined = true;
  sol.method = "dense LU";
  return true;
}

void LowRankBandSolver::refine(const Eigen::Ref<const Eigen::MatrixXd>& mo, BandSolution& sol, double tol,
                               int max_iter) const {
  sol.method = "low-rank core + CG";
  const Eigen::VectorXd& area = net_.area();
  const Eigen::Index cols = mo.cols();
  Eigen::VectorXd scale(cols);
  for (Eigen::Index c = 0; c < cols; ++c) scale[c] = std::max(mo.col(c).norm(), std::numeric_limits<double>::min());

  Eigen::MatrixXd z = sqrt_rho_.asDiagonal() * sol.irradiance;  // the low-rank answer as the start
  // Its residual b − K z without a product with G: with b = R^½ G M_o and
  // G R^½ z = G (M_k − M_o), b − K z = R^½ G M_k − A z, and G M_k is the residual check's
  // full_flux. b itself only for a restart (after recurrence drift).
  const Eigen::MatrixXd start_residual = sqrt_rho_.asDiagonal() * sol.full_flux - area.asDiagonal() * z;
  Eigen::MatrixXd b;
  bool low_rank_pc = true;
  sol.refined = true;
  int total = 0;
  for (int restart = 0; restart < 4 && total < max_iter; ++restart) {
    bool broke_down = false;
    if (restart > 0 && b.size() == 0) b = sqrt_rho_.asDiagonal() * net_.applyConductance(mo);
    total += pcgRun(b, start_residual, z, scale, tol, max_iter - total, low_rank_pc, broke_down);
    if (broke_down) {
      sol.status = Status::Singular;
      sol.message = "refinement: A − R^½ G R^½ is not positive definite (spectral radius of S G ≥ 1?)";
      break;
    }
    // Recompute the true residual (the recurrence drifts); restart if it is not yet met.
    sol.exitance = mo + sqrt_rho_.asDiagonal() * z;
    sol.full_flux = net_.applyConductance(sol.exitance);
    sol.residual = relativeResidual(sol.full_flux, area, rho_, mo, sol.exitance);
    sol.max_residual = sol.residual.maxCoeff();
    sol.irradiance = area.cwiseInverse().asDiagonal() * sol.full_flux;
    if (sol.max_residual <= tol || !z.allFinite()) break;
  }
  sol.refine_iterations = total;
  if (sol.status == Status::Converged && !(sol.max_residual <= tol)) {
    sol.status = Status::NotConverged;
    std::ostringstream m;  // %g: residuals live near 1e-10, where std::to_string prints 0.000000
    m << "refinement reached " << total << " iterations with residual " << sol.max_residual << " > " << tol;
    sol.message = m.str();
  }
  if (!low_rank_pc && sol.message.empty())
    sol.message = "low-rank preconditioner was indefinite; refined with the diagonal preconditioner";
}

}  // namespace radnet::solver
