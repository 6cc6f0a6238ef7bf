#include "solver/thermal/optics.hpp"

#include <algorithm>
#include <cmath>

namespace radnet::solver {

double OpticalCurve::next(double previous, double t) const {
  if (!hysteresis()) return warming.at(t);
  const double w = warming.at(t), c = cooling.at(t);
  return std::clamp(previous, std::min(w, c), std::max(w, c));
}

void opticsAt(const TemperatureOptics& optics, const OpticsState& from, const Eigen::VectorXd& t,
              Eigen::VectorXd& emissivity, Eigen::VectorXd& absorptivity) {
  emissivity = from.emissivity;
  absorptivity = from.absorptivity;
  for (size_t k = 0; k < optics.nodes.size(); ++k) {
    const int i = optics.nodes[k];
    if (!optics.emissivity[k].warming.temperature_k.empty())
      emissivity[i] = optics.emissivity[k].next(from.emissivity[i], t[i]);
    if (!optics.absorptivity[k].warming.temperature_k.empty())
      absorptivity[i] = optics.absorptivity[k].next(from.absorptivity[i], t[i]);
  }
}

void OpticsState::start(ThermalNetwork& net, const Eigen::VectorXd& t) {
  const TemperatureOptics& optics = *net.optics;
  emissivity = optics.nominal_emissivity;
  absorptivity = optics.nominal_absorptivity;
  for (size_t k = 0; k < optics.nodes.size(); ++k) {
    const int i = optics.nodes[k];
    if (!optics.emissivity[k].warming.temperature_k.empty()) emissivity[i] = optics.emissivity[k].start(t[i]);
    if (!optics.absorptivity[k].warming.temperature_k.empty()) absorptivity[i] = optics.absorptivity[k].start(t[i]);
  }
  emissivity_in_gr = optics.nominal_emissivity;  // what the caller's GR was formed with
  exchange_updates = 0;
  refreshExchange(net, 0.0);
}

void OpticsState::follow(const TemperatureOptics& optics, const Eigen::VectorXd& t) {
  Eigen::VectorXd e, a;
  opticsAt(optics, *this, t, e, a);
  emissivity = std::move(e);
  absorptivity = std::move(a);
}

bool OpticsState::refreshExchange(ThermalNetwork& net, double step) {
  const double moved = (emissivity - emissivity_in_gr).cwiseAbs().maxCoeff();
  if (!(moved > step)) return false;
  ExchangeUpdate u = net.optics->exchange(emissivity);
  net.gr = std::move(u.gr);
  net.gr_space = std::move(u.gr_space);
  emissivity_in_gr = emissivity;
  ++exchange_updates;
  return true;
}

bool stepOptics(const OpticsState& accepted, const Eigen::VectorXd& t_predicted, ThermalNetwork& net, OpticsState& step) {
  opticsAt(*net.optics, accepted, t_predicted, step.emissivity, step.absorptivity);
  return step.refreshExchange(net, net.optics->emissivity_step);
}

Eigen::VectorXd OpticsState::loadCorrection(const TemperatureOptics& optics, const Eigen::VectorXd& q_solar,
                                            const Eigen::VectorXd& q_ir) const {
  Eigen::VectorXd dq = Eigen::VectorXd::Zero(emissivity.size());
  if (q_solar.size() == 0 && q_ir.size() == 0) return dq;
  for (const int i : optics.nodes) {
    // Nominal optics are > 0 wherever a curve is given (the case's check), so the ratios exist.
    if (q_solar.size() > 0) dq[i] += (absorptivity[i] / optics.nominal_absorptivity[i] - 1.0) * q_solar[i];
    if (q_ir.size() > 0) dq[i] += (emissivity_in_gr[i] / optics.nominal_emissivity[i] - 1.0) * q_ir[i];
  }
  return dq;
}

}  // namespace radnet::solver
