#pragma once
// The matrices of a run whose rows are shared out over MPI ranks (cases/pipeline/
// shared_rows.hpp), in the layout of every other run (hdf5_matrices.hpp: scipy CSR groups
// under /network/sparse, GR's factors): rank 0 writes each CSR block by block as the ranks
// join the block's entries from the rows they hold, so no rank ever holds a whole matrix.
#include "cases/output/hdf5_matrices.hpp"
#include "cases/pipeline/results.hpp"

namespace radnet::cases {

/// True when the run's network holds only this rank's rows.
bool sharedRowsResult(const GeometryRunResult& r);

/// Rank 0 (h5 given) writes, every other rank (h5 null) takes part in the same joins, in one
/// order: G, F = A⁻¹ G, GR's direct part, the raw F and σ_F (and /network/<name> links).
/// Every rank must call it, after rank 0 has written the rest. No-op unless sharedRowsResult.
void writeSharedMatrices(Hdf5Writer* h5, const GeometryRunResult& r);

}  // namespace radnet::cases
