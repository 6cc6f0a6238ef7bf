#include "cases/output/expectations.hpp"

#include "cases/pipeline/case_merge.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <ostream>

namespace radnet::cases {
namespace {

using Q = ExpectQuantity;

// A temperature of any thermal node (lumped ones too) at output `index` (default the first).
std::optional<double> lookupTemperature(const ThermalSolution& thermal, const Expectation& x) {
  const int p = std::max(0, x.index);
  if (x.quantity != Q::Temperature || p >= thermal.temperature().cols()) return std::nullopt;
  const auto& names = thermal.node_names;
  const auto it = std::find(names.begin(), names.end(), x.node);
  if (it == names.end()) return std::nullopt;
  return thermal.temperature()(it - names.begin(), p);
}

// Quantities both case forms have: view factors, exchange factors, eigenvalues, temperatures.
std::optional<double> lookupShared(const RadiativeNetwork& radiative, const std::optional<ThermalSolution>& thermal,
                                   const Expectation& x) {
  const solver::Network& net = *radiative.network;
  const int i = x.node.empty() ? -1 : net.indexOf(x.node);
  const int j = x.to.empty() ? -1 : net.indexOf(x.to);
  switch (x.quantity) {
    case Q::ViewFactor: return net.conductance(i, j) / net.area()[i];
    case Q::SpaceViewFactor: return net.spaceViewFactor()[i];
    case Q::Eigenvalue:
      if (x.index >= radiative.pairs.rank()) return std::nullopt;
      return radiative.pairs.values[x.index];
    case Q::RadiativeExchange:
      if (!radiative.exchange) return std::nullopt;
      return radiative.exchange->entry(i, j);
    case Q::GrSpace:
      if (!radiative.exchange) return std::nullopt;
      return radiative.exchange->gr_space[i];
    case Q::Temperature: return thermal ? lookupTemperature(*thermal, x) : std::nullopt;
    default: return std::nullopt;
  }
}

}  // namespace

std::optional<double> lookupResult(const NetworkRunResult& r, const Expectation& x) {
  const int i = x.node.empty() ? -1 : r.radiative.network->indexOf(x.node);
  if (x.quantity == Q::Exitance) return r.solution.exitance(i, 0);
  if (x.quantity == Q::Irradiance) return r.solution.irradiance(i, 0);
  return lookupShared(r.radiative, r.thermal, x);
}

std::optional<double> lookupResult(const ImportRunResult& r, const Expectation& x) {
  return lookupTemperature(r.thermal, x);
}

std::optional<double> lookupResult(const GeometryRunResult& r, const Expectation& x) {
  const int i = x.node.empty() ? -1 : r.radiative.network->indexOf(x.node);
  const DesignCasesResult& c = r.cases;
  const auto at = [](const std::vector<int>& v, int k) { return v[static_cast<size_t>(k)]; };
  const bool spans = !c.position_start.empty() && x.design_case + 1 < static_cast<int>(c.position_start.size());
  if ((x.quantity == Q::OrbitMeanAbsorbed || x.quantity == Q::OrbitMaxAbsorbedSolar) && r.sweep && spans) {
    // The design case's positions; its orbit mean is time-weighted (the periodic trapezoid per
    // orbit case), as the console, the report and /solution/case_temperature_mean are.
    const int k = x.design_case, first = at(c.position_start, k), count = at(c.position_start, k + 1) - first;
    if (x.quantity == Q::OrbitMaxAbsorbedSolar) return r.sweep->absorbed_solar.row(i).segment(first, count).maxCoeff();
    std::vector<double> times;
    for (const auto& p : r.sweep->positions) times.push_back(p.t_s);
    const Eigen::VectorXd w = timeWeights(&*r.sweep, times, count, at(c.orbit_case_start, k), at(c.orbit_case_start, k + 1));
    return r.sweep->absorbed_total.row(i).segment(first, count).dot(w);
  }
  if (x.quantity == Q::OrbitMeanAbsorbed || x.quantity == Q::OrbitMaxAbsorbedSolar) return std::nullopt;
  if ((x.quantity == Q::RadiativeExchange || x.quantity == Q::GrSpace) && x.case_given &&
      x.design_case < static_cast<int>(c.optics.size())) {  // the GR of the case's optical set
    const auto set = std::find(c.optics_names.begin(), c.optics_names.end(), c.optics[static_cast<size_t>(x.design_case)]);
    const auto k = set - c.optics_names.begin();
    if (k > 0 && static_cast<size_t>(k) <= c.optics_exchange.size()) {
      const solver::ExchangeFactors& ex = c.optics_exchange[static_cast<size_t>(k) - 1];
      const int j = x.to.empty() ? -1 : r.radiative.network->indexOf(x.to);
      return x.quantity == Q::GrSpace ? ex.gr_space[i] : ex.entry(i, j);
    }
  }
  if (x.quantity == Q::Temperature && x.case_given && spans) {  // index: the position within the design case
    Expectation global = x;
    global.index = at(c.position_start, x.design_case) + std::max(0, x.index);
    if (global.index >= at(c.position_start, x.design_case + 1)) return std::nullopt;
    return lookupShared(r.radiative, r.thermal, global);
  }
  return lookupShared(r.radiative, r.thermal, x);
}

int evaluateExpectations(const std::vector<Expectation>& expectations, const ResultLookup& lookup, std::ostream& out) {
  int failed = 0;
  for (const auto& x : expectations) {
    const std::optional<double> got = lookup(x);
    std::string label(toString(x.quantity));
    if (!x.node.empty()) label += " " + x.node;
    if (!x.to.empty()) label += " -> " + x.to;
    if (x.index >= 0) label += " #" + std::to_string(x.index);
    const bool ok = got && std::isfinite(*got) && std::abs(*got - x.value) <= x.tolerance;
    if (!ok) ++failed;
    out << (ok ? "PASS " : "FAIL ") << std::left << std::setw(40) << label << " expected " << std::setprecision(10)
        << x.value << " ± " << x.tolerance << ", got ";
    if (got)
      out << *got << " (error " << std::abs(*got - x.value) << ")";
    else
      out << "nothing (the run has no such result)";
    out << "  [" << x.where << "]\n";
  }
  return failed;
}

}  // namespace radnet::cases
