#include "solver/radiative/network.hpp"

#include "solver/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_set>

namespace radnet::solver {
namespace {

std::string nodeLabel(const std::vector<std::string>& names, int i) {
  std::ostringstream s;
  s << "node " << i << " '" << names[static_cast<size_t>(i)] << "'";
  return s.str();
}

void checkShape(Eigen::Index rows, Eigen::Index cols, int n) {
  if (rows != n || cols != n) {
    std::ostringstream s;
    s << "view-factor matrix is " << rows << "×" << cols << "; expected " << n << "×" << n;
    throw NetworkError(s.str());
  }
}

void checkEntry(const std::vector<std::string>& names, int i, int j, double f) {
  if (!std::isfinite(f) || f < 0.0) {
    std::ostringstream s;
    s << "view factor F[" << i << "][" << j << "] from " << nodeLabel(names, i) << " to " << nodeLabel(names, j)
      << " is " << f << "; expected a finite value in [0, 1]";
    throw NetworkError(s.str());
  }
}

}  // namespace

void checkRange(const Network& net, const Eigen::VectorXd& values, const char* what, double lo, double hi) {
  if (values.size() != net.size()) {
    std::ostringstream s;
    s << what << " has " << values.size() << " entries; expected one per node (" << net.size() << ")";
    throw NetworkError(s.str());
  }
  for (int i = 0; i < net.size(); ++i) {
    const double v = values[i];
    if (!(std::isfinite(v) && v >= lo && v <= hi)) {  // written so that NaN fails too
      std::ostringstream s;
      s << what << " of " << nodeLabel(net.names(), i) << " is " << v << "; expected a value in [" << lo << ", " << hi
        << "]";
      throw NetworkError(s.str());
    }
  }
}

void Network::validateCommon(const NetworkTolerances& tol) {
  const int n = size();
  if (n == 0) throw NetworkError("the network has no nodes");
  if (!(std::isfinite(tol.row_sum) && tol.row_sum >= 0) || !(std::isfinite(tol.reciprocity) && tol.reciprocity >= 0))
    throw NetworkError("network tolerances must be finite and >= 0");
  if (area_.size() != n) {
    std::ostringstream s;
    s << "areas have " << area_.size() << " entries; expected " << n << " (one per node)";
    throw NetworkError(s.str());
  }
  std::unordered_set<std::string> seen;
  for (int i = 0; i < n; ++i) {
    if (names_[static_cast<size_t>(i)].empty()) {
      throw NetworkError("node " + std::to_string(i) + " has an empty name");
    }
    if (!seen.insert(names_[static_cast<size_t>(i)]).second) {
      throw NetworkError("node name '" + names_[static_cast<size_t>(i)] + "' is used twice");
    }
    if (!(std::isfinite(area_[i]) && area_[i] > 0.0)) {
      std::ostringstream s;
      s << "area of " << nodeLabel(names_, i) << " is " << area_[i] << " m²; expected a finite value > 0";
      throw NetworkError(s.str());
    }
  }
  if (blocked_.size() == 0) blocked_ = Eigen::VectorXd::Zero(n);
  if (blocked_.size() != n) throw NetworkError("blocked fractions need one entry per node");
  for (int i = 0; i < n; ++i) {
    if (!(std::isfinite(blocked_[i]) && blocked_[i] >= 0.0 && blocked_[i] <= 1.0)) {
      std::ostringstream s;
      s << "blocked fraction of " << nodeLabel(names_, i) << " is " << blocked_[i] << "; expected [0, 1]";
      throw NetworkError(s.str());
    }
  }
}

namespace {

void checkRowSums(const std::vector<std::string>& names, const Eigen::VectorXd& row_sums,
                  const Eigen::VectorXd& blocked, double tol) {
  for (int i = 0; i < row_sums.size(); ++i) {
    const double total = row_sums[i] + blocked[i];
    if (total > 1.0 + tol) {
      std::ostringstream s;
      s << "view factors from " << nodeLabel(names, i) << " sum to " << total
        << " (including the blocked fraction); expected at most 1 (+ tolerance " << tol << ")";
      throw NetworkError(s.str());
    }
  }
}

// Records the largest view-factor change ½|g_ij − g_ji| / min(A_i, A_j) of the pair (i, j).
void noteDefect(ReciprocityReport& rep, const Eigen::VectorXd& area, int i, int j, double gij, double gji) {
  const double change = 0.5 * std::abs(gij - gji) / std::min(area[i], area[j]);
  if (change > rep.max_view_factor_change) {
    rep.max_view_factor_change = change;
    rep.worst_from = i;
    rep.worst_to = j;
  }
}

}  // namespace

void Network::finish(const Eigen::VectorXd& row_sums_after, const NetworkTolerances& tol) {
  if (reciprocity_.max_view_factor_change > tol.reciprocity) {
    const int i = reciprocity_.worst_from, j = reciprocity_.worst_to;
    std::ostringstream s;
    s << "reciprocity A_i F_ij = A_j F_ji is violated between " << nodeLabel(names_, i) << " and "
      << nodeLabel(names_, j) << ": making it hold moves a view factor by " << reciprocity_.max_view_factor_change
      << "; expected at most " << tol.reciprocity;
    throw NetworkError(s.str());
  }
  const int n = size();
  f_space_.resize(n);
  for (int i = 0; i < n; ++i) {
    const double rest = 1.0 - row_sums_after[i] - blocked_[i];
    reciprocity_.max_row_overshoot = std::max(reciprocity_.max_row_overshoot, -rest);
    f_space_[i] = std::max(0.0, rest);
  }
}

Network::Network(std::vector<std::string> names, Eigen::VectorXd area_m2, const Eigen::MatrixXd& view_factors,
                 Eigen::VectorXd blocked, NetworkTolerances tol)
    : Network(std::move(names), std::move(area_m2), Eigen::MatrixXd(view_factors), std::move(blocked), tol) {}

Network::Network(std::vector<std::string> names, Eigen::VectorXd area_m2, Eigen::MatrixXd&& view_factors,
                 Eigen::VectorXd blocked, NetworkTolerances tol)
    : names_(std::move(names)), area_(std::move(area_m2)), blocked_(std::move(blocked)) {
  validateCommon(tol);
  const int n = size();
  checkShape(view_factors.rows(), view_factors.cols(), n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) checkEntry(names_, i, j, view_factors(i, j));
  checkRowSums(names_, view_factors.rowwise().sum(), blocked_, tol.row_sum);

  // G = ½ (A F + (A F)ᵀ) in F's own storage: A F by rows, then each pair averaged once by
  // tiles (no n × n temporaries: 288 MiB each at 6,144 nodes).
  g_dense_.swap(view_factors);
  g_dense_ = area_.asDiagonal() * g_dense_;
  forEachLowerPairByTiles(n, [&](Eigen::Index i, Eigen::Index j) {
    noteDefect(reciprocity_, area_, int(i), int(j), g_dense_(i, j), g_dense_(j, i));
    g_dense_(i, j) = g_dense_(j, i) = 0.5 * (g_dense_(i, j) + g_dense_(j, i));
  });
  finish(g_dense_.rowwise().sum().cwiseQuotient(area_), tol);
}

Network::Network(std::vector<std::string> names, Eigen::VectorXd area_m2,
                 const Eigen::SparseMatrix<double>& view_factors, Eigen::VectorXd blocked, NetworkTolerances tol)
    : names_(std::move(names)), area_(std::move(area_m2)), blocked_(std::move(blocked)), sparse_(true) {
  validateCommon(tol);
  const int n = size();
  checkShape(view_factors.rows(), view_factors.cols(), n);
  Eigen::VectorXd row_sums = Eigen::VectorXd::Zero(n);
  for (int k = 0; k < view_factors.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(view_factors, k); it; ++it) {
      checkEntry(names_, static_cast<int>(it.row()), static_cast<int>(it.col()), it.value());
      row_sums[it.row()] += it.value();
    }
  checkRowSums(names_, row_sums, blocked_, tol.row_sum);

  // (A F)ᵀ and G = ½ (A F + (A F)ᵀ), A F itself never stored: each is 12 B a non-zero (2.4 GB
  // at 2e8), and the 100,002-node run's peak is this constructor. The defects A_i F_ij −
  // A_j F_ji are read by walking F, (A F)ᵀ and G column by column (G's pattern is the union).
  {
    const Eigen::SparseMatrix<double> aft = (area_.asDiagonal() * view_factors).transpose();
    g_sparse_ = 0.5 * (area_.asDiagonal() * view_factors + aft);
    g_sparse_.makeCompressed();  // its arrays are read in place as its rows (applyConductance, Lanczos, the file)
    for (int k = 0; k < g_sparse_.outerSize(); ++k) {
      Eigen::SparseMatrix<double>::InnerIterator f(view_factors, k), t(aft, k);
      for (Eigen::SparseMatrix<double>::InnerIterator it(g_sparse_, k); it; ++it) {
        const Eigen::Index i = it.row();
        while (f && f.row() < i) ++f;
        while (t && t.row() < i) ++t;
        if (i <= k) continue;  // each pair once, from the lower triangle
        const double af = f && f.row() == i ? area_[i] * f.value() : 0.0;
        const double aft_ik = t && t.row() == i ? t.value() : 0.0;
        noteDefect(reciprocity_, area_, static_cast<int>(i), k, af - aft_ik, 0.0);
      }
    }
  }
  finish(heldRowSums().cwiseQuotient(area_), tol);
}

// G's row sums, whole: column i is row i (G = Gᵀ), summed in order by its holder and joined.
Eigen::VectorXd Network::heldRowSums() const {
  const int n = size();
  Eigen::VectorXd sums = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < n; ++i)
    for (Eigen::SparseMatrix<double>::InnerIterator it(g_sparse_, i); it; ++it) sums[i] += it.value();
  share_.joinRows(sums.data(), static_cast<size_t>(n));
  return sums;
}

