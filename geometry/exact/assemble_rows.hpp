#pragma once
// The exact method's pair values summed into node rows (F, σ_F, F_blocked, F_space),
// written straight into compressed rows: no triplet list, no global sort.
#include "geometry/exact/pair_values.hpp"
#include "geometry/reciprocity.hpp"

#include <vector>

namespace radnet::geometry {

/// Each pair value is credited to both its rows (A_P F_PQ / A_i and / A_j) unless the row is
/// in `sampled_rows` (left empty: rays fill it); a pair with an inactive side (node −1)
/// adds to F_blocked. F_space = max(0, 1 − row sum − F_blocked), its error the row's summed
/// errors. `values` is emptied as it is read (it can be as large as F).
/// @param patch_node  node of each patch (−1: an inactive side)
/// @param area        node areas, m²
void assemblePairRows(const std::vector<int>& patch_node, std::vector<std::vector<PairValue>>& values,
                      const Eigen::VectorXd& area, const std::vector<char>& sampled_rows, int threads,
                      ViewFactorEstimate& out);

}  // namespace radnet::geometry
