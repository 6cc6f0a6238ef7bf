#include "cases/output/export.hpp"

#include "cases/config/errors.hpp"
#include "cases/output/hdf5_matrix_reader.hpp"
#include "cases/output/hdf5_reader.hpp"

#include <algorithm>
#include <cmath>

// Reading the network to export back from a result: every dataset checked before it is used.
namespace radnet::cases {
namespace {

// A result that is not what radnet writes (damaged, edited, foreign) is refused naming the
// dataset, before any of it is used: indices, shapes and values all checked.
[[noreturn]] void malformed(const Hdf5Reader& h5, const std::string& path, const std::string& what) {
  throw InputError(h5.path(), 0, 0, path + ": " + what + " (not a result radnet wrote, or a damaged one)");
}

std::string shape(const Eigen::MatrixXd& m) { return std::to_string(m.rows()) + " × " + std::to_string(m.cols()); }

// Every value finite: a NaN or ∞ would reach a deck as a plausible number or as text.
template <class M>
const M& finite(const Hdf5Reader& h5, const std::string& path, const M& m) {
  if (!m.allFinite()) malformed(h5, path, "holds a value that is not finite");
  return m;
}

// A node index stored as a double: integral and in [0, n).
int nodeIndexAt(const Hdf5Reader& h5, const std::string& path, double value, Eigen::Index n) {
  if (!(value >= 0 && value < static_cast<double>(n) && value == std::floor(value)))
    malformed(h5, path, "holds node index " + std::to_string(value) + ", not one of the " + std::to_string(n) + " nodes");
  return static_cast<int>(value);
}

Eigen::VectorXd orZeros(const Hdf5Reader& h5, const std::string& path, Eigen::Index n) {
  if (!h5.has(path)) return Eigen::VectorXd::Zero(n);
  const Eigen::VectorXd stored = finite(h5, path, h5.vector(path));  // optics sets hold the radiative nodes only
  if (stored.size() > n) malformed(h5, path, std::to_string(stored.size()) + " values for " + std::to_string(n) + " nodes");
  Eigen::VectorXd v = Eigen::VectorXd::Zero(n);
  v.head(std::min(n, stored.size())) = stored.head(std::min(n, stored.size()));
  return v;
}

// Row p of a (P, n) dataset, or zeros when the result does not have it.
Eigen::VectorXd rowOf(const Hdf5Reader& h5, const std::string& path, int p, Eigen::Index n) {
  if (!h5.has(path)) return Eigen::VectorXd::Zero(n);
  const Eigen::MatrixXd m = h5.matrix(path);
  if (m.cols() != n) malformed(h5, path, "shape " + shape(m) + " for " + std::to_string(n) + " nodes");
  if (p >= m.rows()) throw InputError(h5.path(), 0, 0, path + " does not have position " + std::to_string(p));
  return finite(h5, path, Eigen::VectorXd(m.row(p).transpose()));
}

// Row p of a (P, n_radiative) load dataset padded to n nodes, or zeros without it.
Eigen::VectorXd loadRow(const Hdf5Reader& h5, const std::string& path, int p, Eigen::Index n) {
  Eigen::VectorXd v = Eigen::VectorXd::Zero(n);
  if (!h5.has(path)) return v;
  const Eigen::MatrixXd m = h5.matrix(path);
  if (m.cols() > n || p >= m.rows()) malformed(h5, path, "shape " + shape(m) + " for " + std::to_string(n) + " nodes");
  v.head(m.cols()) = finite(h5, path, Eigen::VectorXd(m.row(p).transpose()));
  return v;
}

// Picks the design case and the position, and the optics set whose GR the case uses.
std::string selectCase(const Hdf5Reader& h5, const ExportOptions& o, ExportedNetwork& net, int positions) {
  int first = 0, end = positions, k = 0;
  std::string optics = "base";
  if (h5.has("/cases/name")) {
    const std::vector<std::string> names = h5.strings("/cases/name");
    if (!o.design_case.empty()) {
      const auto it = std::find(names.begin(), names.end(), o.design_case);
      if (it == names.end()) {
        std::string list;
        for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
        throw InputError(h5.path(), 0, 0, "no design case '" + o.design_case + "' (the result has: " + list + ")");
      }
      k = static_cast<int>(it - names.begin());
    }
    const Eigen::VectorXd start = h5.vector("/cases/position_start");
    const std::vector<std::string> optics_of = h5.strings("/cases/optics");
    if (start.size() != static_cast<Eigen::Index>(names.size()) + 1 || optics_of.size() != names.size())
      malformed(h5, "/cases", "position_start, optics and name disagree on the number of cases");
    for (Eigen::Index i = 0; i < start.size(); ++i)
      if (!(start[i] >= 0 && start[i] <= positions && start[i] == std::floor(start[i]) && (i == 0 || start[i] >= start[i - 1])))
        malformed(h5, "/cases/position_start", "not increasing positions within the run's " + std::to_string(positions));
    first = static_cast<int>(start[k]), end = static_cast<int>(start[k + 1]);
    optics = optics_of[static_cast<size_t>(k)];
    net.design_case = names[static_cast<size_t>(k)];
  } else if (!o.design_case.empty()) {
    throw InputError(h5.path(), 0, 0, "--case '" + o.design_case + "': the result has no design cases");
  }
  net.case_first = first, net.case_end = end;
  net.position = o.position < 0 ? first : o.position;
  if (net.position < first || net.position >= end)
    throw InputError(h5.path(), 0, 0,
                     "--position " + std::to_string(net.position) + " is not a position of " +
                         (net.design_case.empty() ? "the run" : "case '" + net.design_case + "'") + " (" +
                         std::to_string(first) + " … " + std::to_string(end - 1) + ")");
  const std::string set = "/optics/" + optics + "/";
  return hasExchange(h5, set) ? set : "/network/";
}

// GR between nodes (i < j) and to space (j = n), user couplings and MLI added. GR is taken
// by blocks of rows (formed from the factors when the file holds no (n,n) GR), so a large
// network is never held whole.
void readCouplings(const Hdf5Reader& h5, const std::string& gr_group, ExportedNetwork& net, double min_gr) {
  const auto n = static_cast<Eigen::Index>(net.nodes.size());
  // An imported network has no radiative node of radnet's (its GR are couplings, below).
  const bool imported = h5.has("/meta") && !h5.textAttribute("/meta", "imported_from", "").empty();
  const bool has_exchange = !imported || hasExchange(h5, gr_group);
  const solver::ExchangeFactors exchange = has_exchange ? readExchange(h5, gr_group) : solver::ExchangeFactors{};
  const Eigen::Index nr = has_exchange ? exchange.gr_space.size() : 0;
  if (nr > n) malformed(h5, gr_group + "gr_space", std::to_string(nr) + " radiative nodes of " + std::to_string(n) + " nodes");
  std::vector<Eigen::Triplet<double>> coupled;  // the user's couplings, both ways
  if (h5.has("/thermal/coupling_nodes") && h5.vector("/thermal/coupling_gr").size()) {
    const Eigen::MatrixXd pairs = h5.matrix("/thermal/coupling_nodes");
    const Eigen::VectorXd value = finite(h5, "/thermal/coupling_gr", h5.vector("/thermal/coupling_gr"));
    if (pairs.cols() != 2 || pairs.rows() != value.size())
      malformed(h5, "/thermal/coupling_nodes", "shape " + shape(pairs) + " for " + std::to_string(value.size()) + " couplings");
    for (Eigen::Index k = 0; k < pairs.rows(); ++k) {
      const int i = nodeIndexAt(h5, "/thermal/coupling_nodes", pairs(k, 0), n);
      const int j = nodeIndexAt(h5, "/thermal/coupling_nodes", pairs(k, 1), n);
      coupled.emplace_back(i, j, value[k]), coupled.emplace_back(j, i, value[k]);
    }
  }
  Eigen::SparseMatrix<double, Eigen::RowMajor> couplings(n, n);
  couplings.setFromTriplets(coupled.begin(), coupled.end());
  // Each node's total: its GR to other nodes and to space.
  Eigen::VectorXd total = couplings * Eigen::VectorXd::Ones(n) - Eigen::VectorXd(couplings.diagonal());
  Eigen::VectorXd to_space = Eigen::VectorXd::Zero(n);
  if (nr > 0) {
    to_space.head(nr) = exchange.gr_space;
    Eigen::VectorXd diagonal(nr);
    for (Eigen::Index i = 0; i < nr; ++i) diagonal[i] = exchange.entry(i, i);
    total.head(nr) += exchange.apply(Eigen::VectorXd::Ones(nr)) - diagonal;
  }
  total += to_space;
  Eigen::VectorXd dropped = Eigen::VectorXd::Zero(n);
  const Eigen::Index block = std::max<Eigen::Index>(1, (Eigen::Index{1} << 22) / std::max<Eigen::Index>(n, 1));
  for (Eigen::Index first = 0; first < n; first += block) {
    const Eigen::Index count = std::min(block, n - first);
    Eigen::MatrixXd rows = Eigen::MatrixXd::Zero(count, n);  // rows first … of GR + couplings
    if (first < nr) rows.topLeftCorner(std::min(count, nr - first), nr) = exchange.rows(first, std::min(count, nr - first));
    for (Eigen::Index r = 0; r < count; ++r)
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(couplings, first + r); it; ++it)
        rows(r, it.col()) += it.value();
    for (Eigen::Index r = 0; r < count; ++r) {
      const Eigen::Index i = first + r;
      for (Eigen::Index j = i + 1; j < n; ++j) {
        const double g = rows(r, j);
        if (!(g > 0)) continue;
        if (g < min_gr * total[i] && g < min_gr * total[j]) {
          dropped[i] += g, dropped[j] += g;
          continue;
        }
        net.gr.push_back({static_cast<int>(i), static_cast<int>(j), g});
      }
      if (to_space[i] > 0) net.gr.push_back({static_cast<int>(i), static_cast<int>(n), to_space[i]});
    }
  }
  for (Eigen::Index i = 0; i < n; ++i)
    if (total[i] > 0) net.dropped_gr_share = std::max(net.dropped_gr_share, dropped[i] / total[i]);
}

void readThermal(const Hdf5Reader& h5, ExportedNetwork& net) {
  // Without /thermal the deck would lack every conductor and boundary node, and look fine.
  if (!h5.has("/thermal/conductor_nodes"))
    throw InputError(h5.path(), 0, 0,
                     "the result has temperatures but no /thermal group (written by an older radnet): run the case "
                     "again to export its conductors");
  const auto n = static_cast<Eigen::Index>(net.nodes.size());
  const int p = net.position;
  net.temperature_k = rowOf(h5, "/solution/temperature", p, n);
  net.capacitance_j_k = orZeros(h5, "/nodes/capacitance", n);
  net.q_solar_w = rowOf(h5, "/solution/heat/solar", p, n);
  net.q_albedo_w = rowOf(h5, "/solution/heat/albedo", p, n);
  net.q_earth_ir_w = rowOf(h5, "/solution/heat/earth_ir", p, n);
  net.q_heater_w = rowOf(h5, "/solution/heat/heater", p, n);
  net.q_internal_w = rowOf(h5, "/solution/heat/dissipation", p, n) + net.q_heater_w;
  net.fixed_temperature_k = Eigen::VectorXd::Constant(n, NAN);
  if (h5.has("/thermal/fixed_temperature")) {
    const Eigen::VectorXd t = h5.vector("/thermal/fixed_temperature");
    // /thermal/fixed marks the held nodes; results before it had NaN for free nodes.
    const Eigen::VectorXd held = h5.has("/thermal/fixed") ? h5.vector("/thermal/fixed") : t.array().isFinite().cast<double>();
    if (t.size() != n || held.size() != n)
      malformed(h5, "/thermal/fixed", std::to_string(held.size()) + " flags and " + std::to_string(t.size()) +
                                          " temperatures for " + std::to_string(n) + " nodes");
    for (Eigen::Index i = 0; i < n; ++i)
      if (held[i] != 0) {
        if (!(std::isfinite(t[i]) && t[i] > 0)) malformed(h5, "/thermal/fixed_temperature", "a held node without a temperature in K");
        net.fixed_temperature_k[i] = t[i];
      }
  }
  net.space_temperature_k = h5.attribute("/thermal", "space_temperature", 3.0);
  if (!(std::isfinite(net.space_temperature_k) && net.space_temperature_k >= 0))
    malformed(h5, "/thermal", "space_temperature is not a temperature in K");
  if (h5.has("/thermal/conductor_nodes") && h5.matrix("/thermal/conductance").size()) {
    const Eigen::MatrixXd pairs = h5.matrix("/thermal/conductor_nodes");
    const Eigen::MatrixXd g = finite(h5, "/thermal/conductance", h5.matrix("/thermal/conductance"));
    if (pairs.cols() != 2 || g.cols() != pairs.rows() || p >= g.rows())
      malformed(h5, "/thermal/conductance", "shape " + shape(g) + " for " + std::to_string(pairs.rows()) +
                                                " conductors at position " + std::to_string(p));
    for (Eigen::Index k = 0; k < pairs.rows(); ++k)
      net.gl.push_back({nodeIndexAt(h5, "/thermal/conductor_nodes", pairs(k, 0), n),
                        nodeIndexAt(h5, "/thermal/conductor_nodes", pairs(k, 1), n), g(p, k)});
  }
}

}  // namespace

