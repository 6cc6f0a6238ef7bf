#include "cases/config/thermal_settings.hpp"

#include <algorithm>
#include <limits>

namespace radnet::cases {
namespace {

constexpr double kBig = std::numeric_limits<double>::max();
constexpr double kDefaultInitialTemperature = 293.15;  // K

// A dissipation in W. Schedules ({sunlit, eclipse} or {table}) are refused until the
// thermal model has them, rather than accepted and ignored.
double dissipation(const YamlDocument& doc, const YAML::Node& node, const std::string& what) {
  if (node.IsMap())
    throw doc.error(node, what + ": dissipation schedules are not supported yet; give a constant power in W");
  return doc.number(node, what + " (W)", -kBig, kBig);
}

// The properties every node block may give: capacitance, dissipation, boundary
// temperature and initial temperature.
void parseNodeProperties(const YamlDocument& doc, const YAML::Node& props, const std::string& what, int i,
                         ThermalSettings& s) {
  doc.expectMap(props, what, {"capacitance", "dissipation", "temperature", "initial_temperature"});
  if (props["capacitance"]) {
    if (props["capacitance"].IsMap())
      throw doc.error(props["capacitance"], what +
                                                ".capacitance: temperature tables are not supported yet; "
                                                "give a constant in J/K");
    s.capacitance[i] = doc.number(props["capacitance"], what + ".capacitance (J/K)", 0, kBig);
  }
  if (props["dissipation"]) s.dissipation[i] = dissipation(doc, props["dissipation"], what + ".dissipation");
  if (props["temperature"])
    s.fixed_temperature[i] = doc.number(props["temperature"], what + ".temperature (K, boundary node)", 1e-3, 1e5);
  if (props["initial_temperature"])
    s.initial_temperature[i] = doc.number(props["initial_temperature"], what + ".initial_temperature (K)", 1e-3, 1e5);
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

// `[node, node, value]` entries of `conductors` (W/K) and `radiative_couplings` (m²).
void parsePairs(const YamlDocument& doc, const YAML::Node& list, const std::string& key, const char* unit,
                std::vector<Eigen::Triplet<double>>& out, const std::vector<std::string>& names) {
  doc.expectSequence(list, "thermal." + key);
  for (size_t k = 0; k < list.size(); ++k) {
    const std::string what = "thermal." + key + "[" + std::to_string(k) + "]";
    const YAML::Node e = list[k];
    if (!e.IsSequence() || e.size() != 3) throw doc.error(e, what + ": expected [node, node, " + unit + "]");
    const int i = doc.nodeIndex(e[0], what, names), j = doc.nodeIndex(e[1], what, names);
    if (i == j) throw doc.error(e, what + ": joins a node to itself; expected two different nodes");
    if (e[2].IsMap())
      throw doc.error(e[2], what + ": temperature tables are not supported yet; give a constant in " + unit);
    const double g = doc.number(e[2], what + " (" + unit + ")", 0, kBig);
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

void parseTransient(const YamlDocument& doc, const YAML::Node& tr, bool has_orbit, ThermalSettings& s) {
  doc.expectMap(tr, "thermal.transient", {"orbits", "time_step"});
  if (!has_orbit)
    throw doc.error(tr, "thermal.transient: a transient follows an orbit; add 'orbit:' or remove 'transient'");
  s.transient_orbits = tr["orbits"] ? doc.number(tr["orbits"], "thermal.transient.orbits", 1e-3, 1e4) : 1.0;
  if (tr["time_step"]) s.options.max_step_s = doc.number(tr["time_step"], "thermal.transient.time_step (s)", 1e-3, 1e5);
}

}  // namespace

std::optional<ThermalSettings> parseThermalSettings(const YamlDocument& doc, const std::vector<std::string>& names,
                                                    const Eigen::VectorXd& area, bool has_orbit) {
  const YAML::Node t = doc.root()["thermal"];
  if (!t) return std::nullopt;
  doc.expectMap(t, "thermal",
                {"nodes", "lumped", "conductors", "radiative_couplings", "mli", "initial_temperature",
                 "space_temperature", "transient", "tolerance"});
  ThermalSettings s;
  s.node_names = names;
  s.radiative_nodes = static_cast<int>(names.size());
  if (t["lumped"]) parseLumpedNames(doc, t["lumped"], s);
  const Eigen::Index n = s.nodeCount();
  s.capacitance = Eigen::VectorXd::Zero(n);
  s.dissipation = Eigen::VectorXd::Zero(n);
  s.fixed_temperature = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::quiet_NaN());
  const double initial = t["initial_temperature"]
                             ? doc.number(t["initial_temperature"], "thermal.initial_temperature (K)", 1e-3, 1e5)
                             : kDefaultInitialTemperature;
  s.initial_temperature = Eigen::VectorXd::Constant(n, initial);
  if (const YAML::Node nodes = t["nodes"]) {
    if (!nodes.IsMap()) throw doc.error(nodes, "thermal.nodes: expected a mapping of node names");
    for (const auto& kv : nodes) {
      const int i = doc.nodeIndex(kv.first, "thermal.nodes", names);
      parseNodeProperties(doc, kv.second, "thermal.nodes." + names[static_cast<size_t>(i)], i, s);
    }
  }
  for (int i = s.radiative_nodes; i < n; ++i) {
    const std::string& name = s.node_names[static_cast<size_t>(i)];
    parseNodeProperties(doc, t["lumped"][name], "thermal.lumped." + name, i, s);
  }
  if (t["conductors"]) parsePairs(doc, t["conductors"], "conductors", "W/K", s.conductors, s.node_names);
  if (t["radiative_couplings"])
    parsePairs(doc, t["radiative_couplings"], "radiative_couplings", "m²", s.radiative_couplings, s.node_names);
  if (t["mli"]) parseMli(doc, t["mli"], area, s);
  if (t["space_temperature"])
    s.space_temperature = doc.number(t["space_temperature"], "thermal.space_temperature (K)", 0, 1e4);
  if (t["tolerance"]) s.options.tolerance_w = doc.number(t["tolerance"], "thermal.tolerance (relative)", 1e-15, 1e-2);
  if (t["transient"]) parseTransient(doc, t["transient"], has_orbit, s);
  return s;
}

}  // namespace radnet::cases
