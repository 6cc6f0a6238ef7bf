#include "solver/thermal/network.hpp"

#include "solver/units.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace radnet::solver {
namespace {

using units::kStefanBoltzmann;

// The segment k of a table with temperature_k[k] ≤ t < temperature_k[k + 1]; −1 below the
// first point, size − 1 at or above the last.
long segment(const TemperatureTable& table, double t) {
  const auto& x = table.temperature_k;
  return static_cast<long>(std::upper_bound(x.begin(), x.end(), t) - x.begin()) - 1;
}

bool finitePositive(double x) { return std::isfinite(x) && x > 0; }

void validateHeater(const Heater& h, Eigen::Index n) {
  const std::string what = "heater '" + h.name + "'";
  if (h.node < 0 || h.node >= n || h.sensor < 0 || h.sensor >= n)
    throw std::invalid_argument(what + ": node or sensor index out of range");
  if (!(finitePositive(h.power_w) && finitePositive(h.on_below_k) && std::isfinite(h.off_above_k)))
    throw std::invalid_argument(what + ": power and set points must be finite and > 0");
  if (!(h.off_above_k > h.on_below_k))
    throw std::invalid_argument(what + ": off_above must lie above on_below (a thermostat needs a dead band)");
}

void validateSchedule(const DissipationSchedule& s, Eigen::Index n) {
  if (s.node < 0 || s.node >= n) throw std::invalid_argument("dissipation schedule: node index out of range");
  if (!std::isfinite(s.sunlit_w) || !std::isfinite(s.eclipse_w))
    throw std::invalid_argument("dissipation schedule: powers must be finite");
  if (s.kind == DissipationSchedule::Kind::Illumination) return;
  if (s.times_s.empty() || s.times_s.size() != s.power_w.size() || s.times_s.front() != 0.0)
    throw std::invalid_argument("dissipation table: one power per time, the first at 0 s");
  for (size_t k = 0; k < s.times_s.size(); ++k)
    if (!std::isfinite(s.power_w[k]) || !std::isfinite(s.times_s[k]) || (k > 0 && !(s.times_s[k] > s.times_s[k - 1])))
      throw std::invalid_argument("dissipation table: times must increase and powers be finite");
}

// Union–find over the nodes, joined where a link carries heat.
struct Groups {
  std::vector<int> parent;
  explicit Groups(Eigen::Index n) : parent(static_cast<size_t>(n)) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int i) {
    while (parent[static_cast<size_t>(i)] != i) i = parent[static_cast<size_t>(i)] = parent[static_cast<size_t>(parent[static_cast<size_t>(i)])];
    return i;
  }
  void join(int i, int j) { parent[static_cast<size_t>(find(i))] = find(j); }
};

using Direct = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// A factored GR's reflected part R = W K Wᵀ joins nodes that see each other only by way of
// a reflector (one of ε = 0 has no direct exchange to carry the link). Pairwise that is n²;
// by groups it is one product: R d, d the indicator of the nodes already determined, summed
// over an undetermined group, is the group's reflected exchange with them (R ≥ 0, so the sum
// is significant exactly when some link is). Below 1e-9 of the strongest node coupling it is
// the factors' round-off (blocks of a network that never meet leave R_AB at round-off).
void determineThroughReflections(const FactoredExchange& f, double w_gr, const Eigen::VectorXd& coupling,
                                 Groups& groups, std::vector<char>& determined) {
  const Eigen::Index n = f.size();
  if (f.rank() == 0 || n == 0) return;
  const double floor = 1e-9 * coupling.maxCoeff();
  for (bool changed = true; changed;) {
    changed = false;
    Eigen::VectorXd d(n);
    for (Eigen::Index i = 0; i < n; ++i) d[i] = determined[static_cast<size_t>(groups.find(static_cast<int>(i)))];
    if (d.sum() == 0 || d.sum() == n) return;
    const Eigen::VectorXd to_determined = f.reflectedTimes(d);
    std::vector<double> group_sum(static_cast<size_t>(n), 0.0);
    for (Eigen::Index i = 0; i < n; ++i)
      if (d[i] == 0) group_sum[static_cast<size_t>(groups.find(static_cast<int>(i)))] += to_determined[i];
    for (Eigen::Index g = 0; g < n; ++g)
      if (w_gr * group_sum[static_cast<size_t>(g)] > floor) determined[static_cast<size_t>(g)] = 1, changed = true;
  }
}

}  // namespace

