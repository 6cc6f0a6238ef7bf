#include "cases/config/expect_block.hpp"

namespace radnet::cases {
namespace {

Expectation parseExpectation(const YamlDocument& doc, const YAML::Node& e, const std::string& what,
                             const std::vector<std::string>& radiative_names,
                             const std::vector<std::string>& thermal_names) {
  doc.expectMap(e, what, {"quantity", "node", "to", "index", "value", "tolerance"});
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
  x.value = doc.number(doc.required(e, "value", what), what + ".value", -1e300, 1e300);
  x.tolerance = doc.number(doc.required(e, "tolerance", what), what + ".tolerance", 0.0, 1e300);
  return x;
}

}  // namespace

std::vector<Expectation> parseExpectations(const YamlDocument& doc, const YAML::Node& node,
                                           const std::vector<std::string>& radiative_names,
                                           const std::vector<std::string>& thermal_names) {
  doc.expectSequence(node, "expect");
  std::vector<Expectation> out;
  for (size_t i = 0; i < node.size(); ++i)
    out.push_back(parseExpectation(doc, node[i], "expect[" + std::to_string(i) + "]", radiative_names, thermal_names));
  return out;
}

}  // namespace radnet::cases
