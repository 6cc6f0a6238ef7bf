#include "cases/config/error_budget.hpp"
#include "cases/config/expect_block.hpp"
#include "cases/config/geometry_case.hpp"
#include "cases/config/primitive_specs.hpp"
#include "cases/config/shell_block.hpp"
#include "cases/config/work_estimate.hpp"
#include "geometry/scene/coincidence.hpp"

#include <cmath>
#include <iomanip>
#include <set>
#include <sstream>
#include <filesystem>

namespace radnet::cases {
namespace {

// What the surfaces of a case share while they are read: the case, and each node's material.
struct GeometryContext {
  GeometryCase& c;
  std::vector<std::string> material_names;
  std::map<std::string, std::string> node_material;  // node name → material
  // Node name → the entry that made it (its `where` and line), so that a later entry reaching
  // the same node without `join: true` is refused instead of merging silently.
  std::map<std::string, std::pair<std::string, int>> node_origin;
  std::string entry_where;  // the entry being read
  int entry_line = 0;
  bool entry_joins = false;
};

std::string materialOf(const YamlDocument& doc, const YAML::Node& node, const std::string& what,
                       const GeometryContext& ctx) {
  if (!node) return "";
  const std::string m = doc.string(node, what);
  if (!ctx.c.materials.count(m)) {
    std::string msg = what + ": unknown material '" + m + "'";
    if (auto near = nearestWord(m, ctx.material_names)) msg += " (did you mean '" + *near + "'?)";
    throw doc.error(node, msg);
  }
  if (!ctx.c.materials.at(m).has_optics)
    throw doc.error(node, what + ": material '" + m + "' has no emissivity and absorptivity; a surface side needs both");
  return m;
}

// A thin shell: beyond 0.1 m the plate is no longer thin against any sensible node, and a
// thickness of 2 is far likelier 2 mm than 2 m.
double parseThickness(const YamlDocument& doc, const YAML::Node& thickness, const std::string& what) {
  const double t = doc.number(thickness, what + ".thickness (m)", 1e-7, 1e3);
  if (t > 0.1)
    throw doc.error(thickness, what + ".thickness: " + std::to_string(t) +
                                   " m is not a thin shell; thicknesses are in metres (2 mm is 0.002)");
  return t;
}

// `shell: {material, thickness}` of a primitive whose faces are [first_face, end_face). A
// mesh may leave either out for its file to give (shellFromFile; checked after the build).
ShellSpec parseShell(const YamlDocument& doc, const YAML::Node& node, const std::string& what,
                     const GeometryContext& ctx, bool file_may_give) {
  doc.expectMap(node, what, {"material", "thickness"});
  ShellSpec shell;
  shell.what = what;
  const InputError where = doc.error(node, "");
  shell.file = where.file();
  shell.line = where.line();
  shell.column = where.column();
  if (file_may_give && !node["material"] && !node["thickness"]) return shell;
  if (file_may_give && !node["material"]) {
    shell.thickness_m = parseThickness(doc, doc.required(node, "thickness", what), what);
    return shell;
  }
  const YAML::Node mat = doc.required(node, "material", what);
  shell.material = doc.string(mat, what + ".material");
  const auto it = ctx.c.materials.find(shell.material);
  if (it == ctx.c.materials.end()) {
    std::string msg = what + ".material: unknown material '" + shell.material + "'";
    if (auto near = nearestWord(shell.material, ctx.material_names)) msg += " (did you mean '" + *near + "'?)";
    throw doc.error(mat, msg);
  }
  if (!it->second.has_bulk)
    throw doc.error(mat, what + ".material: '" + shell.material +
                             "' has no conductivity, density and specific_heat; a shell needs them");
  if (!file_may_give || node["thickness"]) shell.thickness_m = parseThickness(doc, doc.required(node, "thickness", what), what);
  return shell;
}

const PrimitiveSpec& primitiveSpec(const YamlDocument& doc, const YAML::Node& key, const std::string& where) {
  const std::string kind = key.Scalar();
  if (const PrimitiveSpec* spec = findPrimitive(kind)) return *spec;
  std::vector<std::string> kinds = {"include"};
  std::string expected;
  const auto& specs = primitiveSpecs();
  for (size_t k = 0; k < specs.size(); ++k) {
    kinds.emplace_back(specs[k].kind);
    expected += (k == 0 ? "" : k + 1 == specs.size() ? " or " : ", ") + std::string(specs[k].kind);
  }
  std::string msg = where + ": unknown primitive '" + kind + "'";
  if (auto near = nearestWord(kind, kinds)) msg += " (did you mean '" + *near + "'?)";
  throw doc.error(key, msg + "; expected " + expected);
}

// '.' joins the names radnet derives from a primitive (<name>.back, a box's <name>.+x, a
// grid's <name>.<i>.<j>): a rectangle named bus.+x would silently merge into the box's face.
void checkPrimitiveName(const YamlDocument& doc, const YAML::Node& p, const std::string& what, const std::string& name) {
  if (name.find('.') != std::string::npos)
    throw doc.error(p["name"], what + ".name: '" + name + "' contains '.', which is reserved for the node names "
                                      "radnet derives from a primitive (<name>.back, a box's <name>.+x, a grid's "
                                      "<name>.<i>.<j>); to add triangles to an existing node, name the surface "
                                      "exactly as that node's primitive");
}

// Where a surface goes: its name, its node's name and the file it came from ("" for a primitive).
struct SurfacePlace {
  const std::string& surface;
  const std::string& node;
  const std::string& mesh_file;
};

// Adds one surface with the materials of its sides ("" = inactive): node `node` for the front,
// `node`.back for the back; a node may not change material between surfaces.
void addSides(const YamlDocument& doc, const YAML::Node& entry, const std::string& what, const std::string& kind,
              const SurfacePlace& at, const geometry::TriangleSoup& soup, const std::string& front,
              const std::string& back, GeometryContext& ctx) {
  GeometryCase& c = ctx.c;
  const std::string label = kind + " '" + at.surface + "'" + (at.mesh_file.empty() ? "" : " from " + at.mesh_file);
  const std::string fn = front.empty() ? "" : at.node, bn = back.empty() ? "" : at.node + ".back";
  for (const auto& [nn, mat] : {std::pair{fn, front}, std::pair{bn, back}}) {
    if (nn.empty()) continue;
    const auto [origin, first] = ctx.node_origin.emplace(nn, std::pair{ctx.entry_where, ctx.entry_line});
    if (!first && origin->second.first != ctx.entry_where && !ctx.entry_joins)
      throw doc.error(entry, what + ": node '" + nn + "' is already made by " + origin->second.first + ":" +
                                 std::to_string(origin->second.second) +
                                 "; two surfaces reaching one node name would merge into one node unseen: "
                                 "give this one a name of its own, or 'join: true' to add its triangles to '" +
                                 nn + "'");
    auto [it, fresh] = ctx.node_material.emplace(nn, mat);
    if (!fresh && it->second != mat)
      throw geometry::GeometryError("node '" + nn + "' would have two materials ('" + it->second + "' and '" + mat +
                                    "')");
  }
  checkSceneMemory(doc, entry, what, static_cast<double>(c.scene.faces().size() + soup.triangles.size()));
  c.scene.addSurface(at.surface, label, soup, fn, bn);
}

// One `- <primitive>: {...}` entry: keys checked against its spec, sides' materials, then
// its builder adds the surfaces to the scene.
// Which entry adds surfaces now, for the error when it reaches a node another entry made.
void noteEntry(const YamlDocument& doc, const YAML::Node& entry, const std::string& where, const std::string& what,
               GeometryContext& ctx) {
  const YAML::Node p = entry.begin()->second;
  // `where` is unique within one file; the file name keeps entries of two includes apart.
  ctx.entry_where = where + " at " + doc.file();
  ctx.entry_line = entry.Mark().line + 1;
  ctx.entry_joins = p["join"] && doc.boolean(p["join"], what + ".join");
}

void parsePrimitive(const YamlDocument& doc, const YAML::Node& entry, const std::string& where, GeometryContext& ctx) {
  GeometryCase& c = ctx.c;
  const PrimitiveSpec& spec = primitiveSpec(doc, entry.begin()->first, where);
  const YAML::Node p = entry.begin()->second;
  const std::string what = where + "." + std::string(spec.kind);
  if (!p.IsMap()) throw doc.error(p, what + ": expected a mapping of parameters");
  std::vector<std::string> allowed = {"name", "front", "back", "subdivisions", "shell", "join"};
  allowed.insert(allowed.end(), spec.keys.begin(), spec.keys.end());
  doc.expectMap(p, what, allowed);
  const std::string name = doc.string(doc.required(p, "name", what), what + ".name");
  noteEntry(doc, entry, where, what, ctx);
  checkPrimitiveName(doc, p, what, name);
  const std::string front = materialOf(doc, p["front"], what + ".front", ctx);
  const std::string back = materialOf(doc, p["back"], what + ".back", ctx);
  // Neither side naming a material: a pure occluder (it blocks rays and belongs to no node).
  std::optional<ShellSpec> shell;
  if (p["shell"]) {
    if (front.empty() && back.empty())
      throw doc.error(p["shell"], what + ".shell: the surface names no material on either side, so it has no node "
                                         "to give the shell's capacitance and conductors to");
    shell = parseShell(doc, p["shell"], what + ".shell", ctx, spec.kind == "mesh");
  }
  const int first_face = static_cast<int>(c.scene.faces().size());
  std::vector<std::pair<int, int>> added;  // the scene faces of each add call, for a shell from the file
  auto place = [&](const std::string& surface, const std::string& node, const geometry::TriangleSoup& soup,
                   const std::string& mesh_file, const std::string& front_material, const std::string& back_material) {
    const int before = static_cast<int>(c.scene.faces().size());
    addSides(doc, entry, what, std::string(spec.kind), {surface, node, mesh_file}, soup, front_material, back_material,
             ctx);
    added.emplace_back(before, static_cast<int>(c.scene.faces().size()));
  };
  auto add = [&](const std::string& surface, const std::string& node, const geometry::TriangleSoup& soup,
                 const std::string& mesh_file) { place(surface, node, soup, mesh_file, front, back); };
  auto add_with_sides = [&](const std::string& surface, const std::string& node, const geometry::TriangleSoup& soup,
                            const std::string& mesh_file, const YAML::Node& sides, const std::string& sides_what) {
    doc.expectMap(sides, sides_what, {"front", "back"});
    place(surface, node, soup, mesh_file, materialOf(doc, sides["front"], sides_what + ".front", ctx),
          materialOf(doc, sides["back"], sides_what + ".back", ctx));
  };
  std::vector<PrimitiveInput::FileBulk> file_bulk;
  try {
    const auto subdivisions = parseCounts(doc, p["subdivisions"], what + ".subdivisions", spec.default_subdivisions);
    const int active_sides = (front.empty() ? 0 : 1) + (back.empty() ? 0 : 1);
    const auto note = [&](const std::string& kind, const std::string& at) { c.scene.noteDefect(kind, at); };
    PrimitiveInput input{doc, p, what, name, subdivisions, active_sides, c.scene.nodes().size(),
                         std::filesystem::path(doc.file()).parent_path(), add, !front.empty(), note, add_with_sides};
    input.file_bulk = &file_bulk;
    spec.build(input);
    if (shell) {
      shell->first_face = first_face;
      shell->end_face = static_cast<int>(c.scene.faces().size());
      if (shell->material.empty() || shell->thickness_m == 0.0)
        shellFromFile(doc, p["shell"], c.materials, added, file_bulk, *shell);
      c.shells.push_back(*shell);
    }
  } catch (const geometry::GeometryError& e) {
    throw doc.error(entry, what + ": " + e.what());
  }
}

void parseGeometryList(const YamlDocument& doc, const YAML::Node& geom, const std::string& list_what,
                       GeometryContext& ctx, int depth) {
  doc.expectSequence(geom, list_what);
  if (geom.size() == 0) throw doc.error(geom, list_what + ": the list is empty; expected at least one surface");
  for (size_t k = 0; k < geom.size(); ++k) {
    const YAML::Node entry = geom[k];
    const std::string where = list_what + "[" + std::to_string(k) + "]";
    if (!entry.IsMap() || entry.size() != 1)
      throw doc.error(entry, where + ": expected one primitive, e.g. '- rectangle: {...}'");
    if (entry.begin()->first.Scalar() == "include") {  // surfaces in another file, read with its own positions
      const YamlDocument inc = includeDocument(doc, entry.begin()->second, where + ".include", depth, ctx.c.included);
      parseGeometryList(inc, inc.root(), inc.file(), ctx, depth + 1);
      continue;
    }
    parsePrimitive(doc, entry, where, ctx);
  }
}

// Coordinates within 1000 km of the body origin (a spacecraft in metres; 35786 written for
// km, or 1e80, would make ray offsets, which scale with the largest coordinate, swamp the
// parts), and every triangle at least 1e-9 of that largest coordinate across (a 1e-9 m part
// 1e6 m from the origin is below what a double resolves there: its view factors came out 0).
std::string metres(double v) {
  std::ostringstream s;
  s << std::setprecision(6) << v << " m";
  return s.str();
}

std::string squareMetres(double v) {
  std::ostringstream s;
  s << std::setprecision(4) << v << " m²";
  return s.str();
}

void checkSceneScale(const YamlDocument& doc, const YAML::Node& geom, const geometry::Scene& scene) {
  constexpr double kMaxCoordinate = 1e6, kMinRelativeSize = 1e-9;
  double largest = 0.0;
  for (const auto& f : scene.faces())
    for (const auto& v : f.v) largest = std::max(largest, v.cwiseAbs().maxCoeff());
  if (!(largest <= kMaxCoordinate))
    throw doc.error(geom, "geometry: a coordinate of " + metres(largest) +
                              " lies beyond 1000 km of the origin: the model is in metres, in the body frame "
                              "(millimetres or kilometres meant? use a mesh's scale)");
  for (const auto& f : scene.faces()) {
    const double size = std::sqrt(2.0 * f.area_m2);
    if (size < kMinRelativeSize * largest)
      throw doc.error(geom, "geometry: a triangle of surface '" + scene.surfaceNames()[static_cast<size_t>(f.surface)] +
                                "' is " + metres(size) + " across, below 1e-9 of the largest coordinate (" +
                                metres(largest) + "): too small to resolve there; move the model "
                                "near the origin or scale it");
  }
}

// Coincident surfaces with a side facing the same way double every load and exchange of
// their overlap (geometry/scene/coincidence.hpp): refused, naming both.
void checkCoincidentSurfaces(const YamlDocument& doc, const YAML::Node& geom, const geometry::Scene& scene) {
  const std::vector<geometry::Coincidence> found = geometry::coincidentFaces(scene, 1);
  if (found.empty()) return;
  // A triangle as the user can find it: its number within its surface and the surface's label
  // (which names the mesh file).
  const auto triangle = [&](int face) {
    const int s = scene.faces()[static_cast<size_t>(face)].surface;
    return "triangle " + std::to_string(face - scene.surfaceFirstFace(s)) + " of " + scene.surfaceLabel(s);
  };
  const int sa = scene.faces()[static_cast<size_t>(found[0].face_a)].surface;
  const int sb = scene.faces()[static_cast<size_t>(found[0].face_b)].surface;
  const std::string a = scene.surfaceNames()[static_cast<size_t>(sa)], b = scene.surfaceNames()[static_cast<size_t>(sb)];
  throw doc.error(geom, "geometry: " + (sa == sb ? "surface '" + a + "' holds two coincident triangles"
                                                 : "surfaces '" + a + "' and '" + b + "' coincide") +
                            " (" + triangle(found[0].face_a) + " and " + triangle(found[0].face_b) + " overlap by " +
                            squareMetres(found[0].overlap_m2) +
                            " in one plane, a side of each facing the same way): rays cannot tell them "
                            "apart, so both would take the full sun there; offset one (a radiator on a box face: "
                            "make it the face's material, or lift it by its thickness)");
}

// The scene's nodes get their names and their material's optical properties.
void assignNodeMaterials(GeometryCase& c, const std::map<std::string, std::string>& node_material) {
  const int n = static_cast<int>(c.scene.nodes().size());
  c.emissivity.resize(n);
  c.absorptivity.resize(n);
  for (int i = 0; i < n; ++i) {
    const std::string& node = c.scene.nodes()[static_cast<size_t>(i)].name;
    const std::string& mat = node_material.at(node);
    c.node_names.push_back(node);
    c.node_material.push_back(mat);
    c.emissivity[i] = c.materials.at(mat).emissivity;
    c.absorptivity[i] = c.materials.at(mat).absorptivity;
  }
}

// A table against temperature with no temperatures to follow: say which value stood.
void warnUnfollowedTables(GeometryCase& c) {
  for (const std::string& m : std::set<std::string>(c.node_material.begin(), c.node_material.end()))
    if (c.materials.at(m).hasCurves())
      c.warnings.push_back("materials." + m + ": its ε/α table is taken at 293.15 K (no 'thermal:' block, so no "
                           "temperatures for it to follow)");
}

// `solver:` and its `view_factors:`.
void parseSolverBlock(const YamlDocument& doc, GeometryCase& c) {
  const YAML::Node& root = doc.root();
  c.solver = parseSolverSettings(doc, root["solver"]);
  c.output = parseOutputSettings(doc, root);
  if (root["solver"]) c.view_factors = parseViewFactorSettings(doc, root["solver"]["view_factors"]);
}

Eigen::VectorXd nodeAreas(const geometry::Scene& scene) {
  Eigen::VectorXd area(static_cast<Eigen::Index>(scene.nodes().size()));
  for (size_t i = 0; i < scene.nodes().size(); ++i) area[static_cast<Eigen::Index>(i)] = scene.nodes()[i].area_m2;
  return area;
}

}  // namespace

bool isGeometryCase(const YamlDocument& doc) { return doc.root().IsMap() && doc.root()["geometry"].IsDefined(); }


GeometryCase loadGeometryCase(const YamlDocument& doc) {
  const YAML::Node& root = doc.root();
  doc.expectMap(root, "case",
                {"name", "description", "materials", "geometry", "solver", "expect", "orbit", "attitude", "environment",
                 "thermal", "optics", "cases", "uncertainty", "limits", "articulation", "output"});
  GeometryCase c;
  c.file = doc.file();
  c.yaml_text = doc.text();
  c.name = doc.string(doc.required(root, "name", "case"), "name");

  parseMaterials(doc, doc.required(root, "materials", "case"), c.materials, c.included, 0);
  if (c.materials.empty()) throw doc.error(root["materials"], "materials: expected at least one material");
  GeometryContext ctx{c, {}, {}};
  for (const auto& [k, v] : c.materials) ctx.material_names.push_back(k);

  const YAML::Node geom = doc.required(root, "geometry", "case");
  parseGeometryList(doc, geom, "geometry", ctx, 0);
  try {
    c.seams = geometry::closeSeams(c.scene);
    for (const std::string& w : geometry::partialSeamWarnings(c.scene, c.seams)) c.warnings.push_back("geometry: " + w);
  } catch (const geometry::GeometryError& e) {
    throw doc.error(geom, std::string("geometry: ") + e.what());
  }
  checkNodeMemory(doc, geom, "geometry", static_cast<double>(c.scene.nodes().size()));
  try {
    c.scene.validate();
  } catch (const geometry::GeometryError& e) {
    throw doc.error(geom, std::string("geometry: ") + e.what());
  }
  checkSceneScale(doc, geom, c.scene);
  checkCoincidentSurfaces(doc, geom, c.scene);
  assignNodeMaterials(c, ctx.node_material);
  parseOpticalSets(doc, c);  // and, with specular surfaces, the network's ε/κ, α/κ (applySpecularOptics)

  parseSolverBlock(doc, c);
  warnSpecularSurfaces(c);  // against solver.accuracy
  parseDesignCases(doc, c);
  parseArticulation(doc, c);  // turns fixed-angle parts before the nodes' areas are read
  Eigen::VectorXd area = nodeAreas(c.scene);
  std::optional<double> orbit_period_s;
  for (const DesignCase& d : c.design_cases)
    if (d.orbit)
      for (const OrbitCase& oc : d.orbit->cases)
        orbit_period_s = std::min(orbit_period_s.value_or(oc.orbit->nodalPeriod()), oc.orbit->nodalPeriod());
  c.thermal = parseThermalSettings(doc, c.node_names, area, orbit_period_s);
  if (!c.thermal) warnUnfollowedTables(c);
  parseCaseDissipations(doc, c);
  parseOpticalUncertainty(doc, c);
  parseLimits(doc, c);
  applyShells(c);
  applyErrorBudget(c);
  checkWorkEstimate(doc, c);
  if (root["expect"]) {
    std::vector<std::string> case_names;
    for (const DesignCase& d : c.design_cases) case_names.push_back(d.name);
    c.expectations = parseExpectations(doc, root["expect"], c.node_names,
                                       c.thermal ? c.thermal->node_names : c.node_names, case_names);
  }
  return c;
}

}  // namespace radnet::cases
