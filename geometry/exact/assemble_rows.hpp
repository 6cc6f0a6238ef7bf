#pragma once
// The exact method's pair values summed into node rows (F, σ_F, F_blocked, F_space),
// written straight into compressed rows: no triplet list, no global sort.
#include "geometry/exact/pair_values.hpp"
#include "geometry/reciprocity.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace radnet::geometry {

/// An entry's target error: the larger of an absolute one and a share of the entry.
struct ErrorTarget {
  double absolute = 0.0, relative = 0.0;
};
/// An entry's error estimate and its target.
struct ErrorAgainstTarget {
  double error = 0.0, target = 0.0;
};

/// F's and σ_F's compressed rows laid out before the pairs are integrated, so that each pair
/// writes its two entries into place as it is computed (no list of pair values beside F: on
/// the 6,144-node room those were 0.25 GB of memory touched for the first time, held while
/// F and σ_F filled). The pairs are cut into chunks, runs of emitting patches in order;
/// every pair of a chunk takes a slot in each row it credits, chunk c's slots of row i after
/// those of chunks before it and in the order the chunk visits its pairs. So a row holds its
/// entries in the order one pass over every pair gives, whichever thread integrates which
/// chunk, and F is the same to the last bit for any threads and any chunking.
///
/// Each pair is credited to both its rows (A_P F_PQ / A_i and / A_j) unless the row is in
/// `sampled_rows` (left empty: rays fill it); a pair with an inactive side (node −1) adds to
/// F_blocked instead. In the upper mode (no row sampled) a pair takes one slot, in row
/// min(i, j), holding its exchange area and error themselves (ViewFactorEstimate::
/// upper_exchange), and the space terms are summed from both directions of each entry. finish() drops the slots of pairs that had no value, sums repeated
/// columns (a node of several patches) in slot order, and sets F_space = max(0, 1 − row sum
/// − F_blocked), its error the row's summed errors; it returns the entry whose error is
/// largest against its target (the first of equals in row order).
class PairRowWriter {
 public:
  /// @param area          node areas, m²
  /// @param chunk_count   the pairs' chunks
  /// @param errors_on_pattern  σ into out.error_on_pattern (F's index) instead of standard_error
  /// @param upper_exchange     each pair once, as its exchange area in the upper triangle
  ///        (ViewFactorEstimate::upper_exchange, σ on its pattern): only when no row is sampled
  ///        and every pair is credited once
  PairRowWriter(const Eigen::VectorXd& area, const std::vector<char>& sampled_rows, size_t chunk_count,
                bool errors_on_pattern = false, bool upper_exchange = false);

  /// Counting, before layout(): a pair between nodes i and j (−1: inactive) in chunk c.
  void count(size_t c, int i, int j) {
    if (upper_) {
      if (i >= 0 && j >= 0) ++fill_[c * n_ + size_t(std::min(i, j))];
      return;
    }
    if (credits(i, j)) ++fill_[c * n_ + size_t(i)];
    if (credits(j, i)) ++fill_[c * n_ + size_t(j)];
  }
  /// F's and σ's rows sized to the slots counted, in `out`.
  void layout(ViewFactorEstimate& out);
  /// Chunk c's next pair: its exchange area A_P F_PQ and the estimate's error, m². The error
  /// is kept to float's seven digits, as a PairValue keeps it (so values gathered from
  /// processes give the same σ as pairs written in place), and so is each σ_ij (stored in
  /// float when it lies on F's pattern, the same numbers either way).
  void credit(size_t c, int i, int j, double exchange_area_m2, double error_m2) {
    const double error = static_cast<float>(error_m2);
    if (upper_ && i >= 0 && j >= 0) {
      // A node's own pair counts in both orders (A_P F_PQ + A_Q F_QP): twice, exactly.
      const double times = i == j ? 2.0 : 1.0;
      const std::int64_t at = fill_[c * n_ + size_t(std::min(i, j))]++;
      f_cols_[at] = std::max(i, j);
      f_values_[at] = times * exchange_area_m2;
      e_floats_[at] = static_cast<float>(times * error);
      return;
    }
    creditRow(c, i, j, exchange_area_m2, error);
    creditRow(c, j, i, exchange_area_m2, error);
  }
  /// Chunk c's next pair had no value (culled, hidden, left to rays, or zero): its slots stay empty.
  void skip(size_t c, int i, int j) {
    if (upper_) {
      if (i >= 0 && j >= 0) f_cols_[fill_[c * n_ + size_t(std::min(i, j))]++] = kEmpty;
      return;
    }
    if (credits(i, j)) f_cols_[fill_[c * n_ + size_t(i)]++] = kEmpty;
    if (credits(j, i)) f_cols_[fill_[c * n_ + size_t(j)]++] = kEmpty;  // σ's index follows F's in finish()
  }
  /// Empty slots dropped, repeated columns summed, F_blocked and F_space set; the entry
  /// whose error is largest against `target`.
  ErrorAgainstTarget finish(int threads, const ErrorTarget& target);

  /// The column of a slot left empty until finish().
  static constexpr int kEmpty = -1;

 private:
  bool credits(int i, int j) const { return i >= 0 && j >= 0 && !sampled_rows_[size_t(i)]; }
  void creditRow(size_t c, int i, int j, double g, double err) {
    if (i < 0 || sampled_rows_[size_t(i)]) return;
    if (j < 0) return blocked_[c].push_back({i, g / area_[i], err / area_[i]});
    const std::int64_t at = fill_[c * n_ + size_t(i)]++;
    f_cols_[at] = j;
    if (e_cols_) e_cols_[at] = j;
    f_values_[at] = g / area_[i];
    const float e = static_cast<float>(err / area_[i]);
    if (e_floats_)
      e_floats_[at] = e;
    else
      e_values_[at] = e;
  }
  struct Blocked {
    int row;
    double share, error;
  };
  const Eigen::VectorXd& area_;
  const std::vector<char>& sampled_rows_;
  size_t n_;
  std::vector<std::int64_t> fill_;  // chunk c's count, then its cursor, of row i at c × n + i
  std::vector<std::int64_t> start_, length_;
  std::vector<std::vector<Blocked>> blocked_;  // per chunk, added in chunk order
  bool errors_on_pattern_ = false;
  bool upper_ = false;
  ViewFactorEstimate* out_ = nullptr;
  int* f_cols_ = nullptr;
  int* e_cols_ = nullptr;  // σ's own index (null: σ on F's pattern)
  template <class Error>
  ErrorAgainstTarget finishRows(int threads, const ErrorTarget& target, Error* e_values);
  double* f_values_ = nullptr;
  double* e_values_ = nullptr;  // σ beside its own columns, or
  float* e_floats_ = nullptr;   // σ on F's pattern
};

/// Emitting patches cut into at most `wanted` runs in order, of about equal weight (pairs):
/// the first position of each run and, last, weights.size().
std::vector<size_t> equalRuns(const std::vector<size_t>& weights, size_t wanted);

/// Pair values integrated apart (the processes' parts gathered, ExactOptions::parts)
/// credited through a PairRowWriter; `values` is emptied as it is read (it can be as large
/// as F). @param patch_node  node of each patch (−1: an inactive side)
ErrorAgainstTarget assemblePairRows(const std::vector<int>& patch_node, std::vector<std::vector<PairValue>>& values,
                                    const Eigen::VectorXd& area, const std::vector<char>& sampled_rows,
                                    const ErrorTarget& target, int threads, ViewFactorEstimate& out,
                                    bool errors_on_pattern = false);

}  // namespace radnet::geometry
