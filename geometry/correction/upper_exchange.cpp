// F from exchange areas held as their upper triangle (ViewFactorEstimate::upper_exchange):
// the exact method integrates each pair once, so g_ij = A_i F_ij = A_j F_ji is one number and
// its partner entry is the same number divided by the other area.
#include "geometry/reciprocity.hpp"

#include <algorithm>
#include <stdexcept>
#include <vector>

namespace radnet::geometry {
namespace {

using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;

constexpr int kBlocks = 8;

// Calls visit(i, j, u) for the upper entries of rows [first, last), u the entry's index.
template <class Visit>
void forEachUpper(const RowSparse& upper, int first, int last, Visit&& visit) {
  const int* outer = upper.outerIndexPtr();
  const int* inner = upper.innerIndexPtr();
  for (int i = first; i < last; ++i)
    for (int u = outer[i]; u < outer[i + 1]; ++u) visit(i, inner[u], u);
}

void checkUpper(const RowSparse& upper, const Eigen::VectorXd& area) {
  if (upper.rows() != upper.cols() || upper.rows() != area.size() || !upper.isCompressed())
    throw std::invalid_argument("exchange areas as an upper triangle: a compressed n × n matrix and n areas");
}

// Writes full's values from the upper entries, full laid out as viewFactorsFromUpper lays
// it: row j's lower entries (from the upper rows i < j, in order of i: ascending columns),
// then its own upper row. value(u, row) is entry u's value seen from `row`. Each of `parts`
// tasks writes the rows of its own range, reading the whole triangle.
template <class Value>
void fillFromUpper(const RowSparse& upper, RowSparse& full, bool columns, const Value& value) {
  const int n = static_cast<int>(upper.rows());
  const int* outer = upper.outerIndexPtr();
  const int* inner = upper.innerIndexPtr();
  const int parts = static_cast<int>(std::max(1u, solver::threadCount()));
  solver::parallelFor(parts, [&](long long part) {
    const int first = static_cast<int>(static_cast<long long>(n) * part / parts);
    const int last = static_cast<int>(static_cast<long long>(n) * (part + 1) / parts);
    std::vector<int> cursor(full.outerIndexPtr() + first, full.outerIndexPtr() + last);
    auto put = [&](int row, int col, int u) {
      const int k = cursor[static_cast<size_t>(row - first)]++;
      if (columns) full.innerIndexPtr()[k] = col;
      full.valuePtr()[k] = value(u, row);
    };
    for (int i = 0; i < last; ++i)
      for (int u = outer[i]; u < outer[i + 1]; ++u) {
        const int j = inner[u];
        if (i >= first) put(i, j, u);  // row i's own upper entries come after its lower ones
        if (j != i && j >= first && j < last) put(j, i, u);
      }
  });
}

}  // namespace

std::vector<int> upperRowBlocks(const RowSparse& upper, int blocks) {
  const int n = static_cast<int>(upper.rows());
  const int* outer = upper.outerIndexPtr();
  std::vector<int> first{0};
  const long long total = outer[n];
  for (int b = 1; b < blocks; ++b) {
    const long long share = total * b / blocks;
    first.push_back(std::max(first.back(), static_cast<int>(std::lower_bound(outer, outer + n, share) - outer)));
  }
  first.push_back(n);
  return first;
}

// A row's diagonal entry, when it has one, is its first (columns ascending, all ≥ the row).
long long fullNonZeros(const RowSparse& upper) {
  const int* outer = upper.outerIndexPtr();
  const int* inner = upper.innerIndexPtr();
  long long diagonal = 0;
  for (int i = 0; i < upper.rows(); ++i) diagonal += outer[i] < outer[i + 1] && inner[outer[i]] == i;
  return 2 * static_cast<long long>(upper.nonZeros()) - diagonal;
}

RowSparse viewFactorsFromUpper(const RowSparse& upper, const Eigen::VectorXd& area) {
  checkUpper(upper, area);
  const int n = static_cast<int>(upper.rows());
  const int* outer = upper.outerIndexPtr();
  std::vector<long long> lower(static_cast<size_t>(n), 0);
  forEachUpper(upper, 0, n, [&](int i, int j, int) { lower[static_cast<size_t>(j)] += j != i; });
  RowSparse f(n, n);
  f.resizeNonZeros(static_cast<Eigen::Index>(fullNonZeros(upper)));
  long long at = 0;
  for (int i = 0; i < n; ++i) {
    f.outerIndexPtr()[i] = static_cast<int>(at);
    at += lower[static_cast<size_t>(i)] + (outer[i + 1] - outer[i]);
  }
  f.outerIndexPtr()[n] = static_cast<int>(at);
  const double* g = upper.valuePtr();
  fillFromUpper(upper, f, true, [&](int u, int row) { return g[u] / area[row]; });
  return f;
}

void errorsOverUpperLayout(RowSparse& full, const RowSparse& upper, const Eigen::VectorXd& area, const float* error) {
  checkUpper(upper, area);
  if (full.rows() != upper.rows() || full.nonZeros() != fullNonZeros(upper))
    throw std::invalid_argument("σ over F's layout: F must be laid out from the same exchange areas");
  fillFromUpper(upper, full, false,
                [&](int u, int row) { return double(static_cast<float>(double(error[u]) / area[row])); });
}

// F(i, j) = g_ij / A_i and F(j, i) = g_ij / A_j, row i's block of 8 rows at a time: the column
// writes of F (column-major) are contiguous, the row writes fill each cache line 8 times over.
Eigen::MatrixXd denseViewFactorsFromUpper(const RowSparse& upper, const Eigen::VectorXd& area) {
  checkUpper(upper, area);
  const int n = static_cast<int>(upper.rows());
  Eigen::MatrixXd f = Eigen::MatrixXd::Zero(n, n);
  const double* g = upper.valuePtr();
  constexpr int kRows = 8;
  // Blocks of rows write disjoint entries: block I the rows I at columns ≥ their own, and the
  // columns I at rows ≥ their own.
  solver::parallelFor((n + kRows - 1) / kRows, [&](long long block) {
    const int first = static_cast<int>(block) * kRows, last = std::min(n, first + kRows);
    forEachUpper(upper, first, last, [&](int i, int j, int u) {
      f(i, j) = g[u] / area[i];
      if (j != i) f(j, i) = g[u] / area[j];
    });
  });
  return f;
}

Eigen::VectorXd upperRowSums(const RowSparse& upper, const Eigen::VectorXd& area) {
  checkUpper(upper, area);
  const int n = static_cast<int>(upper.rows());
  const double* g = upper.valuePtr();
  const std::vector<int> blocks = upperRowBlocks(upper, kBlocks);
  Eigen::VectorXd own = Eigen::VectorXd::Zero(n);
  std::vector<Eigen::VectorXd> column(kBlocks);
  solver::parallelFor(kBlocks, [&](long long b) {
    Eigen::VectorXd& mine = column[static_cast<size_t>(b)] = Eigen::VectorXd::Zero(n);
    forEachUpper(upper, blocks[size_t(b)], blocks[size_t(b) + 1], [&](int i, int j, int u) {
      own[i] += g[u] / area[i];
      if (j != i) mine[j] += g[u] / area[j];
    });
  });
  for (const Eigen::VectorXd& c : column) own += c;
  return own;
}

void expandUpper(ViewFactorEstimate& est) {
  if (!est.upper_exchange) return;
  est.view_factors = viewFactorsFromUpper(est.exchange_upper, est.upper_area);
  RowSparse sigma = est.view_factors;
  errorsOverUpperLayout(sigma, est.exchange_upper, est.upper_area, est.exchange_error_upper.data());
  est.error_on_pattern = Eigen::Map<const Eigen::VectorXd>(sigma.valuePtr(), sigma.nonZeros()).cast<float>();
  est.errors_on_pattern = true;
  est.standard_error = RowSparse();
  RowSparse().swap(est.exchange_upper);
  Eigen::VectorXf().swap(est.exchange_error_upper);
  est.upper_area.resize(0);
  est.upper_exchange = false;
}

Eigen::VectorXd upperRowLargestErrors(const ViewFactorEstimate& est) {
  const RowSparse& upper = est.exchange_upper;
  const Eigen::VectorXd& area = est.upper_area;
  checkUpper(upper, area);
  const int n = static_cast<int>(upper.rows());
  const float* e = est.exchange_error_upper.data();
  const std::vector<int> blocks = upperRowBlocks(upper, kBlocks);
  std::vector<Eigen::VectorXd> largest(kBlocks);
  solver::parallelFor(kBlocks, [&](long long b) {
    Eigen::VectorXd& mine = largest[static_cast<size_t>(b)] = Eigen::VectorXd::Zero(n);
    forEachUpper(upper, blocks[size_t(b)], blocks[size_t(b) + 1], [&](int i, int j, int u) {
      // σ_ij as the expanded σ holds it (float of e / A_i), so both views give the same maxima
      mine[i] = std::max(mine[i], double(static_cast<float>(double(e[u]) / area[i])));
      mine[j] = std::max(mine[j], double(static_cast<float>(double(e[u]) / area[j])));
    });
  });
  Eigen::VectorXd all = Eigen::VectorXd::Zero(n);
  for (const Eigen::VectorXd& m : largest) all = all.cwiseMax(m);
  return all;
}

}  // namespace radnet::geometry