double TemperatureTable::at(double t) const {
  const long k = segment(*this, t), last = static_cast<long>(value.size()) - 1;
  if (k < 0) return value.front();
  if (k >= last) return value.back();
  const size_t a = static_cast<size_t>(k);
  const double w = (t - temperature_k[a]) / (temperature_k[a + 1] - temperature_k[a]);
  return (1 - w) * value[a] + w * value[a + 1];
}

double TemperatureTable::slope(double t) const {
  const long k = segment(*this, t), last = static_cast<long>(value.size()) - 1;
  if (k < 0 || k >= last) return 0.0;
  const size_t a = static_cast<size_t>(k);
  return (value[a + 1] - value[a]) / (temperature_k[a + 1] - temperature_k[a]);
}

void TemperatureTable::validate(const std::string& what) const {
  if (temperature_k.empty() || temperature_k.size() != value.size())
    throw std::invalid_argument(what + ": a table needs at least one [temperature, value] point");
  for (size_t k = 0; k < value.size(); ++k) {
    if (!finitePositive(temperature_k[k]) || !(std::isfinite(value[k]) && value[k] >= 0))
      throw std::invalid_argument(what + ": table temperatures must be finite and > 0 K, values finite and >= 0");
    if (k > 0 && !(temperature_k[k] > temperature_k[k - 1]))
      throw std::invalid_argument(what + ": table temperatures must increase");
  }
}

double DissipationSchedule::at(double t, double sunlit_fraction, double period) const {
  if (kind == Kind::Illumination) return eclipse_w + sunlit_fraction * (sunlit_w - eclipse_w);
  if (kind == Kind::Interpolated) return interpolateHeld(times_s, power_w, t);
  const double tau = period > 0 ? t - period * std::floor(t / period) : t;
  const auto it = std::upper_bound(times_s.begin(), times_s.end(), tau);
  return it == times_s.begin() ? power_w.front() : power_w[static_cast<size_t>(it - times_s.begin()) - 1];
}

double interpolateHeld(const std::vector<double>& x, const std::vector<double>& y, double at) {
  const auto hi = std::upper_bound(x.begin(), x.end(), at);
  if (hi == x.begin()) return y.front();
  if (hi == x.end()) return y.back();
  const size_t k = static_cast<size_t>(hi - x.begin());
  const double w = (at - x[k - 1]) / (x[k] - x[k - 1]);
  return (1 - w) * y[k - 1] + w * y[k];
}

double BoundarySchedule::at(double t_s) const { return interpolateHeld(times_s, temperature_k, t_s); }

bool ThermalNetwork::isFixed(Eigen::Index i) const { return !std::isnan(fixed_temperature[i]); }

Eigen::VectorXd ThermalNetwork::exchangeTimes(const Eigen::VectorXd& x) const {
  return gr_factored ? gr_factored->times(x) : Eigen::VectorXd(gr * x);
}

Eigen::VectorXd ThermalNetwork::exchangeRowSum() const {
  return gr_factored ? gr_factored->rowSum() : Eigen::VectorXd(gr.rowwise().sum());
}

Eigen::MatrixXd ThermalNetwork::exchangeDense() const { return gr_factored ? gr_factored->dense() : gr; }

