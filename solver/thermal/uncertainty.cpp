#include "solver/thermal/uncertainty.hpp"

#include <Eigen/LU>

namespace radnet::solver {

namespace {

// (J_ff⁻¹ ∘ J_ff⁻¹) var_q over the free nodes at temperatures t, for columns of var_q.
Eigen::MatrixXd propagate(const ThermalNetwork& net, const Eigen::VectorXd& t, const Eigen::MatrixXd& var_q,
                          const std::vector<Eigen::Index>& free, bool diagonal) {
  const Eigen::Index f = static_cast<Eigen::Index>(free.size());
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(net.size(), var_q.cols());
  if (diagonal) {
    const Eigen::VectorXd jd = netHeatJacobianDiagonal(net, t);
    for (Eigen::Index a = 0; a < f; ++a) {
      const double d = jd[free[static_cast<size_t>(a)]];
      out.row(free[static_cast<size_t>(a)]) = var_q.row(free[static_cast<size_t>(a)]) / (d * d);
    }
    return out;
  }
  const Eigen::MatrixXd j = netHeatJacobian(net, t);
  Eigen::MatrixXd jf(f, f), vq(f, var_q.cols());
  for (Eigen::Index a = 0; a < f; ++a) {
    vq.row(a) = var_q.row(free[static_cast<size_t>(a)]);
    for (Eigen::Index b = 0; b < f; ++b) jf(a, b) = j(free[static_cast<size_t>(a)], free[static_cast<size_t>(b)]);
  }
  const Eigen::MatrixXd inv = jf.partialPivLu().inverse();
  const Eigen::MatrixXd vt = inv.array().square().matrix() * vq;
  for (Eigen::Index a = 0; a < f; ++a) out.row(free[static_cast<size_t>(a)]) = vt.row(a);
  return out;
}

}  // namespace

Eigen::MatrixXd temperatureStderr(const ThermalNetwork& net, const Eigen::MatrixXd& t, const Eigen::MatrixXd& var_q,
                                  const std::vector<int>& span_start, TemperaturePropagation& used) {
  const Eigen::Index n = net.size(), P = t.cols();
  std::vector<Eigen::Index> free;
  for (Eigen::Index i = 0; i < n; ++i)
    if (!net.isFixed(i)) free.push_back(i);
  used = n <= kTemperaturePerPositionMaxNodes ? TemperaturePropagation::PerPosition
         : n <= kTemperaturePerSpanMaxNodes   ? TemperaturePropagation::PerSpan
                                              : TemperaturePropagation::Diagonal;
  Eigen::MatrixXd var_t(n, P);
  if (used == TemperaturePropagation::PerPosition) {
    for (Eigen::Index p = 0; p < P; ++p) var_t.col(p) = propagate(net, t.col(p), var_q.col(p), free, false);
  } else {
    for (size_t s = 0; s + 1 < span_start.size(); ++s) {
      const Eigen::Index b = span_start[s], e = span_start[s + 1];
      const Eigen::VectorXd mean = t.middleCols(b, e - b).rowwise().mean();
      var_t.middleCols(b, e - b) =
          propagate(net, mean, var_q.middleCols(b, e - b), free, used == TemperaturePropagation::Diagonal);
    }
  }
  return var_t.cwiseMax(0.0).cwiseSqrt();
}

}  // namespace radnet::solver
