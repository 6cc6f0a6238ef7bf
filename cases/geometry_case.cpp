#include "cases/geometry_case.hpp"

#include "cases/expectations.hpp"
#include "geometry/mesh_io.hpp"
#include "geometry/primitives.hpp"

#include <filesystem>
#include <sstream>
#include <unistd.h>
#include <limits>

namespace radnet::cases {
namespace {

using geometry::Vec3;
constexpr double kBig = std::numeric_limits<double>::max();

Vec3 vec3(const YamlDocument& doc, const YAML::Node& node, const std::string& what) {
  if (!node.IsSequence() || node.size() != 3) throw doc.error(node, what + ": expected [x, y, z]");
  return Vec3(doc.number(node[0], what + "[0]", -kBig, kBig), doc.number(node[1], what + "[1]", -kBig, kBig),
              doc.number(node[2], what + "[2]", -kBig, kBig));
}

// `subdivisions: [a, b]` or a single count.
std::pair<int, int> subdivisions(const YamlDocument& doc, const YAML::Node& node, const std::string& what, int da,
                                 int db) {
  if (!node) return {da, db};
  if (node.IsScalar()) {
    const int n = static_cast<int>(doc.integer(node, what, 1, 10000));
    return {n, n};
  }
  if (!node.IsSequence() || node.size() != 2) throw doc.error(node, what + ": expected [count, count] or a count");
  return {static_cast<int>(doc.integer(node[0], what + "[0]", 1, 10000)),
          static_cast<int>(doc.integer(node[1], what + "[1]", 1, 10000))};
}

double optionalNumber(const YamlDocument& doc, const YAML::Node& map, const char* key, const std::string& what,
                      double fallback, double lo, double hi) {
  return map[key] ? doc.number(map[key], what + "." + key, lo, hi) : fallback;
}

geometry::Sweep sweep(const YamlDocument& doc, const YAML::Node& map, const std::string& what) {
  geometry::Sweep s;
  if (map["angles"]) {
    const YAML::Node a = map["angles"];
    if (!a.IsSequence() || a.size() != 2) throw doc.error(a, what + ".angles: expected [start, end] in degrees");
    s.start_deg = doc.number(a[0], what + ".angles[0] (deg)", -360, 360);
    s.end_deg = doc.number(a[1], what + ".angles[1] (deg)", -360, 720);
  }
  if (map["reference"]) s.reference = vec3(doc, map["reference"], what + ".reference");
  return s;
}

// Dense n × n matrices of a run (raw and corrected F, their errors, G, GR and its LU)
// take about 6 × 8 n² bytes: refuse a network that cannot fit in this machine's memory
// before building anything.
void checkNodeMemory(const YamlDocument& doc, const YAML::Node& where, const std::string& what, double nodes) {
  const double physical = double(::sysconf(_SC_PHYS_PAGES)) * double(::sysconf(_SC_PAGE_SIZE));
  const double need = 48.0 * nodes * nodes;
  if (need > 0.75 * physical) {
    std::ostringstream s;
    s << what << ": " << nodes << " thermal nodes need about " << need / 1073741824.0
      << " GiB for the dense node × node matrices; this machine has " << physical / 1073741824.0
      << " GiB. Use fewer nodes (subdivisions refine the mesh, not the node count)";
    throw doc.error(where, s.str());
  }
}

struct SurfaceEntry {
  std::string kind, name, front, back;
  YAML::Node node;
};

struct GeometryContext {
  GeometryCase& c;
  std::vector<std::string> material_names;
  std::map<std::string, std::string> node_material;  // node name → material
};

// Reads an included YAML file named by `node` (relative to the including file).
std::pair<YamlDocument, std::string> includeDocument(const YamlDocument& doc, const YAML::Node& node,
                                                     const std::string& what, int depth, GeometryCase& c) {
  if (depth >= 8) throw doc.error(node, what + ": includes nested more than 8 deep (a cycle?)");
  std::filesystem::path path = doc.string(node, what);
  if (path.is_relative()) path = std::filesystem::path(doc.file()).parent_path() / path;
  if (!std::filesystem::exists(path)) throw doc.error(node, what + ": file '" + path.string() + "' not found");
  YamlDocument inc = YamlDocument::load(path.string());
  c.included.emplace_back(path.string(), inc.text());
  return {std::move(inc), path.string()};
}

void parseMaterials(const YamlDocument& doc, const YAML::Node& mats, GeometryCase& c, int depth) {
  if (!mats.IsMap()) throw doc.error(mats, "materials: expected a mapping of material names");
  for (const auto& kv : mats) {
    const std::string mname = doc.string(kv.first, "material name");
    if (mname == "include") {  // a file (or list of files) of material definitions
      const YAML::Node files = kv.second;
      for (size_t k = 0; k < (files.IsSequence() ? files.size() : 1); ++k) {
        const auto [inc, path] = includeDocument(doc, files.IsSequence() ? files[k] : files, "materials.include", depth, c);
        parseMaterials(inc, inc.root(), c, depth + 1);
      }
      continue;
    }
    const std::string what = "materials." + mname;
    doc.expectMap(kv.second, what, {"emissivity", "absorptivity"});
    Material m;
    m.emissivity = doc.number(doc.required(kv.second, "emissivity", what), what + ".emissivity", 0.0, 1.0);
    m.absorptivity = doc.number(doc.required(kv.second, "absorptivity", what), what + ".absorptivity", 0.0, 1.0);
    if (c.materials.count(mname)) throw doc.error(kv.first, what + ": defined twice");
    c.materials[mname] = m;
  }
}

void parseGeometryList(const YamlDocument& doc, const YAML::Node& geom, const std::string& list_what,
                       GeometryContext& ctx, int depth) {
  GeometryCase& c = ctx.c;
  doc.expectSequence(geom, list_what);
  if (geom.size() == 0) throw doc.error(geom, list_what + ": the list is empty; expected at least one surface");
  const std::filesystem::path base = std::filesystem::path(doc.file()).parent_path();
  auto material = [&](const YAML::Node& node, const std::string& what) -> std::string {
    if (!node) return "";
    const std::string m = doc.string(node, what);
    if (!c.materials.count(m)) {
      std::string msg = what + ": unknown material '" + m + "'";
      if (auto near = nearestWord(m, ctx.material_names)) msg += " (did you mean '" + *near + "'?)";
      throw doc.error(node, msg);
    }
    return m;
  };
  for (size_t k = 0; k < geom.size(); ++k) {
    const YAML::Node entry = geom[k];
    const std::string where = list_what + "[" + std::to_string(k) + "]";
    if (!entry.IsMap() || entry.size() != 1)
      throw doc.error(entry, where + ": expected one primitive, e.g. '- rectangle: {...}'");
    const std::string kind = entry.begin()->first.Scalar();
    if (kind == "include") {  // a list of surfaces in another file, read with its own positions
      const auto [inc, path] = includeDocument(doc, entry.begin()->second, where + ".include", depth, ctx.c);
      parseGeometryList(inc, inc.root(), path, ctx, depth + 1);
      continue;
    }
    const YAML::Node p = entry.begin()->second;
    const std::string what = where + "." + kind;
    static const std::initializer_list<const char*> kinds = {"include", "rectangle", "quadrilateral", "triangle", "disc",
                                                             "cylinder",  "cone",          "sphere",   "box", "mesh"};
    if (std::none_of(kinds.begin(), kinds.end(), [&](const char* s) { return kind == s; })) {
      std::string msg = where + ": unknown primitive '" + kind + "'";
      if (auto near = nearestWord(kind, kinds)) msg += " (did you mean '" + *near + "'?)";
      throw doc.error(entry.begin()->first, msg + "; expected rectangle, quadrilateral, triangle, disc, cylinder, cone, sphere, box or mesh");
    }
    const std::initializer_list<const char*> common = {"name", "front", "back", "subdivisions"};
    std::vector<const char*> allowed(common);
    auto allow = [&](std::initializer_list<const char*> more) { allowed.insert(allowed.end(), more); };
    if (kind == "rectangle") allow({"origin", "u", "v", "nodes"});
    if (kind == "quadrilateral") allow({"corners"});
    if (kind == "triangle") allow({"corners"});
    if (kind == "disc") allow({"center", "normal", "radius", "inner_radius", "angles", "reference"});
    if (kind == "cylinder") allow({"base", "axis", "radius", "angles", "reference"});
    if (kind == "cone") allow({"base", "axis", "base_radius", "top_radius", "angles", "reference"});
    if (kind == "sphere") allow({"center", "radius", "axis", "polar", "angles", "reference"});
    if (kind == "box") allow({"origin", "size", "nodes"});
    if (kind == "mesh") allow({"file", "scale", "groups"});
    if (!p.IsMap()) throw doc.error(p, what + ": expected a mapping of parameters");
    for (const auto& kv : p) {
      const std::string key = kv.first.Scalar();
      if (std::none_of(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; })) {
        std::vector<std::string> names(allowed.begin(), allowed.end());
        std::string msg = what + ": unknown key '" + key + "'";
        if (auto near = nearestWord(key, names)) msg += " (did you mean '" + *near + "'?)";
        msg += "; expected one of:";
        for (const auto& a : names) msg += " " + a;
        throw doc.error(kv.first, msg);
      }
    }
    const std::string name = doc.string(doc.required(p, "name", what), what + ".name");
    const std::string front = material(p["front"], what + ".front");
    const std::string back = material(p["back"], what + ".back");
    if (front.empty() && back.empty())
      throw doc.error(p, what + ": neither 'front' nor 'back' names a material; the surface would belong to no node");
    try {
      auto add = [&](const std::string& surface, const std::string& node, const geometry::TriangleSoup& soup,
                     const std::string& mesh_file = "") {
        const std::string label = kind + " '" + surface + "'" + (mesh_file.empty() ? "" : " from " + mesh_file);
        const std::string fn = front.empty() ? "" : node, bn = back.empty() ? "" : node + ".back";
        for (const auto& [nn, mat] : {std::pair{fn, front}, std::pair{bn, back}}) {
          if (nn.empty()) continue;
          auto [it, fresh] = ctx.node_material.emplace(nn, mat);
          if (!fresh && it->second != mat)
            throw geometry::GeometryError("node '" + nn + "' would have two materials ('" + it->second + "' and '" +
                                          mat + "')");
        }
        c.scene.addSurface(surface, label, soup, fn, bn);
      };
      const auto [sa, sb] = subdivisions(doc, p["subdivisions"], what + ".subdivisions",
                                         kind == "disc" || kind == "cylinder" || kind == "cone" ? 1 : (kind == "sphere" ? 12 : 1),
                                         kind == "disc" || kind == "cylinder" || kind == "cone" ? 32 : (kind == "sphere" ? 24 : 1));
      if (kind == "rectangle" && p["nodes"]) {
        // A grid of thermal nodes <name>.<i>.<j>, each with its share of the subdivisions.
        const auto [na, nb] = subdivisions(doc, p["nodes"], what + ".nodes", 1, 1);
        const double sides = (front.empty() ? 0 : 1) + (back.empty() ? 0 : 1);
        checkNodeMemory(doc, p["nodes"], what + ".nodes",
                        static_cast<double>(c.scene.nodes().size()) + sides * double(na) * double(nb));
        const Vec3 o = vec3(doc, doc.required(p, "origin", what), what + ".origin");
        const Vec3 u = vec3(doc, doc.required(p, "u", what), what + ".u");
        const Vec3 v = vec3(doc, doc.required(p, "v", what), what + ".v");
        const int ca = std::max(1, (sa + na - 1) / na), cb = std::max(1, (sb + nb - 1) / nb);
        for (int i = 0; i < na; ++i)
          for (int j = 0; j < nb; ++j) {
            const std::string cell = name + "." + std::to_string(i) + "." + std::to_string(j);
            add(cell, cell, geometry::rectangle(o + (double(i) / na) * u + (double(j) / nb) * v, u / na, v / nb, ca, cb));
          }
      } else if (kind == "rectangle") {
        add(name, name, geometry::rectangle(vec3(doc, doc.required(p, "origin", what), what + ".origin"),
                                            vec3(doc, doc.required(p, "u", what), what + ".u"),
                                            vec3(doc, doc.required(p, "v", what), what + ".v"), sa, sb));
      } else if (kind == "quadrilateral" || kind == "triangle") {
        const YAML::Node cs = doc.required(p, "corners", what);
        const size_t want = kind == "triangle" ? 3 : 4;
        if (!cs.IsSequence() || cs.size() != want)
          throw doc.error(cs, what + ".corners: expected " + std::to_string(want) + " points [x, y, z]");
        std::vector<Vec3> pts;
        for (size_t q = 0; q < want; ++q) pts.push_back(vec3(doc, cs[q], what + ".corners[" + std::to_string(q) + "]"));
        add(name, name, kind == "triangle" ? geometry::triangle(pts[0], pts[1], pts[2], sa)
                                           : geometry::quadrilateral({pts[0], pts[1], pts[2], pts[3]}, sa, sb));
      } else if (kind == "disc") {
        const double r = doc.number(doc.required(p, "radius", what), what + ".radius (m)", 0, kBig);
        add(name, name,
            geometry::disc(vec3(doc, doc.required(p, "center", what), what + ".center"),
                           vec3(doc, doc.required(p, "normal", what), what + ".normal"), r,
                           optionalNumber(doc, p, "inner_radius", what, 0.0, 0.0, kBig), sweep(doc, p, what), sa, sb));
      } else if (kind == "cylinder") {
        add(name, name,
            geometry::cylinder(vec3(doc, doc.required(p, "base", what), what + ".base"),
                               vec3(doc, doc.required(p, "axis", what), what + ".axis"),
                               doc.number(doc.required(p, "radius", what), what + ".radius (m)", 0, kBig),
                               sweep(doc, p, what), sa, sb));
      } else if (kind == "cone") {
        add(name, name,
            geometry::cone(vec3(doc, doc.required(p, "base", what), what + ".base"),
                           vec3(doc, doc.required(p, "axis", what), what + ".axis"),
                           doc.number(doc.required(p, "base_radius", what), what + ".base_radius (m)", 0, kBig),
                           optionalNumber(doc, p, "top_radius", what, 0.0, 0.0, kBig), sweep(doc, p, what), sa, sb));
      } else if (kind == "sphere") {
        double t0 = 0, t1 = 180;
        if (p["polar"]) {
          const YAML::Node pr = p["polar"];
          if (!pr.IsSequence() || pr.size() != 2) throw doc.error(pr, what + ".polar: expected [min, max] in degrees");
          t0 = doc.number(pr[0], what + ".polar[0] (deg)", 0, 180);
          t1 = doc.number(pr[1], what + ".polar[1] (deg)", 0, 180);
        }
        add(name, name,
            geometry::sphere(vec3(doc, doc.required(p, "center", what), what + ".center"),
                             doc.number(doc.required(p, "radius", what), what + ".radius (m)", 0, kBig),
                             p["axis"] ? vec3(doc, p["axis"], what + ".axis") : Vec3(0, 0, 1), t0, t1,
                             sweep(doc, p, what), sa, sb));
      } else if (kind == "box") {
        const auto faces = geometry::boxFaces(vec3(doc, doc.required(p, "origin", what), what + ".origin"),
                                              vec3(doc, doc.required(p, "size", what), what + ".size"), sa);
        std::string mode = p["nodes"] ? doc.string(p["nodes"], what + ".nodes") : "per_face";
        if (mode != "per_face" && mode != "single")
          throw doc.error(p["nodes"], what + ".nodes: '" + mode + "'; expected per_face or single");
        for (int f = 0; f < 6; ++f)
          add(name + geometry::kBoxFaceNames[f], mode == "single" ? name : name + "." + geometry::kBoxFaceNames[f],
              faces[static_cast<size_t>(f)]);
      } else if (kind == "mesh") {
        const YAML::Node fnode = doc.required(p, "file", what);
        std::filesystem::path path = doc.string(fnode, what + ".file");
        if (path.is_relative()) path = base / path;
        const double scale = optionalNumber(doc, p, "scale", what, 1.0, std::numeric_limits<double>::min(), kBig);
        try {
          if (p["groups"] && doc.boolean(p["groups"], what + ".groups")) {
            for (const auto& g : geometry::readObjGroups(path.string(), scale))
              add(name + "." + g.name, name + "." + g.name, g.soup, path.string());
          } else {
            add(name, name, geometry::readMesh(path.string(), scale), path.string());
          }
        } catch (const geometry::GeometryError& e) {
          throw doc.error(fnode, what + ".file: " + e.what());
        }
      }
    } catch (const geometry::GeometryError& e) {
      throw doc.error(entry, what + ": " + e.what());
    }
    }
}

}  // namespace

