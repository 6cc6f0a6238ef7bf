#pragma once
// What a case asks of the network solve: the rank of the eigendecomposition (fixed or
// from a tolerance), refinement, the eigensolver. The policy (policy.hpp) turns these
// settings into algorithm choices.
#include "solver/radiative/eigenpairs.hpp"

#include <optional>

namespace radnet::solver {

/// The `solver:` block of a case file (docs/case-files.md).
struct SolverSettings {
  int rank = 0;                ///< explicit k (0: from the tolerance)
  double tolerance = 1e-10;    ///< relative residual target, and the a-priori truncation bound
  bool tolerance_given = false;  ///< the case set it (else the error budget may, from the view factors' noise)
  /// The error budget: relative standard uncertainty wanted on each node's absorbed power
  /// (docs/solver.md, "Error budget"), –
  double accuracy = 0.01;
  std::optional<bool> refine;  ///< default: refine when no explicit rank is given
  int max_rank = 200;          ///< cap on k chosen from a tolerance
  EigenMethod method = EigenMethod::Auto;
  /// GR from the pairs (E G E + E V (C − Λ) Vᵀ E, the rank chosen to meet the tolerance on it)
  /// at every size, not by dense LU: a run with turning parts forms one GR per configuration,
  /// and O(n³) each would dwarf the rest (docs/solver.md, "Moving parts").
  bool exchange_from_pairs = false;
  bool refineEnabled() const { return refine.value_or(rank == 0); }
  /// The band solves' refinement tolerance: 0 (keep the rank-k answer) unless refining.
  double refineTolerance() const { return refineEnabled() ? tolerance : 0.0; }
};

}  // namespace radnet::solver
