#pragma once
// Eigenpairs of a conductance matrix that differs from a decomposed one only in some rows and
// columns (an articulated part turned: docs/solver.md, "Moving parts"), without a new
// decomposition. With G' = G + ΔG and ΔG ≈ U M Uᵀ of low rank (a randomised range finder on
// the sparse ΔG, Halko, Martinsson & Tropp 2011, alg. 4.2 with its a-posteriori bound, §4.3),
// G'_k = [V U] diag(Λ, M) [V U]ᵀ is re-orthogonalised by one thin QR and a small symmetric
// eigenproblem: the Rayleigh–Ritz pairs of G'_k in span[V U], exact for G'_k.
#include "solver/radiative/eigenpairs.hpp"
#include "solver/radiative/network.hpp"

#include <Eigen/SparseCore>

#include <cstdint>
#include <vector>

namespace radnet::solver {

/// What an update did.
struct PairUpdateStats {
  int changed_nodes = 0;   ///< rows and columns where G' differs from G
  int update_rank = 0;     ///< rank kept of ΔG
  double residual = 0.0;   ///< bound on ‖ΔG − Q B Qᵀ‖₂ of the range found (99.99 % probability), m²
  double cut = 0.0;        ///< components of ΔG at or below this were dropped, m²
};

/// ΔG = G' − G on the rows and columns `changed` (the other entries of G' must equal G's),
/// symmetric, sparse, m².
Eigen::SparseMatrix<double> conductanceChange(const Network& base, const Network& moved, const std::vector<int>& changed);

/// The pairs of G' = G + ΔG from the pairs of G. Components of ΔG with |μ| at most drop_below
/// (m²) or 1e-3 of its largest are dropped; the range finder grows its block until at most half
/// the block is above that cut. The result's dropped_bound adds the residual bound (99.99 %)
/// and the cut: a-priori only, the caller measures the pairs (policy::measuredPairs).
/// @param seed  the range finder's Gaussian probes (fixed: runs are reproducible)
EigenPairs updatedPairs(const EigenPairs& base, const Eigen::SparseMatrix<double>& change, double drop_below,
                        std::uint64_t seed = 1, PairUpdateStats* stats = nullptr);

}  // namespace radnet::solver
