#include "solver/radiative/exchange.hpp"

#include <algorithm>
#include <stdexcept>
#include <cmath>

namespace radnet::solver {
namespace {

// GR ← (GR + GRᵀ)/2 in place, returning max |GR_ij − GR_ji|. By tiles: an in-place
// `g = 0.5 * (g + g.transpose())` would read entries it has already overwritten.
double symmetrize(Eigen::Ref<Eigen::MatrixXd> g) {
  double worst = 0.0;
  forEachLowerPairByTiles(g.rows(), [&](Eigen::Index i, Eigen::Index j) {
    worst = std::max(worst, std::abs(g(i, j) - g(j, i)));
    g(i, j) = g(j, i) = 0.5 * (g(i, j) + g(j, i));
  });
  return worst;
}

void finishFactors(ExchangeFactors& ex, const Network& net, const Eigen::VectorXd& emissivity) {
  const double scale = ex.gr.cwiseAbs().maxCoeff();
  const double asymmetry = symmetrize(ex.gr);
  ex.asymmetry = scale > 0 ? asymmetry / scale : 0.0;
  // Everything node i emits (ε_i A_i per unit σT⁴) is absorbed by some node or lost to space.
  ex.gr_space = emissivity.cwiseProduct(net.area()) - ex.gr.rowwise().sum();
  if (!ex.gr.allFinite()) {
    ex.status = Status::NonFinite;
    ex.message = "exchange factors are not finite";
  }
}

// GR += E G E: the direct (unreflected) exchange, from the network's own G.
void addDirectExchange(Eigen::MatrixXd& gr, const Network& net, const Eigen::VectorXd& emissivity) {
  if (net.isSparse()) {
    const Eigen::SparseMatrix<double>& g = net.sparseConductance();
    for (int j = 0; j < g.outerSize(); ++j)
      for (Eigen::SparseMatrix<double>::InnerIterator it(g, j); it; ++it)
        gr(it.row(), it.col()) += emissivity[it.row()] * it.value() * emissivity[it.col()];
    return;
  }
  gr += emissivity.asDiagonal() * net.heldDenseConductance() * emissivity.asDiagonal();
}

// L⁻¹ in place of a lower-triangular L (LAPACK's dtrtri, blocked from the last block
// column back): each block column below the diagonal becomes −L₂₂⁻¹ L₂₁ L₁₁⁻¹ from the
// already inverted trailing block, then the diagonal block is inverted. The upper triangle
// is not touched.
void invertLowerInPlace(Eigen::Ref<Eigen::MatrixXd> a) {
  constexpr Eigen::Index kBlock = 128;
  const Eigen::Index n = a.rows();
  for (Eigen::Index j = ((n - 1) / kBlock) * kBlock; j >= 0; j -= kBlock) {
    const Eigen::Index jb = std::min(kBlock, n - j), below = n - j - jb;
    if (below > 0) {
      auto column = a.block(j + jb, j, below, jb);
      column = a.block(j + jb, j + jb, below, below).triangularView<Eigen::Lower>() * column;  // (aliasing: a temporary)
      a.block(j, j, jb, jb).triangularView<Eigen::Lower>().solveInPlace<Eigen::OnTheRight>(column);
      column = -column;
    }
    const Eigen::MatrixXd inverse =
        a.block(j, j, jb, jb).triangularView<Eigen::Lower>().solve(Eigen::MatrixXd::Identity(jb, jb));
    a.block(j, j, jb, jb).triangularView<Eigen::Lower>() = inverse;
  }
}

// Lᵀ L in place of a lower-triangular L, its lower triangle (LAPACK's dlauum, blocked by
// rows): block row i of the product needs only L's blocks at or below row i, so the rows
// are overwritten top down.
void lowerGramInPlace(Eigen::Ref<Eigen::MatrixXd> a) {
  constexpr Eigen::Index kBlock = 128;
  const Eigen::Index n = a.rows();
  for (Eigen::Index i = 0; i < n; i += kBlock) {
    const Eigen::Index ib = std::min(kBlock, n - i), below = n - i - ib;
    const Eigen::MatrixXd diagonal = a.block(i, i, ib, ib).triangularView<Eigen::Lower>();
    auto left = a.block(i, 0, ib, i);
    left = diagonal.transpose() * left;
    const Eigen::MatrixXd gram = diagonal.transpose() * diagonal;
    a.block(i, i, ib, ib).triangularView<Eigen::Lower>() = gram;
    if (below > 0) {
      const auto under = a.block(i + ib, i, below, ib);
      left.noalias() += under.transpose() * a.block(i + ib, 0, below, i);
      a.block(i, i, ib, ib).selfadjointView<Eigen::Lower>().rankUpdate(under.transpose());
    }
  }
}

// GR = E G (I − S G)⁻¹ E in one n × n matrix besides G, by symmetry. With every ρ_i > 0,
// M = S⁻¹ − G is symmetric and diagonally dominant (S⁻¹_ii = A_i/ρ_i ≥ A_i ≥ Σ_j G_ij), so
// positive definite, and G (I − S G)⁻¹ = S⁻¹ M⁻¹ S⁻¹ − S⁻¹: GR_ij = d_i (M⁻¹)_ij d_j −
// δ_ij ε_i² A_i/ρ_i, d = ε A/ρ. M⁻¹ by Cholesky, L⁻¹ and L⁻ᵀ L⁻¹ all in place: n³ flops
// against the LU's 2n³/3 plus 4n³ of solves and G X. False (`work` spent) when M is not
// positive definite numerically.
bool symmetricExchange(const Network& net, const Eigen::VectorXd& emissivity, Eigen::MatrixXd& work) {
  const Eigen::VectorXd rho = Eigen::VectorXd::Ones(net.size()) - emissivity;
  if (net.isSparse()) {
    work = net.denseConductance();
    work = -work;
  } else {
    work = -net.heldDenseConductance();  // one pass over G, no copy of it first
  }
  work.diagonal() += net.area().cwiseQuotient(rho);
  {
    Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>, Eigen::Lower> llt(work);
    // Near singular (a closed cavity of ε → 0): the LU's own test and status decide.
    if (llt.info() != Eigen::Success || llt.rcond() < 1e-14) return false;
  }
  invertLowerInPlace(work);
  lowerGramInPlace(work);
  const Eigen::VectorXd d = emissivity.cwiseProduct(net.area()).cwiseQuotient(rho);
  const Eigen::Index n = work.rows();
  for (Eigen::Index j = 0; j < n; ++j) {
    work.col(j).tail(n - j) = d.tail(n - j).cwiseProduct(work.col(j).tail(n - j)) * d[j];
    work(j, j) -= emissivity[j] * emissivity[j] * net.area()[j] / rho[j];
  }
  forEachLowerPairByTiles(n, [&](Eigen::Index i, Eigen::Index j) { work(j, i) = work(i, j); });  // the upper triangle
  return work.allFinite();
}

}  // namespace

ExchangeFactors exchangeFactorsDense(const Network& net, const Eigen::VectorXd& emissivity) {
  checkRange(net, emissivity, "emissivity", 0.0, 1.0);
  const Eigen::VectorXd s = (Eigen::VectorXd::Ones(net.size()) - emissivity).cwiseQuotient(net.area());
  ExchangeFactors ex;
  // ρ ≥ 1e-3 everywhere: the diagonal's cancellation in the symmetric form costs at most
  // 1e-16/ρ of ε A (a black node, ρ = 0, has no S⁻¹ at all); else the LU.
  if (emissivity.size() > 0 && emissivity.maxCoeff() <= 1.0 - kSymmetricExchangeMinReflectance &&
      symmetricExchange(net, emissivity, ex.gr)) {
    ex.method = "dense Cholesky";
    finishFactors(ex, net, emissivity);
    return ex;
  }
  ex.gr = Eigen::MatrixXd();
  ex.method = "dense LU";
  // Two n × n matrices at a time, not seven: I − S G factored in place, (I − S G)⁻¹ E solved
  // in place, then G X once the factor is gone (the 6,144-node room: seven were 2.1 GB).
  Eigen::MatrixXd work = net.denseConductance();
  work.array().colwise() *= -s.array();
  work.diagonal().array() += 1.0;
  Eigen::MatrixXd x = emissivity.asDiagonal();
  {
    Eigen::PartialPivLU<Eigen::Ref<Eigen::MatrixXd>> lu(work);
    if (lu.rcond() < 1e-14) {
      ex.status = Status::Singular;
      ex.message = "I − S G is singular in the IR band (a closed cavity with ε = 0 everywhere?)";
      return ex;
    }
    // (I − S G)⁻¹ E maps emissive voltages to exitances: P, then L and U, in place.
    x = lu.permutationP() * x;
    lu.matrixLU().triangularView<Eigen::UnitLower>().solveInPlace(x);
    lu.matrixLU().triangularView<Eigen::Upper>().solveInPlace(x);
  }
  work = Eigen::MatrixXd();
  // E G then gives the absorbed power.
  ex.gr = net.applyConductance(x);
  x = Eigen::MatrixXd();
  ex.gr.array().colwise() *= emissivity.array();
  finishFactors(ex, net, emissivity);
  return ex;
}

ExchangeFactors exchangeFactorsLowRank(const Network& net, const LowRankBandSolver& ir_band,
                                       const Eigen::VectorXd& emissivity) {
  checkRange(net, emissivity, "emissivity", 0.0, 1.0);
  ExchangeFactors ex;
  ex.method = "direct + low-rank reflected (k = " + std::to_string(ir_band.rank()) + ")";
  ex.from_pairs = true;
  if (ir_band.status() != Status::Converged) {
    ex.status = ir_band.status();
    ex.message = ir_band.message();
    return ex;
  }
  // G (I − S G)⁻¹ = G + G S G (I − S G)⁻¹: the direct exchange E G E is kept exact (sparse
  // or dense, no truncation), and only the reflected part is taken from the rank-k
  // decomposition, G'(I − S G')⁻¹ − G' = V (C − Λ) Vᵀ. A pure E V C Vᵀ E would truncate the
  // direct exchange too: on the 1,602-node satellite at k = 200 it moved a node's row of GR
  // by up to 3.9 % of ε A, this by 6.7e-5 (docs/solver.md, "IR band and exchange factors").
  // For black surfaces (ρ = 0, C = Λ) GR = G exactly.
  ex.core = ir_band.core();
  ex.core.diagonal() -= ir_band.values();
  // (k = 0 when G = 0: nothing sees anything; maxCoeff of an empty matrix is undefined.)
  const double core_scale = ex.core.size() ? ex.core.cwiseAbs().maxCoeff() : 0.0;
  const double core_asymmetry = ex.core.size() ? (ex.core - ex.core.transpose()).cwiseAbs().maxCoeff() : 0.0;
  ex.core = (0.5 * (ex.core + ex.core.transpose())).eval();  // C is symmetric up to round-off
  ex.basis = emissivity.asDiagonal() * ir_band.vectors();
  if (!net.isSparse()) {  // a dense G: the dense GR costs no more than its own G
    ex.gr.noalias() = (ex.basis * ex.core) * ex.basis.transpose();
    addDirectExchange(ex.gr, net, emissivity);
    finishFactors(ex, net, emissivity);
    return ex;
  }
  // G's column-major arrays are its rows (G = Gᵀ): the held rows when they are shared out.
  const Eigen::SparseMatrix<double>& g = net.sparseConductance();
  ex.direct = Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor>>(
      g.rows(), g.cols(), g.nonZeros(), g.outerIndexPtr(), g.innerIndexPtr(), g.valuePtr());
  for (Eigen::Index i = 0; i < ex.direct.outerSize(); ++i)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(ex.direct, i); it; ++it)
      it.valueRef() *= emissivity[it.row()] * emissivity[it.col()];
  ex.share = net.share();
  // Row sums without GR: D 1 + W (K (Wᵀ 1)).
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(net.size());
  Eigen::VectorXd direct_sum = ex.direct * ones;
  ex.share.joinRows(direct_sum.data(), static_cast<size_t>(direct_sum.size()));
  const Eigen::VectorXd row_sum = direct_sum + ex.basis * (ex.core * (ex.basis.transpose() * ones));
  ex.gr_space = emissivity.cwiseProduct(net.area()) - row_sum;
  // Symmetric by construction (G and the symmetrised K); what K's round-off was, relative.
  ex.asymmetry = core_scale > 0 ? core_asymmetry / core_scale : 0.0;
  if (!ex.core.allFinite() || !ex.basis.allFinite() || !row_sum.allFinite()) {
    ex.status = Status::NonFinite;
    ex.message = "exchange factors are not finite";
  }
  return ex;
}