void ThermalNetwork::validate() const {
  const Eigen::Index n = size();
  if (gr_factored) {
    const FactoredExchange& f = *gr_factored;
    if (gr.size() != 0 || f.direct.cols() != n || f.basis.rows() != n || f.core.rows() != f.rank() ||
        f.core.cols() != f.rank())
      throw std::invalid_argument("thermal network: a factored GR needs D (n×n), W (n×k) and K (k×k), and no dense GR");
    if (!f.basis.allFinite() || !f.core.allFinite() ||
        !Eigen::Map<const Eigen::VectorXd>(f.direct.valuePtr(), f.direct.nonZeros()).allFinite())
      throw std::invalid_argument("exchange factors and dissipations must be finite");
  } else if (gr.cols() != n || !gr.allFinite()) {
    throw std::invalid_argument("thermal network: GR must be square (n×n) and finite");
  }
  if (gr_space.size() != n || capacitance.size() != n || dissipation.size() != n ||
      fixed_temperature.size() != n || conductors.rows() != n || conductors.cols() != n)
    throw std::invalid_argument("thermal network: every per-node array needs " + std::to_string(n) + " entries");
  if (!(std::isfinite(space_temperature) && space_temperature >= 0))
    throw std::invalid_argument("space temperature must be finite and >= 0 K");
  if ((capacitance.array() < 0).any() || !capacitance.allFinite())
    throw std::invalid_argument("capacitances must be finite and >= 0 J/K");
  if (!gr_space.allFinite() || !dissipation.allFinite())
    throw std::invalid_argument("exchange factors and dissipations must be finite");
  for (Eigen::Index i = 0; i < n; ++i)
    if (isFixed(i) && !finitePositive(fixed_temperature[i]))
      throw std::invalid_argument("fixed temperatures must be finite and > 0 K");
  for (const BoundarySchedule& b : boundary_schedules) {
    bool increasing = !b.times_s.empty() && b.times_s.size() == b.temperature_k.size();
    for (size_t k = 0; increasing && k < b.times_s.size(); ++k)
      increasing = std::isfinite(b.times_s[k]) && finitePositive(b.temperature_k[k]) &&
                   (k == 0 || b.times_s[k] > b.times_s[k - 1]);
    if (b.node < 0 || b.node >= n || !isFixed(b.node) || !increasing)
      throw std::invalid_argument("boundary schedule: a boundary node, increasing times and temperatures > 0 K");
  }
  for (const auto& [i, table] : capacitance_tables) {
    if (i < 0 || i >= n) throw std::invalid_argument("capacitance table: node index out of range");
    table.validate("capacitance table");
  }
  for (const TabledConductor& c : tabled_conductors) {
    if (c.i < 0 || c.i >= n || c.j < 0 || c.j >= n || c.i == c.j)
      throw std::invalid_argument("tabulated conductor: needs two different nodes");
    c.conductance.validate("tabulated conductor");
  }
  for (const DissipationSchedule& s : schedules) validateSchedule(s, n);
  for (const Heater& h : heaters) {
    validateHeater(h, n);
    if (isFixed(h.node) || isFixed(h.sensor))
      throw std::invalid_argument("heater '" + h.name + "': its node and sensor must not be boundary nodes");
  }
}

Eigen::VectorXd capacitanceAt(const ThermalNetwork& net, const Eigen::VectorXd& t) {
  Eigen::VectorXd c = net.capacitance;
  for (const auto& [i, table] : net.capacitance_tables) c[i] = table.at(t[i]);
  return c;
}

Eigen::VectorXd capacitanceSlope(const ThermalNetwork& net, const Eigen::VectorXd& t) {
  Eigen::VectorXd s = Eigen::VectorXd::Zero(t.size());
  for (const auto& [i, table] : net.capacitance_tables) s[i] = table.slope(t[i]);
  return s;
}

Eigen::VectorXd dissipationAt(const ThermalNetwork& net, double t_s, double sunlit_fraction, double period_s,
                              double interpolated_at_s) {
  Eigen::VectorXd q = net.dissipation;
  for (const DissipationSchedule& s : net.schedules) {
    const bool end = s.kind == DissipationSchedule::Kind::Interpolated && std::isfinite(interpolated_at_s);
    q[s.node] += s.at(end ? interpolated_at_s : t_s, sunlit_fraction, period_s);
  }
  return q;
}

Eigen::VectorXd conductedHeat(const ThermalNetwork& net, const Eigen::VectorXd& t) {
  // Σ_j K_ij (T_j − T_i) term by term: the round-off is then relative to each difference,
  // not to K T (a 1e6 W/K joint at 300 K would otherwise lose 1e-7 W to cancellation).
  Eigen::VectorXd g = Eigen::VectorXd::Zero(t.size());
  for (int k = 0; k < net.conductors.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(net.conductors, k); it; ++it)
      g[it.row()] += it.value() * (t[it.col()] - t[it.row()]);
  for (const TabledConductor& c : net.tabled_conductors) {
    const double q = c.conductance.at(0.5 * (t[c.i] + t[c.j])) * (t[c.j] - t[c.i]);
    g[c.i] += q;
    g[c.j] -= q;
  }
  return g;
}

