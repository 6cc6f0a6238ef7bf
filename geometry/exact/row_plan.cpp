// Method auto's choice of rows from its plan's per-row figures (geometry/exact/view_factors.cpp
// plans; this concludes).
#include "geometry/exact/row_plan.hpp"

#include <algorithm>

namespace radnet::geometry::detail {
namespace {

// The cap on F's entries from pairs (ExactOptions::max_entries): the exact rows with the
// most entries go to rays first (each leaves its entries, the pairs' values for its row; a
// pair to an exact row still gives that row its entry). Ties by node index: deterministic.
void capEntries(const ExactOptions& opt, const std::vector<std::int64_t>& entries, std::vector<char>& rows,
                ExactResult& res) {
  if (opt.max_entries < 0) return;
  std::int64_t total = 0;
  std::vector<int> order;
  for (size_t i = 0; i < rows.size(); ++i)
    if (!rows[i]) total += entries[i], order.push_back(static_cast<int>(i));
  if (total <= opt.max_entries) return;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return entries[size_t(a)] != entries[size_t(b)] ? entries[size_t(a)] > entries[size_t(b)] : a < b;
  });
  for (size_t k = 0; k < order.size() && total > opt.max_entries; ++k) {
    const size_t i = size_t(order[k]);
    rows[i] = 1;
    total -= entries[i];
    res.entries_for_memory += entries[i];
    ++res.rows_for_memory;
  }
}

}  // namespace

// The plan's rows from its per-row costs, blockers and entries; returns the predicted cost of
// the pairs integrated, s on one thread.
double concludePlan(const ExactOptions& opt, const std::vector<std::int64_t>& cost, const std::vector<char>& crowded,
                    const std::vector<std::int64_t>& entries, std::vector<char>& rows, ExactResult& res) {
  const double limit_ns = opt.row_sampling_seconds * 1e9;
  for (size_t i = 0; i < rows.size(); ++i)
    rows[i] = rows[i] || crowded[i] || (opt.row_sampling_seconds > 0 && double(cost[i]) > limit_ns);
  capEntries(opt, entries, rows, res);
  res.row_nanoseconds = cost;
  double predicted = 0.0;
  for (size_t i = 0; i < rows.size(); ++i) {
    // Each pair's cost was counted on both its rows: half per exact row (a pair with a row
    // left to rays is thus counted at half, which the cast rows' cost more than covers).
    if (!rows[i]) predicted += 0.5e-9 * double(cost[i]);
  }
  return predicted;
}

}  // namespace radnet::geometry::detail
