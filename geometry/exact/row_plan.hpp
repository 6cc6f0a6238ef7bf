#pragma once
// Method auto's choice of rows (internal to geometry/exact): which rows are cast as rays
// instead of integrated, from the plan's per-row figures.
#include "geometry/exact/view_factors.hpp"

#include <cstdint>
#include <vector>

namespace radnet::geometry::detail {

/// Marks in `rows` the rows to cast: those already marked, those `crowded` (a pair of too many
/// blockers, or a patch that stopped planning), those whose pairs cost more than casting
/// (`cost`, ns on one thread, against opt.row_sampling_seconds), and past opt.max_entries the
/// rows with the most `entries` (res.rows_for_memory, res.entries_for_memory say how many).
/// @return the predicted cost of the pairs integrated, s on one thread
double concludePlan(const ExactOptions& opt, const std::vector<std::int64_t>& cost, const std::vector<char>& crowded,
                    const std::vector<std::int64_t>& entries, std::vector<char>& rows, ExactResult& res);

}  // namespace radnet::geometry::detail
