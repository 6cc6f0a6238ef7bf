#include "geometry/exact/assemble_rows.hpp"  // and solver::releaseFreedMemory, through reciprocity.hpp

#include <algorithm>
#include <numeric>

namespace radnet::geometry {
namespace {

using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// Where a row's entries lie: F's columns and values, σ's values (double beside its own
// columns, float on F's pattern) and σ's own columns (null when σ lies on F's pattern).
template <class Error>
struct RowEntries {
  int* f_cols;
  int* e_cols;
  double* f_values;
  Error* e_values;
};

// A row's entries taken in `order` (by column), repeated columns summed, written back over
// the row's first entries; returns how many remain.
template <class Error>
std::int64_t sumInOrder(const std::vector<int>& order, int* cols, int* e_cols, double* fs, Error* es,
                        std::vector<int>& col, std::vector<double>& fv, std::vector<double>& ev) {
  col.clear();
  fv.clear();
  ev.clear();
  for (int k : order) {
    if (!col.empty() && col.back() == cols[k]) {
      fv.back() += fs[k];
      ev.back() += es[k];
    } else {
      col.push_back(cols[k]);
      fv.push_back(fs[k]);
      ev.push_back(es[k]);
    }
  }
  std::copy(col.begin(), col.end(), cols);
  if (e_cols) std::copy(col.begin(), col.end(), e_cols);
  std::copy(fv.begin(), fv.end(), fs);
  // A repeated column's σ summed in double, kept to float's digits as every σ of the method
  // (the same numbers whether σ is stored in double or float).
  std::transform(ev.begin(), ev.end(), es, [](double e) { return static_cast<float>(e); });
  return static_cast<std::int64_t>(col.size());
}

// Orders row i of F and σ (entries [s, s + m) of their buffers, same columns) by column,
// stably (a node pair's patch pairs are summed in the order they were credited, so the
// result does not depend on the threads), and sums repeated columns; returns the length.
// A row arrives as a few ascending runs (the values of the patches before its own, in
// patch order, then its own patches' lists, cluster by cluster): the runs are merged
// pairwise, stably, instead of sorting the row (the same order as a stable sort; the sort
// was 0.2 s of the 6,144-node room's assembly).
template <class Error>
std::int64_t mergeRow(const RowEntries<Error>& row, std::int64_t s, std::int64_t m, std::vector<int>& order,
                      std::vector<int>& col, std::vector<double>& fv, std::vector<double>& ev) {
  int *cols = row.f_cols + s, *e_cols = row.e_cols ? row.e_cols + s : nullptr;
  double* fs = row.f_values + s;
  Error* es = row.e_values + s;
  // Empty slots (pairs that had no value) out first, in order. Most rows then arrive in
  // order already, without repeats (one patch a node: the values of the patches before it,
  // then its own, ascending): left as they are (σ's columns were written beside F's).
  std::int64_t kept = 0;
  bool in_order = true;
  for (std::int64_t k = 0; k < m; ++k) {
    if (cols[k] == PairRowWriter::kEmpty) continue;
    if (kept != k) {
      cols[kept] = cols[k];
      if (e_cols) e_cols[kept] = cols[k];
      fs[kept] = fs[k];
      es[kept] = es[k];
    }
    in_order = in_order && (kept == 0 || cols[kept] > cols[kept - 1]);
    ++kept;
  }
  m = kept;
  if (in_order) return m;
  order.resize(size_t(m));
  std::iota(order.begin(), order.end(), 0);
  const auto by_column = [&](int a, int b) { return cols[a] < cols[b]; };
  thread_local std::vector<std::int64_t> runs;
  runs.assign(1, 0);
  for (std::int64_t k = 1; k < m; ++k)
    if (cols[k] < cols[k - 1]) runs.push_back(k);
  runs.push_back(m);
  while (runs.size() > 2) {
    size_t kept = 0;
    for (size_t r = 0; r + 1 < runs.size(); r += 2) {
      runs[kept++] = runs[r];
      if (r + 2 < runs.size())
        std::inplace_merge(order.begin() + runs[r], order.begin() + runs[r + 1], order.begin() + runs[r + 2], by_column);
    }
    runs[kept++] = runs.back();
    runs.resize(kept);
  }
  return sumInOrder(order, cols, e_cols, fs, es, col, fv, ev);
}

// Rows merged in place (row i at start[i], length[i]) shifted together: the columns (none:
// σ on F's pattern) and values. Returns the entries kept.
template <class Value>
std::int64_t compact(int* cols, Value* values, const std::vector<std::int64_t>& start,
                     const std::vector<std::int64_t>& length) {
  std::int64_t at = 0;
  for (size_t i = 0; i < length.size(); ++i) {
    const std::int64_t s = start[i], len = length[i];
    if (s != at) {  // rows that lost no slot or repeated column (all of them, often) stay where they are
      if (cols) std::copy(cols + s, cols + s + len, cols + at);
      std::copy(values + s, values + s + len, values + at);
    }
    at += len;
  }
  return at;
}

// A compressed matrix's outer indices set to the compacted rows, its entries cut to `total`.
void setRows(RowSparse& m, const std::vector<std::int64_t>& length, std::int64_t total) {
  std::int64_t at = 0;
  for (size_t i = 0; i < length.size(); ++i) {
    m.outerIndexPtr()[i] = static_cast<int>(at);
    at += length[i];
  }
  m.outerIndexPtr()[length.size()] = static_cast<int>(at);
  m.data().resize(static_cast<Eigen::Index>(total));
}

// What an integrated row leaves to space (1 − Σ F − blocked, its error the summed
// estimates), from its merged entries [s, s + m); and in `worst` its entry whose error
// estimate is largest against its target max(tolerance, relative × F_ij), the first of equals.
template <class Error>
void rowTerms(const RowEntries<Error>& entries, Eigen::Index row, std::int64_t s, std::int64_t m,
              const ErrorTarget& target, ViewFactorEstimate& out, ErrorAgainstTarget& worst) {
  double sum = 0.0, sum_error = 0.0;
  for (std::int64_t k = s; k < s + m; ++k) {
    const double value = entries.f_values[k], error = entries.e_values[k];
    sum += value;
    sum_error += error;
    const double entry_target = std::max(target.absolute, target.relative * value);
    if (error / entry_target > worst.error / worst.target) worst = {error, entry_target};
  }
  out.space[row] = std::max(0.0, 1.0 - (sum + out.blocked[row]));
  out.space_error[row] = sum_error + out.blocked_error[row];
}

// An upper_exchange estimate's space terms and its entry whose error is largest against
// its target: row i's Σ_j F_ij holds its own upper entries (g_ij / A_i) and, from the rows
// before it, g_ji / A_i; each entry is measured in both directions, σ as the expanded σ holds
// it (float of e / A). Summed by fixed blocks of rows, added in block order (the same bits
// for any thread count).
ErrorAgainstTarget upperTerms(ViewFactorEstimate& out, const ErrorTarget& target) {
  const RowSparse& g = out.exchange_upper;
  const Eigen::VectorXd& area = out.upper_area;
  const float* e = out.exchange_error_upper.data();
  const int n = static_cast<int>(g.rows());
  const int* outer = g.outerIndexPtr();
  const int* inner = g.innerIndexPtr();
  constexpr int kBlocks = 8;
  const std::vector<int> first = upperRowBlocks(g, kBlocks);
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(n), sum_error = Eigen::VectorXd::Zero(n);
  std::vector<Eigen::VectorXd> column(kBlocks), column_error(kBlocks);
  std::vector<ErrorAgainstTarget> worst(kBlocks, ErrorAgainstTarget{0.0, target.absolute});
  solver::parallelFor(kBlocks, [&](long long b) {
    Eigen::VectorXd& col = column[size_t(b)] = Eigen::VectorXd::Zero(n);
    Eigen::VectorXd& col_error = column_error[size_t(b)] = Eigen::VectorXd::Zero(n);
    ErrorAgainstTarget& mine = worst[size_t(b)];
    auto measure = [&](double value, double error) {
      const double entry_target = std::max(target.absolute, target.relative * value);
      if (error / entry_target > mine.error / mine.target) mine = {error, entry_target};
    };
    for (int i = first[size_t(b)]; i < first[size_t(b) + 1]; ++i)
      for (int u = outer[i]; u < outer[i + 1]; ++u) {
        const int j = inner[u];
        const double fi = g.valuePtr()[u] / area[i], si = static_cast<float>(double(e[u]) / area[i]);
        sum[i] += fi, sum_error[i] += si;
        measure(fi, si);
        if (j == i) continue;
        const double fj = g.valuePtr()[u] / area[j], sj = static_cast<float>(double(e[u]) / area[j]);
        col[j] += fj, col_error[j] += sj;
        measure(fj, sj);
      }
  });
  ErrorAgainstTarget largest{0.0, target.absolute};
  for (int b = 0; b < kBlocks; ++b) {
    sum += column[size_t(b)], sum_error += column_error[size_t(b)];
    if (worst[size_t(b)].error / worst[size_t(b)].target > largest.error / largest.target) largest = worst[size_t(b)];
  }
  out.space = (1.0 - (sum + out.blocked).array()).max(0.0).matrix();
  out.space_error = sum_error + out.blocked_error;
  return largest;
}

// Pair values cut into at most kValueChunks runs of emitting patches (equalRuns).
constexpr size_t kValueChunks = 32;

}  // namespace

std::vector<size_t> equalRuns(const std::vector<size_t>& weights, size_t wanted) {
  size_t total = 0;
  for (size_t w : weights) total += w;
  std::vector<size_t> first{0};
  size_t seen = 0;
  for (size_t k = 0; k < weights.size(); ++k) {
    seen += weights[k];
    if (first.size() < wanted && seen * wanted >= total * first.size() && k + 1 < weights.size())
      first.push_back(k + 1);
  }
  first.push_back(weights.size());
  return first;
}

PairRowWriter::PairRowWriter(const Eigen::VectorXd& area, const std::vector<char>& sampled_rows, size_t chunk_count,
                             bool errors_on_pattern, bool upper_exchange)
    : area_(area),
      sampled_rows_(sampled_rows),
      n_(sampled_rows.size()),
      fill_(chunk_count * sampled_rows.size(), 0),
      start_(sampled_rows.size(), 0),
      length_(sampled_rows.size(), 0),
      blocked_(chunk_count),
      errors_on_pattern_(errors_on_pattern || upper_exchange),
      upper_(upper_exchange) {
  if (upper_ && std::find(sampled_rows.begin(), sampled_rows.end(), 1) != sampled_rows.end())
    throw std::logic_error("exchange areas in the upper triangle need every row integrated");
}

// Turns the chunks' counts into where chunk c writes row i: after the row's entries from the
// chunks before it. Filled straight into F's and σ's own buffers (at 6,144 nodes F has 31 M
// entries: a staging copy would be 0.6 GB of fresh memory more).
void PairRowWriter::layout(ViewFactorEstimate& out) {
  const size_t chunk_count = blocked_.size();
  std::int64_t total = 0;
  for (size_t i = 0; i < n_; ++i) {
    start_[i] = total;
    for (size_t c = 0; c < chunk_count; ++c) {
      const std::int64_t here = fill_[c * n_ + i];
      fill_[c * n_ + i] = total;
      total += here;
    }
    length_[i] = total - start_[i];
  }
  out_ = &out;
  RowSparse& f = upper_ ? out.exchange_upper : out.view_factors;
  f.resize(area_.size(), area_.size());
  f.resizeNonZeros(static_cast<Eigen::Index>(total));
  f_cols_ = f.innerIndexPtr();
  f_values_ = f.valuePtr();
  if (upper_) {  // F and σ empty: the exchange areas and their errors only
    out.view_factors = RowSparse();
    out.standard_error = RowSparse();
    out.errors_on_pattern = false;
    out.error_on_pattern.resize(0);
    out.upper_exchange = true;
    out.upper_area = area_;
    out.exchange_error_upper.resize(static_cast<Eigen::Index>(total));
    e_floats_ = out.exchange_error_upper.data();
    e_values_ = nullptr;
  } else if (errors_on_pattern_) {  // uninitialised, as resizeNonZeros leaves F: each page is first touched where
                                    // written
    out.standard_error = RowSparse();
    out.errors_on_pattern = true;
    out.error_on_pattern.resize(static_cast<Eigen::Index>(total));
    e_floats_ = out.error_on_pattern.data();
    e_values_ = nullptr;
  } else {
    out.error_on_pattern.resize(0);
    out.errors_on_pattern = false;
    out.standard_error.resize(area_.size(), area_.size());
    out.standard_error.resizeNonZeros(static_cast<Eigen::Index>(total));
    e_cols_ = out.standard_error.innerIndexPtr();
    e_values_ = out.standard_error.valuePtr();
    e_floats_ = nullptr;
  }
}

// Each row merged, then its space terms and worst entry read while it is in cache (one pass
// over F and σ on all cores; sampled rows get their space terms from the rays); the rows'
// worst entries compared in row order.
ErrorAgainstTarget PairRowWriter::finish(int threads, const ErrorTarget& target) {
  return e_floats_ ? finishRows(threads, target, e_floats_) : finishRows(threads, target, e_values_);
}

template <class Error>
ErrorAgainstTarget PairRowWriter::finishRows(int threads, const ErrorTarget& target, Error* e_values) {
  ViewFactorEstimate& out = *out_;
  const auto n = static_cast<Eigen::Index>(n_);
  out.blocked = out.blocked_error = Eigen::VectorXd::Zero(n);
  for (const std::vector<Blocked>& lost : blocked_)
    for (const Blocked& b : lost) out.blocked[b.row] += b.share, out.blocked_error[b.row] += b.error;
  out.space = out.space_error = Eigen::VectorXd::Zero(n);
  std::vector<ErrorAgainstTarget> worst(n_, ErrorAgainstTarget{0.0, target.absolute});
  const RowEntries<Error> entries{f_cols_, e_cols_, f_values_, e_values};
#ifdef _OPENMP
#pragma omp parallel num_threads(threads)
#endif
  {
    std::vector<int> order, col;
    std::vector<double> fv, ev;
#ifdef _OPENMP
#pragma omp for schedule(dynamic, 64)
#endif
    for (size_t i = 0; i < n_; ++i) {
      length_[i] = mergeRow(entries, start_[i], length_[i], order, col, fv, ev);
      if (!sampled_rows_[i] && !upper_)
        rowTerms(entries, Eigen::Index(i), start_[i], length_[i], target, out, worst[i]);
    }
  }
  (void)threads;
  const std::int64_t total = compact(f_cols_, f_values_, start_, length_);
  setRows(upper_ ? out.exchange_upper : out.view_factors, length_, total);
  compact(e_cols_, e_values, start_, length_);
  if (upper_) {
    out.exchange_error_upper.conservativeResize(static_cast<Eigen::Index>(total));
    return upperTerms(out, target);
  }
  if (errors_on_pattern_)
    out.error_on_pattern.conservativeResize(static_cast<Eigen::Index>(total));
  else
    setRows(out.standard_error, length_, total);
  ErrorAgainstTarget largest{0.0, target.absolute};
  for (const ErrorAgainstTarget& w : worst)
    if (w.error / w.target > largest.error / largest.target) largest = w;
  return largest;
}

// The values are freed as they are read and, when they are large, their pages handed back
// after every round of chunks: they sit in the worker threads' malloc arenas, which keep
// freed pages resident, and F and σ fill as they empty.
ErrorAgainstTarget assemblePairRows(const std::vector<int>& patch_node, std::vector<std::vector<PairValue>>& values,
                                    const Eigen::VectorXd& area, const std::vector<char>& sampled_rows,
                                    const ErrorTarget& target, int threads, ViewFactorEstimate& out,
                                    bool errors_on_pattern) {
  std::vector<size_t> sizes;
  for (const auto& v : values) sizes.push_back(v.size());
  const std::vector<size_t> chunks = equalRuns(sizes, kValueChunks);
  const size_t chunk_count = chunks.size() - 1;
  PairRowWriter rows(area, sampled_rows, chunk_count, errors_on_pattern);
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
#endif
  for (size_t c = 0; c < chunk_count; ++c)
    for (size_t a = chunks[c]; a < chunks[c + 1]; ++a)
      for (const PairValue& v : values[a]) rows.count(c, patch_node[a], patch_node[size_t(v.q)]);
  rows.layout(out);
  size_t stored = 0;
  for (const auto& v : values) stored += v.size();
  const bool hand_back = double(stored) * sizeof(PairValue) > 64e6;  // over 64 MB
  const size_t round = hand_back ? static_cast<size_t>(std::max(1, threads)) : chunk_count;
  for (size_t first = 0; first < chunk_count; first += round) {
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
#endif
    for (size_t c = first; c < std::min(chunk_count, first + round); ++c)
      for (size_t a = chunks[c]; a < chunks[c + 1]; ++a) {
        for (const PairValue& v : values[a])
          rows.credit(c, patch_node[a], patch_node[size_t(v.q)], v.exchange_area, v.error);
        std::vector<PairValue>().swap(values[a]);
      }
    if (hand_back) solver::releaseFreedMemory();
  }
  return rows.finish(threads, target);
}

}  // namespace radnet::geometry
