// Shells: the capacitance and conductors a primitive's `shell: {material, thickness}` gives
// its nodes (docs/case-files.md, "Shells").
#include "cases/config/shell_block.hpp"
#include "geometry/scene/shell.hpp"

#include <cmath>
#include <map>
#include <set>
#include <sstream>

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

// The faces' bulk: the file's (face_bulk) or the material's and thickness for all.
std::vector<ShellSpec::FaceBulk> faceBulk(const GeometryCase& c, const ShellSpec& shell) {
  if (!shell.face_bulk.empty()) return shell.face_bulk;
  const Material& m = c.materials.at(shell.material);
  return std::vector<ShellSpec::FaceBulk>(static_cast<size_t>(shell.end_face - shell.first_face),
                                          {shell.thickness_m, m.conductivity, m.density * m.specific_heat});
}

std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

void shellFromFile(const YamlDocument& doc, const YAML::Node& shell_node, const std::map<std::string, Material>& materials,
                   const std::vector<std::pair<int, int>>& ranges, const std::vector<PrimitiveInput::FileBulk>& bulk,
                   ShellSpec& shell) {
  const Material* given = shell.material.empty() ? nullptr : &materials.at(shell.material);
  shell.face_bulk.assign(static_cast<size_t>(shell.end_face - shell.first_face), {});
  for (size_t k = 0; k < ranges.size() && k < bulk.size(); ++k) {
    const PrimitiveInput::FileBulk& b = bulk[k];
    const double t = shell.thickness_m > 0 ? shell.thickness_m : b.thickness_m;
    if (!(t > 0))
      throw doc.error(shell_node, shell.what + ".thickness: not given, and " + b.group +
                                      " has no PSHELL thickness (only a NASTRAN file's PSHELL can give one); give shell.thickness (m)");
    if (t > 0.1)
      throw doc.error(shell_node, shell.what + ": the PSHELL thickness of " + b.group + " is " + number(t) +
                                      " m, not a thin shell (is the file's length unit what scale says?)");
    ShellSpec::FaceBulk face{t, 0.0, 0.0};
    if (given) {
      face.conductivity = given->conductivity;
      face.rho_c = given->density * given->specific_heat;
    } else {
      if (!(b.conductivity > 0 && b.density > 0 && b.specific_heat > 0))
        throw doc.error(shell_node, shell.what + ".material: not given, and " + b.group +
                                        " has no MAT4 with K, CP and RHO (only a NASTRAN file's can give them); give shell.material");
      // MAT4 values are read as SI whatever the file's length unit: a file in mm-tonne-s
      // gives RHO ~ 1e-9 and CP ~ 1e8, which these ranges refuse rather than use.
      auto check = [&](double v, const char* field, const char* unit, double lo, double hi) {
        if (!(v >= lo && v <= hi))
          throw doc.error(shell_node, shell.what + ": " + b.group + " has " + field + " = " + number(v) +
                                          ", not a plausible value in " + unit + " (MAT4 is read in SI units); "
                                          "give shell.material");
      };
      check(b.conductivity, "K", "W/(m K)", 1e-3, 1e4);
      check(b.density, "RHO", "kg/m³", 1.0, 1e5);
      check(b.specific_heat, "CP", "J/(kg K)", 10.0, 1e5);
      face.conductivity = b.conductivity;
      face.rho_c = b.density * b.specific_heat;
    }
    for (int f = ranges[k].first; f < ranges[k].second; ++f)
      shell.face_bulk[static_cast<size_t>(f - shell.first_face)] = face;
  }
}

void applyShells(GeometryCase& c) {
  for (const ShellSpec& shell : c.shells) {
    if (!c.thermal)
      throw InputError(shell.file, shell.line, shell.column,
                       shell.what + ": a shell gives capacitance and conductors to the thermal model; add a "
                                    "'thermal:' block (or remove the shell)");
    ThermalSettings& ts = *c.thermal;
    const std::vector<ShellSpec::FaceBulk> bulk = faceBulk(c, shell);
    auto bulkOf = [&](int f) -> const ShellSpec::FaceBulk& { return bulk[static_cast<size_t>(f - shell.first_face)]; };
    // Capacitance ρ c t A per triangle; a two-sided triangle gives half to each side's node,
    // so that the panel holds ρ c t A in all, not twice that. Each node's k t, area-weighted
    // over its faces, for the in-plane conductors below (one value where the bulk is uniform).
    Eigen::VectorXd added = Eigen::VectorXd::Zero(ts.nodeCount());
    std::map<int, std::pair<double, double>> node_kt;  // node → (Σ A k t, Σ A)
    for (int f = shell.first_face; f < shell.end_face; ++f) {
      const geometry::Face& face = c.scene.faces()[static_cast<size_t>(f)];
      const ShellSpec::FaceBulk& fb = bulkOf(f);
      const bool two_sided = face.front_node >= 0 && face.back_node >= 0;
      for (int node : {face.front_node, face.back_node}) {
        if (node < 0) continue;
        added[node] += fb.rho_c * fb.thickness_m * face.area_m2 * (two_sided ? 0.5 : 1.0);
        auto& [akt, area] = node_kt[node];
        akt += face.area_m2 * fb.conductivity * fb.thickness_m;
        area += face.area_m2;
      }
    }
    ts.capacitance += added;
    for (auto& [i, table] : ts.capacitance_tables)  // "added to any given": tables shift by the shell's part
      for (double& value : table.value) value += added[i];
    // In-plane k t L / d between neighbours of the same side (a two-sided shell carries half
    // of its thickness on each side's network, so the panel conducts k t L / d in all); where
    // k t differs, the two half-paths in series, L / (d_a / (k t)_a + d_b / (k t)_b). And
    // k A / t through the thickness between each element's front and back node.
    const geometry::ShellAdjacency adj = geometry::shellAdjacency(c.scene, shell.first_face, shell.end_face);
    const double sides = adj.front_back.empty() ? 1.0 : 0.5;
    const bool uniform = shell.face_bulk.empty();
    auto ktOf = [&](int node) { return node_kt.at(node).first / node_kt.at(node).second; };
    for (const auto& nb : adj.neighbours) {
      const double g =
          uniform ? bulk.front().conductivity * (sides * bulk.front().thickness_m) * nb.shared_length_m / nb.distance_m
                  : nb.shared_length_m / (nb.distance_a_m / (sides * ktOf(nb.a)) + nb.distance_b_m / (sides * ktOf(nb.b)));
      ts.conductors.emplace_back(nb.a, nb.b, g);
      ts.conductors.emplace_back(nb.b, nb.a, g);
    }
    std::map<std::pair<int, int>, double> through;  // (front, back) → Σ k A / t
    for (const auto& fb : adj.front_back)
      if (uniform) through[{fb.front, fb.back}] = bulk.front().conductivity * fb.area_m2 / bulk.front().thickness_m;
    for (int f = shell.first_face; f < shell.end_face && !uniform; ++f) {
      const geometry::Face& face = c.scene.faces()[static_cast<size_t>(f)];
      if (face.front_node < 0 || face.back_node < 0) continue;
      through[{face.front_node, face.back_node}] += bulkOf(f).conductivity * face.area_m2 / bulkOf(f).thickness_m;
    }
    warnIfDisconnected(c, shell, adj, ts);
    for (const auto& [pair, g] : through) {
      ts.conductors.emplace_back(pair.first, pair.second, g);
      ts.conductors.emplace_back(pair.second, pair.first, g);
    }
  }
}

}  // namespace radnet::cases