void ExchangeFactors::denseInto(Eigen::Ref<Eigen::MatrixXd> out) const {
  if (!factored()) {
    out = gr;
    return;
  }
  if (!share.whole()) throw std::logic_error("a dense GR of a network whose rows are shared out");
  out.noalias() = (basis * core) * basis.transpose();
  for (Eigen::Index i = 0; i < direct.outerSize(); ++i)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(direct, i); it; ++it)
      out(it.row(), it.col()) += it.value();
  symmetrize(out);  // the GEMM's round-off, as the dense form is
}

Eigen::MatrixXd ExchangeFactors::dense() const {
  if (!factored()) return gr;
  Eigen::MatrixXd out(size(), size());
  denseInto(out);
  return out;
}

Eigen::MatrixXd ExchangeFactors::rows(Eigen::Index first, Eigen::Index count) const {
  if (!factored()) return gr.middleRows(first, count);
  Eigen::MatrixXd out = (basis.middleRows(first, count) * core) * basis.transpose();
  if (share.whole()) {
    for (Eigen::Index r = 0; r < count; ++r)
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(direct, first + r); it; ++it)
        out(r, it.col()) += it.value();
    return out;
  }
  Eigen::MatrixXd held = Eigen::MatrixXd::Zero(count, direct.cols());  // the direct rows, from their holders
  for (Eigen::Index r = 0; r < count; ++r)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(direct, first + r); it; ++it)
      held(r, it.col()) = it.value();
  share.joinRows(held.data(), static_cast<size_t>(held.size()));
  for (Eigen::Index j = 0; j < held.cols(); ++j)
    for (Eigen::Index r = 0; r < count; ++r)
      if (held(r, j) != 0.0) out(r, j) += held(r, j);
  return out;
}