Network::Network(std::vector<std::string> names, Eigen::VectorXd area_m2,
                 const Eigen::SparseMatrix<double, Eigen::RowMajor>& held_f,
                 const Eigen::SparseMatrix<double, Eigen::RowMajor>& held_ft, Eigen::VectorXd blocked,
                 NetworkTolerances tol, RowShare share)
    : names_(std::move(names)), area_(std::move(area_m2)), blocked_(std::move(blocked)), sparse_(true),
      share_(std::move(share)) {
  using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;
  validateCommon(tol);
  const int n = size();
  checkShape(held_f.rows(), held_f.cols(), n);
  checkShape(held_ft.rows(), held_ft.cols(), n);
  Eigen::VectorXd row_sums = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < n; ++i)
    for (RowSparse::InnerIterator it(held_f, i); it; ++it) {
      checkEntry(names_, i, static_cast<int>(it.col()), it.value());
      row_sums[i] += it.value();
    }
  share_.joinRows(row_sums.data(), static_cast<size_t>(n));
  checkRowSums(names_, row_sums, blocked_, tol.row_sum);
  // G's held rows as the one-process sum forms them (a + b, or the one side present), then
  // its column-major arrays: a symmetric matrix's rows are its columns.
  // (Stored column-major, the held rows' transpose is their own arrays: one copy, no second.)
  g_sparse_ = (0.5 * (area_.asDiagonal() * held_f + held_ft * area_.asDiagonal())).transpose();
  g_sparse_.makeCompressed();
  // Defects of the pairs (i, j < i) from row i's holder; the first of equal ones in the
  // one-process order (by j, then i).
  for (int i = 0; i < n; ++i) {
    RowSparse::InnerIterator f(held_f, i), t(held_ft, i);
    for (; f || t;) {
      const Eigen::Index j = std::min(f ? f.col() : n, t ? t.col() : n);
      if (j >= i) break;
      const double af = f && f.col() == j ? area_[i] * f.value() : 0.0;
      const double aft = t && t.col() == j ? area_[j] * t.value() : 0.0;
      const double change = 0.5 * std::abs(af - aft) / std::min(area_[i], area_[j]);
      const ReciprocityReport& r = reciprocity_;
      if (change > r.max_view_factor_change ||
          (change == r.max_view_factor_change && change > 0 &&
           (j < r.worst_to || (j == r.worst_to && i < r.worst_from))))
        reciprocity_ = {change, i, static_cast<int>(j), 0.0};
      if (f && f.col() == j) ++f;
      if (t && t.col() == j) ++t;
    }
  }
  if (!share_.whole()) {
    const double largest = share_.largest(reciprocity_.max_view_factor_change);
    const double key = reciprocity_.max_view_factor_change == largest && reciprocity_.worst_from >= 0
                           ? -(double(reciprocity_.worst_to) * n + reciprocity_.worst_from)
                           : -1e300;
    const double first = share_.largest(key);
    reciprocity_ = {largest, -1, -1, 0.0};
    if (first > -1e300) {
      reciprocity_.worst_to = static_cast<int>(-first / n);
      reciprocity_.worst_from = static_cast<int>(-first - double(reciprocity_.worst_to) * n);
    }
  }
  finish(heldRowSums().cwiseQuotient(area_), tol);
}