Eigen::VectorXd netHeat(const ThermalNetwork& net, const Eigen::VectorXd& t, const Eigen::VectorXd& q,
                        const Eigen::VectorXd* gr_row_sum) {
  const Eigen::VectorXd t4 = t.array().square().square();
  const Eigen::VectorXd gr_row = gr_row_sum ? *gr_row_sum : net.exchangeRowSum();
  return q + conductedHeat(net, t) + kStefanBoltzmann * (net.exchangeTimes(t4) - gr_row.cwiseProduct(t4)) -
         kStefanBoltzmann * net.gr_space.cwiseProduct((t4.array() - std::pow(net.space_temperature, 4)).matrix());
}

Eigen::MatrixXd netHeatJacobian(const ThermalNetwork& net, const Eigen::VectorXd& t) {
  Eigen::MatrixXd j = net.exchangeDense();
  const Eigen::VectorXd gr_row = j.rowwise().sum();
  j.diagonal() -= gr_row + net.gr_space;
  j = kStefanBoltzmann * j * (4.0 * t.array().cube()).matrix().asDiagonal();
  conductionJacobianEntries(net, t, [&](Eigen::Index r, Eigen::Index c, double v) { j(r, c) += v; });
  return j;
}

Eigen::VectorXd netHeatJacobianDiagonal(const ThermalNetwork& net, const Eigen::VectorXd& t) {
  const Eigen::VectorXd gr_diagonal = net.gr_factored ? net.gr_factored->diagonal() : Eigen::VectorXd(net.gr.diagonal());
  Eigen::VectorXd d = kStefanBoltzmann * (gr_diagonal - net.exchangeRowSum() - net.gr_space)
                                             .cwiseProduct((4.0 * t.array().cube()).matrix());
  conductionJacobianEntries(net, t, [&](Eigen::Index r, Eigen::Index c, double v) {
    if (r == c) d[r] += v;
  });
  return d;
}

Eigen::VectorXd balanceScale(const ThermalNetwork& net, const Eigen::VectorXd& t, const Eigen::VectorXd& q) {
  // What flows, term by term as the heat flows report it: applied powers, the net exchange
  // with space σ GR_space |T⁴ − T_space⁴| and with each node σ GR_ij |T_j⁴ − T_i⁴|, and each
  // conductor's |K (T_j − T_i)|. (Gross emission would hide an imbalance of a node near the
  // space temperature; its round-off is in balanceRoundOff instead.)
  const Eigen::ArrayXd t4 = t.array().square().square();
  Eigen::VectorXd s = q.cwiseAbs() + kStefanBoltzmann * net.gr_space.cwiseProduct(
                                                            (t4 - std::pow(net.space_temperature, 4)).abs().matrix());
  const Eigen::Index n = t.size();
  if (net.gr_factored) s += kStefanBoltzmann * net.gr_factored->spread(t4.matrix());
  for (Eigen::Index j = 0; j < n && !net.gr_factored; ++j)  // column by column (GR is symmetric)
    s += kStefanBoltzmann * net.gr.col(j).cwiseProduct((t4 - t4[j]).abs().matrix());
  for (int k = 0; k < net.conductors.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(net.conductors, k); it; ++it)
      s[it.row()] += std::abs(it.value() * (t[it.col()] - t[it.row()]));
  for (const TabledConductor& c : net.tabled_conductors) {
    const double flow = std::abs(c.conductance.at(0.5 * (t[c.i] + t[c.j])) * (t[c.j] - t[c.i]));
    s[c.i] += flow;
    s[c.j] += flow;
  }
  return s;
}

Eigen::VectorXd balanceRoundOff(const ThermalNetwork& net, const Eigen::VectorXd& t, const Eigen::VectorXd* gr_row_sum) {
  // A difference of nearly equal numbers is known to ε of the numbers: each conductor's
  // T_j − T_i to ε (|T_i| + |T_j|), each radiative exchange T_j⁴ − T_i⁴ to ε (T_i⁴ + T_j⁴),
  // the exchange with space to ε (T⁴ + T_space⁴). 16 ε allows for the sums.
  constexpr double kRoundOff = 16 * std::numeric_limits<double>::epsilon();
  const Eigen::VectorXd t4 = t.array().square().square();
  Eigen::VectorXd noise =
      kRoundOff * kStefanBoltzmann *
      ((gr_row_sum ? *gr_row_sum : net.exchangeRowSum()).cwiseProduct(t4) + net.exchangeTimes(t4) +
       net.gr_space.cwiseProduct((t4.array() + std::pow(net.space_temperature, 4)).matrix()));
  for (int k = 0; k < net.conductors.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(net.conductors, k); it; ++it)
      noise[it.row()] += kRoundOff * std::abs(it.value()) * (std::abs(t[it.row()]) + std::abs(t[it.col()]));
  for (const TabledConductor& c : net.tabled_conductors) {
    const double e = kRoundOff * c.conductance.at(0.5 * (t[c.i] + t[c.j])) * (std::abs(t[c.i]) + std::abs(t[c.j]));
    noise[c.i] += e;
    noise[c.j] += e;
  }
  return noise;
}