int deckNodeNumber(const ExportedNetwork& net, int i) {
  const int n = static_cast<int>(net.nodes.size());
  return i == n ? std::max(99999, n + 1) : i + 1;
}

// Parts that turn: the GR of the position's configuration (/articulation/configuration_<k>/),
// which only the base optics have.
std::string turnedGroup(const Hdf5Reader& h5, const std::string& gr_group, int position) {
  if (!h5.has("/articulation/configuration")) return gr_group;
  const Eigen::VectorXd configuration = h5.vector("/articulation/configuration");
  if (position < 0 || position >= configuration.size() || !(configuration[position] >= 0) ||
      configuration[position] != std::floor(configuration[position]))
    malformed(h5, "/articulation/configuration", "no configuration for position " + std::to_string(position));
  const int k = static_cast<int>(configuration[position]);
  if (k == 0) return gr_group;  // the as-written geometry: /network/ or the base optics'
  const std::string group = "/articulation/configuration_" + std::to_string(k) + "/";
  if (gr_group != "/network/" && gr_group != "/optics/base/")
    throw InputError(h5.path(), 0, 0, "position " + std::to_string(position) + " has turned parts (configuration " +
                                          std::to_string(k) + ") and an optical set of its own: the file keeps the "
                                          "turned configurations' GR for the base optics only");
  if (!hasExchange(h5, group))
    throw InputError(h5.path(), 0, 0, "position " + std::to_string(position) + " has turned parts, and " + group +
                                          "radiative_exchange is not in the file (" +
                                          h5.textAttribute("/articulation", "radiative_exchange", "not written") + ")");
  return group;
}

