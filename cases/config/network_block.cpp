#include "cases/config/network_case.hpp"

#include "cases/config/expect_block.hpp"
#include "cases/config/solver_block.hpp"

#include <cmath>
#include <limits>
#include <unordered_map>

namespace radnet::cases {
namespace {

constexpr double kHuge = std::numeric_limits<double>::max();
// An exitance beyond 1e15 W/m² (a 1e5 K black body is 5.7e12) would overflow the residual
// norms of the band solve into infinities and NaN.
constexpr double kMaxExitance = 1e15;  // W/m²

Eigen::MatrixXd parseDenseViewFactors(const YamlDocument& doc, const YAML::Node& node, int n) {
  doc.expectSequence(node, "network.view_factors");
  if (static_cast<int>(node.size()) != n)
    throw doc.error(node, "network.view_factors: " + std::to_string(node.size()) + " rows; expected " +
                              std::to_string(n) + " (one per node, in node order)");
  Eigen::MatrixXd f(n, n);
  for (int i = 0; i < n; ++i) {
    const YAML::Node row = node[static_cast<size_t>(i)];
    const std::string what = "network.view_factors[" + std::to_string(i) + "]";
    doc.expectSequence(row, what);
    if (static_cast<int>(row.size()) != n)
      throw doc.error(row, what + ": " + std::to_string(row.size()) + " entries; expected " + std::to_string(n));
    for (int j = 0; j < n; ++j)
      f(i, j) = doc.number(row[static_cast<size_t>(j)], what + "[" + std::to_string(j) + "]", 0.0, 1.0);
  }
  return f;
}

Eigen::SparseMatrix<double> parseEntries(const YamlDocument& doc, const YAML::Node& node,
                                         const std::unordered_map<std::string, int>& index, int n) {
  doc.expectSequence(node, "network.view_factor_entries");
  std::vector<Eigen::Triplet<double>> triplets;
  for (size_t k = 0; k < node.size(); ++k) {
    const YAML::Node e = node[k];
    const std::string what = "network.view_factor_entries[" + std::to_string(k) + "]";
    if (!e.IsSequence() || e.size() != 3) throw doc.error(e, what + ": expected [from_node, to_node, view_factor]");
    int ij[2];
    for (int s = 0; s < 2; ++s) {
      const std::string name = doc.string(e[static_cast<size_t>(s)], what);
      auto it = index.find(name);
      if (it == index.end()) throw doc.error(e[static_cast<size_t>(s)], what + ": no node named '" + name + "'");
      ij[s] = it->second;
    }
    triplets.emplace_back(ij[0], ij[1], doc.number(e[2], what + " view factor", 0.0, 1.0));
  }
  Eigen::SparseMatrix<double> f(n, n);
  f.setFromTriplets(triplets.begin(), triplets.end());  // duplicates are summed
  return f;
}

// `network.nodes`: names, areas, reflectances (or emissivities) and initial exitances.
std::unordered_map<std::string, int> parseNodes(const YamlDocument& doc, const YAML::Node& nodes, NetworkCase& c) {
  doc.expectSequence(nodes, "network.nodes");
  const int n = static_cast<int>(nodes.size());
  if (n == 0) throw doc.error(nodes, "network.nodes: the list is empty; expected at least one node");
  c.area.resize(n);
  c.reflectance.resize(n);
  c.initial_exitance.resize(n);
  Eigen::VectorXd emissivity(n);
  int with_emissivity = 0;
  std::unordered_map<std::string, int> index;
  for (int i = 0; i < n; ++i) {
    const YAML::Node node = nodes[static_cast<size_t>(i)];
    const std::string what = "network.nodes[" + std::to_string(i) + "]";
    doc.expectMap(node, what, {"name", "area", "reflectance", "emissivity", "initial_exitance"});
    const std::string name = doc.string(doc.required(node, "name", what), what + ".name");
    if (!index.emplace(name, i).second) throw doc.error(node["name"], what + ".name: '" + name + "' is used twice");
    c.names.push_back(name);
    c.area[i] =
        doc.number(doc.required(node, "area", what), what + ".area (m²)", std::numeric_limits<double>::min(), kHuge);
    if (node["emissivity"]) {
      emissivity[i] = doc.number(node["emissivity"], what + ".emissivity", 0.0, 1.0);
      ++with_emissivity;
    }
    if (node["reflectance"]) {
      c.reflectance[i] = doc.number(node["reflectance"], what + ".reflectance", 0.0, 1.0);
    } else if (node["emissivity"]) {
      c.reflectance[i] = 1.0 - emissivity[i];  // grey opaque surface: ρ = 1 − ε
    } else {
      throw doc.error(node, what + ": missing 'reflectance' (or 'emissivity', from which ρ = 1 − ε)");
    }
    c.initial_exitance[i] = node["initial_exitance"]
                                ? doc.number(node["initial_exitance"], what + ".initial_exitance (W/m²)", -kMaxExitance, kMaxExitance)
                                : 0.0;
  }
  if (with_emissivity != 0 && with_emissivity != n)
    throw doc.error(nodes, "network.nodes: 'emissivity' is given for " + std::to_string(with_emissivity) + " of " +
                               std::to_string(n) + " nodes; expected all or none");
  if (with_emissivity == n) c.emissivity = emissivity;
  return index;
}

// The `network:` block: nodes, view factors (dense rows or sparse entries), tolerances.
void parseNetwork(const YamlDocument& doc, const YAML::Node& net, NetworkCase& c) {
  doc.expectMap(net, "network",
                {"nodes", "view_factors", "view_factor_entries", "row_sum_tolerance", "reciprocity_tolerance"});
  c.network_line = net.Mark().line + 1;
  c.network_column = net.Mark().column + 1;
  const auto index = parseNodes(doc, doc.required(net, "nodes", "network"), c);
  const int n = static_cast<int>(c.names.size());
  const bool dense = net["view_factors"].IsDefined(), entries = net["view_factor_entries"].IsDefined();
  if (dense == entries)
    throw doc.error(net, "network: expected exactly one of 'view_factors' (n×n rows) or 'view_factor_entries'");
  if (dense) {
    c.view_factors = parseDenseViewFactors(doc, net["view_factors"], n);
  } else {
    c.sparse = true;
    c.view_factors_sparse = parseEntries(doc, net["view_factor_entries"], index, n);
  }
  if (net["row_sum_tolerance"])
    // Above 0.1 a row summing to 1.5 would pass and give a negative GR to space.
    c.tolerances.row_sum = doc.number(net["row_sum_tolerance"], "network.row_sum_tolerance", 0.0, 0.1);
  if (net["reciprocity_tolerance"])
    c.tolerances.reciprocity = doc.number(net["reciprocity_tolerance"], "network.reciprocity_tolerance", 0.0, 1.0);
}

}  // namespace

bool isNetworkCase(const YamlDocument& doc) { return doc.root().IsMap() && doc.root()["network"].IsDefined(); }

NetworkCase loadNetworkCase(const YamlDocument& doc) {
  const YAML::Node& root = doc.root();
  doc.expectMap(root, "case", {"name", "description", "network", "solver", "thermal", "expect", "output"});
  NetworkCase c;
  c.file = doc.file();
  c.yaml_text = doc.text();
  c.name = doc.string(doc.required(root, "name", "case"), "name");
  parseNetwork(doc, doc.required(root, "network", "case"), c);
  c.solver = parseSolverSettings(doc, root["solver"]);
  c.output = parseOutputSettings(doc, root);
  if (root["solver"] && root["solver"]["view_factors"])
    throw doc.error(root["solver"]["view_factors"],
                    "solver.view_factors: only for geometry cases; this case gives the view factors");
  // The budget splits accuracy over rays and load samples; a network case has neither.
  if (root["solver"] && root["solver"]["accuracy"])
    throw doc.error(root["solver"]["accuracy"],
                    "solver.accuracy is the error budget of a geometry case (rays, load sampling); this case's view "
                    "factors are given exactly, so give solver.tolerance for the band solve instead");
  c.thermal = parseThermalSettings(doc, c.names, c.area, std::nullopt);
  if (c.thermal && !c.emissivity)
    throw doc.error(root["thermal"], "thermal: temperatures need the nodes' 'emissivity' (for the exchange factors)");
  if (root["expect"])
    c.expectations = parseExpectations(doc, root["expect"], c.names, c.thermal ? c.thermal->node_names : c.names);
  // Validate the network now, so that `radnet validate` catches what `run` would.
  (void)c.buildNetwork();
  return c;
}

solver::Network NetworkCase::buildNetwork() const {
  try {
    if (sparse) return solver::Network(names, area, view_factors_sparse, {}, tolerances);
    return solver::Network(names, area, view_factors, {}, tolerances);
  } catch (const solver::NetworkError& e) {
    throw InputError(file, network_line, network_column, std::string("network: ") + e.what());
  }
}

}  // namespace radnet::cases