double ExchangeFactors::entry(Eigen::Index i, Eigen::Index j) const {
  if (!factored()) return gr(i, j);
  double d = direct.coeff(i, j);
  share.joinRows(&d, 1);
  return d + basis.row(i).dot(core * basis.row(j).transpose());
}

Eigen::MatrixXd ExchangeFactors::apply(const Eigen::Ref<const Eigen::MatrixXd>& x) const {
  if (!factored()) return gr * x;
  Eigen::MatrixXd y = direct * x;
  share.joinRows(y.data(), static_cast<size_t>(y.size()));
  y.noalias() += basis * (core * (basis.transpose() * x));
  return y;
}

BandSolution irNetPower(const Network& net, const LowRankBandSolver& ir_band, const Eigen::VectorXd& emissivity,
                        const Eigen::Ref<const Eigen::MatrixXd>& temperature_k,
                        const Eigen::Ref<const Eigen::MatrixXd>& external_irradiance, double refine_tolerance,
                        Eigen::MatrixXd& net_power_w) {
  checkRange(net, emissivity, "emissivity", 0.0, 1.0);
  const int n = net.size();
  if (temperature_k.rows() != n) throw std::invalid_argument("temperatures need one row per node");
  if (!temperature_k.allFinite() || (temperature_k.array() < 0).any())
    throw std::invalid_argument("temperatures must be finite and >= 0 K");
  const Eigen::MatrixXd eb = kStefanBoltzmann * temperature_k.array().square().square().matrix();  // σT⁴
  Eigen::MatrixXd e_ext = Eigen::MatrixXd::Zero(n, temperature_k.cols());
  if (external_irradiance.size() != 0) {
    if (external_irradiance.rows() != n || external_irradiance.cols() != temperature_k.cols())
      throw std::invalid_argument("external IR irradiance must have the shape of the temperatures");
    e_ext = external_irradiance;
  }
  const Eigen::MatrixXd mo = emissivity.asDiagonal() * eb + ir_band.reflectance().asDiagonal() * e_ext;
  BandSolution sol = ir_band.solve(mo, refine_tolerance);
  if (sol.status == Status::Converged)
    net_power_w = (emissivity.cwiseProduct(net.area())).asDiagonal() * (sol.irradiance + e_ext - eb);
  return sol;
}