ExportedNetwork readExportedNetwork(const Hdf5Reader& h5, const ExportOptions& o, bool couplings) {
  if (!(o.min_gr >= 0 && o.min_gr < 1)) throw InputError(h5.path(), 0, 0, "--min-gr must be in [0, 1)");
  ExportedNetwork net;
  net.name = h5.textAttribute("/meta", "case_name", "radnet");
  net.nodes = h5.strings("/nodes/name");
  const auto n = static_cast<Eigen::Index>(net.nodes.size());
  if (n == 0) malformed(h5, "/nodes/name", "no node");
  net.thermal = h5.has("/solution/temperature");
  net.transient = h5.textAttribute("/solution/temperature", "mode", "steady") == "transient";
  const int positions = net.thermal            ? static_cast<int>(h5.matrix("/solution/temperature").rows())
                        : h5.has("/loads/solar") ? static_cast<int>(h5.rows("/loads/solar"))
                                                 : 1;
  const std::string case_group = selectCase(h5, o, net, positions);
  const std::string gr_group = turnedGroup(h5, case_group, net.position);
  const bool imported = !h5.textAttribute("/meta", "imported_from", "").empty();  // no radiative node of radnet's
  const Eigen::Index radiative = imported && !hasExchange(h5, "/network/") ? 0 : h5.rows("/network/gr_space");
  for (Eigen::Index i = 0; i < n; ++i) net.lumped.push_back(i >= radiative);
  // Every result has one area per node (lumped nodes 0): missing or short is a foreign file,
  // not zeros to write into a deck.
  if (!h5.has("/nodes/area") || h5.vector("/nodes/area").size() != n)
    malformed(h5, "/nodes/area", "missing or not one value per node (" + std::to_string(n) + ")");
  net.area_m2 = orZeros(h5, "/nodes/area", n);
  // The optics are the case's (a turned configuration's GR is of the base optics).
  net.emissivity = orZeros(h5, case_group == "/network/" ? "/nodes/emissivity" : case_group + "emissivity", n);
  net.absorptivity = orZeros(h5, case_group == "/network/" ? "/nodes/absorptivity" : case_group + "absorptivity", n);
  if (h5.has("/orbit/time")) {
    const Eigen::VectorXd time = h5.vector("/orbit/time");
    if (net.position >= time.size()) malformed(h5, "/orbit/time", std::to_string(time.size()) + " times for position " + std::to_string(net.position));
    net.time_s = time[net.position];
  }
  if (net.thermal) {
    readThermal(h5, net);
  } else {  // loads only: the absorbed loads of /loads, no temperature, no dissipation (no thermal: block)
    net.temperature_k = net.fixed_temperature_k = Eigen::VectorXd::Constant(n, NAN);
    net.capacitance_j_k = net.q_internal_w = net.q_heater_w = Eigen::VectorXd::Zero(n);
    net.q_solar_w = loadRow(h5, "/loads/solar", net.position, n);
    net.q_albedo_w = loadRow(h5, "/loads/albedo", net.position, n);
    net.q_earth_ir_w = loadRow(h5, "/loads/earth_ir", net.position, n);
  }
  if (couplings) readCouplings(h5, gr_group, net, o.min_gr);
  return net;
}

