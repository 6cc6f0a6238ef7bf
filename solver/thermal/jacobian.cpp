#include "solver/thermal/jacobian.hpp"

#include "solver/thermal/newton.hpp"
#include "solver/units.hpp"

#include <Eigen/LU>
#include <Eigen/SparseLU>
#include <unsupported/Eigen/IterativeSolvers>

#include <limits>
#include <vector>

namespace radnet::solver::detail {
namespace {

using units::kStefanBoltzmann;
using Triplets = std::vector<Eigen::Triplet<double>>;

// Rows of boundary nodes are T_i = T_fixed: the identity.
bool fixedRow(const ImplicitSystem& s, Eigen::Index i) { return i < s.net.size() && s.net.isFixed(i); }

Eigen::MatrixXd denseJacobian(const ImplicitSystem& s, const Eigen::VectorXd& t, Eigen::Index a) {
  const ThermalNetwork& net = s.net;
  const Eigen::Index n = t.size();
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(n + a, n + a);
  j.topLeftCorner(n, n) = -s.hb * netHeatJacobian(net, t);
  if (s.transient)
    j.topLeftCorner(n, n).diagonal() +=
        capacitanceAt(net, t) + capacitanceSlope(net, t).cwiseProduct(t - s.history);
  for (Eigen::Index k = 0; k < a; ++k) {
    const Heater& h = net.heaters[static_cast<size_t>(s.controlled[static_cast<size_t>(k)])];
    j(h.node, n + k) = -s.hb;
    j(n + k, h.sensor) = 1.0;
  }
  for (Eigen::Index i = 0; i < n; ++i)
    if (net.isFixed(i)) {
      j.row(i).setZero();
      j(i, i) = 1.0;
    }
  return j;
}

// The conductive skeleton's entries of J (the conduction Jacobian times −hβ; the controlled
// heaters' columns and rows) as add(row, column, value).
template <class Add>
void skeletonEntries(const ImplicitSystem& s, const Eigen::VectorXd& t, Eigen::Index a, const Add& add) {
  const ThermalNetwork& net = s.net;
  const Eigen::Index n = t.size();
  conductionJacobianEntries(net, t, [&](Eigen::Index r, Eigen::Index c, double v) { add(r, c, -s.hb * v); });
  for (Eigen::Index k = 0; k < a; ++k) {
    const Heater& h = net.heaters[static_cast<size_t>(s.controlled[static_cast<size_t>(k)])];
    add(h.node, n + k, -s.hb);
    add(n + k, h.sensor, 1.0);
  }
}

}  // namespace

// J = S + U Vᵀ of a network whose GR is factored (jacobian.hpp).
class FactoredJacobian {
 public:
  FactoredJacobian(const ImplicitSystem& s, const Eigen::VectorXd& t, Eigen::Index a);
  Eigen::Index rows() const { return sparse_.rows(); }
  Eigen::VectorXd operator*(const Eigen::VectorXd& x) const {
    return sparsePlusLowRankTimes(sparse_, low_u_, Eigen::MatrixXd(), low_v_, x);
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

 private:
  // The preconditioner as Eigen's GMRES calls it.
  struct Skeleton {
    const Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>>* lu;
    Eigen::VectorXd solve(const Eigen::VectorXd& b) const { return lu->solve(b); }
  };
  Eigen::SparseMatrix<double, Eigen::RowMajor> sparse_;  // S
  Eigen::MatrixXd low_u_, low_v_;                        // U, V (N×k)
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> skeleton_;
  bool singular_ = false;
};

FactoredJacobian::FactoredJacobian(const ImplicitSystem& s, const Eigen::VectorXd& t, Eigen::Index a) {
  const ThermalNetwork& net = s.net;
  const FactoredExchange& gr = *net.gr_factored;
  const Eigen::Index n = t.size(), N = n + a;
  const Eigen::VectorXd t3 = t.array().cube();
  // ∂G/∂T's radiative part: 4σ (GR − diag(Σ_j GR_ij + GR_space)) diag(T³); J = −hβ ∂G/∂T + ….
  const double w = -s.hb * 4 * kStefanBoltzmann;
  Eigen::VectorXd diagonal = -w * t3.cwiseProduct(net.exchangeRowSum() + net.gr_space);
  if (s.transient) diagonal += capacitanceAt(net, t) + capacitanceSlope(net, t).cwiseProduct(t - s.history);
  Triplets skeleton, radiative;
  auto add = [&](Triplets& to, Eigen::Index r, Eigen::Index c, double v) {
    if (fixedRow(s, r)) return;
    if (r == c && r < n) diagonal[r] += v;
    else to.emplace_back(static_cast<int>(r), static_cast<int>(c), v);
  };
  for (Eigen::Index i = 0; i < gr.direct.outerSize(); ++i)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(gr.direct, i); it; ++it)
      add(radiative, i, it.col(), w * it.value() * t3[it.col()]);
  skeletonEntries(s, t, a, [&](Eigen::Index r, Eigen::Index c, double v) { add(skeleton, r, c, v); });
  // The reflected part U Vᵀ: U = −hβ 4σ W K (boundary and heater rows 0), Vᵀ = Wᵀ diag(T³).
  const Eigen::Index k = gr.rank();
  low_u_ = Eigen::MatrixXd::Zero(N, k);
  low_v_ = Eigen::MatrixXd::Zero(N, k);
  if (k > 0) {
    low_u_.topRows(n).noalias() = w * (gr.basis * gr.core);
    low_v_.topRows(n) = t3.asDiagonal() * gr.basis;
    for (Eigen::Index i = 0; i < n; ++i)
      if (net.isFixed(i)) low_u_.row(i).setZero();
    diagonal += low_u_.topRows(n).cwiseProduct(low_v_.topRows(n)).rowwise().sum();
  }
  for (Eigen::Index i = 0; i < n; ++i)
    if (net.isFixed(i)) diagonal[i] = 1.0;
  Triplets all = skeleton;
  for (Eigen::Index i = 0; i < n; ++i) skeleton.emplace_back(static_cast<int>(i), static_cast<int>(i), diagonal[i]);
  // J's diagonal already holds the low-rank part's; S carries it without (U Vᵀ adds it back).
  Eigen::VectorXd s_diagonal = diagonal;
  if (k > 0)
    for (Eigen::Index i = 0; i < n; ++i)
      if (!net.isFixed(i)) s_diagonal[i] -= low_u_.row(i).dot(low_v_.row(i));
  for (Eigen::Index i = 0; i < n; ++i) all.emplace_back(static_cast<int>(i), static_cast<int>(i), s_diagonal[i]);
  all.insert(all.end(), radiative.begin(), radiative.end());
  sparse_.resize(N, N);
  sparse_.setFromTriplets(all.begin(), all.end());
  Eigen::SparseMatrix<double> p(N, N);
  p.setFromTriplets(skeleton.begin(), skeleton.end());
  skeleton_.analyzePattern(p);
  skeleton_.factorize(p);
  singular_ = skeleton_.info() != Eigen::Success;
}

Eigen::VectorXd FactoredJacobian::solve(const Eigen::VectorXd& b) const {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size());
  if (singular_) return Eigen::VectorXd::Constant(b.size(), std::numeric_limits<double>::quiet_NaN());
  Eigen::Index iterations = kJacobianMaxIterations;
  double tolerance = kJacobianRelativeResidual;
  // Eigen's GMRES (unsupported/IterativeSolvers) called on the operator directly: it needs
  // only rows(), J * x and the preconditioner's solve().
  Eigen::internal::gmres(*this, b, x, Skeleton{&skeleton_}, iterations, Eigen::Index{kJacobianRestart}, tolerance);
  return x;
}

JacobianSolver::JacobianSolver(const ImplicitSystem& s, const Eigen::VectorXd& t, Eigen::Index controlled) {
  if (s.net.gr_factored) factored_ = std::make_shared<const FactoredJacobian>(s, t, controlled);
  else lu_ = std::make_shared<const Eigen::PartialPivLU<Eigen::MatrixXd>>(denseJacobian(s, t, controlled));
}

Eigen::VectorXd JacobianSolver::solve(const Eigen::VectorXd& b) const {
  if (factored_) return factored_->solve(b);
  return lu_->solve(b);
}

}  // namespace radnet::solver::detail
