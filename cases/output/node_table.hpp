#pragma once
// Per-node tables of the console summary that stay readable on large models: up to
// kAllRowsUpTo nodes (or with --all) one row per node; beyond, the extremes of the table's
// key column first, then one row per group of nodes (a primitive, a side of one).
#include <Eigen/Dense>

#include <iosfwd>
#include <string>
#include <vector>

namespace radnet::geometry {
class Scene;
}

namespace radnet::cases {

/// Nodes grouped for the summary.
struct NodeGroups {
  std::vector<int> of_node;        ///< group of each node
  std::vector<std::string> names;  ///< each group's name
};

/// Groups by the primitive (surface) a node's triangles come from, its back sides apart
/// ("<surface>.back"); nodes without triangles (lumped) each form their own group.
NodeGroups groupsByPrimitive(const geometry::Scene& scene, const std::vector<std::string>& node_names);

/// Groups by the node name up to its first '.' (networks, where there is no scene).
NodeGroups groupsByNamePrefix(const std::vector<std::string>& node_names);

/// How a group row combines its nodes' values.
enum class Aggregate { Min, Max, Mean, Sum };

struct NodeColumn {
  std::string header;
  Eigen::VectorXd values;  ///< one per node (rows beyond it print as "-")
  Aggregate aggregate = Aggregate::Mean;
  int precision = 5;
  bool fixed = false;  ///< fixed-point (temperatures), else general
  int width = 12;
  /// Text per node shown instead of the value (e.g. the design case that sets an extreme);
  /// a group row shows the text of the node that set column `follows`'s aggregate.
  std::vector<std::string> text;
  int follows = -1;
};

struct NodeTableOptions {
  bool all = false;    ///< every node, whatever the size (`radnet run --all`)
  int key_column = 0;  ///< extremes are ranked by this column
  int extremes = 5;    ///< nodes shown from each end when grouped
  int name_width = 20;
};

constexpr size_t kAllRowsUpTo = 40;

/// Prints the header and the rows. A value smaller than 1e-12 of its column's largest
/// magnitude prints as 0 (round-off such as −2.3e-15 W is not a heat flow).
void printNodeTable(const std::vector<std::string>& names, const NodeGroups& groups,
                    const std::vector<NodeColumn>& columns, const NodeTableOptions& options, std::ostream& out);

}  // namespace radnet::cases
