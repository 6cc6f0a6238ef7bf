#include "solver/radiative/pair_update.hpp"

#include "solver/parallel.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/Cholesky>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

namespace radnet::solver {
namespace {

// The column j entries of G's row i (symmetric: column i), (j, G_ij), as one list.
void rowEntries(const Network& net, int i, std::vector<std::pair<int, double>>& out) {
  out.clear();
  if (net.isSparse()) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(net.sparseConductance(), i); it; ++it)
      out.emplace_back(static_cast<int>(it.row()), it.value());
    return;
  }
  for (int j = 0; j < net.size(); ++j)
    if (const double g = net.conductance(i, j); g != 0.0) out.emplace_back(j, g);
}

// ΔG X on the cores (solver/parallel.hpp: ΔG is symmetric), X row-major. Eigen's own product
// ran one thread through ΔG once per column of X: 2.5 s of the 2,006-node tracking wings' 17
// configurations, 0.7 s so.
constexpr Eigen::Index kChangeRowsPerBlock = 64;
Eigen::MatrixXd times(const Eigen::SparseMatrix<double>& change, const Eigen::MatrixXd& x) {
  using RowDense = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  return symmetricTimes(change, RowDense(x), kChangeRowsPerBlock);
}

// The dense products of an update on all cores, in a fixed number of chunks (independent
// columns or rows, each an Eigen product of its own), so the sums do not depend on the
// threads: at rank 174 on 2,102 nodes the range finder's Gram matrices and Rayleigh–Ritz
// products were most of a configuration, on one core.
constexpr Eigen::Index kDenseChunks = 8;