std::vector<int> undeterminedNodes(const ThermalNetwork& net, bool transient) {
  const Eigen::Index n = net.size();
  // Links compared in W/K: GR linearised at 300 K (4σT³ ≈ 6.1 W/(m² K)); a link below 1e-14
  // of the network's strongest node coupling is round-off (a 1e-6 W/K strap beside a 1e6 W/K
  // joint is 1e-12 of it, and counts).
  const double w_gr = 4 * kStefanBoltzmann * std::pow(300.0, 3);
  const Eigen::VectorXd gr_abs_row =
      net.gr_factored ? Eigen::VectorXd(net.gr_factored->direct.cwiseAbs() * Eigen::VectorXd::Ones(n) +
                                        net.gr_factored->reflectedTimes(Eigen::VectorXd::Ones(n)).cwiseAbs())
                      : Eigen::VectorXd(net.gr.cwiseAbs().rowwise().sum());
  Eigen::VectorXd coupling = w_gr * (gr_abs_row + net.gr_space.cwiseAbs());
  coupling += net.conductors.cwiseAbs() * Eigen::VectorXd::Ones(n);
  for (const TabledConductor& c : net.tabled_conductors) {
    const double k = *std::max_element(c.conductance.value.begin(), c.conductance.value.end());
    coupling[c.i] += k;
    coupling[c.j] += k;
  }
  const double floor = 1e-14 * (n > 0 ? coupling.maxCoeff() : 0.0);
  Groups groups(n);
  if (net.gr_factored) {  // the direct part here; the reflected part once the sinks are known
    const Direct& d = net.gr_factored->direct;
    for (Eigen::Index i = 0; i < d.outerSize(); ++i)
      for (Direct::InnerIterator it(d, i); it; ++it)
        if (w_gr * std::abs(it.value()) > floor) groups.join(static_cast<int>(i), static_cast<int>(it.col()));
  }
  for (Eigen::Index i = 0; i < n && !net.gr_factored; ++i)
    for (Eigen::Index j = i + 1; j < n; ++j)
      if (w_gr * std::abs(net.gr(i, j)) > floor) groups.join(static_cast<int>(i), static_cast<int>(j));
  for (int k = 0; k < net.conductors.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(net.conductors, k); it; ++it)
      if (std::abs(it.value()) > floor) groups.join(static_cast<int>(it.row()), static_cast<int>(it.col()));
  for (const TabledConductor& c : net.tabled_conductors)
    if (*std::max_element(c.conductance.value.begin(), c.conductance.value.end()) > floor) groups.join(c.i, c.j);
  // A group is determined by a sink (space, a boundary node) or, in a transient, by its heat capacity.
  std::vector<char> determined(static_cast<size_t>(n), 0);
  Eigen::VectorXd c = net.capacitance;
  for (const auto& [i, table] : net.capacitance_tables) c[i] = *std::max_element(table.value.begin(), table.value.end());
  for (Eigen::Index i = 0; i < n; ++i)
    if (w_gr * net.gr_space[i] > floor || net.isFixed(i) || (transient && c[i] > 0))
      determined[static_cast<size_t>(groups.find(static_cast<int>(i)))] = 1;
  if (net.gr_factored) determineThroughReflections(*net.gr_factored, w_gr, coupling, groups, determined);
  std::vector<int> out;
  for (Eigen::Index i = 0; i < n; ++i)
    if (!determined[static_cast<size_t>(groups.find(static_cast<int>(i)))]) out.push_back(static_cast<int>(i));
  return out;
}

}  // namespace radnet::solver
