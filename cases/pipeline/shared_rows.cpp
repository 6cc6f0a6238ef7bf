#include "cases/pipeline/shared_rows.hpp"

#include "cases/cluster/cluster.hpp"
#include "solver/radiative/uncertainty.hpp"

#include <algorithm>

namespace radnet::cases {

bool sharesRows(const GeometryCase& c) {
  const auto n = static_cast<long>(c.scene.nodes().size());
  const bool own_optics = std::any_of(c.optical_sets.begin(), c.optical_sets.end(),
                                      [](const OpticalSet& set) { return set.own_specular; });
  return cluster::distributed() && n >= kSharedRowsMinNodes && !c.hasSpecular() && c.articulation.empty() &&
         !own_optics && !c.thermal && !c.optical_uncertainty && !c.output.dense_matrices.value_or(false) &&
         !c.output.dense_exchange_factors.value_or(false);
}

solver::RowShare clusterRowShare() {
  solver::RowShare share;
  share.part = cluster::rank();
  share.parts = cluster::size();
  share.join = [](double* data, std::size_t count) { cluster::join(data, count); };
  share.max = [](double* data, std::size_t count) { cluster::max(data, count); };
  share.exchange = [](const std::vector<std::vector<double>>& send) { return cluster::exchange(send); };
  return share;
}

void keepHeldRows(Eigen::SparseMatrix<double, Eigen::RowMajor>& m, const solver::RowShare& share) {
  if (share.whole()) return;
  using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;
  const Eigen::Index n = m.outerSize();
  std::vector<int> outer(static_cast<size_t>(n) + 1, 0);
  Eigen::Index nnz = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    outer[static_cast<size_t>(i)] = static_cast<int>(nnz);
    if (share.holds(i)) nnz += m.innerVector(i).nonZeros();
  }
  outer[static_cast<size_t>(n)] = static_cast<int>(nnz);
  RowSparse held(m.rows(), m.cols());
  held.resizeNonZeros(nnz);
  std::copy(outer.begin(), outer.end(), held.outerIndexPtr());
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!share.holds(i)) continue;
    Eigen::Index at = outer[static_cast<size_t>(i)];
    for (RowSparse::InnerIterator it(m, i); it; ++it, ++at) {
      held.innerIndexPtr()[at] = static_cast<int>(it.col());
      held.valuePtr()[at] = it.value();
    }
  }
  m.swap(held);
}

void keepHeldRows(geometry::ViewFactorEstimate& estimate, const solver::RowShare& share) {
  keepHeldRows(estimate.view_factors, share);
  keepHeldRows(estimate.standard_error, share);
}

void joinHeldRowVectors(geometry::ViewFactorResult& vf) {
  for (Eigen::VectorXd* v : {&vf.space, &vf.space_error, &vf.blocked, &vf.blocked_error})
    cluster::join(v->data(), static_cast<std::size_t>(v->size()));
  cluster::sum(vf.rays.data(), vf.rays.size());
  vf.total_rays = 0;
  for (std::int64_t r : vf.rays) vf.total_rays += r;
  cluster::max(&vf.seconds, 1);
}

Eigen::VectorXd rowLargestStderr(const Eigen::Ref<const Eigen::SparseMatrix<double, Eigen::RowMajor>>& sigma,
                                 const solver::RowShare& share) {
  Eigen::VectorXd out = solver::rowLargestEntries(sigma, sigma.rows());
  share.joinRows(out.data(), static_cast<std::size_t>(out.size()));
  return out;
}

}  // namespace radnet::cases
