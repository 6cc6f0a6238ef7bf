#pragma once
// The exact method's pair integrals, run on all threads into F's and σ_F's rows.
// Internal to geometry/exact/.
#include "geometry/exact/pair_solver.hpp"
#include "geometry/exact/pair_values.hpp"
#include "geometry/reciprocity.hpp"

#include <vector>

namespace radnet::geometry {

/// Every pair of which at least one row is exact (rows not in `sampled_rows`) into `out`:
/// straight into its rows in one process (PairRowWriter); shared out over processes
/// (opt.parts), each integrates its emitting patches into values, gathered and then credited.
/// Sets out's F, σ, space and blocked terms and its worst entry against the targets.
/// @param area  node areas, m²
PairCounts integrateExactRows(const ExactScene& scene, const ExactOptions& opt, int threads,
                              const Eigen::VectorXd& area, const std::vector<char>& sampled_rows, ExactResult& out);

}  // namespace radnet::geometry
