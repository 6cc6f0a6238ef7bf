#include "cases/config/expect_block.hpp"

#include <algorithm>

namespace radnet::cases {
namespace {

Expectation parseExpectation(const YamlDocument& doc, const YAML::Node& e, const std::string& what,
                             const std::vector<std::string>& radiative_names,
                             const std::vector<std::string>& thermal_names,
                             const std::vector<std::string>& case_names) {
  doc.expectMap(e, what, {"quantity", "node", "to", "index", "value", "tolerance", "case"});
  Expectation x;
  const YAML::Mark mark = e.Mark();
  x.where = doc.file() + ":" + std::to_string(mark.line + 1) + ":" + std::to_string(mark.column + 1);
  const YAML::Node q = doc.required(e, "quantity", what);
  const std::string word = doc.string(q, what + ".quantity");
  const auto quantity = expectQuantity(word);
  if (!quantity) {
    const std::vector<std::string> known(kExpectQuantityNames.begin(), kExpectQuantityNames.end());
    std::string msg = what + ".quantity: unknown quantity '" + word + "'";
    if (auto near = nearestWord(word, known)) msg += " (did you mean '" + *near + "'?)";
    throw doc.error(q, msg);
  }
  x.quantity = *quantity;
  if (radiative_names.empty() && x.quantity != ExpectQuantity::Temperature)
    throw doc.error(q, what + ".quantity: '" + word + "' needs radiative nodes and this case has none (an imported "
                                                      "network: its GR came with the file); expect temperatures");
  const std::vector<std::string>& names = x.quantity == ExpectQuantity::Temperature ? thermal_names : radiative_names;
  auto nodeName = [&](const char* key) {
    const YAML::Node n = doc.required(e, key, what);
    return names[static_cast<size_t>(doc.nodeIndex(n, what + "." + key, names))];
  };
  if (x.quantity == ExpectQuantity::Eigenvalue) {
    x.index = static_cast<int>(doc.integer(doc.required(e, "index", what), what + ".index", 0, 1 << 30));
  } else {
    if (e["index"]) x.index = static_cast<int>(doc.integer(e["index"], what + ".index (position)", 0, 1 << 30));
    x.node = nodeName("node");
    if (isPairQuantity(x.quantity)) x.to = nodeName("to");
  }
  if (e["case"]) {
    if (case_names.empty()) throw doc.error(e["case"], what + ".case: this case has no design cases");
    const std::string name = doc.choice(e["case"], what + ".case", case_names);
    x.design_case = static_cast<int>(std::find(case_names.begin(), case_names.end(), name) - case_names.begin());
    x.case_given = true;
  }
  const bool orbit_quantity = x.quantity == ExpectQuantity::OrbitMeanAbsorbed || x.quantity == ExpectQuantity::OrbitMaxAbsorbedSolar;
  if (orbit_quantity && !x.case_given && case_names.size() > 1)
    throw doc.error(e, what + ": the case has " + std::to_string(case_names.size()) +
                           " design cases; give 'case:' to say whose orbit (one of: " + [&] {
                             std::string list;
                             for (const std::string& n : case_names) list += (list.empty() ? "" : ", ") + n;
                             return list;
                           }() + ")");
  x.value = doc.number(doc.required(e, "value", what), what + ".value", -1e300, 1e300);
  x.tolerance = doc.number(doc.required(e, "tolerance", what), what + ".tolerance", 0.0, 1e300);
  return x;
}

}  // namespace

std::vector<Expectation> parseExpectations(const YamlDocument& doc, const YAML::Node& node,
                                           const std::vector<std::string>& radiative_names,
                                           const std::vector<std::string>& thermal_names,
                                           const std::vector<std::string>& case_names) {
  doc.expectSequence(node, "expect");
  std::vector<Expectation> out;
  for (size_t i = 0; i < node.size(); ++i)
    out.push_back(parseExpectation(doc, node[i], "expect[" + std::to_string(i) + "]", radiative_names, thermal_names, case_names));
  return out;
}

}  // namespace radnet::cases