EmissivityUpdate::EmissivityUpdate(Eigen::MatrixXd nominal, Eigen::VectorXd emissivity, Eigen::VectorXd area,
                                   std::vector<int> nodes)
    : gr_(std::move(nominal)), emissivity_(std::move(emissivity)), area_(std::move(area)), nodes_(std::move(nodes)) {
  const Eigen::Index m = static_cast<Eigen::Index>(nodes_.size());
  m_uu_.resize(m, m);
  for (Eigen::Index a = 0; a < m; ++a) {
    const int u = nodes_[static_cast<size_t>(a)];
    if (!(emissivity_[u] > 0)) throw NetworkError("emissivity update: the nominal emissivity of node " + std::to_string(u) + " is 0");
    for (Eigen::Index b = 0; b < m; ++b) {
      const int v = nodes_[static_cast<size_t>(b)];
      m_uu_(a, b) = gr_(u, v) / (emissivity_[u] * emissivity_[v]);
    }
  }
}

ExchangeFactors EmissivityUpdate::operator()(const Eigen::VectorXd& emissivity) const {
  const Eigen::Index n = gr_.rows(), m = static_cast<Eigen::Index>(nodes_.size());
  Eigen::VectorXd ratio = Eigen::VectorXd::Ones(n), d(m);
  for (Eigen::Index a = 0; a < m; ++a) {
    const int u = nodes_[static_cast<size_t>(a)];
    ratio[u] = emissivity[u] / emissivity_[u];
    d[a] = -(emissivity[u] - emissivity_[u]) / area_[u];  // ΔS = S' − S
  }
  ExchangeFactors ex;
  ex.method = "nominal GR + rank-" + std::to_string(m) + " emissivity update";
  ex.gr = ratio.asDiagonal() * gr_ * ratio.asDiagonal();
  if (m > 0 && d.cwiseAbs().maxCoeff() > 0) {
    Eigen::MatrixXd w(n, m);  // R GR_{:U} diag(1/ε_U) = diag(ε') M_{:U}
    for (Eigen::Index a = 0; a < m; ++a) {
      const int u = nodes_[static_cast<size_t>(a)];
      w.col(a) = ratio.cwiseProduct(gr_.col(u)) / emissivity_[u];
    }
    // K = D (I − M_UU D)⁻¹, symmetric (push-through); D may be singular, the LU is of I − M_UU D.
    const Eigen::MatrixXd core = Eigen::MatrixXd::Identity(m, m) - m_uu_ * d.asDiagonal();
    const Eigen::MatrixXd k = d.asDiagonal() * core.partialPivLu().inverse();
    ex.gr.noalias() += w * (k * w.transpose());
    ex.gr = 0.5 * (ex.gr + ex.gr.transpose()).eval();
  }
  ex.gr_space = emissivity.cwiseProduct(area_) - ex.gr.rowwise().sum();
  if (!ex.gr.allFinite()) {
    ex.status = Status::NonFinite;
    ex.message = "exchange factors are not finite";
  }
  return ex;
}

}  // namespace radnet::solver
