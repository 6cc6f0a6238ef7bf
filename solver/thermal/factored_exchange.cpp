#include "solver/thermal/factored_exchange.hpp"

#include "solver/parallel.hpp"

#include <algorithm>
#include <cmath>

namespace radnet::solver {

using Direct = Eigen::SparseMatrix<double, Eigen::RowMajor>;

Eigen::MatrixXd FactoredExchange::reflectedTimes(const Eigen::Ref<const Eigen::MatrixXd>& x) const {
  if (rank() == 0) return Eigen::MatrixXd::Zero(size(), x.cols());
  return basis * (core * (basis.transpose() * x));
}

Eigen::VectorXd FactoredExchange::times(const Eigen::VectorXd& x) const {
  return sparsePlusLowRankTimes(direct, basis, core, basis, x);
}

Eigen::VectorXd FactoredExchange::rowSum() const { return times(Eigen::VectorXd::Ones(size())); }

Eigen::VectorXd FactoredExchange::diagonal() const {
  Eigen::VectorXd d = direct.diagonal();
  if (rank() > 0) d += (basis * core).cwiseProduct(basis).rowwise().sum();
  return d;
}

Eigen::MatrixXd FactoredExchange::dense() const {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(size(), size());
  if (rank() > 0) out.noalias() = (basis * core) * basis.transpose();
  for (Eigen::Index i = 0; i < direct.outerSize(); ++i)
    for (Direct::InnerIterator it(direct, i); it; ++it) out(it.row(), it.col()) += it.value();
  return out;
}

Eigen::VectorXd FactoredExchange::spread(const Eigen::VectorXd& x) const {
  Eigen::VectorXd s = Eigen::VectorXd::Zero(size());
  for (Eigen::Index i = 0; i < direct.outerSize(); ++i)
    for (Direct::InnerIterator it(direct, i); it; ++it) s[i] += std::abs(it.value()) * std::abs(x[it.col()] - x[i]);
  if (rank() == 0) return s;
  // The sum is the same for x − c, any c: centred, the three terms cancel less.
  const Eigen::VectorXd xc = x.array() - x.mean();
  Eigen::MatrixXd columns(size(), 3);
  columns << Eigen::VectorXd::Ones(size()), xc, xc.cwiseAbs2();
  const Eigen::MatrixXd r = reflectedTimes(columns);  // R 1, R x, R x²
  for (Eigen::Index i = 0; i < size(); ++i) {
    const double squares = r(i, 2) - 2 * xc[i] * r(i, 1) + xc[i] * xc[i] * r(i, 0);
    s[i] += std::sqrt(std::max(0.0, r(i, 0)) * std::max(0.0, squares));
  }
  return s;
}

}  // namespace radnet::solver