namespace {

// The thermostats with their set points; none from a result that does not store them.
std::vector<ExportedThermostat> readThermostats(const Hdf5Reader& h5, const ExportedNetwork& net) {
  std::vector<ExportedThermostat> out;
  if (!h5.has("/heaters/on_below") || !h5.has("/heaters/name")) return out;
  const std::vector<std::string> name = h5.strings("/heaters/name"), node = h5.strings("/heaters/node"),
                                 sensor = h5.strings("/heaters/sensor");
  const Eigen::VectorXd power = finite(h5, "/heaters/rated_power", h5.vector("/heaters/rated_power"));
  const Eigen::VectorXd on = finite(h5, "/heaters/on_below", h5.vector("/heaters/on_below"));
  const Eigen::VectorXd off = finite(h5, "/heaters/off_above", h5.vector("/heaters/off_above"));
  const Eigen::MatrixXd supplied = h5.matrix("/heaters/power");  // (P, h)
  const auto h = static_cast<Eigen::Index>(name.size());
  if (node.size() != name.size() || sensor.size() != name.size() || power.size() != h || on.size() != h ||
      off.size() != h || supplied.cols() != h || supplied.rows() <= net.case_first)
    malformed(h5, "/heaters", "name, node, sensor, rated_power, on_below, off_above and power disagree");
  const auto index = [&](const std::string& n) {
    const auto it = std::find(net.nodes.begin(), net.nodes.end(), n);
    if (it == net.nodes.end()) malformed(h5, "/heaters/node", "names '" + n + "', not a node");
    return static_cast<int>(it - net.nodes.begin());
  };
  for (Eigen::Index k = 0; k < h; ++k)
    out.push_back({name[static_cast<size_t>(k)], index(node[static_cast<size_t>(k)]), index(sensor[static_cast<size_t>(k)]),
                   power[k], on[k], off[k], supplied(net.case_first, k) > 0});
  return out;
}

// The span the loads repeat over: the orbit case's nodal period, or whole periods of it.
double loadPeriod(const Hdf5Reader& h5, const ExportedNetwork& first, double last_time) {
  if (!h5.has("/orbit/period") || !h5.has("/orbit/case")) return 0.0;
  const Eigen::VectorXd period = finite(h5, "/orbit/period", h5.vector("/orbit/period"));
  const Eigen::VectorXd orbit_case = h5.vector("/orbit/case");
  const double k = orbit_case.size() > first.case_first ? orbit_case[first.case_first] : -1;
  if (!(k >= 0 && k < static_cast<double>(period.size()) && period[static_cast<Eigen::Index>(k)] > 0))
    malformed(h5, "/orbit/case", "not an orbit case of /orbit/period");
  const double one = period[static_cast<Eigen::Index>(k)];
  return one * std::max(1.0, std::floor(last_time / one) + 1.0);
}

}  // namespace

