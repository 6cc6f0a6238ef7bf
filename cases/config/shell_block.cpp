// Shells: the capacitance and conductors a primitive's `shell: {material, thickness}` gives
// its nodes (docs/case-files.md, "Shells").
#include "cases/config/geometry_case.hpp"
#include "geometry/scene/shell.hpp"

#include <cmath>
#include <map>
#include <set>

namespace radnet::cases {
namespace {

// A shell whose nodes on one side fall into pieces that no in-plane conductor joins is
// legal (separate parts in one mesh) but usually means edges that do not coincide, such as
// T-junctions between different subdivisions: say so rather than conduct nothing silently.
void warnIfDisconnected(const GeometryCase& c, const ShellSpec& shell, const geometry::ShellAdjacency& adj,
                        ThermalSettings& ts) {
  std::map<int, int> parent;  // node → representative, over the shell's nodes
  for (int f = shell.first_face; f < shell.end_face; ++f)
    for (int node : {c.scene.faces()[static_cast<size_t>(f)].front_node, c.scene.faces()[static_cast<size_t>(f)].back_node})
      if (node >= 0) parent.emplace(node, node);
  auto find = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (const auto& nb : adj.neighbours) parent[find(nb.a)] = find(nb.b);
  for (int side : {+1, -1}) {
    std::set<int> pieces;
    for (const auto& [node, rep] : parent)
      if (c.scene.nodes()[static_cast<size_t>(node)].side == side) pieces.insert(find(node));
    if (pieces.size() > 1)
      ts.warnings.push_back(shell.what + ": the " + (side > 0 ? "front" : "back") + " nodes fall into " +
                            std::to_string(pieces.size()) +
                            " pieces that no in-plane conductor joins (triangle edges that do not coincide, e.g. "
                            "T-junctions between different subdivisions?)");
  }
}

}  // namespace

void applyShells(GeometryCase& c) {
  for (const ShellSpec& shell : c.shells) {
    if (!c.thermal)
      throw InputError(shell.file, shell.line, shell.column,
                       shell.what + ": a shell gives capacitance and conductors to the thermal model; add a "
                                    "'thermal:' block (or remove the shell)");
    ThermalSettings& ts = *c.thermal;
    const Material& m = c.materials.at(shell.material);
    const double t = shell.thickness_m, k = m.conductivity, rho_c = m.density * m.specific_heat;
    // Capacitance ρ c t A per triangle; a two-sided triangle gives half to each side's node,
    // so that the panel holds ρ c t A in all, not twice that.
    Eigen::VectorXd added = Eigen::VectorXd::Zero(ts.nodeCount());
    for (int f = shell.first_face; f < shell.end_face; ++f) {
      const geometry::Face& face = c.scene.faces()[static_cast<size_t>(f)];
      const bool two_sided = face.front_node >= 0 && face.back_node >= 0;
      for (int node : {face.front_node, face.back_node})
        if (node >= 0) added[node] += rho_c * t * face.area_m2 * (two_sided ? 0.5 : 1.0);
    }
    ts.capacitance += added;
    for (auto& [i, table] : ts.capacitance_tables)  // "added to any given": tables shift by the shell's part
      for (double& value : table.value) value += added[i];
    // In-plane k t L / d between neighbours of the same side (a two-sided shell carries half
    // of its thickness on each side's network, so the panel conducts k t L / d in all), and
    // k A / t through the thickness between each element's front and back node.
    const geometry::ShellAdjacency adj = geometry::shellAdjacency(c.scene, shell.first_face, shell.end_face);
    bool two_sided = !adj.front_back.empty();
    for (const auto& nb : adj.neighbours) {
      const double g = k * (two_sided ? 0.5 * t : t) * nb.shared_length_m / nb.distance_m;
      ts.conductors.emplace_back(nb.a, nb.b, g);
      ts.conductors.emplace_back(nb.b, nb.a, g);
    }
    warnIfDisconnected(c, shell, adj, ts);
    for (const auto& fb : adj.front_back) {
      const double g = k * fb.area_m2 / t;
      ts.conductors.emplace_back(fb.front, fb.back, g);
      ts.conductors.emplace_back(fb.back, fb.front, g);
    }
  }
}

}  // namespace radnet::cases