long long Network::conductanceNonZeros() const {
  if (!sparse_) return static_cast<long long>(g_dense_.size());
  return static_cast<long long>(share_.total(double(g_sparse_.nonZeros())));
}

double Network::conductance(int i, int j) const {
  if (!sparse_) return g_dense_(i, j);
  if (share_.whole()) return g_sparse_.coeff(i, j);
  double g = share_.holds(j) ? g_sparse_.coeff(i, j) : 0.0;  // column j is row j, held by j's holder
  share_.joinRows(&g, 1);
  return g;
}

Eigen::MatrixXd Network::denseConductance() const {
  if (!sparse_) return g_dense_;
  if (!share_.whole()) throw std::logic_error("a dense G of a network whose rows are shared out");
  return Eigen::MatrixXd(g_sparse_);
}

const Eigen::MatrixXd& Network::heldDenseConductance() const {
  if (sparse_) throw std::logic_error("heldDenseConductance of a sparse network");
  return g_dense_;
}

Eigen::MatrixXd Network::applyConductance(const Eigen::Ref<const Eigen::MatrixXd>& x) const {
  if (!sparse_) return g_dense_ * x;
  // The band solves' and probes' products with n × P blocks, on the cores by blocks of rows.
  constexpr Eigen::Index kRowsPerBlock = 4096;
  Eigen::MatrixXd y = symmetricTimes(g_sparse_, x, kRowsPerBlock);
  share_.joinRows(y.data(), static_cast<size_t>(y.size()));  // rows not held are +0.0 here
  return y;
}

Eigen::MatrixXd Network::viewFactors() const { return area_.cwiseInverse().asDiagonal() * denseConductance(); }

double Network::spectralBound() const {
  if (sparse_) {  // column k is row k (G = Gᵀ): its |G_kj| summed in j order, as by rows
    Eigen::VectorXd rows = Eigen::VectorXd::Zero(size());
    for (int k = 0; k < g_sparse_.outerSize(); ++k)
      for (Eigen::SparseMatrix<double>::InnerIterator it(g_sparse_, k); it; ++it) rows[k] += std::abs(it.value());
    return share_.largest(rows.maxCoeff());
  }
  return g_dense_.cwiseAbs().rowwise().sum().maxCoeff();
}

int Network::indexOf(const std::string& name) const {
  auto it = std::find(names_.begin(), names_.end(), name);
  return it == names_.end() ? -1 : static_cast<int>(it - names_.begin());
}

}  // namespace radnet::solver
