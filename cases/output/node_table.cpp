#include "cases/output/node_table.hpp"

#include "geometry/scene/scene.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <map>
#include <numeric>
#include <ostream>
#include <sstream>

namespace radnet::cases {
namespace {

NodeGroups groupsByKey(const std::vector<std::string>& keys) {
  NodeGroups g;
  std::map<std::string, int> index;
  for (const std::string& key : keys) {
    const auto [it, added] = index.emplace(key, static_cast<int>(g.names.size()));
    if (added) g.names.push_back(key);
    g.of_node.push_back(it->second);
  }
  return g;
}

// A primitive's node grid names its cells <primitive>.<i>.<j> (cases/config/primitive_specs.cpp):
// the two cell indices are dropped; any other name is its own primitive.
std::string primitiveOf(const std::string& surface) {
  std::string s = surface;
  for (int k = 0; k < 2; ++k) {
    const size_t dot = s.rfind('.');
    const bool index = dot != std::string::npos && dot + 1 < s.size() &&
                       s.find_first_not_of("0123456789", dot + 1) == std::string::npos;
    if (!index) return surface;
    s.resize(dot);
  }
  return s;
}

double columnScale(const NodeColumn& c) { return c.values.size() ? c.values.cwiseAbs().maxCoeff() : 0.0; }

void printValue(const NodeColumn& c, double v, double scale, std::ostream& out) {
  if (std::abs(v) < 1e-12 * scale) v = 0.0;
  if (c.fixed) {
    std::ostringstream text;
    text << std::fixed << std::setprecision(c.precision) << v;
    // A value too wide for fixed notation (a 1e8 K node) would run into its neighbour.
    if (static_cast<int>(text.str().size()) >= c.width) {
      text.str("");
      text << std::defaultfloat << std::setprecision(std::max(1, c.width - 6)) << v;
    }
    out << std::setw(c.width) << text.str();
  } else
    out << std::setprecision(c.precision) << std::setw(c.width) << v;
}

void printText(const NodeColumn& c, const std::string& text, std::ostream& out) {
  out << "  " << std::left << std::setw(c.width - 2) << text << std::right;
}

// One node's row.
void nodeRow(const std::string& name, Eigen::Index i, const std::vector<NodeColumn>& columns,
             const std::vector<double>& scales, int name_width, std::ostream& out) {
  out << std::left << std::setw(name_width) << name << std::right;
  for (size_t k = 0; k < columns.size(); ++k) {
    const NodeColumn& c = columns[k];
    if (!c.text.empty())
      printText(c, i < static_cast<Eigen::Index>(c.text.size()) ? c.text[static_cast<size_t>(i)] : "-", out);
    else if (i < c.values.size())
      printValue(c, c.values[i], scales[k], out);
    else
      out << std::setw(c.width) << "-";
  }
  out << "\n";
}

// One group's row: each column's aggregate over the group's nodes that have a value; a text
// column shows the text of the node that set the Min/Max of the column it follows.
void groupRow(const std::string& label, const std::vector<Eigen::Index>& members, const std::vector<NodeColumn>& columns,
              const std::vector<double>& scales, int name_width, std::ostream& out) {
  std::vector<double> value(columns.size(), 0.0);
  std::vector<Eigen::Index> setter(columns.size(), -1);
  std::vector<int> count(columns.size(), 0);
  for (size_t k = 0; k < columns.size(); ++k) {
    const NodeColumn& c = columns[k];
    if (!c.text.empty()) continue;
    for (Eigen::Index i : members) {
      if (i >= c.values.size()) continue;
      const double v = c.values[i];
      const bool first = count[k]++ == 0;
      if (c.aggregate == Aggregate::Mean || c.aggregate == Aggregate::Sum)
        value[k] += v;
      else if (first || (c.aggregate == Aggregate::Min ? v < value[k] : v > value[k]))
        value[k] = v, setter[k] = i;
    }
    if (c.aggregate == Aggregate::Mean && count[k]) value[k] /= count[k];
  }
  out << std::left << std::setw(name_width) << label << std::right;
  for (size_t k = 0; k < columns.size(); ++k) {
    const NodeColumn& c = columns[k];
    if (!c.text.empty()) {
      const Eigen::Index i = c.follows >= 0 ? setter[static_cast<size_t>(c.follows)] : -1;
      printText(c, i >= 0 && i < static_cast<Eigen::Index>(c.text.size()) ? c.text[static_cast<size_t>(i)] : "-", out);
    } else if (count[k]) {
      printValue(c, value[k], scales[k], out);
    } else {
      out << std::setw(c.width) << "-";
    }
  }
  out << "\n";
}

}  // namespace

NodeGroups groupsByPrimitive(const geometry::Scene& scene, const std::vector<std::string>& node_names) {
  std::vector<std::string> keys;
  const auto& nodes = scene.nodes();
  for (size_t i = 0; i < node_names.size(); ++i) {
    if (i >= nodes.size() || nodes[i].faces.empty()) {
      keys.push_back(node_names[i]);
      continue;
    }
    const int surface = scene.faces()[static_cast<size_t>(nodes[i].faces.front())].surface;
    keys.push_back(primitiveOf(scene.surfaceNames()[static_cast<size_t>(surface)]) + (nodes[i].side < 0 ? ".back" : ""));
  }
  return groupsByKey(keys);
}

NodeGroups groupsByNamePrefix(const std::vector<std::string>& node_names) {
  std::vector<std::string> keys;
  for (const std::string& n : node_names) keys.push_back(n.substr(0, n.find('.')));
  return groupsByKey(keys);
}

void printNodeTable(const std::vector<std::string>& names, const NodeGroups& groups,
                    const std::vector<NodeColumn>& columns, const NodeTableOptions& options, std::ostream& out) {
  std::vector<double> scales;
  for (const NodeColumn& c : columns) scales.push_back(columnScale(c));
  size_t longest = 0;  // names and group labels, so the columns line up
  for (const std::string& name : names) longest = std::max(longest, name.size());
  for (const std::string& name : groups.names) longest = std::max(longest, name.size() + 8);
  NodeTableOptions o = options;
  o.name_width = std::max(o.name_width, static_cast<int>(std::min<size_t>(longest + 1, 40)));
  out << std::left << std::setw(o.name_width) << "node" << std::right;
  for (const NodeColumn& c : columns)
    if (c.text.empty())
      out << std::setw(c.width) << c.header;
    else
      printText(c, c.header, out);
  out << "\n";
  const auto n = static_cast<Eigen::Index>(names.size());
  if (o.all || names.size() <= kAllRowsUpTo) {
    for (Eigen::Index i = 0; i < n; ++i) nodeRow(names[static_cast<size_t>(i)], i, columns, scales, o.name_width, out);
    return;
  }
  // The extremes of the key column, largest first, then the smallest.
  const Eigen::VectorXd& key = columns[static_cast<size_t>(o.key_column)].values;
  std::vector<Eigen::Index> order(static_cast<size_t>(std::min(n, key.size())));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  std::stable_sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) { return key[a] > key[b]; });
  const size_t ends = std::min(order.size() / 2, static_cast<size_t>(o.extremes));
  out << "  largest " << columns[static_cast<size_t>(o.key_column)].header << ":\n";
  for (size_t k = 0; k < ends; ++k) nodeRow(names[static_cast<size_t>(order[k])], order[k], columns, scales, o.name_width, out);
  out << "  smallest:\n";
  for (size_t k = 0; k < ends; ++k) {
    const Eigen::Index i = order[order.size() - 1 - k];
    nodeRow(names[static_cast<size_t>(i)], i, columns, scales, o.name_width, out);
  }
  std::vector<std::vector<Eigen::Index>> members(groups.names.size());
  for (Eigen::Index i = 0; i < n; ++i) members[static_cast<size_t>(groups.of_node[static_cast<size_t>(i)])].push_back(i);
  out << "  by primitive (" << names.size() << " nodes in " << groups.names.size()
      << " groups: a row sums W and m², averages ratios, takes the extremes of K; --all for every node):\n";
  for (size_t g = 0; g < members.size(); ++g)
    groupRow(groups.names[g] + " (" + std::to_string(members[g].size()) + ")", members[g], columns, scales,
             o.name_width, out);
}

}  // namespace radnet::cases
