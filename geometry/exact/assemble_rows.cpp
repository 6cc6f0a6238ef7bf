#include "geometry/exact/assemble_rows.hpp"

#include <algorithm>
#include <numeric>

namespace radnet::geometry {
namespace {

using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// Raw compressed rows: entries of row i at [start[i], start[i] + length[i]).
struct RawRows {
  std::vector<std::int64_t> start, length;
  std::vector<int> col;
  std::vector<double> f, e;
};

// Orders row i by column (stably: a node pair's patch pairs are summed in the order they
// were credited, so the result does not depend on the threads) and sums repeated columns.
void mergeRow(RawRows& r, size_t i, std::vector<int>& order, std::vector<int>& col, std::vector<double>& f,
              std::vector<double>& e) {
  const std::int64_t s = r.start[i], m = r.length[i];
  order.resize(size_t(m));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return r.col[size_t(s + a)] < r.col[size_t(s + b)]; });
  col.clear();
  f.clear();
  e.clear();
  for (int k : order) {
    const size_t at = size_t(s + k);
    if (!col.empty() && col.back() == r.col[at]) {
      f.back() += r.f[at];
      e.back() += r.e[at];
    } else {
      col.push_back(r.col[at]);
      f.push_back(r.f[at]);
      e.push_back(r.e[at]);
    }
  }
  std::copy(col.begin(), col.end(), r.col.begin() + s);
  std::copy(f.begin(), f.end(), r.f.begin() + s);
  std::copy(e.begin(), e.end(), r.e.begin() + s);
  r.length[i] = static_cast<std::int64_t>(col.size());
}

// One matrix from the merged rows (entries shifted together).
RowSparse compressed(const RawRows& r, const std::vector<double>& values) {
  const Eigen::Index n = static_cast<Eigen::Index>(r.start.size());
  const std::int64_t nnz = std::accumulate(r.length.begin(), r.length.end(), std::int64_t{0});
  RowSparse m(n, n);
  m.resizeNonZeros(static_cast<Eigen::Index>(nnz));
  std::int64_t at = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    m.outerIndexPtr()[i] = static_cast<int>(at);
    const auto s = r.start[size_t(i)], len = r.length[size_t(i)];
    std::copy(r.col.begin() + s, r.col.begin() + s + len, m.innerIndexPtr() + at);
    std::copy(values.begin() + s, values.begin() + s + len, m.valuePtr() + at);
    at += len;
  }
  m.outerIndexPtr()[n] = static_cast<int>(at);
  return m;
}

}  // namespace

void assemblePairRows(const std::vector<int>& patch_node, std::vector<std::vector<PairValue>>& values,
                      const Eigen::VectorXd& area, const std::vector<char>& sampled_rows, int threads,
                      ViewFactorEstimate& out) {
  const auto n = static_cast<size_t>(area.size());
  auto credited = [&](int i, int j) { return i >= 0 && j >= 0 && !sampled_rows[size_t(i)]; };
  RawRows r;
  r.start.assign(n, 0);
  r.length.assign(n, 0);
  for (size_t a = 0; a < values.size(); ++a)
    for (const PairValue& v : values[a]) {
      const int i = patch_node[a], j = patch_node[size_t(v.q)];
      if (credited(i, j)) ++r.length[size_t(i)];
      if (credited(j, i)) ++r.length[size_t(j)];
    }
  std::int64_t total = 0;
  for (size_t i = 0; i < n; ++i) r.start[i] = total, total += r.length[i];
  r.col.resize(size_t(total));
  r.f.resize(size_t(total));
  r.e.resize(size_t(total));
  std::vector<std::int64_t> fill = r.start;
  out.blocked = out.blocked_error = Eigen::VectorXd::Zero(area.size());
  auto credit = [&](int i, int j, double g, double err) {
    if (i < 0 || sampled_rows[size_t(i)]) return;
    if (j < 0) {
      out.blocked[i] += g / area[i];
      out.blocked_error[i] += err / area[i];
      return;
    }
    const auto at = size_t(fill[size_t(i)]++);
    r.col[at] = j;
    r.f[at] = g / area[i];
    r.e[at] = err / area[i];
  };
  for (size_t a = 0; a < values.size(); ++a) {
    for (const PairValue& v : values[a]) {
      const int i = patch_node[a], j = patch_node[size_t(v.q)];
      credit(i, j, v.exchange_area, v.error);
      credit(j, i, v.exchange_area, v.error);
    }
    std::vector<PairValue>().swap(values[a]);
  }
#ifdef _OPENMP
#pragma omp parallel num_threads(threads)
#endif
  {
    std::vector<int> order, col;
    std::vector<double> f, e;
#ifdef _OPENMP
#pragma omp for schedule(dynamic, 64)
#endif
    for (size_t i = 0; i < n; ++i) mergeRow(r, i, order, col, f, e);
  }
  (void)threads;
  out.view_factors = compressed(r, r.f);
  out.standard_error = compressed(r, r.e);
  out.space.resize(area.size());
  out.space_error.resize(area.size());
  for (size_t i = 0; i < n; ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    if (sampled_rows[i]) {
      out.space[k] = out.space_error[k] = 0.0;
      continue;
    }
    const auto s = r.start[i], len = r.length[i];
    // Summed in column order, as Eigen's row sum did.
    const double row = std::accumulate(r.f.begin() + s, r.f.begin() + s + len, 0.0) + out.blocked[k];
    out.space[k] = std::max(0.0, 1.0 - row);
    out.space_error[k] = std::accumulate(r.e.begin() + s, r.e.begin() + s + len, 0.0) + out.blocked_error[k];
  }
}

}  // namespace radnet::geometry
