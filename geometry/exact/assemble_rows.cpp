#include "geometry/exact/assemble_rows.hpp"  // and solver::releaseFreedMemory, through reciprocity.hpp

#include <algorithm>
#include <numeric>

namespace radnet::geometry {
namespace {

using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// Orders row i of F and σ (entries [s, s + m) of their buffers, same columns) by column,
// stably (a node pair's patch pairs are summed in the order they were credited, so the
// result does not depend on the threads), and sums repeated columns; returns the length.
// A row arrives as a few ascending runs (the values of the patches before its own, in
// patch order, then its own patches' lists, cluster by cluster): the runs are merged
// pairwise, stably, instead of sorting the row (the same order as a stable sort; the sort
// was 0.2 s of the 6,144-node room's assembly).
std::int64_t mergeRow(RowSparse& f, RowSparse& e, std::int64_t s, std::int64_t m, std::vector<int>& order,
                      std::vector<int>& col, std::vector<double>& fv, std::vector<double>& ev) {
  int* cols = f.innerIndexPtr() + s;
  double *fs = f.valuePtr() + s, *es = e.valuePtr() + s;
  // Most rows arrive in order already, without repeats (one patch a node: the values of the
  // patches before it, then its own, ascending): left as they are (σ's columns were written
  // beside F's).
  bool in_order = true;
  for (std::int64_t k = 1; k < m && in_order; ++k) in_order = cols[k] > cols[k - 1];
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
  std::copy(col.begin(), col.end(), e.innerIndexPtr() + s);
  std::copy(fv.begin(), fv.end(), fs);
  std::copy(ev.begin(), ev.end(), es);
  return static_cast<std::int64_t>(col.size());
}

// Rows merged in place (row i at start[i], length[i]) shifted together, outer indices set.
void compact(RowSparse& m, const std::vector<std::int64_t>& start, const std::vector<std::int64_t>& length) {
  std::int64_t at = 0;
  const auto n = static_cast<Eigen::Index>(length.size());
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::int64_t s = start[size_t(i)], len = length[size_t(i)];
    if (s != at) {  // rows that lost no repeated column (all of them, often) stay where they are
      std::copy(m.innerIndexPtr() + s, m.innerIndexPtr() + s + len, m.innerIndexPtr() + at);
      std::copy(m.valuePtr() + s, m.valuePtr() + s + len, m.valuePtr() + at);
    }
    m.outerIndexPtr()[i] = static_cast<int>(at);
    at += len;
  }
  m.outerIndexPtr()[n] = static_cast<int>(at);
  m.data().resize(static_cast<Eigen::Index>(at));
}

// The pair values cut into kCreditChunks runs of emitting patches holding about as many
// values each (a fixed count, not one per thread: the rows' order of entries, and so F to
// the last bit, does not depend on the threads). Returns the first patch of each chunk and,
// last, the number of patches.
constexpr int kCreditChunks = 32;
std::vector<size_t> creditChunks(const std::vector<std::vector<PairValue>>& values) {
  size_t total = 0;
  for (const auto& v : values) total += v.size();
  std::vector<size_t> first{0};
  size_t seen = 0;
  for (size_t a = 0; a < values.size(); ++a) {
    seen += values[a].size();
    if (first.size() < kCreditChunks && seen * kCreditChunks >= total * first.size() && a + 1 < values.size())
      first.push_back(a + 1);
  }
  first.push_back(values.size());
  return first;
}

// Per chunk, the entries each node's row receives from its values (a pair credits both its
// rows, except rows left to sampling and the blocked side, j < 0): chunk c's counts at
// [c × n, (c + 1) × n).
std::vector<std::int64_t> chunkRowCounts(const std::vector<int>& patch_node,
                                         const std::vector<std::vector<PairValue>>& values,
                                         const std::vector<char>& sampled_rows, const std::vector<size_t>& chunks,
                                         int threads) {
  const size_t n = sampled_rows.size(), count = chunks.size() - 1;
  std::vector<std::int64_t> counts(count * n, 0);
  auto credited = [&](int i, int j) { return i >= 0 && j >= 0 && !sampled_rows[size_t(i)]; };
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
#endif
  for (size_t c = 0; c < count; ++c) {
    std::int64_t* mine = counts.data() + c * n;
    for (size_t a = chunks[c]; a < chunks[c + 1]; ++a)
      for (const PairValue& v : values[a]) {
        const int i = patch_node[a], j = patch_node[size_t(v.q)];
        if (credited(i, j)) ++mine[i];
        if (credited(j, i)) ++mine[j];
      }
  }
  (void)threads;
  return counts;
}

// What an integrated row leaves to space (1 − Σ F − blocked, its error the summed
// estimates); sampled rows get theirs from the rays.
void spaceTerms(const std::vector<char>& sampled_rows, ViewFactorEstimate& out) {
  const auto n = static_cast<Eigen::Index>(sampled_rows.size());
  out.space.resize(n);
  out.space_error.resize(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    if (sampled_rows[size_t(k)]) {
      out.space[k] = out.space_error[k] = 0.0;
      continue;
    }
    const double row = out.view_factors.row(k).sum() + out.blocked[k];
    out.space[k] = std::max(0.0, 1.0 - row);
    out.space_error[k] = out.standard_error.row(k).sum() + out.blocked_error[k];
  }
}

// Turns the chunks' counts (fill[c × n + i]) into where chunk c writes row i: after the row's
// entries from the chunks before it, so each row holds its entries in the order one pass
// over the values would give. Sets each row's start and length; returns the total.
std::int64_t rowOffsets(size_t chunk_count, std::vector<std::int64_t>& fill, std::vector<std::int64_t>& start,
                        std::vector<std::int64_t>& length) {
  const size_t n = start.size();
  std::int64_t total = 0;
  for (size_t i = 0; i < n; ++i) {
    start[i] = total;
    for (size_t c = 0; c < chunk_count; ++c) {
      const std::int64_t here = fill[c * n + i];
      fill[c * n + i] = total;
      total += here;
    }
    length[i] = total - start[i];
  }
  return total;
}

// Credits every chunk's values to F's and σ's rows (A_P F_PQ / A_i at the chunk's place in
// row i), chunks in parallel. A pair with an inactive side adds to F_blocked: kept per chunk
// and added in the chunks' order (the same sums whatever the threads). The values are freed
// as they are read and, when they are large, their pages handed back after every round of
// chunks: they sit in the worker threads' malloc arenas, which keep freed pages resident, and
// F and σ fill as they empty (on the 6,144-node room the values are 0.25 GB and F with σ
// 0.75 GB: 1.0 GB at once otherwise).
void creditValues(const std::vector<int>& patch_node, std::vector<std::vector<PairValue>>& values,
                  const Eigen::VectorXd& area, const std::vector<char>& sampled_rows, const std::vector<size_t>& chunks,
                  std::vector<std::int64_t>& fill, int threads, ViewFactorEstimate& out) {
  const size_t n = sampled_rows.size(), chunk_count = chunks.size() - 1;
  RowSparse &f = out.view_factors, &e = out.standard_error;
  struct Blocked {
    int row;
    double share, error;
  };
  std::vector<std::vector<Blocked>> blocked(chunk_count);
  auto credit = [&](std::int64_t* row_fill, std::vector<Blocked>& lost, int i, int j, double g, double err) {
    if (i < 0 || sampled_rows[size_t(i)]) return;
    if (j < 0) return lost.push_back({i, g / area[i], err / area[i]});
    const auto at = row_fill[i]++;
    f.innerIndexPtr()[at] = e.innerIndexPtr()[at] = j;
    f.valuePtr()[at] = g / area[i];
    e.valuePtr()[at] = err / area[i];
  };
  const bool hand_back = double(f.nonZeros()) / 2 * sizeof(PairValue) > 64e6;  // over 64 MB (a value credits two entries)
  const size_t round = hand_back ? static_cast<size_t>(std::max(1, threads)) : chunk_count;
  for (size_t first = 0; first < chunk_count; first += round) {
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
#endif
    for (size_t c = first; c < std::min(chunk_count, first + round); ++c)
      for (size_t a = chunks[c]; a < chunks[c + 1]; ++a) {
        for (const PairValue& v : values[a]) {
          const int i = patch_node[a], j = patch_node[size_t(v.q)];
          credit(fill.data() + c * n, blocked[c], i, j, v.exchange_area, v.error);
          credit(fill.data() + c * n, blocked[c], j, i, v.exchange_area, v.error);
        }
        std::vector<PairValue>().swap(values[a]);
      }
    if (hand_back) solver::releaseFreedMemory();
  }
  out.blocked = out.blocked_error = Eigen::VectorXd::Zero(area.size());
  for (const std::vector<Blocked>& lost : blocked)
    for (const Blocked& b : lost) out.blocked[b.row] += b.share, out.blocked_error[b.row] += b.error;
}

}  // namespace

