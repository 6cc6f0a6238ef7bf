#include "cases/output/hdf5_matrices.hpp"

#include "solver/radiative/policy.hpp"

#include <algorithm>
#include <stdexcept>
#include <type_traits>
#include <vector>

namespace radnet::cases {

namespace {

// indices and indptr of a CSR group (scipy's convention) and its attributes, its `data`
// written by the caller; `pattern_from` non-empty: indices and indptr are links to that
// group's (the same pattern, checked by the caller).
void writeCsrPattern(Hdf5Writer& h5, const std::string& group, const Eigen::Ref<const Eigen::VectorXi>& indices,
                     const std::vector<long long>& indptr, long long cols, const std::string& units,
                     const std::string& pattern_from = "") {
  // The indices, sorted within rows, shrink threefold and are deflated; the values (written
  // whole by the callers) deflate by 6 % (19,202-node satellite) for a second of compression.
  if (pattern_from.empty()) {
    h5.writeIntegers(group + "/indices", indices, "1");
    h5.writeLongs(group + "/indptr", indptr, "1");
  } else {
    h5.link(pattern_from + "/indices", group + "/indices");
    h5.link(pattern_from + "/indptr", group + "/indptr");
  }
  h5.attribute(group, "shape", std::vector<long long>{static_cast<long long>(indptr.size()) - 1, cols});
  h5.attribute(group, "format", std::string("csr"));
  h5.attribute(group, "units", units);
}

void writeCsrParts(Hdf5Writer& h5, const std::string& group, const Eigen::Ref<const Eigen::VectorXd>& data,
                   const Eigen::Ref<const Eigen::VectorXi>& indices, const std::vector<long long>& indptr, long long cols,
                   const std::string& units) {
  h5.writeVector(group + "/data", data, units, false);
  writeCsrPattern(h5, group, indices, indptr, cols, units);
}

// Equal sparsity patterns, entry for entry (both compressed).
template <class Rows>
bool samePattern(const Rows& a, const CsrPattern& b) {
  if (!b.outer || a.rows() != b.rows || a.nonZeros() != b.nonzeros) return false;
  return std::equal(a.outerIndexPtr(), a.outerIndexPtr() + a.rows() + 1, b.outer) &&
         std::equal(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros(), b.inner);
}

}  // namespace

CsrPattern::CsrPattern(std::string pattern_group, const CsrRef& m) {
  if (!m.isCompressed()) return;  // no sharing (Eigen's products and conversions leave matrices compressed)
  group = std::move(pattern_group);
  rows = m.rows();
  nonzeros = m.nonZeros();
  outer = m.outerIndexPtr();
  inner = m.innerIndexPtr();
}

Eigen::Map<const SparseRows> rowsOfSymmetric(const Eigen::SparseMatrix<double>& m) {
  if (!m.isCompressed() || m.rows() != m.cols())
    throw std::logic_error("rowsOfSymmetric: a compressed square matrix is required");
  return {m.rows(), m.cols(), m.nonZeros(), m.outerIndexPtr(), m.innerIndexPtr(), m.valuePtr()};
}

namespace {

// writeCsr for double or float values (the latter written as doubles, by blocks).
template <class Rows>
void writeCsrRows(Hdf5Writer& h5, const std::string& group, const Rows& m, const std::string& units,
                  const Eigen::VectorXd& row_scale, const CsrPattern& shared) {
  using Value = typename Rows::Scalar;
  if (!m.isCompressed()) {
    Eigen::SparseMatrix<Value, Eigen::RowMajor> compressed(m);
    compressed.makeCompressed();
    writeCsrRows(h5, group, compressed, units, row_scale, {});
    return;
  }
  // The matrix's own arrays, no copy of them (2.4 GB at 2e8 non-zeros); scaled or converted
  // values made and written by blocks.
  const Eigen::Index rows = m.rows(), nnz = m.nonZeros();
  const int* outer = m.outerIndexPtr();
  const std::vector<long long> indptr(outer, outer + rows + 1);
  if constexpr (std::is_same_v<Value, double>) {
    if (row_scale.size() == 0) {
      h5.writeVector(group + "/data", Eigen::Map<const Eigen::VectorXd>(m.valuePtr(), nnz), units, false);
      writeCsrPattern(h5, group, Eigen::Map<const Eigen::VectorXi>(m.innerIndexPtr(), nnz), indptr, m.cols(), units,
                      samePattern(m, shared) ? shared.group : "");
      return;
    }
  }
  h5.writeVectorBlocks(
      group + "/data", nnz,
      [&](long long first, long long count, double* out) {
        long long r = std::upper_bound(outer, outer + rows + 1, first) - outer - 1;  // the row of entry `first`
        for (long long k = first; k < first + count; ++k) {
          while (outer[r + 1] <= k) ++r;
          out[k - first] = double(m.valuePtr()[k]) * (row_scale.size() ? row_scale[r] : 1.0);
        }
      },
      units);
  writeCsrPattern(h5, group, Eigen::Map<const Eigen::VectorXi>(m.innerIndexPtr(), nnz), indptr, m.cols(), units,
                  samePattern(m, shared) ? shared.group : "");
}

}  // namespace

void writeCsr(Hdf5Writer& h5, const std::string& group, const CsrRef& m, const std::string& units,
              const Eigen::VectorXd& row_scale, const CsrPattern& shared) {
  writeCsrRows(h5, group, m, units, row_scale, shared);
}

void writeCsrOfDense(Hdf5Writer& h5, const std::string& group, const Eigen::MatrixXd& m, const std::string& units,
                     const Eigen::VectorXd& row_scale) {
  // Two passes over blocks of rows copied row-major (a row of the column-major matrix is
  // strided): count, then fill; no sparse copy of a matrix that may be 80 % non-zero.
  constexpr Eigen::Index kBlock = 256;
  const Eigen::Index rows = m.rows(), cols = m.cols();
  std::vector<long long> indptr(static_cast<size_t>(rows) + 1, 0);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> block;
  for (int pass = 0; pass < 2; ++pass) {
    Eigen::VectorXd data(pass ? indptr.back() : 0);
    Eigen::VectorXi indices(pass ? indptr.back() : 0);
    for (Eigen::Index r0 = 0; r0 < rows; r0 += kBlock) {
      block = m.middleRows(r0, std::min(kBlock, rows - r0));
      if (row_scale.size())
        for (Eigen::Index r = 0; r < block.rows(); ++r) block.row(r) *= row_scale[r0 + r];
      for (Eigen::Index r = 0; r < block.rows(); ++r) {
        auto k = static_cast<Eigen::Index>(indptr[static_cast<size_t>(r0 + r)]);
        Eigen::Index count = 0;
        for (Eigen::Index c = 0; c < cols; ++c) {
          if (block(r, c) == 0.0) continue;
          if (pass) data[k + count] = block(r, c), indices[k + count] = static_cast<int>(c);
          ++count;
        }
        if (!pass) indptr[static_cast<size_t>(r0 + r) + 1] = indptr[static_cast<size_t>(r0 + r)] + count;
      }
    }
    if (pass) writeCsrParts(h5, group, data, indices, indptr, cols, units);
  }
}

// Without the (n,n) dataset, /network/<name> names the CSR group itself (a hard link, no
// copy): a reader that opens /network/view_factors finds the matrix at every size, as a
// dataset or as a group of the CSR convention.
namespace {
// The CSR copy beside an (n,n) dataset, except past kDenseOutputMaxNodes for a matrix 25 % or
// more non-zero: there CSR (12 B an entry) is larger than the dense form (8 B) and only
// duplicates it (the 6,144-node closed room: 2.4 GB file and 23 s of writing with the copies).
bool csrAlso(Eigen::Index n, double nonzeros, bool dense) {
  return !dense || n <= kDenseOutputMaxNodes || nonzeros < solver::policy::kSparseStorageMaxDensity * double(n) * double(n);
}
}  // namespace

void writeNetworkMatrix(Hdf5Writer& h5, const std::string& name, const CsrRef& m, const std::string& units,
                        bool dense, const Eigen::VectorXd& row_scale, const CsrPattern& shared) {
  if (dense) h5.writeMatrix("/network/" + name, m, units, row_scale);
  if (csrAlso(m.rows(), double(m.nonZeros()), dense)) writeCsr(h5, "/network/sparse/" + name, m, units, row_scale, shared);
  if (!dense) h5.link("/network/sparse/" + name, "/network/" + name);
}

void writeFloatNetworkMatrix(Hdf5Writer& h5, const std::string& name, const Hdf5Writer::FloatRowsRef& m,
                             const std::string& units, bool dense, const CsrPattern& shared) {
  if (dense) h5.writeFloatMatrix("/network/" + name, m, units);
  if (csrAlso(m.rows(), double(m.nonZeros()), dense)) writeCsrRows(h5, "/network/sparse/" + name, m, units, {}, shared);
  if (!dense) h5.link("/network/sparse/" + name, "/network/" + name);
}

void writeDenseNetworkMatrix(Hdf5Writer& h5, const std::string& name, const Eigen::MatrixXd& m, const std::string& units,
                        bool dense, const Eigen::VectorXd& row_scale) {
  if (dense) h5.writeMatrix("/network/" + name, m, units, row_scale);
  // Held dense: a network with 25 % or more of F non-zero (policy::storeSparse).
  if (csrAlso(m.rows(), double(m.size()), dense)) writeCsrOfDense(h5, "/network/sparse/" + name, m, units, row_scale);
  if (!dense) h5.link("/network/sparse/" + name, "/network/" + name);
}

void writeExchange(Hdf5Writer& h5, const std::string& prefix, const solver::ExchangeFactors& ex, bool dense,
                   const CsrPattern& shared) {
  if (dense) {
    if (ex.factored()) h5.writeMatrix(prefix + "radiative_exchange", ex.dense(), "m^2");
    else h5.writeMatrix(prefix + "radiative_exchange", ex.gr, "m^2");
    h5.attribute(prefix + "radiative_exchange", "method", ex.method);
  }
  h5.writeVector(prefix + "gr_space", ex.gr_space, "m^2");
  const std::string factors = prefix + "radiative_exchange_factors";
  const Eigen::Index n = ex.size();
  if (!ex.factored() && !csrAlso(n, double(n) * double(n), dense)) return;  // the (n,n) GR is its compact form
  if (ex.factored()) {
    if (ex.share.whole()) writeCsr(h5, factors + "/direct", ex.direct, "m^2", {}, shared);  // else writeSharedMatrices
    h5.writeMatrix(factors + "/basis", ex.basis, "1");
    h5.writeMatrix(factors + "/core", ex.core, "m^2");
  } else {  // held whole: GR is its own direct part, k = 0
    writeCsrOfDense(h5, factors + "/direct", ex.gr, "m^2");
    h5.writeMatrix(factors + "/basis", Eigen::MatrixXd(n, 0), "1");
    h5.writeMatrix(factors + "/core", Eigen::MatrixXd(0, 0), "m^2");
  }
  h5.attribute(factors, "formula", std::string("GR = direct + basis @ core @ basis.T"));
  h5.attribute(factors, "rank", static_cast<long long>(ex.factored() ? ex.core.rows() : 0));
  h5.attribute(factors, "method", ex.method);
  if (!dense) h5.link(factors, prefix + "radiative_exchange");  // the name finds GR at every size
}

}  // namespace radnet::cases
