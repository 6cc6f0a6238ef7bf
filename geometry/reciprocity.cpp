#include "geometry/reciprocity.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <utility>

namespace radnet::geometry {
namespace {


// 24 B (15.7 M of them on a 6,144-node room): a pair pinned at zero keeps ĝ = v = 0, as
// every estimate's variance is floored at one ray's (> 0).
struct Pair {
  int i, j;      // i <= j
  double g_hat;  // combined estimate of g_ij, m²
  double var;    // its variance, m⁴; 0: pinned at zero
  bool pinned() const { return var == 0.0; }
};

using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// Above this many entries of K the multipliers come from conjugate gradients, not a
// sparse LDLᵀ (whose fill-in on dense patterns costs n³/3: 6 of 8 s on a 1,536-node room).
constexpr Eigen::Index kDirectSolveEntries = 200000;

// One ray's worth of variance, (A_i / N_i)², m⁴: the floor under every estimate of row i.
double rayFloorVariance(const Eigen::VectorXd& area, const Eigen::VectorXd& rays, int i) {
  return std::pow(area[i] / std::max(1.0, rays[i]), 2);
}

// Both directional estimates of each pair, x = A_i F_ij with variance (A_i σ_ij)² floored
// at one ray's worth, combined by inverse variance; a pair seen from one side only takes the
// other side's zero with one ray's variance. F and σ share one compressed pattern (both come
// from the same tallies or pair values), so an entry's σ sits at its index in F. Row i's
// upper entries (j ≥ i) are walked in order; the partner F_ji is found by a cursor into row
// j that only moves forward (rows are visited in increasing i, so column i is the next of
// row j's lower entries still unvisited): no transpose of F or σ (2.8 of the 4.1 s of the
// correction on a 6,144-node room). A lower entry a cursor steps over had no partner.
std::vector<Pair> combinedPairs(const Eigen::VectorXd& area, const ViewFactorEstimate& est,
                                const Eigen::VectorXd& rays) {
  const RowSparse &f = est.view_factors, &sigma = est.standard_error;
  const int n = static_cast<int>(area.size());
  const int* outer = f.outerIndexPtr();
  const int* inner = f.innerIndexPtr();
  const double* value = f.valuePtr();
  const double* error = sigma.valuePtr();
  auto variance = [&](int row, int k) {
    return std::max(std::pow(area[row] * error[k], 2), rayFloorVariance(area, rays, row));
  };
  std::vector<Pair> pairs, one_sided;
  // At most one pair per upper entry: reserved (pages untouched until written), so the list
  // is never copied as it grows (15.7 M pairs on a 6,144-node room).
  pairs.reserve(static_cast<size_t>(f.nonZeros()) / 2 + static_cast<size_t>(n) + 1);
  auto lowerOnly = [&](int row, int k) {  // F_row,col (col < row) whose partner F_col,row is absent
    const int col = inner[k];
    const double v = variance(row, k), den = 1.0 / v + 1.0 / rayFloorVariance(area, rays, col);
    one_sided.push_back({col, row, area[row] * value[k] / v / den, 1.0 / den});
  };
  std::vector<int> cursor(outer, outer + n);  // each row's next lower entry not yet visited
  for (int i = 0; i < n; ++i) {
    // Row i's lower entries left unvisited by rows 0 … i−1: their partners are absent.
    for (int& c = cursor[static_cast<size_t>(i)]; c < outer[i + 1] && inner[c] < i; ++c) lowerOnly(i, c);
    for (int k = cursor[static_cast<size_t>(i)]; k < outer[i + 1]; ++k) {
      const int j = inner[k];
      const double v = variance(i, k);
      double num = area[i] * value[k] / v, den = 1.0 / v;
      if (j != i) {
        int& c = cursor[static_cast<size_t>(j)];
        for (; c < outer[j + 1] && inner[c] < i; ++c) lowerOnly(j, c);
        if (c < outer[j + 1] && inner[c] == i) {  // A_j F_ji, its σ from row j
          const double vj = variance(j, c);
          num += area[j] * value[c] / vj;
          den += 1.0 / vj;
          ++c;
        } else {
          den += 1.0 / rayFloorVariance(area, rays, j);
        }
      }
      pairs.push_back({i, j, num / den, 1.0 / den});
    }
  }
  if (!one_sided.empty()) {  // sorted by (i, j) like the rest, then merged in
    auto before = [](const Pair& a, const Pair& b) { return a.i != b.i ? a.i < b.i : a.j < b.j; };
    std::sort(one_sided.begin(), one_sided.end(), before);
    const auto middle = static_cast<std::ptrdiff_t>(pairs.size());
    pairs.insert(pairs.end(), one_sided.begin(), one_sided.end());
    std::inplace_merge(pairs.begin(), pairs.begin() + middle, pairs.end(), before);
  }
  return pairs;
}

// Whether σ is stored on F's compressed pattern, entry for entry (as combinedPairs reads it).
bool samePattern(const RowSparse& f, const RowSparse& sigma) {
  return f.isCompressed() && sigma.isCompressed() && f.rows() == sigma.rows() && f.nonZeros() == sigma.nonZeros() &&
         std::equal(f.outerIndexPtr(), f.outerIndexPtr() + f.outerSize() + 1, sigma.outerIndexPtr()) &&
         std::equal(f.innerIndexPtr(), f.innerIndexPtr() + f.nonZeros(), sigma.innerIndexPtr());
}

// σ laid on F's pattern (compressed F): an entry σ does not hold is 0 (all of them when σ
// was left empty or has another shape).
RowSparse sigmaOnPattern(const RowSparse& f, const RowSparse& sigma) {
  RowSparse out = f;
  if (sigma.rows() != f.rows() || sigma.cols() != f.cols()) {
    std::fill(out.valuePtr(), out.valuePtr() + out.nonZeros(), 0.0);
    return out;
  }
  for (Eigen::Index i = 0; i < f.outerSize(); ++i) {
    RowSparse::InnerIterator e(sigma, i);
    for (RowSparse::InnerIterator it(out, i); it; ++it) {
      while (e && e.col() < it.col()) ++e;
      it.valueRef() = (e && e.col() == it.col()) ? e.value() : 0.0;
    }
  }
  return out;
}

// K's upper triangle in compressed rows, built straight from the pairs (sorted by i, then
// j ≥ i): row i holds its diagonal, then v_ij of every free pair (i, j > i).
Eigen::SparseMatrix<double, Eigen::RowMajor> upperK(const std::vector<Pair>& pairs, const Eigen::VectorXd& diag) {
  const Eigen::Index n = diag.size();
  std::vector<int> count(static_cast<size_t>(n), 1);
  for (const Pair& p : pairs)
    if (!p.pinned() && p.i != p.j) ++count[static_cast<size_t>(p.i)];
  Eigen::SparseMatrix<double, Eigen::RowMajor> k(n, n);
  Eigen::Index nnz = 0;
  for (int c : count) nnz += c;
  k.resizeNonZeros(nnz);
  Eigen::Index at = 0;
  size_t q = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    k.outerIndexPtr()[i] = static_cast<int>(at);
    k.innerIndexPtr()[at] = static_cast<int>(i);
    k.valuePtr()[at++] = diag[i] > 0 ? diag[i] : 1.0;  // isolated rows: μ = 0
    for (; q < pairs.size() && pairs[q].i == i; ++q)
      if (!pairs[q].pinned() && pairs[q].j != i) {
        k.innerIndexPtr()[at] = pairs[q].j;
        k.valuePtr()[at++] = pairs[q].var;
      }
  }
  k.outerIndexPtr()[n] = static_cast<int>(at);
  return k;
}

// The Lagrange multipliers μ of the closure constraints: K μ = c − (row sums of the
// estimates), K = Σ v over each row's terms (diagonal) and v_ij off it. Pinned pairs are
// fixed at zero (their estimate leaves the right-hand side).
Eigen::VectorXd closureMultipliers(const std::vector<Pair>& pairs, const Eigen::VectorXd& free_rhs,
                                   const Eigen::VectorXd& free_variance) {
  const Eigen::Index n = free_rhs.size();
  Eigen::VectorXd rhs = free_rhs, diag = free_variance;
  Eigen::Index off_diagonal = 0;
  for (const Pair& p : pairs) {
    if (p.pinned()) continue;
    rhs[p.i] -= p.g_hat;
    diag[p.i] += p.var;
    if (p.i != p.j) {
      rhs[p.j] -= p.g_hat;
      diag[p.j] += p.var;
      off_diagonal += 2;
    }
  }
  Eigen::VectorXd mu = Eigen::VectorXd::Zero(n);
  if (off_diagonal + n > kDirectSolveEntries) {
    // A dense pattern (every cell of a closed room sees the others): the factor fills in to
    // n² and costs n³/3; K is diagonally dominant (each diagonal holds its row's variances),
    // so Jacobi-preconditioned conjugate gradients converge in tens of products.
    const Eigen::SparseMatrix<double, Eigen::RowMajor> k = upperK(pairs, diag);
    Eigen::ConjugateGradient<Eigen::SparseMatrix<double, Eigen::RowMajor>, Eigen::Upper> cg(k);
    cg.setTolerance(1e-13);
    cg.setMaxIterations(2000);
    mu = cg.solve(rhs);
    if (cg.info() == Eigen::Success && mu.allFinite()) return mu;
  }
  std::vector<Eigen::Triplet<double>> k;
  for (const Pair& p : pairs)
    if (!p.pinned() && p.i != p.j) {
      k.emplace_back(p.i, p.j, p.var);
      k.emplace_back(p.j, p.i, p.var);
    }
  for (Eigen::Index i = 0; i < n; ++i) k.emplace_back(i, i, diag[i] > 0 ? diag[i] : 1.0);  // isolated rows: μ = 0
  Eigen::SparseMatrix<double> km(n, n);
  km.setFromTriplets(k.begin(), k.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(km);
  if (ldlt.info() == Eigen::Success) mu = ldlt.solve(rhs);
  if (ldlt.info() != Eigen::Success || !mu.allFinite()) {
    // Singular (e.g. a bipartite network with every row fixed): least squares instead.
    Eigen::LeastSquaresConjugateGradient<Eigen::SparseMatrix<double>> lscg(km);
    mu = lscg.solve(rhs);
  }
  return mu;
}

}  // namespace

// How far each entry moved, in view-factor units and in standard errors, and the closure.
// The corrected rows hold a subset of the estimate's columns: both are walked together.
void reportCorrection(const ViewFactorEstimate& est, const Eigen::VectorXd& rays, ReciprocityCorrection& out,
                      const solver::RowShare& share) {
  const int n = static_cast<int>(rays.size());
  for (int i = 0; i < n; ++i) {
    if (!share.holds(i)) continue;
    RowSparse::InnerIterator f(est.view_factors, i), e(est.standard_error, i);
    for (RowSparse::InnerIterator it(out.view_factors, i); it; ++it) {
      const int j = static_cast<int>(it.col());
      while (f && f.col() < j) ++f;
      while (e && e.col() < j) ++e;
      const double before = (f && f.col() == j) ? f.value() : 0.0;
      const double sigma = (e && e.col() == j) ? e.value() : 0.0;
      const double change = std::abs(it.value() - before);
      // A cast row's σ comes from its own hits: an entry that drew no hit says σ = 0 whatever
      // its size, one that drew one hit σ = its value. Measured against the binomial σ at the
      // larger of the two values (what N rays scatter an entry of that size by), floored at
      // one ray. An integrated row (N = 1 / tolerance) is measured generously this way, but
      // its entries barely move: where it and a cast row disagree, the cast entry moves.
      const double n_rays = std::max(1.0, rays[i]), p = std::min(1.0, std::max(it.value(), before));
      const double s = std::max({sigma, std::sqrt(p * (1.0 - p) / n_rays), 1.0 / n_rays});
      if (change > out.max_change) {
        out.max_change = change;
        out.worst_from = i;
        out.worst_to = j;
      }
      out.max_change_sigma = std::max(out.max_change_sigma, change / s);
    }
    const double closure = out.view_factors.row(i).sum() + out.space[i] + out.blocked[i] - 1.0;
    out.max_closure_error = std::max(out.max_closure_error, std::abs(closure));
  }
  if (share.whole()) return;
  // The largest move and, among equal ones, the first pair in row order: its −(i n + j) the largest.
  const double largest = share.largest(out.max_change);
  double first = out.max_change == largest && out.worst_from >= 0
                     ? -(double(out.worst_from) * n + out.worst_to)
                     : -1e300;
  first = share.largest(first);
  out.max_change = largest;
  if (first > -1e300) {
    out.worst_from = static_cast<int>(-first / n);
    out.worst_to = static_cast<int>(-first - double(out.worst_from) * n);
  }
  out.max_change_sigma = share.largest(out.max_change_sigma);
  out.max_closure_error = share.largest(out.max_closure_error);
}

namespace {

// A pair's corrected conductance g_ij = ĝ_ij + v_ij (μ_i + μ_j) (0 when pinned), m².
double corrected(const Pair& p, const Eigen::VectorXd& mu) {
  return p.g_hat + p.var * (p.i == p.j ? mu[p.i] : mu[p.i] + mu[p.j]);
}

// The corrected F in compressed rows, straight from the pairs (sorted by i, then j ≥ i):
// row r receives g_ir / A_r from the pairs (i < r, r) in increasing i, then g_rj / A_r from
// its own pairs in increasing j, so every row comes out in column order.
RowSparse correctedRows(const std::vector<Pair>& pairs, const Eigen::VectorXd& mu, const Eigen::VectorXd& area) {
  const Eigen::Index n = area.size();
  std::vector<Eigen::Index> start(static_cast<size_t>(n) + 1, 0);
  for (size_t q = 0; q < pairs.size(); ++q) {
    if (corrected(pairs[q], mu) <= 0) continue;
    ++start[static_cast<size_t>(pairs[q].i) + 1];
    if (pairs[q].i != pairs[q].j) ++start[static_cast<size_t>(pairs[q].j) + 1];
  }
  for (size_t i = 0; i < static_cast<size_t>(n); ++i) start[i + 1] += start[i];
  RowSparse f(n, n);
  f.resizeNonZeros(start.back());
  std::vector<Eigen::Index> fill(start.begin(), start.end() - 1);
  auto put = [&](int row, int col, double value) {
    const Eigen::Index at = fill[static_cast<size_t>(row)]++;
    f.innerIndexPtr()[at] = col;
    f.valuePtr()[at] = value;
  };
  for (const Pair& p : pairs) {
    const double g = corrected(p, mu);
    if (g <= 0) continue;
    put(p.i, p.j, g / area[p.i]);
    if (p.i != p.j) put(p.j, p.i, g / area[p.j]);
  }
  for (Eigen::Index i = 0; i <= n; ++i) f.outerIndexPtr()[i] = static_cast<int>(start[static_cast<size_t>(i)]);
  return f;
}

}  // namespace

const ViewFactorEstimate& onOnePattern(const ViewFactorEstimate& est, ViewFactorEstimate& storage) {
  if (samePattern(est.view_factors, est.standard_error)) return est;
  storage.view_factors = est.view_factors;
  storage.view_factors.makeCompressed();
  storage.standard_error = sigmaOnPattern(storage.view_factors, est.standard_error);
  return storage;
}

ReciprocityCorrection enforceReciprocity(const Eigen::VectorXd& area, const ViewFactorEstimate& est,
                                         const Eigen::VectorXd& rays) {
  const int n = static_cast<int>(area.size());
  // combinedPairs reads F and σ on one compressed pattern: a copy only when they differ.
  ViewFactorEstimate relaid;
  const ViewFactorEstimate* shared = &onOnePattern(est, relaid);
  std::vector<Pair> pairs = combinedPairs(area, *shared, rays);
  // Space and blocked conductances: free per node, variance from their own errors.
  Eigen::VectorXd g_space = area.cwiseProduct(est.space), g_blocked = area.cwiseProduct(est.blocked);
  Eigen::VectorXd v_space(n), v_blocked(n);
  for (int i = 0; i < n; ++i) {
    const double floor_var = rayFloorVariance(area, rays, i);
    v_space[i] = est.space[i] > 0 ? std::max(std::pow(area[i] * est.space_error[i], 2), floor_var) : 0.0;
    v_blocked[i] = est.blocked[i] > 0 ? std::max(std::pow(area[i] * est.blocked_error[i], 2), floor_var) : 0.0;
  }
  // Entries driven negative are pinned to zero and the multipliers solved again.
  Eigen::VectorXd mu = Eigen::VectorXd::Zero(n);
  for (int pass = 0; pass < 20; ++pass) {
    mu = closureMultipliers(pairs, area - g_space - g_blocked, v_space + v_blocked);
    bool changed = false;
    for (Pair& p : pairs)
      if (!p.pinned() && corrected(p, mu) < 0) {
        p.g_hat = p.var = 0.0;
        changed = true;
      }
    // Space and blocked terms likewise: one driven below zero is pinned there (clamping it
    // afterwards would leave the row's closure to nothing: a closed enclosure's row summed
    // over 1 by its quadrature error).
    for (int i = 0; i < n; ++i)
      for (auto [g_term, v_term] : {std::pair{&g_space, &v_space}, std::pair{&g_blocked, &v_blocked}})
        if ((*v_term)[i] > 0 && (*g_term)[i] + (*v_term)[i] * mu[i] < 0) {
          (*g_term)[i] = (*v_term)[i] = 0.0;
          changed = true;
        }
    if (!changed) break;
  }
  ReciprocityCorrection out;
  out.space = (g_space + v_space.cwiseProduct(mu)).cwiseMax(0.0).cwiseQuotient(area);
  out.blocked = (g_blocked + v_blocked.cwiseProduct(mu)).cwiseMax(0.0).cwiseQuotient(area);
  {  // swapped in: an assignment copies (Eigen 3.4), 0.38 GB at the stage's peak on the 6,144-node room
    RowSparse corrected = correctedRows(pairs, mu, area);
    out.view_factors.swap(corrected);
  }
  std::vector<Pair>().swap(pairs);  // before the report: 0.38 GB on the 6,144-node room
  reportCorrection(*shared, rays, out);  // σ on F's pattern (absent entries 0)
  return out;
}

}  // namespace radnet::geometry
