// Thermostat heaters and the tables of the thermal block.
#include "cases/config/thermal_settings.hpp"
#include "solver/thermal/temperatures.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <set>

namespace radnet::cases {

void parseTable(const YamlDocument& doc, const YAML::Node& node, const std::string& what, double x_lo, double x_hi,
                double y_lo, double y_hi, std::vector<double>& x, std::vector<double>& y) {
  doc.expectSequence(node, what);
  if (node.size() == 0) throw doc.error(node, what + ": the table is empty; expected [[x, y], ...]");
  x.clear();
  y.clear();
  for (size_t k = 0; k < node.size(); ++k) {
    const YAML::Node row = node[k];
    const std::string at = what + "[" + std::to_string(k) + "]";
    if (!row.IsSequence() || row.size() != 2) throw doc.error(row, at + ": expected a pair [x, y]");
    x.push_back(doc.number(row[0], at + "[0]", x_lo, x_hi));
    y.push_back(doc.number(row[1], at + "[1]", y_lo, y_hi));
    if (k > 0 && !(x[k] > x[k - 1]))
      throw doc.error(row[0], at + ": the first column must increase (" + std::to_string(x[k]) + " follows " +
                                  std::to_string(x[k - 1]) + ")");
  }
}

void parseHeaters(const YamlDocument& doc, const YAML::Node& list, ThermalSettings& s) {
  doc.expectSequence(list, "thermal.heaters");
  std::set<std::string> names;
  for (size_t k = 0; k < list.size(); ++k) {
    const std::string what = "thermal.heaters[" + std::to_string(k) + "]";
    const YAML::Node e = list[k];
    doc.expectMap(e, what, {"name", "node", "power", "on_below", "off_above", "sensor"});
    solver::Heater h;
    const YAML::Node name = doc.required(e, "name", what);
    h.name = doc.string(name, what + ".name");
    if (!names.insert(h.name).second) throw doc.error(name, what + ".name: a heater named '" + h.name + "' exists already");
    const YAML::Node node = doc.required(e, "node", what);
    h.node = doc.nodeIndex(node, what + ".node", s.node_names);
    const YAML::Node sensor = e["sensor"] ? e["sensor"] : node;
    h.sensor = doc.nodeIndex(sensor, what + ".sensor", s.node_names);
    for (const auto& [index, key] : {std::pair{h.node, "node"}, std::pair{h.sensor, "sensor"}})
      if (!std::isnan(s.fixed_temperature[index]))
        throw doc.error(e[key] ? e[key] : node, what + "." + key + ": '" + s.node_names[static_cast<size_t>(index)] +
                                                    "' is a boundary node (its temperature is fixed); a heater "
                                                    "cannot heat or sense it");
    h.power_w = doc.number(doc.required(e, "power", what), what + ".power (W)", 1e-12, 1e9);
    h.on_below_k = doc.number(doc.required(e, "on_below", what), what + ".on_below (K)", 1e-3, 1e5);
    const YAML::Node off = doc.required(e, "off_above", what);
    h.off_above_k = doc.number(off, what + ".off_above (K)", 1e-3, 1e5);
    if (!(h.off_above_k > h.on_below_k))
      throw doc.error(off, what + ".off_above: must lie above on_below (" + std::to_string(h.on_below_k) +
                               " K); a thermostat needs a dead band between switching on and off");
    // The transient locates a switch to within switch_tolerance_k of its set point: a narrower
    // band cannot be resolved (1e-12 K ran without end before the switching cap).
    const double min_band_k = 2.0 * solver::ThermalOptions{}.switch_tolerance_k;
    if (h.off_above_k - h.on_below_k < min_band_k) {
      std::ostringstream msg;
      msg << what << ".off_above: a dead band of " << std::setprecision(3) << h.off_above_k - h.on_below_k
          << " K is narrower than the transient resolves a switch (±" << min_band_k / 2
          << " K about each set point); widen it to at least " << min_band_k << " K";
      throw doc.error(off, msg.str());
    }
    warnIfCelsius(doc, e["on_below"], what + ".on_below", h.on_below_k, s.warnings);
    s.heaters.push_back(h);
  }
}

}  // namespace radnet::cases
