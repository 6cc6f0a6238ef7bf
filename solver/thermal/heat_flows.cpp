// The heat balance of a solution split by kind, per node and position.
#include "solver/thermal/optics.hpp"
#include "solver/thermal/temperatures.hpp"
#include "solver/units.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace radnet::solver {

Eigen::VectorXd heatBalance(const ThermalNetwork& net, const Eigen::VectorXd& t, const Eigen::VectorXd& q_env) {
  return netHeat(net, t, q_env + net.dissipation);
}

namespace {

// Exchange with space and with the other nodes at each position: the network's own GR (dense
// or factored) until a position brings another (optics that follow temperature, turning
// parts: always dense).
void radiativeFlows(const ThermalNetwork& net, const ThermalResult& solution, const Eigen::MatrixXd& t4,
                    const std::vector<const ExchangeUpdate*>& exchange_per_position, HeatFlows& f) {
  using units::kStefanBoltzmann;
  const Eigen::Index P = t4.cols();
  const bool per_position = net.optics && solution.emissivity.cols() == P;
  ExchangeUpdate other;
  const ExchangeUpdate *gr = nullptr, *turned = nullptr;
  Eigen::VectorXd gr_emissivity, gr_row = net.exchangeRowSum();
  for (Eigen::Index p = 0; p < P; ++p) {
    const ExchangeUpdate* at = static_cast<Eigen::Index>(exchange_per_position.size()) == P
                                   ? exchange_per_position[static_cast<size_t>(p)] : nullptr;
    if (at && at != turned) {  // this position's arrangement of turning parts
      gr = turned = at;
      gr_row = gr->gr.rowwise().sum();
    }
    if (per_position && (gr_emissivity.size() == 0 || gr_emissivity != solution.emissivity.col(p))) {
      gr_emissivity = solution.emissivity.col(p);
      other = net.optics->exchange(gr_emissivity);
      gr = &other;
      gr_row = gr->gr.rowwise().sum();
    }
    const Eigen::VectorXd& gr_space = gr ? gr->gr_space : net.gr_space;
    const Eigen::VectorXd exchanged = gr ? Eigen::VectorXd(gr->gr * t4.col(p)) : net.exchangeTimes(t4.col(p));
    f.emitted.col(p) = -kStefanBoltzmann * gr_space.cwiseProduct((t4.col(p).array() - std::pow(net.space_temperature, 4)).matrix());
    f.radiative.col(p) = kStefanBoltzmann * (exchanged - gr_row.cwiseProduct(t4.col(p)));
  }
}

}  // namespace

HeatFlows heatFlows(const ThermalNetwork& net, const ThermalResult& solution, const Eigen::MatrixXd& q_env,
                    const std::vector<const ExchangeUpdate*>& exchange_per_position) {
  using units::kStefanBoltzmann;
  const Eigen::MatrixXd& t = solution.temperature;
  const Eigen::Index n = t.rows(), P = t.cols(), H = static_cast<Eigen::Index>(net.heaters.size());
  if (q_env.rows() != n || q_env.cols() != P || solution.temperature_rate.rows() != n ||
      solution.temperature_rate.cols() != P || solution.rate_roundoff.rows() != n ||
      solution.rate_roundoff.cols() != P || net.size() != n || solution.dissipation.rows() != n ||
      solution.dissipation.cols() != P || solution.heater_power.rows() != H || solution.heater_power.cols() != P)
    throw std::invalid_argument("heat flows: temperatures, rates, dissipations and loads need (n × P) entries");
  const Eigen::MatrixXd t4 = t.array().square().square().matrix();
  HeatFlows f;
  f.emitted.resize(n, P);
  f.radiative.resize(n, P);
  radiativeFlows(net, solution, t4, exchange_per_position, f);
  f.conducted.resize(n, P);
  f.stored.resize(n, P);
  f.roundoff.resize(n, P);
  for (Eigen::Index p = 0; p < P; ++p) {
    f.conducted.col(p) = conductedHeat(net, t.col(p));
    const Eigen::VectorXd c = capacitanceAt(net, t.col(p));
    f.stored.col(p) = -c.cwiseProduct(solution.temperature_rate.col(p));
    f.roundoff.col(p) = c.cwiseProduct(solution.rate_roundoff.col(p)) + balanceRoundOff(net, t.col(p));
  }
  f.dissipation = solution.dissipation;
  f.heater = Eigen::MatrixXd::Zero(n, P);
  for (Eigen::Index k = 0; k < H; ++k) f.heater.row(net.heaters[static_cast<size_t>(k)].node) += solution.heater_power.row(k);
  f.boundary = Eigen::MatrixXd::Zero(n, P);
  const Eigen::MatrixXd gross = q_env.cwiseAbs() + f.emitted.cwiseAbs() + f.radiative.cwiseAbs() +
                                f.conducted.cwiseAbs() + f.dissipation.cwiseAbs() + f.heater.cwiseAbs() +
                                f.stored.cwiseAbs();
  f.roundoff += 16 * std::numeric_limits<double>::epsilon() * gross;
  for (Eigen::Index i = 0; i < n; ++i)
    if (net.isFixed(i)) {  // its temperature does not move: it stores nothing, the boundary supplies the rest
      f.stored.row(i).setZero();
      f.boundary.row(i) = -(q_env.row(i) + f.emitted.row(i) + f.radiative.row(i) + f.conducted.row(i) +
                            f.dissipation.row(i) + f.heater.row(i));
    }
  return f;
}

}  // namespace radnet::solver
