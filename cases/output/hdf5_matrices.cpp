#include "cases/output/hdf5_matrices.hpp"

#include "solver/radiative/policy.hpp"

#include <algorithm>
#include <vector>

namespace radnet::cases {

namespace {

// data, indices and indptr as one CSR group (scipy's convention); `pattern_from` non-empty:
// indices and indptr are links to that group's (the same pattern, checked by the caller).
void writeCsrParts(Hdf5Writer& h5, const std::string& group, const Eigen::Ref<const Eigen::VectorXd>& data,
                   const Eigen::Ref<const Eigen::VectorXi>& indices, const std::vector<long long>& indptr, long long cols,
                   const std::string& units,
                   const std::string& pattern_from = "") {
  // Stored whole: the non-zeros of F, G or GR deflate by 6 % (19,202-node satellite) for a
  // second of compression; the indices, sorted within rows, shrink threefold and are deflated.
  h5.writeVector(group + "/data", data, units, false);
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

// Equal sparsity patterns, entry for entry (both compressed, as Eigen's products leave them).
bool samePattern(const SparseRows& a, const SparseRows& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols() || a.nonZeros() != b.nonZeros() || !a.isCompressed() ||
      !b.isCompressed())
    return false;
  return std::equal(a.outerIndexPtr(), a.outerIndexPtr() + a.rows() + 1, b.outerIndexPtr()) &&
         std::equal(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros(), b.innerIndexPtr());
}

}  // namespace

void writeCsr(Hdf5Writer& h5, const std::string& group, const SparseRows& m, const std::string& units,
              const Eigen::VectorXd& row_scale, const CsrPattern& shared) {
  const Eigen::Index rows = m.rows();
  std::vector<long long> indptr(static_cast<size_t>(rows) + 1, 0);
  for (Eigen::Index r = 0; r < rows; ++r) indptr[static_cast<size_t>(r) + 1] = indptr[static_cast<size_t>(r)] + m.innerVector(r).nonZeros();
  const Eigen::Index nnz = static_cast<Eigen::Index>(indptr.back());
  const bool linked = shared.matrix && samePattern(m, *shared.matrix);
  if (m.isCompressed() && row_scale.size() == 0) {  // the matrix's own arrays: no copy (2.4 GB at 2e8 non-zeros)
    writeCsrParts(h5, group, Eigen::Map<const Eigen::VectorXd>(m.valuePtr(), nnz),
                  Eigen::Map<const Eigen::VectorXi>(m.innerIndexPtr(), nnz), indptr, m.cols(), units,
                  linked ? shared.group : "");
    return;
  }
  Eigen::VectorXd data(nnz);
  Eigen::VectorXi indices(nnz);
  for (Eigen::Index r = 0; r < rows; ++r) {
    Eigen::Index k = static_cast<Eigen::Index>(indptr[static_cast<size_t>(r)]);
    const double scale = row_scale.size() ? row_scale[r] : 1.0;
    for (SparseRows::InnerIterator it(m, r); it; ++it, ++k) {
      data[k] = it.value() * scale;
      indices[k] = static_cast<int>(it.col());
    }
  }
  writeCsrParts(h5, group, data, indices, indptr, m.cols(), units, linked ? shared.group : "");
}

void writeCsr(Hdf5Writer& h5, const std::string& group, const Eigen::MatrixXd& m, const std::string& units) {
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

void writeNetworkMatrix(Hdf5Writer& h5, const std::string& name, const SparseRows& m, const std::string& units,
                        bool dense, const Eigen::VectorXd& row_scale, const CsrPattern& shared) {
  if (dense) h5.writeMatrix("/network/" + name, m, units, row_scale);
  if (csrAlso(m.rows(), double(m.nonZeros()), dense)) writeCsr(h5, "/network/sparse/" + name, m, units, row_scale, shared);
  if (!dense) h5.link("/network/sparse/" + name, "/network/" + name);
}

void writeNetworkMatrix(Hdf5Writer& h5, const std::string& name, const Eigen::MatrixXd& m, const std::string& units,
                        bool dense) {
  if (dense) h5.writeMatrix("/network/" + name, m, units);
  // Held dense: a network with 25 % or more of F non-zero (policy::storeSparse).
  if (csrAlso(m.rows(), double(m.size()), dense)) writeCsr(h5, "/network/sparse/" + name, m, units);
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
    writeCsr(h5, factors + "/direct", ex.direct, "m^2", {}, shared);
    h5.writeMatrix(factors + "/basis", ex.basis, "1");
    h5.writeMatrix(factors + "/core", ex.core, "m^2");
  } else {  // held whole: GR is its own direct part, k = 0
    writeCsr(h5, factors + "/direct", ex.gr, "m^2");
    h5.writeMatrix(factors + "/basis", Eigen::MatrixXd(n, 0), "1");
    h5.writeMatrix(factors + "/core", Eigen::MatrixXd(0, 0), "m^2");
  }
  h5.attribute(factors, "formula", std::string("GR = direct + basis @ core @ basis.T"));
  h5.attribute(factors, "rank", static_cast<long long>(ex.factored() ? ex.core.rows() : 0));
  h5.attribute(factors, "method", ex.method);
  if (!dense) h5.link(factors, prefix + "radiative_exchange");  // the name finds GR at every size
}

}  // namespace radnet::cases