Eigen::MatrixXd transposeTimes(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {  // Aᵀ B
  Eigen::MatrixXd out(a.cols(), b.cols());
  const Eigen::Index chunks = std::max<Eigen::Index>(1, std::min(kDenseChunks, b.cols()));
  parallelFor(chunks, [&](long long c) {
    const Eigen::Index first = b.cols() * c / chunks, last = b.cols() * (c + 1) / chunks;
    out.middleCols(first, last - first).noalias() = a.transpose() * b.middleCols(first, last - first);
  });
  return out;
}

Eigen::MatrixXd times(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {  // A B
  Eigen::MatrixXd out(a.rows(), b.cols());
  const Eigen::Index chunks = std::max<Eigen::Index>(1, std::min(kDenseChunks, a.rows()));
  parallelFor(chunks, [&](long long c) {
    const Eigen::Index first = a.rows() * c / chunks, last = a.rows() * (c + 1) / chunks;
    out.middleRows(first, last - first).noalias() = a.middleRows(first, last - first) * b;
  });
  return out;
}

// Orthonormal basis of the columns of y: Cholesky QR twice (CholeskyQR2, Fukaya et al. 2014:
// two Gram matrices and triangular solves, all matrix products, orthogonal to rounding when y's
// condition number is below ~1e8), else thin Householder (rank-deficient or ill-conditioned y).
Eigen::MatrixXd orthonormal(const Eigen::MatrixXd& y) {
  Eigen::MatrixXd q = y;
  for (int pass = 0; pass < 2; ++pass) {
    Eigen::MatrixXd gram = transposeTimes(q, q);
    const Eigen::LLT<Eigen::MatrixXd> llt(gram);
    if (llt.info() != Eigen::Success) q.resize(0, 0);
    if (q.size() == 0) break;
    const Eigen::VectorXd d = llt.matrixLLT().diagonal();
    if (!(d.minCoeff() > 1e-7 * d.maxCoeff())) {  // near rank deficiency: Householder
      q.resize(0, 0);
      break;
    }
    const Eigen::Index chunks = std::max<Eigen::Index>(1, std::min(kDenseChunks, q.rows()));
    parallelFor(chunks, [&](long long c) {  // q ← q U⁻¹ (gram = Uᵀ U), rows apart
      const Eigen::Index first = q.rows() * c / chunks, last = q.rows() * (c + 1) / chunks;
      Eigen::Ref<Eigen::MatrixXd> rows = q.middleRows(first, last - first);
      llt.matrixU().solveInPlace<Eigen::OnTheRight>(rows);
    });
  }
  if (q.size() == y.size()) return q;
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(y);
  return qr.householderQ() * Eigen::MatrixXd::Identity(y.rows(), y.cols());
}

Eigen::MatrixXd gaussian(Eigen::Index rows, Eigen::Index cols, std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Eigen::MatrixXd m(rows, cols);
  for (Eigen::Index j = 0; j < cols; ++j)
    for (Eigen::Index i = 0; i < rows; ++i) m(i, j) = normal(rng);
  return m;
}

// Halko et al. 2011, eq. 4.3: ‖(I − Q Qᵀ) ΔG‖₂ ≤ 10 √(2/π) max_i ‖(I − Q Qᵀ) ΔG ω_i‖ with
// probability 1 − 10⁻⁴ over 4 Gaussian ω_i (ΔG symmetric, Q Qᵀ ΔG Q Qᵀ its compression).
constexpr int kResidualProbes = 4;
double residualBound(const Eigen::SparseMatrix<double>& change, const Eigen::MatrixXd& q, const Eigen::MatrixXd& b,
                     std::mt19937_64& rng) {
  const Eigen::MatrixXd w = gaussian(change.rows(), kResidualProbes, rng);
  const Eigen::MatrixXd e = times(change, w) - q * (b * (q.transpose() * w));
  return 10.0 * std::sqrt(2.0 / 3.14159265358979323846) * e.colwise().norm().maxCoeff();
}

// Components of ΔG below this share of its largest are dropped (or below drop_below): a
// turned wing's coupling to a 2,102-node bus has hundreds above drop_below, whose sum the
// probes find below the tolerance.
constexpr double kUpdateShare = 1e-3;

// An orthonormal basis of the part of span(U) outside span(V) (U's columns unit, V
// orthonormal), of the rank it has: V projected out twice ("twice is enough"), each time the
// result normalised through its Gram matrix's eigenvectors, directions below 1e-7 of a unit
// column dropped (U inside span V: an empty basis, not directions made of rounding).
Eigen::MatrixXd outsideBasis(const Eigen::MatrixXd& u, const Eigen::MatrixXd& v) {
  Eigen::MatrixXd y = u;
  for (int pass = 0; pass < 2 && y.cols() > 0; ++pass) {
    y -= times(v, transposeTimes(v, y));
    y -= times(v, transposeTimes(v, y));
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(transposeTimes(y, y));
    std::vector<Eigen::Index> keep;
    for (Eigen::Index j = 0; j < y.cols(); ++j)
      if (eig.eigenvalues()[j] > 1e-14) keep.push_back(j);
    Eigen::MatrixXd w(y.cols(), static_cast<Eigen::Index>(keep.size()));
    for (size_t c = 0; c < keep.size(); ++c)
      w.col(static_cast<Eigen::Index>(c)) = eig.eigenvectors().col(keep[c]) / std::sqrt(eig.eigenvalues()[keep[c]]);
    y = y * w;
  }
  return y;
}

}  // namespace

Eigen::SparseMatrix<double> conductanceChange(const Network& base, const Network& moved, const std::vector<int>& changed) {
  const int n = base.size();
  std::vector<char> in_changed(static_cast<size_t>(n), 0);
  for (int i : changed) in_changed[static_cast<size_t>(i)] = 1;
  std::vector<Eigen::Triplet<double>> entries;
  std::vector<std::pair<int, double>> before, after;
  std::vector<double> row(static_cast<size_t>(n), 0.0);
  for (int i : changed) {
    rowEntries(base, i, before);
    rowEntries(moved, i, after);
    for (const auto& [j, g] : after) row[static_cast<size_t>(j)] += g;
    for (const auto& [j, g] : before) row[static_cast<size_t>(j)] -= g;
    const auto emit = [&](int j) {
      double& d = row[static_cast<size_t>(j)];
      if (d != 0.0) {
        entries.emplace_back(i, j, d);
        if (!in_changed[static_cast<size_t>(j)]) entries.emplace_back(j, i, d);  // the column, once
      }
      d = 0.0;
    };
    for (const auto& [j, g] : after) emit(j);
    for (const auto& [j, g] : before) emit(j);
  }
  Eigen::SparseMatrix<double> change(n, n);
  change.setFromTriplets(entries.begin(), entries.end());
  return change;
}

namespace {

// ΔG ≈ U M Uᵀ with the components above drop_below (a range finder grown until its residual
// bound is below drop_below, or ΔG's whole range).
void lowRankChange(const Eigen::SparseMatrix<double>& change, double drop_below, std::uint64_t seed,
                   Eigen::MatrixXd& u, Eigen::VectorXd& mu, PairUpdateStats& stats) {
  const Eigen::Index n = change.rows();
  std::vector<char> touched(static_cast<size_t>(n), 0);
  for (int k = 0; k < change.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(change, k); it; ++it) touched[static_cast<size_t>(it.row())] = 1;
  const Eigen::Index changed = std::count(touched.begin(), touched.end(), char(1));
  const Eigen::Index max_rank = std::min<Eigen::Index>(n, 2 * changed);  // its rows plus its columns
  std::mt19937_64 rng(seed);
  // Blocks of 16, 32, 64, … probes, each sharpened by one power step, until at most half the
  // block's components are above the cut (drop_below, or kUpdateShare of ΔG's largest
  // component): the block then holds every component above it with 2× oversampling. What is
  // dropped the probes measure (policy::measuredPairs).
  Eigen::MatrixXd q, b;
  double residual = 0.0, cut = drop_below;
  for (Eigen::Index block = std::min<Eigen::Index>(max_rank, 16); block > 0;
       block = std::min<Eigen::Index>(max_rank, 2 * block)) {
    q = orthonormal(times(change, gaussian(n, block, rng)));
    q = orthonormal(times(change, q));
    b = transposeTimes(q, times(change, q));
    b = 0.5 * (b + b.transpose());
    const Eigen::VectorXd size = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(b, Eigen::EigenvaluesOnly).eigenvalues().cwiseAbs();
    cut = std::max(drop_below, kUpdateShare * size.maxCoeff());
    if (2 * (size.array() > cut).count() <= block || block == max_rank) {
      residual = block < max_rank ? residualBound(change, q, b, rng) : 0.0;
      break;
    }
  }
  u.resize(n, 0);
  mu.resize(0);
  stats = PairUpdateStats{static_cast<int>(changed), 0, residual, cut};
  if (q.cols() == 0) return;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(b);
  std::vector<Eigen::Index> keep;
  for (Eigen::Index j = 0; j < b.rows(); ++j)
    if (std::abs(eig.eigenvalues()[j]) > cut) keep.push_back(j);
  Eigen::MatrixXd kept(b.rows(), static_cast<Eigen::Index>(keep.size()));
  mu.resize(kept.cols());
  for (Eigen::Index c = 0; c < kept.cols(); ++c) {
    kept.col(c) = eig.eigenvectors().col(keep[static_cast<size_t>(c)]);
    mu[c] = eig.eigenvalues()[keep[static_cast<size_t>(c)]];
  }
  u = times(q, kept);
  stats.update_rank = static_cast<int>(u.cols());
}

}  // namespace

EigenPairs updatedPairs(const EigenPairs& base, const Eigen::SparseMatrix<double>& change, double drop_below,
                        std::uint64_t seed, PairUpdateStats* stats) {
  const Eigen::Index n = change.rows();
  Eigen::MatrixXd u;
  Eigen::VectorXd mu;
  PairUpdateStats own;
  lowRankChange(change, drop_below, seed, u, mu, own);
  if (stats) *stats = own;
  EigenPairs out = base;
  out.dropped_bound = base.dropped_bound + own.residual + own.cut;
  if (u.cols() == 0) return out;
  // Rayleigh–Ritz on span[V U]: Q₂ = [V Q_U], Q_U an orthonormal basis of U's part outside V;
  // B = Q₂ᵀ U, and G'_k = Q₂ (diag(Λ, 0) + B M Bᵀ) Q₂ᵀ (matrix products only).
  const Eigen::Index k = base.rank();
  const Eigen::MatrixXd vu = transposeTimes(base.vectors, u);
  const Eigen::MatrixXd outside = outsideBasis(u, base.vectors);
  const Eigen::Index m = k + outside.cols();
  Eigen::MatrixXd q2(n, m);
  q2.leftCols(k) = base.vectors;
  q2.rightCols(outside.cols()) = outside;
  Eigen::MatrixXd b(m, u.cols());
  b.topRows(k) = vu;
  if (outside.cols() > 0) b.bottomRows(outside.cols()) = transposeTimes(outside, u);
  Eigen::MatrixXd core = b * mu.asDiagonal() * b.transpose();
  core.diagonal().head(k) += base.values;
  core = 0.5 * (core + core.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(core);
  std::vector<Eigen::Index> order(static_cast<size_t>(m));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](Eigen::Index x, Eigen::Index y) {
    return std::abs(eig.eigenvalues()[x]) > std::abs(eig.eigenvalues()[y]);
  });
  const double largest = std::abs(eig.eigenvalues()[order.front()]);
  while (!order.empty() && !(std::abs(eig.eigenvalues()[order.back()]) > 1e-14 * largest)) order.pop_back();
  out.values.resize(static_cast<Eigen::Index>(order.size()));
  Eigen::MatrixXd kept(m, out.values.size());
  for (Eigen::Index c = 0; c < out.values.size(); ++c) {
    out.values[c] = eig.eigenvalues()[order[static_cast<size_t>(c)]];
    kept.col(c) = eig.eigenvectors().col(order[static_cast<size_t>(c)]);
  }
  out.vectors = times(q2, kept);
  return out;
}

}  // namespace radnet::solver
