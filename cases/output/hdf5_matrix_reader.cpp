#include "cases/output/hdf5_matrix_reader.hpp"

#include "cases/config/errors.hpp"

#include <cmath>
#include <vector>

namespace radnet::cases {
namespace {

[[noreturn]] void malformed(const Hdf5Reader& h5, const std::string& path, const std::string& what) {
  throw InputError(h5.path(), 0, 0, path + ": " + what + " (not a result radnet wrote, or a damaged one)");
}

std::string shapeOf(Eigen::Index rows, Eigen::Index cols) { return std::to_string(rows) + " × " + std::to_string(cols); }

Eigen::MatrixXd finiteMatrix(const Hdf5Reader& h5, const std::string& path) {
  if (!h5.has(path)) malformed(h5, path, "missing");
  Eigen::MatrixXd m = h5.matrix(path);
  if (!m.allFinite()) malformed(h5, path, "holds a value that is not finite");
  return m;
}

}  // namespace

SparseRows readCsr(const Hdf5Reader& h5, const std::string& group, Eigen::Index rows, Eigen::Index cols) {
  const Eigen::VectorXd data = finiteMatrix(h5, group + "/data").reshaped();
  const Eigen::VectorXd indices = finiteMatrix(h5, group + "/indices").reshaped();
  const Eigen::VectorXd indptr = finiteMatrix(h5, group + "/indptr").reshaped();
  const Eigen::Index nnz = data.size();
  if (indices.size() != nnz) malformed(h5, group + "/indices", std::to_string(indices.size()) + " indices for " + std::to_string(nnz) + " values");
  if (indptr.size() != rows + 1 || indptr[0] != 0 || indptr[rows] != static_cast<double>(nnz))
    malformed(h5, group + "/indptr", "not " + std::to_string(rows + 1) + " row starts from 0 to " + std::to_string(nnz));
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<size_t>(nnz));
  for (Eigen::Index r = 0; r < rows; ++r) {
    if (!(indptr[r + 1] >= indptr[r]) || indptr[r + 1] != std::floor(indptr[r + 1]))
      malformed(h5, group + "/indptr", "decreases or is not whole at row " + std::to_string(r));
    for (auto k = static_cast<Eigen::Index>(indptr[r]); k < static_cast<Eigen::Index>(indptr[r + 1]); ++k) {
      const double c = indices[k];
      if (!(c >= 0 && c < static_cast<double>(cols) && c == std::floor(c)))
        malformed(h5, group + "/indices", "holds column " + std::to_string(c) + " of a matrix of " + std::to_string(cols) + " columns");
      entries.emplace_back(static_cast<int>(r), static_cast<int>(c), data[k]);
    }
  }
  SparseRows m(rows, cols);
  m.setFromTriplets(entries.begin(), entries.end());  // a repeated (row, column) is summed, as scipy does
  return m;
}

bool hasExchange(const Hdf5Reader& h5, const std::string& prefix) {
  return h5.has(prefix + "gr_space") &&
         (h5.has(prefix + "radiative_exchange") || h5.has(prefix + "radiative_exchange_factors/direct/data"));
}

namespace {
// The (n,n) dataset, not the factors' group that the name links to without one.
bool hasDenseExchange(const Hdf5Reader& h5, const std::string& prefix) {
  return h5.has(prefix + "radiative_exchange") && !h5.has(prefix + "radiative_exchange/direct");
}
}  // namespace

solver::ExchangeFactors readExchange(const Hdf5Reader& h5, const std::string& prefix) {
  solver::ExchangeFactors ex;
  ex.gr_space = finiteMatrix(h5, prefix + "gr_space").reshaped();
  const Eigen::Index n = ex.gr_space.size();
  if (hasDenseExchange(h5, prefix)) {
    ex.gr = finiteMatrix(h5, prefix + "radiative_exchange");
    if (ex.gr.rows() != n || ex.gr.cols() != n)
      malformed(h5, prefix + "radiative_exchange", "shape " + shapeOf(ex.gr.rows(), ex.gr.cols()) + " for " + std::to_string(n) + " values of " + prefix + "gr_space");
    ex.method = h5.textAttribute(prefix + "radiative_exchange", "method", "");
    return ex;
  }
  const std::string factors = prefix + "radiative_exchange_factors";
  ex.direct = readCsr(h5, factors + "/direct", n, n);
  ex.basis = finiteMatrix(h5, factors + "/basis");
  ex.core = finiteMatrix(h5, factors + "/core");
  // A basis of k = 0 columns reads back as (n × 0) or as nothing at all.
  if (ex.basis.size() == 0) ex.basis.resize(n, 0);
  if (ex.core.size() == 0) ex.core.resize(0, 0);
  const Eigen::Index k = ex.basis.cols();
  if (ex.basis.rows() != n) malformed(h5, factors + "/basis", "shape " + shapeOf(ex.basis.rows(), k) + " for " + std::to_string(n) + " nodes");
  if (ex.core.rows() != k || ex.core.cols() != k)
    malformed(h5, factors + "/core", "shape " + shapeOf(ex.core.rows(), ex.core.cols()) + " for a basis of " + std::to_string(k) + " columns");
  ex.method = h5.textAttribute(factors, "method", "");
  ex.from_pairs = k > 0;
  if (n == 0) ex.gr.resize(0, 0);
  return ex;
}

}  // namespace radnet::cases
