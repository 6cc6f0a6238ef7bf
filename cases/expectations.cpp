#include "cases/expectations.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <ostream>

namespace radnet::cases {
namespace {

const std::initializer_list<const char*> kQuantities = {
    "exitance",   "irradiance",  "view_factor",         "space_view_factor",       "radiative_exchange", "gr_space",
    "eigenvalue", "temperature", "orbit_mean_absorbed", "orbit_max_absorbed_solar"};

bool isPairQuantity(const std::string& q) { return q == "view_factor" || q == "radiative_exchange"; }

std::string nodeName(const YamlDocument& doc, const YAML::Node& node, const std::string& what,
                     const std::vector<std::string>& names) {
  const std::string name = doc.string(node, what);
  if (std::find(names.begin(), names.end(), name) == names.end()) {
    std::string msg = what + ": no node named '" + name + "'";
    if (auto near = nearestWord(name, names)) msg += " (did you mean '" + *near + "'?)";
    throw doc.error(node, msg);
  }
  return name;
}

}  // namespace

std::vector<Expectation> parseExpectations(const YamlDocument& doc, const YAML::Node& node,
                                           const std::vector<std::string>& names) {
  doc.expectSequence(node, "expect");
  std::vector<Expectation> out;
  for (size_t i = 0; i < node.size(); ++i) {
    const YAML::Node e = node[i];
    const std::string what = "expect[" + std::to_string(i) + "]";
    doc.expectMap(e, what, {"quantity", "node", "to", "index", "value", "tolerance"});
    Expectation x;
    const YAML::Mark mark = e.Mark();
    x.where = doc.file() + ":" + std::to_string(mark.line + 1) + ":" + std::to_string(mark.column + 1);
    const YAML::Node q = doc.required(e, "quantity", what);
    x.quantity = doc.string(q, what + ".quantity");
    if (std::none_of(kQuantities.begin(), kQuantities.end(), [&](const char* k) { return x.quantity == k; })) {
      std::string msg = what + ".quantity: unknown quantity '" + x.quantity + "'";
      if (auto near = nearestWord(x.quantity, kQuantities)) msg += " (did you mean '" + *near + "'?)";
      throw doc.error(q, msg);
    }
    if (x.quantity == "eigenvalue") {
      x.index = static_cast<int>(doc.integer(doc.required(e, "index", what), what + ".index", 0, 1 << 30));
    } else {
      if (e["index"]) x.index = static_cast<int>(doc.integer(e["index"], what + ".index (position)", 0, 1 << 30));
      x.node = nodeName(doc, doc.required(e, "node", what), what + ".node", names);
      if (isPairQuantity(x.quantity)) x.to = nodeName(doc, doc.required(e, "to", what), what + ".to", names);
    }
    x.value = doc.number(doc.required(e, "value", what), what + ".value", -1e300, 1e300);
    x.tolerance = doc.number(doc.required(e, "tolerance", what), what + ".tolerance", 0.0, 1e300);
    out.push_back(x);
  }
  return out;
}

int evaluateExpectations(const std::vector<Expectation>& expectations, const ResultLookup& lookup,
                         std::ostream& out) {
  int failed = 0;
  for (const auto& x : expectations) {
    const std::optional<double> got = lookup(x);
    std::string label = x.quantity;
    if (!x.node.empty()) label += " " + x.node;
    if (!x.to.empty()) label += " -> " + x.to;
    if (x.index >= 0) label += " #" + std::to_string(x.index);
    const bool ok = got && std::isfinite(*got) && std::abs(*got - x.value) <= x.tolerance;
    if (!ok) ++failed;
    out << (ok ? "PASS " : "FAIL ") << std::left << std::setw(40) << label << " expected " << std::setprecision(10)
        << x.value << " ± " << x.tolerance << ", got ";
    if (got) out << *got << " (error " << std::abs(*got - x.value) << ")";
    else out << "nothing (the run has no such result)";
    out << "  [" << x.where << "]\n";
  }
  return failed;
}

}  // namespace radnet::cases
