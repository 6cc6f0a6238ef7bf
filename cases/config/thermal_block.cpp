#include "cases/config/thermal_settings.hpp"

#include <algorithm>
#include <limits>

namespace radnet::cases {
std::optional<ThermalSettings> parseThermalSettings(const YamlDocument& doc, const std::vector<std::string>& names,
                                                    bool has_orbit) {
  const YAML::Node t = doc.root()["thermal"];
  if (!t) return std::nullopt;
  doc.expectMap(t, "thermal",
                {"nodes", "conductors", "initial_temperature", "space_temperature", "transient", "tolerance"});
  const Eigen::Index n = static_cast<Eigen::Index>(names.size());
  ThermalSettings s;
  s.capacitance = Eigen::VectorXd::Zero(n);
  s.dissipation = Eigen::VectorXd::Zero(n);
  s.fixed_temperature = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::quiet_NaN());
  constexpr double kBig = std::numeric_limits<double>::max();
  if (const YAML::Node nodes = t["nodes"]) {
    if (!nodes.IsMap()) throw doc.error(nodes, "thermal.nodes: expected a mapping of node names");
    for (const auto& kv : nodes) {
      const int i = doc.nodeIndex(kv.first, "thermal.nodes", names);
      const std::string what = "thermal.nodes." + names[static_cast<size_t>(i)];
      doc.expectMap(kv.second, what, {"capacitance", "dissipation", "temperature"});
      if (kv.second["capacitance"])
        s.capacitance[i] = doc.number(kv.second["capacitance"], what + ".capacitance (J/K)", 0, kBig);
      if (kv.second["dissipation"])
        s.dissipation[i] = doc.number(kv.second["dissipation"], what + ".dissipation (W)", -kBig, kBig);
      if (kv.second["temperature"])
        s.fixed_temperature[i] =
            doc.number(kv.second["temperature"], what + ".temperature (K, boundary node)", 1e-3, 1e5);
    }
  }
  if (const YAML::Node cs = t["conductors"]) {
    doc.expectSequence(cs, "thermal.conductors");
    for (size_t k = 0; k < cs.size(); ++k) {
      const std::string what = "thermal.conductors[" + std::to_string(k) + "]";
      if (!cs[k].IsSequence() || cs[k].size() != 3) throw doc.error(cs[k], what + ": expected [node, node, W/K]");
      const int i = doc.nodeIndex(cs[k][0], what, names), j = doc.nodeIndex(cs[k][1], what, names);
      if (i == j) throw doc.error(cs[k], what + ": a conductor joins two different nodes");
      const double g = doc.number(cs[k][2], what + " conductance (W/K)", 0, kBig);
      s.conductors.emplace_back(i, j, g);
      s.conductors.emplace_back(j, i, g);
    }
  }
  if (t["initial_temperature"])
    s.initial_temperature = doc.number(t["initial_temperature"], "thermal.initial_temperature (K)", 1e-3, 1e5);
  if (t["space_temperature"])
    s.space_temperature = doc.number(t["space_temperature"], "thermal.space_temperature (K)", 0, 1e4);
  if (t["tolerance"]) s.options.tolerance_w = doc.number(t["tolerance"], "thermal.tolerance (relative)", 1e-15, 1e-2);
  if (const YAML::Node tr = t["transient"]) {
    doc.expectMap(tr, "thermal.transient", {"orbits", "time_step"});
    if (!has_orbit)
      throw doc.error(tr, "thermal.transient: a transient follows an orbit; add 'orbit:' or remove 'transient'");
    s.transient_orbits = tr["orbits"] ? doc.number(tr["orbits"], "thermal.transient.orbits", 1e-3, 1e4) : 1.0;
    if (tr["time_step"])
      s.options.max_step_s = doc.number(tr["time_step"], "thermal.transient.time_step (s)", 1e-3, 1e5);
  }
  return s;
}

}  // namespace radnet::cases
