#include "solver/radiative/uncertainty.hpp"

#include "solver/parallel.hpp"
#include "solver/units.hpp"

#include <algorithm>
#include <cmath>

namespace radnet::solver {
namespace {

constexpr Eigen::Index kRowBlock = 256;  // rows of B (and of σ_F) formed at a time

// body(r, rows) for every row block of n rows, in parallel (solver/parallel.hpp).
template <class Body>
void forRowBlocks(Eigen::Index n, const Body& body) {
  const Eigen::Index blocks = (n + kRowBlock - 1) / kRowBlock;
  parallelFor(blocks, [&](long long b) {
    const Eigen::Index r = static_cast<Eigen::Index>(b) * kRowBlock;
    body(r, std::min(kRowBlock, n - r));
  });
}

// var y = A² ∘ ((σ_F ∘ σ_F) (M ∘ M)), by row blocks of σ_F.
Eigen::MatrixXd receivedVariance(const Eigen::VectorXd& area, const SparseRowMatrix& sigma_f,
                                 const Eigen::MatrixXd& m2) {
  const Eigen::Index n = area.size();
  Eigen::MatrixXd vy(n, m2.cols());
  forRowBlocks(n, [&](Eigen::Index r, Eigen::Index rows) {
    const SparseRowMatrix block = sigma_f.middleRows(r, rows);
    vy.middleRows(r, rows).noalias() = block.cwiseProduct(block) * m2;
  });
  return area.array().square().matrix().asDiagonal() * vy;
}

// (B ∘ B) X with B = V C Vᵀ, by row blocks, in single precision: a variance needs a few
// digits, and the n² k products of B (and n² P of the squares) are the uncertainty stage's
// whole cost, which float GEMM halves (19,202-node satellite: stage 6.4 → 2.9 s, σ moved by
// at most 6e-8 of itself). V C, V and each column of X are scaled to a largest magnitude of
// 1 first, so nothing leaves float's range (1e±38) however the model's areas are scaled; the
// scales are put back in double.
// Rows shared out: each process forms the blocks k ≡ part (mod parts), the others +0.0, joined.
Eigen::MatrixXd squaredCoreTimes(const LowRankBandSolver& band, const Eigen::MatrixXd& vectors,
                                 const Eigen::MatrixXd& x, const RowShare& share) {
  const Eigen::Index n = vectors.rows();
  const auto scaleOf = [](double largest) { return largest > 0 && std::isfinite(largest) ? largest : 1.0; };
  const Eigen::MatrixXd vc = vectors * band.core();
  const double vc_scale = scaleOf(vc.cwiseAbs().maxCoeff()), v_scale = scaleOf(vectors.cwiseAbs().maxCoeff());
  const Eigen::MatrixXf vc_f = (vc / vc_scale).cast<float>();
  const Eigen::MatrixXf vt_f = (vectors.transpose() / v_scale).cast<float>();
  Eigen::VectorXd x_scale(x.cols());
  for (Eigen::Index c = 0; c < x.cols(); ++c) x_scale[c] = scaleOf(x.col(c).cwiseAbs().maxCoeff());
  const Eigen::MatrixXf x_f = (x * x_scale.cwiseInverse().asDiagonal()).cast<float>();
  Eigen::MatrixXd out = share.whole() ? Eigen::MatrixXd(n, x.cols()) : Eigen::MatrixXd::Zero(n, x.cols());
  const Eigen::Index blocks = (n + kRowBlock - 1) / kRowBlock;
  parallelFor(blocks, [&](long long k) {
    if (!share.whole() && k % share.parts != share.part) return;
    const Eigen::Index r = static_cast<Eigen::Index>(k) * kRowBlock, rows = std::min(kRowBlock, n - r);
    const Eigen::MatrixXf b = vc_f.middleRows(r, rows) * vt_f;
    out.middleRows(r, rows) = (b.array().square().matrix() * x_f).cast<double>();
  });
  share.joinRows(out.data(), static_cast<size_t>(out.size()));
  const double b_scale = vc_scale * v_scale;
  return b_scale * b_scale * out * x_scale.asDiagonal();
}

}  // namespace

AbsorbedVariance absorbedVariance(const Network& net, const LowRankBandSolver& band,
                                  const SparseRowMatrix& sigma_f, const Eigen::MatrixXd& m,
                                  const Eigen::MatrixXd& sigma_e) {
  const Eigen::Index n = net.size(), P = m.cols();
  const Eigen::VectorXd& area = net.area();
  const Eigen::VectorXd& rho = band.reflectance();
  const Eigen::VectorXd alpha = Eigen::VectorXd::Ones(n) - rho;
  const Eigen::VectorXd s = rho.cwiseQuotient(area);
  const Eigen::MatrixXd var_e = sigma_e.array().square().matrix();
  Eigen::MatrixXd vy = sigma_f.size() ? receivedVariance(area, sigma_f, m.array().square().matrix())
                                      : Eigen::MatrixXd::Zero(n, P);
  net.share().joinRows(vy.data(), static_cast<size_t>(vy.size()));  // σ_F's rows shared out as G's
  AbsorbedVariance out;
  Eigen::VectorXd b_diag = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd spread = Eigen::MatrixXd::Zero(n, 2 * P);  // (B∘B)[s² var y, ρ² var E]
  if (band.status() == Status::Converged && band.rank() > 0) {
    const Eigen::MatrixXd& v = band.vectors();
    b_diag = (v * band.core()).cwiseProduct(v).rowwise().sum();
    Eigen::MatrixXd x(n, 2 * P);
    x << s.array().square().matrix().asDiagonal() * vy, rho.array().square().matrix().asDiagonal() * var_e;
    spread = squaredCoreTimes(band, v, x, net.share());
  }
  const Eigen::VectorXd alpha2 = alpha.array().square();
  const Eigen::ArrayXd self = 1.0 + 2.0 * b_diag.cwiseProduct(s).array();
  out.view_factors = alpha2.asDiagonal() * Eigen::MatrixXd((self.matrix().asDiagonal() * vy) + spread.leftCols(P));
  const Eigen::VectorXd cross = 2.0 * area.cwiseProduct(b_diag).cwiseProduct(rho);
  out.loads = alpha2.asDiagonal() * Eigen::MatrixXd(area.array().square().matrix().asDiagonal() * var_e +
                                                    cross.asDiagonal() * var_e + spread.rightCols(P));
  out.view_factors = out.view_factors.cwiseMax(0.0);
  out.loads = out.loads.cwiseMax(0.0);
  return out;
}

Eigen::MatrixXd truncationError(const Network& net, const LowRankBandSolver& band, const Eigen::MatrixXd& full,
                                const Eigen::MatrixXd& h, bool refined) {
  const Eigen::Index n = net.size();
  if (refined) return Eigen::MatrixXd::Zero(n, h.cols());
  const Eigen::VectorXd alpha = Eigen::VectorXd::Ones(n) - band.reflectance();
  return alpha.asDiagonal() * (full - net.area().asDiagonal() * h).cwiseAbs();
}

Eigen::MatrixXd exchangeHeatVariance(const SparseRowMatrix& sigma_f, const Eigen::VectorXd& lost,
                                     const Eigen::VectorXd& emissivity, const Eigen::VectorXd& area,
                                     const Eigen::MatrixXd& t, double t_space) {
  const Eigen::Index n = t.rows(), P = t.cols();
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, P);
  if (lost.size() == n) {
    const Eigen::ArrayXd g = emissivity.cwiseProduct(area).cwiseProduct(lost).array().square();
    out = (g.replicate(1, P) * (t.array().square().square() - std::pow(t_space, 4)).square()).matrix();
  }
  if (sigma_f.size() == 0) return units::kStefanBoltzmann * units::kStefanBoltzmann * out;
  // Σ_j w_ij (T_j⁴ − T_i⁴)² = Σ_j w_ij T_j⁸ − 2 T_i⁴ Σ_j w_ij T_j⁴ + T_i⁸ Σ_j w_ij, w = (ε_i ε_j A_i σ_F,ij)².
  const Eigen::ArrayXXd t4 = t.array().square().square();
  forRowBlocks(n, [&](Eigen::Index r, Eigen::Index rows) {
    const SparseRowMatrix e_sigma_e = emissivity.segment(r, rows).cwiseProduct(area.segment(r, rows)).asDiagonal() *
                                      SparseRowMatrix(sigma_f.middleRows(r, rows)) * emissivity.asDiagonal();
    const SparseRowMatrix w = e_sigma_e.cwiseProduct(e_sigma_e);
    const Eigen::MatrixXd w8 = w * t4.square().matrix(), w4 = w * t4.matrix();
    const Eigen::VectorXd w1 = w * Eigen::VectorXd::Ones(n);
    const Eigen::ArrayXXd ti4 = t4.middleRows(r, rows);
    out.middleRows(r, rows) += (w8.array() - 2.0 * ti4 * w4.array() + ti4.square() * w1.replicate(1, P).array())
                                  .max(0.0)
                                  .matrix();
  });
  return units::kStefanBoltzmann * units::kStefanBoltzmann * out;
}

}  // namespace radnet::solver
