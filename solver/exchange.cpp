#include "solver/exchange.hpp"

#include <cmath>

namespace radnet::solver {
namespace {

void finishFactors(ExchangeFactors& ex, const Network& net, const Eigen::VectorXd& emissivity) {
  const double scale = ex.gr.cwiseAbs().maxCoeff();
  ex.asymmetry = scale > 0 ? (ex.gr - ex.gr.transpose()).cwiseAbs().maxCoeff() / scale : 0.0;
  ex.gr = 0.5 * (ex.gr + ex.gr.transpose());
  // Everything node i emits (ε_i A_i per unit σT⁴) is absorbed by some node or lost to space.
  ex.gr_space = emissivity.cwiseProduct(net.area()) - ex.gr.rowwise().sum();
  if (!ex.gr.allFinite()) {
    ex.status = Status::NonFinite;
    ex.message = "exchange factors are not finite";
  }
}

}  // namespace

ExchangeFactors exchangeFactorsDense(const Network& net, const Eigen::VectorXd& emissivity) {
  checkRange(net, emissivity, "emissivity", 0.0, 1.0);
  const int n = net.size();
  const Eigen::MatrixXd g = net.denseConductance();
  const Eigen::VectorXd s = (Eigen::VectorXd::Ones(n) - emissivity).cwiseQuotient(net.area());
  const Eigen::MatrixXd lhs = Eigen::MatrixXd::Identity(n, n) - s.asDiagonal() * g;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu(lhs);
  ExchangeFactors ex;
  ex.method = "dense LU";
  // (I − S G)⁻¹ E maps emissive voltages to exitances; E G then gives the absorbed power.
  if (lu.rcond() < 1e-14) {
    ex.status = Status::Singular;
    ex.message = "I − S G is singular in the IR band (a closed cavity with ε = 0 everywhere?)";
    return ex;
  }
  const Eigen::MatrixXd x = lu.solve(Eigen::MatrixXd(emissivity.asDiagonal()));
  ex.gr = emissivity.asDiagonal() * (g * x);
  finishFactors(ex, net, emissivity);
  return ex;
}

ExchangeFactors exchangeFactorsLowRank(const Network& net, const LowRankBandSolver& ir_band,
                                       const Eigen::VectorXd& emissivity) {
  checkRange(net, emissivity, "emissivity", 0.0, 1.0);
  ExchangeFactors ex;
  ex.method = "low rank (k = " + std::to_string(ir_band.rank()) + ")";
  if (ir_band.status() != Status::Converged) {
    ex.status = ir_band.status();
    ex.message = ir_band.message();
    return ex;
  }
  // G'(I − S G')⁻¹ = V C Vᵀ, so GR = E V C Vᵀ E.
  ex.gr = emissivity.asDiagonal() * ir_band.applyCore(Eigen::MatrixXd(emissivity.asDiagonal()));
  finishFactors(ex, net, emissivity);
  return ex;
}

BandSolution irNetPower(const Network& net, const LowRankBandSolver& ir_band, const Eigen::VectorXd& emissivity,
                        const Eigen::Ref<const Eigen::MatrixXd>& temperature_k,
                        const Eigen::Ref<const Eigen::MatrixXd>& external_irradiance, double refine_tolerance,
                        Eigen::MatrixXd& net_power_w) {
  checkRange(net, emissivity, "emissivity", 0.0, 1.0);
  const int n = net.size();
  if (temperature_k.rows() != n) throw std::invalid_argument("temperatures need one row per node");
  if (!temperature_k.allFinite() || (temperature_k.array() < 0).any())
    throw std::invalid_argument("temperatures must be finite and >= 0 K");
  const Eigen::MatrixXd eb = kStefanBoltzmann * temperature_k.array().square().square().matrix();  // σT⁴
  Eigen::MatrixXd e_ext = Eigen::MatrixXd::Zero(n, temperature_k.cols());
  if (external_irradiance.size() != 0) {
    if (external_irradiance.rows() != n || external_irradiance.cols() != temperature_k.cols())
      throw std::invalid_argument("external IR irradiance must have the shape of the temperatures");
    e_ext = external_irradiance;
  }
  const Eigen::MatrixXd mo = emissivity.asDiagonal() * eb + ir_band.reflectance().asDiagonal() * e_ext;
  BandSolution sol = ir_band.solve(mo, refine_tolerance);
  if (sol.status == Status::Converged)
    net_power_w = (emissivity.cwiseProduct(net.area())).asDiagonal() * (sol.irradiance + e_ext - eb);
  return sol;
}

}  // namespace radnet::solver