ExportedHistory readExportedHistory(const Hdf5Reader& h5, const ExportOptions& o) {
  ExportOptions at = o;
  at.position = -1;
  ExportedHistory history;
  h5.keepMatricesUnder({"/solution/", "/thermal/", "/loads/"});  // each (P × n) dataset read once, not per position
  struct Forget {  // and let go of them however the reading ends
    const Hdf5Reader& h5;
    ~Forget() { h5.keepMatricesUnder({}); }
  } forget{h5};
  const ExportedNetwork first = readExportedNetwork(h5, at);
  const char* time_path = h5.has("/orbit/time") ? "/orbit/time" : h5.has("/solution/time") ? "/solution/time" : nullptr;
  const Eigen::VectorXd times = time_path ? finite(h5, time_path, h5.vector(time_path)) : Eigen::VectorXd::Zero(1);
  if (times.size() < first.case_end)  // no time line at all (one position assumed) included
    malformed(h5, time_path ? time_path : "/orbit/time", "fewer times than positions");
  for (int p = first.case_first; p < first.case_end; ++p) {
    if (!history.times_s.empty() && !(times[p] > history.times_s.back()))
      throw InputError(h5.path(), 0, 0, std::string(time_path) + ": the times of " +
                                            (first.design_case.empty() ? "the run" : "design case '" + first.design_case + "'") +
                                            " do not increase at position " + std::to_string(p) +
                                            " (several orbit cases): one deck or TMD holds one time line; give "
                                            "--position for one position, or run each orbit case on its own");
    history.times_s.push_back(times[p]);
    at.position = p;
    history.at.push_back(p == first.position ? first : readExportedNetwork(h5, at, false));
  }
  if (time_path && std::string(time_path) == "/orbit/time") history.period_s = loadPeriod(h5, first, history.times_s.back());
  if (first.thermal) history.thermostats = readThermostats(h5, first);
  return history;
}

}  // namespace radnet::cases