bool isGeometryCase(const YamlDocument& doc) { return doc.root().IsMap() && doc.root()["geometry"].IsDefined(); }

GeometryCase loadGeometryCase(const YamlDocument& doc) {
  const YAML::Node& root = doc.root();
  doc.expectMap(root, "case",
                {"name", "description", "materials", "geometry", "solver", "expect", "orbit", "attitude",
                 "environment", "thermal"});
  GeometryCase c;
  c.file = doc.file();
  c.yaml_text = doc.text();
  c.name = doc.string(doc.required(root, "name", "case"), "name");

  parseMaterials(doc, doc.required(root, "materials", "case"), c, 0);
  if (c.materials.empty()) throw doc.error(root["materials"], "materials: expected at least one material");
  GeometryContext ctx{c, {}, {}};
  for (const auto& [k, v] : c.materials) ctx.material_names.push_back(k);

  const YAML::Node geom = doc.required(root, "geometry", "case");
  parseGeometryList(doc, geom, "geometry", ctx, 0);
  checkNodeMemory(doc, geom, "geometry", static_cast<double>(c.scene.nodes().size()));
  try {
    c.scene.validate();
  } catch (const geometry::GeometryError& e) {
    throw doc.error(geom, std::string("geometry: ") + e.what());
  }
  const int n = static_cast<int>(c.scene.nodes().size());
  c.emissivity.resize(n);
  c.absorptivity.resize(n);
  for (int i = 0; i < n; ++i) {
    const std::string& mat = ctx.node_material.at(c.scene.nodes()[static_cast<size_t>(i)].name);
    c.node_material.push_back(mat);
    c.emissivity[i] = c.materials.at(mat).emissivity;
    c.absorptivity[i] = c.materials.at(mat).absorptivity;
  }

  const YAML::Node solver = root["solver"];
  c.solver = parseSolverSettings(doc, solver);
  if (solver && solver["view_factors"]) {
    const YAML::Node vf = solver["view_factors"];
    const std::string what = "solver.view_factors";
    doc.expectMap(vf, what, {"rays", "seed", "target_error", "replicas", "sampling", "method", "tolerance"});
    if (vf["rays"]) c.view_factors.rays_per_node = doc.integer(vf["rays"], what + ".rays", 64, 2000000000LL);
    if (vf["seed"]) c.view_factors.seed = static_cast<std::uint64_t>(doc.integer(vf["seed"], what + ".seed", 0, 1LL << 62));
    if (vf["target_error"]) c.view_factors.target_error = doc.number(vf["target_error"], what + ".target_error", 1e-7, 0.5);
    if (vf["replicas"]) c.view_factors.replicas = static_cast<int>(doc.integer(vf["replicas"], what + ".replicas", 2, 1024));
    if (c.view_factors.rays_per_node < c.view_factors.replicas)
      throw doc.error(vf, what + ": rays must be at least the number of replicas");
    if (vf["sampling"]) {
      const std::string s = doc.string(vf["sampling"], what + ".sampling");
      if (s == "sobol") c.view_factors.sampling = geometry::Sampling::Sobol;
      else if (s == "random") c.view_factors.sampling = geometry::Sampling::Random;
      else throw doc.error(vf["sampling"], what + ".sampling: '" + s + "'; expected sobol or random");
    }
    if (vf["method"]) {
      const std::string m = doc.string(vf["method"], what + ".method");
      if (m == "monte_carlo") c.method = ViewFactorMethod::MonteCarlo;
      else if (m == "contour") c.method = ViewFactorMethod::Contour;
      else throw doc.error(vf["method"], what + ".method: '" + m + "'; expected monte_carlo or contour");
    }
    if (vf["tolerance"]) c.contour.tolerance = doc.number(vf["tolerance"], what + ".tolerance", 1e-12, 0.1);
  }
  c.orbit = parseOrbitSettings(doc);
  std::vector<std::string> names;
  for (const auto& node : c.scene.nodes()) names.push_back(node.name);
  c.thermal = parseThermalSettings(doc, names, c.orbit.has_value());
  if (root["expect"]) c.expectations = parseExpectations(doc, root["expect"], names);
  return c;
}

}  // namespace radnet::cases
