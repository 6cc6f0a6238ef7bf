#include "cases/config/thermal_settings.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

namespace radnet::cases {
namespace {

constexpr double kBig = std::numeric_limits<double>::max();
// What the thermal model accepts: far beyond any spacecraft (a 1 GW heater, a 1e12 W/K
// "infinite" joint, a 1e12 J/K tank, a 1e9 m² coupling), yet far enough inside the doubles
// that the heat balance (K T, σ GR T⁴ at 1e5 K) cannot overflow.
constexpr double kMaxPower = 1e9;         // W
constexpr double kMaxConductance = 1e12;  // W/K
constexpr double kMaxCapacitance = 1e12;  // J/K
constexpr double kMaxCoupling = 1e9;      // m²
constexpr double kDefaultInitialTemperature = 293.15;  // K
constexpr double kMinTemperature = 1e-3, kMaxTemperature = 1e5;  // K: what the thermal model accepts
constexpr int kMaxTransientOutputs = 1000000;                   // output times of a transient without an orbit

// A dissipation: W, `{sunlit: W, eclipse: W}` (by the spacecraft's sunlit fraction; needs an
// orbit) or `{table: [[s, W], ...]}` (piecewise constant from each time on, the first at 0 s,
// repeating each orbit). Returns the constant part; schedules go to s.schedules.
double parseDissipation(const YamlDocument& doc, const YAML::Node& node, const std::string& what, int i,
                        std::optional<double> orbit_period_s, ThermalSettings& s) {
  if (!node.IsMap()) return doc.number(node, what + " (W)", -kMaxPower, kMaxPower);
  solver::DissipationSchedule sch;
  sch.node = i;
  if (node["table"]) {
    doc.expectMap(node, what, {"table"});
    sch.kind = solver::DissipationSchedule::Kind::Table;
    parseTable(doc, node["table"], what + ".table (s, W)", 0.0, kBig, -kMaxPower, kMaxPower, sch.times_s, sch.power_w);
    if (sch.times_s.front() != 0.0)
      throw doc.error(node["table"][0], what + ".table: the first entry must be at 0 s (the power from the start on)");
    if (orbit_period_s && !(sch.times_s.back() < *orbit_period_s))
      throw doc.error(node["table"], what + ".table: an entry lies at or beyond the orbit period (" +
                                         std::to_string(*orbit_period_s) + " s); the table repeats each orbit");
  } else {
    doc.expectMap(node, what, {"sunlit", "eclipse"});
    if (!orbit_period_s)
      throw doc.error(node, what + ": a dissipation by illumination needs an orbit; give a constant or a table");
    sch.kind = solver::DissipationSchedule::Kind::Illumination;
    sch.sunlit_w = doc.number(doc.required(node, "sunlit", what), what + ".sunlit (W)", -kMaxPower, kMaxPower);
    sch.eclipse_w = doc.number(doc.required(node, "eclipse", what), what + ".eclipse (W)", -kMaxPower, kMaxPower);
  }
  s.schedules.push_back(sch);
  return 0.0;
}

// The properties every node block may give: capacitance, dissipation, boundary
// temperature and initial temperature.
void parseNodeProperties(const YamlDocument& doc, const YAML::Node& props, const std::string& what, int i,
                         std::optional<double> orbit_period_s, ThermalSettings& s) {
  doc.expectMap(props, what, {"capacitance", "dissipation", "temperature", "initial_temperature"});
  if (const YAML::Node c = props["capacitance"]) {
    if (c.IsMap()) {
      doc.expectMap(c, what + ".capacitance", {"table"});
      solver::TemperatureTable table;
      parseTable(doc, doc.required(c, "table", what + ".capacitance"), what + ".capacitance.table (K, J/K)",
                 kMinTemperature, kMaxTemperature, 0, kMaxCapacitance, table.temperature_k, table.value);
      s.capacitance_tables.emplace_back(i, table);
    } else {
      s.capacitance[i] = doc.number(c, what + ".capacitance (J/K)", 0, kMaxCapacitance);
    }
  }
  if (props["dissipation"]) {  // replaces any the node had (an imported load history)
    s.schedules.erase(std::remove_if(s.schedules.begin(), s.schedules.end(), [i](const auto& x) { return x.node == i; }),
                      s.schedules.end());
    s.dissipation[i] = parseDissipation(doc, props["dissipation"], what + ".dissipation", i, orbit_period_s, s);
  }
  if (props["temperature"]) {  // a constant one replaces any history the node had (an imported one)
    s.boundary_schedules.erase(std::remove_if(s.boundary_schedules.begin(), s.boundary_schedules.end(),
                                              [i](const auto& b) { return b.node == i; }),
                               s.boundary_schedules.end());
    s.fixed_temperature[i] =
        doc.number(props["temperature"], what + ".temperature (K, boundary node)", kMinTemperature, kMaxTemperature);
    warnIfCelsius(doc, props["temperature"], what + ".temperature", s.fixed_temperature[i], s.warnings);
  }
  if (props["initial_temperature"]) {
    s.initial_temperature[i] =
        doc.number(props["initial_temperature"], what + ".initial_temperature (K)", kMinTemperature, kMaxTemperature);
    warnIfCelsius(doc, props["initial_temperature"], what + ".initial_temperature", s.initial_temperature[i], s.warnings);
  }
}

// `lumped:` nodes without geometry, appended after the radiative nodes.
void parseLumpedNames(const YamlDocument& doc, const YAML::Node& lumped, ThermalSettings& s) {
  if (!lumped.IsMap()) throw doc.error(lumped, "thermal.lumped: expected a mapping of node names");
  for (const auto& kv : lumped) {
    const std::string name = doc.string(kv.first, "thermal.lumped");
    if (std::find(s.node_names.begin(), s.node_names.end(), name) != s.node_names.end())
      throw doc.error(kv.first, "thermal.lumped." + name + ": a node named '" + name +
                                    "' exists already; lumped nodes need names of their own");
    s.node_names.push_back(name);
  }
}

// `[node, node, value]` entries of `conductors` (W/K, or a table against the mean
// temperature) and `radiative_couplings` (m²).
void parsePairs(const YamlDocument& doc, const YAML::Node& list, const std::string& key, const char* unit,
                bool tables, ThermalSettings& s, std::vector<Eigen::Triplet<double>>& out) {
  doc.expectSequence(list, "thermal." + key);
  std::map<std::pair<int, int>, size_t> seen;  // a pair given twice (either way round) was summed silently
  for (size_t k = 0; k < list.size(); ++k) {
    const std::string what = "thermal." + key + "[" + std::to_string(k) + "]";
    const YAML::Node e = list[k];
    if (!e.IsSequence() || e.size() != 3) throw doc.error(e, what + ": expected [node, node, " + unit + "]");
    const int i = doc.nodeIndex(e[0], what, s.node_names), j = doc.nodeIndex(e[1], what, s.node_names);
    if (i == j) throw doc.error(e, what + ": joins a node to itself; expected two different nodes");
    const auto [first, fresh] = seen.emplace(std::pair{std::min(i, j), std::max(i, j)}, k);
    if (!fresh)
      throw doc.error(e, what + ": joins '" + s.node_names[static_cast<size_t>(i)] + "' and '" +
                             s.node_names[static_cast<size_t>(j)] + "' again (thermal." + key + "[" +
                             std::to_string(first->second) + "] does already); give one entry with the sum");
    if (e[2].IsMap() && tables) {
      doc.expectMap(e[2], what, {"table"});
      solver::TabledConductor c{i, j, {}};
      parseTable(doc, doc.required(e[2], "table", what), what + ".table (K, W/K)", kMinTemperature, kMaxTemperature,
                 0, kMaxConductance, c.conductance.temperature_k, c.conductance.value);
      s.tabled_conductors.push_back(c);
      continue;
    }
    const double g = doc.number(e[2], what + " (" + unit + ")", 0, tables ? kMaxConductance : kMaxCoupling);
    out.emplace_back(i, j, g);
    out.emplace_back(j, i, g);
  }
}

// `mli: [{outer, inner, effective_emissivity}]`: a blanket between an outer surface node
// and what it covers, GR = A_outer ε* (m²).
void parseMli(const YamlDocument& doc, const YAML::Node& list, const Eigen::VectorXd& area, ThermalSettings& s) {
  doc.expectSequence(list, "thermal.mli");
  for (size_t k = 0; k < list.size(); ++k) {
    const std::string what = "thermal.mli[" + std::to_string(k) + "]";
    const YAML::Node e = list[k];
    doc.expectMap(e, what, {"outer", "inner", "effective_emissivity"});
    const YAML::Node outer_node = doc.required(e, "outer", what);
    const int outer = doc.nodeIndex(outer_node, what + ".outer", s.node_names);
    const int inner = doc.nodeIndex(doc.required(e, "inner", what), what + ".inner", s.node_names);
    if (s.isLumped(outer))
      throw doc.error(outer_node, what + ".outer: '" + s.node_names[static_cast<size_t>(outer)] +
                                      "' is a lumped node; the outer side of a blanket needs an area");
    if (outer == inner) throw doc.error(e, what + ": outer and inner are the same node");
    const double eps = doc.number(doc.required(e, "effective_emissivity", what), what + ".effective_emissivity", 0, 1);
    const double gr = area[outer] * eps;
    s.radiative_couplings.emplace_back(outer, inner, gr);
    s.radiative_couplings.emplace_back(inner, outer, gr);
  }
}

// `duration` (s) and `output_step` (s): a transient without an orbit.
void parseDuration(const YamlDocument& doc, const YAML::Node& tr, bool has_orbit, ThermalSettings& s) {
  if (has_orbit)
    throw doc.error(tr["duration"], "thermal.transient.duration: with an orbit a transient runs whole orbits; give "
                                    "'orbits' or 'periodic: true' instead");
  for (const char* key : {"orbits", "periodic", "periodic_tolerance", "max_orbits"})
    if (tr[key])
      throw doc.error(tr[key], std::string("thermal.transient.") + key + ": needs an orbit; this case has none");
  s.duration_s = doc.number(tr["duration"], "thermal.transient.duration (s)", 1e-3, 1e10);
  s.output_step_s = tr["output_step"] ? doc.number(tr["output_step"], "thermal.transient.output_step (s)", 1e-3, 1e10)
                                      : std::max(s.options.max_step_s, *s.duration_s / 1000.0);
  if (*s.duration_s / s.output_step_s > kMaxTransientOutputs)
    throw doc.error(tr["output_step"] ? tr["output_step"] : tr["duration"],
                    "thermal.transient: more than " + std::to_string(kMaxTransientOutputs) +
                        " output times; raise output_step");
}

void parseTransient(const YamlDocument& doc, const YAML::Node& tr, bool has_orbit, ThermalSettings& s) {
  doc.expectMap(tr, "thermal.transient",
                {"orbits", "time_step", "periodic", "periodic_tolerance", "max_orbits", "duration", "output_step"});
  if (tr["time_step"])
    s.options.max_step_s = doc.number(tr["time_step"], "thermal.transient.time_step (s)", 1e-3, 1e5);
  if (tr["duration"]) return parseDuration(doc, tr, has_orbit, s);
  if (tr["output_step"])
    throw doc.error(tr["output_step"], "thermal.transient.output_step: only with 'duration' (with an orbit the "
                                       "outputs are the orbit's positions)");
  if (!has_orbit)
    throw doc.error(tr, "thermal.transient: this case has no orbit; give 'duration' (s) for a transient without one, "
                        "or add 'orbit:'");
  const bool periodic = tr["periodic"] && doc.boolean(tr["periodic"], "thermal.transient.periodic");
  if (!periodic) {
    for (const char* key : {"periodic_tolerance", "max_orbits"})
      if (tr[key])
        throw doc.error(tr[key], std::string("thermal.transient.") + key + ": only with 'periodic: true'");
    s.transient_orbits = tr["orbits"] ? doc.number(tr["orbits"], "thermal.transient.orbits", 1e-3, 1e4) : 1.0;
    return;
  }
  if (tr["orbits"])
    throw doc.error(tr["orbits"], "thermal.transient.orbits: a periodic transient runs until it repeats; "
                                  "give 'max_orbits' instead");
  solver::PeriodicOptions p;
  if (tr["periodic_tolerance"])
    p.tolerance_k = doc.number(tr["periodic_tolerance"], "thermal.transient.periodic_tolerance (K)", 1e-9, 100);
  if (tr["max_orbits"])
    p.max_orbits = static_cast<int>(doc.integer(tr["max_orbits"], "thermal.transient.max_orbits", 2, 10000));
  s.periodic = p;
}

void parseNodes(const YamlDocument& doc, const YAML::Node& t, const std::vector<std::string>& names,
                std::optional<double> orbit_period_s, int first_lumped, ThermalSettings& s) {
  if (const YAML::Node nodes = t["nodes"]) {
    if (!nodes.IsMap()) throw doc.error(nodes, "thermal.nodes: expected a mapping of node names");
    for (const auto& kv : nodes) {
      const int i = doc.nodeIndex(kv.first, "thermal.nodes", names);
      parseNodeProperties(doc, kv.second, "thermal.nodes." + names[static_cast<size_t>(i)], i, orbit_period_s, s);
    }
  }
  for (int i = first_lumped; i < s.nodeCount(); ++i) {
    const std::string& name = s.node_names[static_cast<size_t>(i)];
    parseNodeProperties(doc, t["lumped"][name], "thermal.lumped." + name, i, orbit_period_s, s);
  }
}

}  // namespace

void warnIfCelsius(const YamlDocument& doc, const YAML::Node& value, const std::string& what, double k,
                   std::vector<std::string>& warnings) {
  if (!(k < kSuspiciousKelvin)) return;
  std::ostringstream msg;
  msg << what << ": " << k << " K is below " << kSuspiciousKelvin << " K; temperatures are in kelvin (" << k
      << " °C would be " << k + 273.15 << " K)";
  warnings.push_back(doc.located(value, msg.str()));
}

std::optional<ThermalSettings> parseThermalSettings(const YamlDocument& doc, const std::vector<std::string>& names,
                                                    const Eigen::VectorXd& area, std::optional<double> orbit_period_s,
                                                    const ThermalSettings* imported) {
  const YAML::Node t = doc.root()["thermal"];
  if (!t) return imported ? std::optional<ThermalSettings>(*imported) : std::nullopt;
  doc.expectMap(t, "thermal",
                {"nodes", "lumped", "conductors", "radiative_couplings", "mli", "heaters", "initial_temperature",
                 "space_temperature", "transient", "tolerance"});
  ThermalSettings s;
  if (imported) s = *imported;
  else s.node_names = names, s.radiative_nodes = static_cast<int>(names.size());
  const int first_lumped = s.nodeCount();
  if (t["lumped"]) parseLumpedNames(doc, t["lumped"], s);
  const Eigen::Index n = s.nodeCount();
  const double initial =
      t["initial_temperature"]
          ? doc.number(t["initial_temperature"], "thermal.initial_temperature (K)", kMinTemperature, kMaxTemperature)
          : kDefaultInitialTemperature;
  // Nodes added here start with nothing; an imported model keeps what its file gave.
  const Eigen::Index fresh = n - (imported ? first_lumped : 0);
  s.capacitance.conservativeResize(n), s.capacitance.tail(fresh).setZero();
  s.dissipation.conservativeResize(n), s.dissipation.tail(fresh).setZero();
  s.fixed_temperature.conservativeResize(n);
  s.fixed_temperature.tail(fresh).setConstant(std::numeric_limits<double>::quiet_NaN());
  s.initial_temperature.conservativeResize(n), s.initial_temperature.tail(fresh).setConstant(initial);
  if (t["initial_temperature"]) {
    s.initial_temperature.setConstant(initial);
    warnIfCelsius(doc, t["initial_temperature"], "thermal.initial_temperature", initial, s.warnings);
  }
  parseNodes(doc, t, names, orbit_period_s, first_lumped, s);
  if (t["conductors"]) parsePairs(doc, t["conductors"], "conductors", "W/K", true, s, s.conductors);
  if (t["radiative_couplings"])
    parsePairs(doc, t["radiative_couplings"], "radiative_couplings", "m²", false, s, s.radiative_couplings);
  if (t["mli"]) parseMli(doc, t["mli"], area, s);
  if (t["heaters"]) parseHeaters(doc, t["heaters"], s);
  if (t["space_temperature"])
    s.space_temperature = doc.number(t["space_temperature"], "thermal.space_temperature (K)", 0, 1e4);
  if (t["tolerance"]) s.options.tolerance_w = doc.number(t["tolerance"], "thermal.tolerance (relative)", 1e-15, 1e-2);
  if (t["transient"] && imported) {  // the file sets the output times; only the step may be refined
    doc.expectMap(t["transient"], "thermal.transient (of an imported model: its file sets the output times)",
                  {"time_step"});
    if (t["transient"]["time_step"])
      s.options.max_step_s = doc.number(t["transient"]["time_step"], "thermal.transient.time_step (s)", 1e-3, 1e5);
  } else if (t["transient"]) {
    parseTransient(doc, t["transient"], orbit_period_s.has_value(), s);
  }
  return s;
}

}  // namespace radnet::cases
