// The exact rows and the sampled ones of method auto joined into one estimate
// (geometry/exact/view_factors.hpp).
#include "geometry/exact/view_factors.hpp"

#include <vector>

namespace radnet::geometry {

ViewFactorEstimate withSampledRows(const ViewFactorEstimate& exact, const ViewFactorEstimate& sampled,
                                   const std::vector<char>& rows) {
  using Sparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;
  // Row i from b where it was sampled, else from a: each row is already in column order, so
  // the compressed arrays are laid out directly (no triplets, 16 B an entry, and no sort).
  auto merge = [&](const Sparse& a, const Sparse& b) {
    const Eigen::Index n = a.rows();
    auto from = [&](Eigen::Index i) -> const Sparse& { return rows[static_cast<size_t>(i)] ? b : a; };
    Eigen::Index nnz = 0;
    for (Eigen::Index i = 0; i < n; ++i)
      for (Sparse::InnerIterator it(from(i), i); it; ++it) ++nnz;
    Sparse m(n, a.cols());
    m.resizeNonZeros(nnz);
    Eigen::Index at = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      m.outerIndexPtr()[i] = static_cast<int>(at);
      for (Sparse::InnerIterator it(from(i), i); it; ++it) {
        m.innerIndexPtr()[at] = static_cast<int>(it.col());
        m.valuePtr()[at++] = it.value();
      }
    }
    m.outerIndexPtr()[n] = static_cast<int>(at);
    return m;
  };
  ViewFactorEstimate out;
  out.space = exact.space, out.space_error = exact.space_error;
  out.blocked = exact.blocked, out.blocked_error = exact.blocked_error;
  Sparse f = merge(exact.view_factors, sampled.view_factors), e = merge(exact.standard_error, sampled.standard_error);
  out.view_factors.swap(f);  // swapped: an assignment copies (Eigen 3.4)
  out.standard_error.swap(e);
  for (Eigen::Index i = 0; i < exact.space.size(); ++i)
    if (rows[static_cast<size_t>(i)]) {
      out.space[i] = sampled.space[i];
      out.space_error[i] = sampled.space_error[i];
      out.blocked[i] = sampled.blocked[i];
      out.blocked_error[i] = sampled.blocked_error[i];
    }
  return out;
}

}  // namespace radnet::geometry
