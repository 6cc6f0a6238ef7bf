#include "cases/config/geometry_case.hpp"
#include "cases/config/thermal_settings.hpp"
#include "geometry/scene/facet_creases.hpp"

#include <algorithm>
#include <filesystem>
#include <limits>
#include <sstream>

namespace radnet::cases {
namespace {

// One branch `[[T_K, value], ...]`: temperatures increasing in (0, 5000] K, values in (0, 1]
// (a surface whose ε or α vanishes has no radiative node to follow).
solver::TemperatureTable opticalBranch(const YamlDocument& doc, const YAML::Node& node, const std::string& what) {
  solver::TemperatureTable t;
  parseTable(doc, node, what, std::numeric_limits<double>::min(), 5000.0, 0.0, 1.0, t.temperature_k, t.value);
  for (size_t k = 0; k < t.value.size(); ++k)
    if (!(t.value[k] > 0))
      throw doc.error(node[k][1], what + "[" + std::to_string(k) + "][1]: 0 is no value to follow; a surface that "
                                         "neither emits nor absorbs needs no table");
  return t;
}

// `emissivity: 0.8`, `{table: [[T, ε], ...]}` or `{warming: [...], cooling: [...]}` (hysteresis:
// the warming branch followed while the surface warms, the cooling one while it cools).
double opticalProperty(const YamlDocument& doc, const YAML::Node& v, const std::string& what, solver::OpticalCurve& curve) {
  if (!v.IsMap()) return doc.number(v, what, 0.0, 1.0);
  doc.expectMap(v, what, {"table", "warming", "cooling"});
  if (v["table"] && (v["warming"] || v["cooling"]))
    throw doc.error(v, what + ": give a 'table', or two branches 'warming' and 'cooling' (hysteresis), not both");
  if (v["table"]) {
    curve.warming = opticalBranch(doc, v["table"], what + ".table");
  } else {
    if (!v["warming"] || !v["cooling"])
      throw doc.error(v, what + ": hysteresis needs both branches, 'warming' and 'cooling' (or one 'table')");
    curve.warming = opticalBranch(doc, v["warming"], what + ".warming");
    curve.cooling = opticalBranch(doc, v["cooling"], what + ".cooling");
  }
  return curve.start(kNominalOpticsTemperature);
}

// Specular reflectance and transmittance per band; the solar ones default to the IR ones.
// Each band's budget must close: ε + ρs + τ ≤ 1 and α + ρs + τ ≤ 1 (ρd takes the rest).
void parseSpecular(const YamlDocument& doc, const YAML::Node& v, const std::string& what, Material& m) {
  const auto fraction = [&](const char* key, double fallback) {
    return v[key] ? doc.number(v[key], what + "." + key + " (a fraction, –)", 0.0, 1.0) : fallback;
  };
  m.specular_ir = fraction("specular_reflectance", 0.0);
  m.transmittance_ir = fraction("transmittance", 0.0);
  m.specular_solar = fraction("solar_specular_reflectance", m.specular_ir);
  m.transmittance_solar = fraction("solar_transmittance", m.transmittance_ir);
  m.solar_specular_given = bool(v["solar_specular_reflectance"]);
  m.solar_transmittance_given = bool(v["solar_transmittance"]);
  if (!m.isSpecular()) return;
  const YAML::Node& where = v["specular_reflectance"] ? v["specular_reflectance"]
                            : v["transmittance"]      ? v["transmittance"]
                            : v["solar_specular_reflectance"] ? v["solar_specular_reflectance"]
                                                              : v["solar_transmittance"];
  constexpr double kRounding = 1e-9;  // sums of values printed to 9 digits
  // A table must keep the band's budget at every temperature: its largest value counts.
  const auto largest = [](const solver::OpticalCurve& curve, double constant) {
    double most = curve.warming.value.empty() ? constant : 0.0;
    for (const solver::TemperatureTable* t : {&curve.warming, &curve.cooling})
      for (double v : t->value) most = std::max(most, v);
    return most;
  };
  const auto check = [&](double absorbed, double specular, double transmitted, const char* band, const char* a) {
    if (absorbed + specular + transmitted > 1.0 + kRounding)
      throw doc.error(where, what + ": the " + band + " band's " + a + " + specular reflectance + transmittance = " +
                                 std::to_string(absorbed + specular + transmitted) +
                                 " exceeds 1 (the diffuse reflectance is what remains of 1)");
  };
  check(largest(m.emissivity_curve, m.emissivity), m.specular_ir, m.transmittance_ir, "IR", "emissivity");
  check(largest(m.absorptivity_curve, m.absorptivity), m.specular_solar, m.transmittance_solar, "solar",
        "absorptivity");
}

}  // namespace

YamlDocument includeDocument(const YamlDocument& doc, const YAML::Node& node, const std::string& what, int depth,
                             IncludedFiles& included) {
  if (depth >= 8) throw doc.error(node, what + ": includes nested more than 8 deep (a cycle?)");
  std::filesystem::path path = doc.string(node, what);
  if (path.is_relative()) path = std::filesystem::path(doc.file()).parent_path() / path;
  if (!std::filesystem::exists(path)) throw doc.error(node, what + ": file '" + path.string() + "' not found");
  YamlDocument inc = YamlDocument::load(path.string());
  included.emplace_back(path.string(), inc.text());
  return inc;
}

void parseMaterials(const YamlDocument& doc, const YAML::Node& mats, std::map<std::string, Material>& materials,
                    IncludedFiles& included, int depth) {
  if (!mats.IsMap()) throw doc.error(mats, "materials: expected a mapping of material names");
  for (const auto& kv : mats) {
    const std::string mname = doc.string(kv.first, "material name");
    if (mname == "include") {  // a file (or list of files) of material definitions
      const YAML::Node files = kv.second;
      for (size_t k = 0; k < (files.IsSequence() ? files.size() : 1); ++k) {
        const YamlDocument inc =
            includeDocument(doc, files.IsSequence() ? files[k] : files, "materials.include", depth, included);
        parseMaterials(inc, inc.root(), materials, included, depth + 1);
      }
      continue;
    }
    const std::string what = "materials." + mname;
    doc.expectMap(kv.second, what,
                  {"emissivity", "absorptivity", "conductivity", "density", "specific_heat", "specular_reflectance",
                   "solar_specular_reflectance", "transmittance", "solar_transmittance"});
    const YAML::Node& v = kv.second;
    Material m;
    m.has_optics = v["emissivity"] || v["absorptivity"];
    if (m.has_optics) {
      m.emissivity = opticalProperty(doc, doc.required(v, "emissivity", what), what + ".emissivity", m.emissivity_curve);
      m.absorptivity =
          opticalProperty(doc, doc.required(v, "absorptivity", what), what + ".absorptivity", m.absorptivity_curve);
      parseSpecular(doc, v, what, m);
    } else if (v["specular_reflectance"] || v["transmittance"] || v["solar_specular_reflectance"] ||
               v["solar_transmittance"]) {
      throw doc.error(v, what + ": specular reflectance and transmittance belong to a surface material: give its "
                                "emissivity and absorptivity too");
    }
    m.has_bulk = v["conductivity"] || v["density"] || v["specific_heat"];
    if (m.has_bulk) {  // W/(m K), kg/m³, J/(kg K): from aerogels to copper and beyond, with room
      m.conductivity = doc.number(doc.required(v, "conductivity", what), what + ".conductivity (W/(m K))", 0.0, 1e5);
      m.density = doc.number(doc.required(v, "density", what), what + ".density (kg/m³)", 0.0, 1e5);
      m.specific_heat = doc.number(doc.required(v, "specific_heat", what), what + ".specific_heat (J/(kg K))", 0.0, 1e5);
    }
    if (!m.has_optics && !m.has_bulk)
      throw doc.error(v, what + ": expected emissivity and absorptivity (a surface material) or conductivity, "
                             "density and specific_heat (a shell material), or both");
    if (materials.count(mname)) throw doc.error(kv.first, what + ": defined twice");
    materials[mname] = m;
  }
}

namespace {

// ε/κ for κ > 0; a pure mirror (κ = 0, hence ε = 0) has no radiosity node: 0.
Eigen::VectorXd perKappa(const Eigen::VectorXd& value, const Eigen::VectorXd& kappa) {
  Eigen::VectorXd out(value.size());
  for (Eigen::Index i = 0; i < value.size(); ++i) out[i] = kappa[i] > 0 ? std::min(1.0, value[i] / kappa[i]) : 0.0;
  return out;
}

}  // namespace

void applySpecularOptics(const YamlDocument& doc, GeometryCase& c) {
  c.surface_emissivity = c.emissivity;
  c.surface_absorptivity = c.absorptivity;
  const OpticalSet& base = c.optical_sets.front();
  for (size_t k = 1; k < c.optical_sets.size(); ++k) {
    OpticalSet& set = c.optical_sets[k];
    set.own_specular = !set.specular_ir.sameAs(base.specular_ir) || !set.specular_solar.sameAs(base.specular_solar);
  }
  for (OpticalSet& set : c.optical_sets) {
    if (!set.specular_ir.anyRedirects() && !set.specular_solar.anyRedirects()) {
      set.specular_ir = set.specular_solar = geometry::SpecularBand{};  // diffuse and opaque throughout
      continue;
    }
    const Eigen::VectorXd kappa_ir = set.specular_ir.kappa(), kappa_solar = set.specular_solar.kappa();
    for (Eigen::Index i = 0; i < kappa_ir.size(); ++i)
      if (set.emissivity[i] > kappa_ir[i] + 1e-9 || set.absorptivity[i] > kappa_solar[i] + 1e-9)
        throw doc.error(doc.root()["optics"] ? doc.root()["optics"] : doc.root()["materials"],
                        (set.name == "base" ? std::string("materials") : "optics." + set.name) + ": node '" +
                            c.node_names[static_cast<size_t>(i)] +
                            "' would have emissivity (absorptivity) + specular reflectance + transmittance above 1 "
                            "in a band");
    set.emissivity = perKappa(set.emissivity, kappa_ir);
    set.absorptivity = perKappa(set.absorptivity, kappa_solar);
  }
  c.specular_ir = base.specular_ir;  // empty when the base case has nothing that redirects
  c.specular_solar = base.specular_solar;
  c.emissivity = base.emissivity;
  c.absorptivity = base.absorptivity;
}

namespace {

// Per degree of crease, the error a facetted specular surface puts in what it reflects: a
// specular sphere pair's exchange is 9 % off at 7.5° facets (24 × 48) and 18 % at 15°
// (docs/geometry.md, "Specular surfaces"), –/deg.
constexpr double kFacetErrorPerDeg = 0.012;

// Node k's largest specular reflectance (or transmittance) in either band under any optical set.
double largestOverSets(const GeometryCase& c, Eigen::Index k, Eigen::VectorXd geometry::SpecularBand::*value) {
  double most = 0.0;
  for (const OpticalSet& set : c.optical_sets)
    if (!set.specular_ir.empty()) most = std::max({most, (set.specular_ir.*value)[k], (set.specular_solar.*value)[k]});
  return most;
}

void warnFacettedMirrors(GeometryCase& c) {
  for (size_t i = 0; i < c.node_names.size(); ++i) {
    const double rs = largestOverSets(c, static_cast<Eigen::Index>(i), &geometry::SpecularBand::specular);
    if (!(rs > 0)) continue;
    const geometry::FacetCreases creases = geometry::facetCreases(c.scene, static_cast<int>(i));
    // The exchange integrates over the surface: between the mean crease's and the largest's
    // estimate (a Blender sphere of 16k vertices: 1.4 % and 7.1 %, measured 3.2 %); warned on
    // the largest, to be safe.
    const double low = kFacetErrorPerDeg * creases.mean_deg * rs, high = kFacetErrorPerDeg * creases.largest_deg * rs;
    if (!(high > c.solver.accuracy)) continue;
    std::ostringstream w;
    w << "node '" << c.node_names[i] << "' reflects specularly (ρs " << rs << ") off facets whose neighbours meet at "
      << creases.mean_deg << "° on average, up to " << creases.largest_deg << "° (" << creases.smooth_edges
      << " such edges): reflected rays leave up to twice that off the smooth surface's direction, of order "
      << 100 * low << "–" << 100 * high
      << " % in what it reflects (solver.accuracy " << c.solver.accuracy
      << "); a sphere, cylinder or cone primitive reflects about its exact normal and OBJ or PLY vertex "
         "normals are followed where the file gives them; or refine the mesh";
    c.warnings.push_back(w.str());
  }
}

void warnOneSidedWindows(GeometryCase& c) {
  const geometry::Scene& scene = c.scene;
  for (size_t i = 0; i < c.node_names.size(); ++i) {
    const double tau = largestOverSets(c, static_cast<Eigen::Index>(i), &geometry::SpecularBand::transmittance);
    if (!(tau > 0)) continue;
    const geometry::Node& node = scene.nodes()[i];
    int one_sided = 0;
    for (int f : node.faces) {
      const geometry::Face& face = scene.faces()[static_cast<size_t>(f)];
      one_sided += (node.side > 0 ? face.back_node : face.front_node) < 0;
    }
    if (one_sided == 0) continue;
    std::ostringstream w;
    w << "node '" << c.node_names[i] << "' transmits (τ up to " << tau << ") but " << one_sided << " of its "
      << node.faces.size() << " triangles have no node on their other side: light passes out through them, while "
      << "light arriving on that side stops there (counted as blocked); give both sides of a window its material";
    c.warnings.push_back(w.str());
  }
}

}  // namespace

void warnSpecularSurfaces(GeometryCase& c) {
  warnFacettedMirrors(c);
  warnOneSidedWindows(c);
}

}  // namespace radnet::cases
