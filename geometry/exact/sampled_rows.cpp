// The exact rows and the sampled ones of method auto joined into one estimate
// (geometry/exact/view_factors.hpp).
#include "geometry/exact/view_factors.hpp"

#include <vector>

namespace radnet::geometry {

ViewFactorEstimate withSampledRows(const ViewFactorEstimate& exact, const ViewFactorEstimate& sampled,
                                   const std::vector<char>& rows) {
  using Sparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;
  auto merge = [&](const Sparse& a, const Sparse& b) {
    std::vector<Eigen::Triplet<double>> t;
    for (Eigen::Index i = 0; i < a.rows(); ++i)
      for (Sparse::InnerIterator it(rows[static_cast<size_t>(i)] ? b : a, i); it; ++it)
        t.emplace_back(static_cast<int>(i), static_cast<int>(it.col()), it.value());
    Sparse m(a.rows(), a.cols());
    m.setFromTriplets(t.begin(), t.end());
    return m;
  };
  ViewFactorEstimate out = exact;
  out.view_factors = merge(exact.view_factors, sampled.view_factors);
  out.standard_error = merge(exact.standard_error, sampled.standard_error);
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
