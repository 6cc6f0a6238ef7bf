#pragma once
// The n × n matrices of a result (docs/hdf5-layout.md, "Matrices"): one layout at every
// size. Each is a group in scipy's compressed-sparse-row convention (`data`, `indices`,
// `indptr`, attribute `shape`) under /network/sparse, GR as a group of factors
// (GR = direct + basis · core · basisᵀ, `direct` a CSR group); the (n,n) datasets of
// /network are written as well up to kDenseOutputMaxNodes or when `output:` asks.
#include "cases/config/output_settings.hpp"
#include "cases/output/hdf5_writer.hpp"
#include "solver/radiative/exchange.hpp"

#include <Eigen/Sparse>

#include <string>

namespace radnet::cases {

using SparseRows = Eigen::SparseMatrix<double, Eigen::RowMajor>;
/// A compressed row-major matrix read in place: a SparseRows or a Map of arrays.
using CsrRef = Hdf5Writer::SparseRowsRef;

/// A symmetric column-major matrix's own arrays read as rows: its CSC is its CSR (M = Mᵀ),
/// so G is written and shared without a row-major copy (2.4 GB at 2e8 non-zeros).
/// @throws std::logic_error when `m` is not compressed and square (symmetry is the caller's word)
Eigen::Map<const SparseRows> rowsOfSymmetric(const Eigen::SparseMatrix<double>& m);

/// A CSR group already written whose sparsity pattern another may share: when a matrix's
/// pattern equals this one's (compared entry for entry), its `indices` and `indptr` are hard
/// links to `group`'s (F, G and GR's direct part of one network share one pattern). It
/// points into the matrix's arrays, which must outlive it; empty: nothing shared.
struct CsrPattern {
  CsrPattern() = default;
  CsrPattern(std::string pattern_group, const CsrRef& m);
  std::string group;
  Eigen::Index rows = 0, nonzeros = 0;
  const int* outer = nullptr;
  const int* inner = nullptr;
};

/// A CSR group at `group`: `data` (nnz, `units`), `indices` (nnz, int32 column of each
/// entry), `indptr` (n+1, int64: row i is data[indptr[i]:indptr[i+1]]), attributes `shape`
/// (rows, cols), `format` "csr" and `units`. Row r scaled by row_scale[r] (empty: 1).
void writeCsr(Hdf5Writer& h5, const std::string& group, const CsrRef& m, const std::string& units,
              const Eigen::VectorXd& row_scale = {}, const CsrPattern& shared = {});
/// The non-zero entries of a dense matrix as a CSR group, row r scaled by row_scale[r] (empty: 1).
void writeCsrOfDense(Hdf5Writer& h5, const std::string& group, const Eigen::MatrixXd& m, const std::string& units,
                     const Eigen::VectorXd& row_scale = {});

/// /network/<name> (n,n) when `dense`, and /network/sparse/<name> always.
void writeNetworkMatrix(Hdf5Writer& h5, const std::string& name, const CsrRef& m, const std::string& units,
                        bool dense, const Eigen::VectorXd& row_scale = {}, const CsrPattern& shared = {});
/// The same from single-precision values (stored as doubles), unscaled.
void writeFloatNetworkMatrix(Hdf5Writer& h5, const std::string& name, const Hdf5Writer::FloatRowsRef& m,
                             const std::string& units, bool dense, const CsrPattern& shared = {});
void writeDenseNetworkMatrix(Hdf5Writer& h5, const std::string& name, const Eigen::MatrixXd& m, const std::string& units,
                        bool dense, const Eigen::VectorXd& row_scale = {});

/// GR of an optical set or configuration under `prefix` (ending in '/'): `gr_space` (n),
/// `radiative_exchange_factors/{direct, basis, core}` always (k = 0 and `direct` the whole GR
/// when GR is held dense), `radiative_exchange` (n,n) when `dense`; `method` attributes.
void writeExchange(Hdf5Writer& h5, const std::string& prefix, const solver::ExchangeFactors& ex, bool dense,
                   const CsrPattern& shared = {});

}  // namespace radnet::cases