void assemblePairRows(const std::vector<int>& patch_node, std::vector<std::vector<PairValue>>& values,
                      const Eigen::VectorXd& area, const std::vector<char>& sampled_rows, int threads,
                      ViewFactorEstimate& out) {
  const auto n = static_cast<size_t>(area.size());
  const std::vector<size_t> chunks = creditChunks(values);
  std::vector<std::int64_t> fill = chunkRowCounts(patch_node, values, sampled_rows, chunks, threads);
  std::vector<std::int64_t> length(n, 0), start(n, 0);
  const std::int64_t total = rowOffsets(chunks.size() - 1, fill, start, length);
  // Filled straight into F's and σ's own buffers (at 6,144 nodes F has 31 M entries: a
  // staging copy would be 0.6 GB of fresh memory more).
  RowSparse& f = out.view_factors;
  RowSparse& e = out.standard_error;
  for (RowSparse* m : {&f, &e}) {
    m->resize(area.size(), area.size());
    m->resizeNonZeros(static_cast<Eigen::Index>(total));
  }
  creditValues(patch_node, values, area, sampled_rows, chunks, fill, threads, out);
#ifdef _OPENMP
#pragma omp parallel num_threads(threads)
#endif
  {
    std::vector<int> order, col;
    std::vector<double> fv, ev;
#ifdef _OPENMP
#pragma omp for schedule(dynamic, 64)
#endif
    for (size_t i = 0; i < n; ++i) length[i] = mergeRow(f, e, start[i], length[i], order, col, fv, ev);
  }
  (void)threads;
  compact(f, start, length);
  compact(e, start, length);
  spaceTerms(sampled_rows, out);
}

}  // namespace radnet::geometry
