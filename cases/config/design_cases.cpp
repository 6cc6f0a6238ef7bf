#include "cases/config/design_cases.hpp"

#include "cases/config/geometry_case.hpp"

#include <algorithm>
#include <cctype>
#include <set>

namespace radnet::cases {
namespace {

constexpr const char* kCaseKeys[] = {"orbit", "attitude", "environment", "optics", "dissipation_scale", "dissipation"};

std::string didYouMean(const std::string& word, const std::vector<std::string>& names) {
  const auto near = nearestWord(word, names);
  return near ? " (did you mean '" + *near + "'?)" : "";
}

// A name that becomes an HDF5 group and a label: refused when it is not a plain word.
std::string caseName(const YamlDocument& doc, const YAML::Node& key, const std::string& what,
                     std::set<std::string>& seen) {
  const std::string name = key.Scalar();
  if (!isCaseName(name))
    throw doc.error(key, what + ": '" + name + "' is not a name; use letters, digits, '_', '-' and '.', starting with a letter, a digit or '_'");
  if (!seen.insert(name).second) throw doc.error(key, what + ": '" + name + "' is given twice");
  return name;
}

// The case's block over the base case's, key by key; a key the case sets to null (`~`) is
// removed. The base keys are added to the case's own mapping in the parsed document (a
// copy would lose every position, YAML::Clone keeps none), so that messages point at the
// case's block, or at the base key they are about.
YAML::Node overlay(const YAML::Node& base, const YAML::Node& over) {
  if (!over) return base;
  if (!over.IsMap() || !base || !base.IsMap()) return over;
  YAML::Node merged = over;  // the same node, not a copy
  std::vector<std::string> removed;
  for (const auto& kv : over)
    if (kv.second.IsNull()) removed.push_back(kv.first.Scalar());
  for (const auto& kv : base) {
    const std::string key = kv.first.Scalar();
    if (!over[key] && std::find(removed.begin(), removed.end(), key) == removed.end()) merged[kv.first] = kv.second;
  }
  for (const std::string& key : removed) merged.remove(key);
  return merged;
}

// A node as text with every mapping's keys sorted, so that the same blocks written in
// another order read the same; `skip` keys of the top mapping left out. An absent block
// reads as an empty one.
std::string canonical(const YAML::Node& node, const std::vector<std::string>& skip = {}) {
  if (!node || node.IsNull()) return "{}";
  if (node.IsScalar()) return node.Scalar();
  std::string out;
  if (node.IsSequence()) {
    for (const auto& item : node) out += canonical(item) + ",";
    return "[" + out + "]";
  }
  if (!node.IsMap()) return "~";
  std::vector<std::pair<std::string, std::string>> entries;
  for (const auto& kv : node) {
    const std::string key = kv.first.Scalar();
    if (std::find(skip.begin(), skip.end(), key) == skip.end()) entries.emplace_back(key, canonical(kv.second));
  }
  std::sort(entries.begin(), entries.end());
  for (const auto& [k, v] : entries) out += k + ":" + v + ",";
  return "{" + out + "}";
}

std::string loadSignature(const YAML::Node& orbit, const YAML::Node& attitude, const YAML::Node& environment) {
  std::vector<std::string> scaled = {"solar_constant", "earth_ir"};
  if (environment && environment["albedo"] && environment["albedo"].IsScalar()) scaled.push_back("albedo");
  // A flux scales; a day–night model (a word or a mapping) changes the loads' shape.
  if (environment && environment["planet_ir"] && environment["planet_ir"].IsScalar()) {
    const std::string v = environment["planet_ir"].Scalar();
    if (!v.empty() && !std::isalpha(static_cast<unsigned char>(v[0]))) scaled.push_back("planet_ir");
  }
  return canonical(orbit) + "|" + canonical(attitude) + "|" + canonical(environment, scaled);
}

// What every case shares is not a case's to change: say so rather than "unknown key".
void checkCaseKeys(const YamlDocument& doc, const YAML::Node& body, const std::string& what) {
  for (const char* shared : {"name", "description", "materials", "geometry", "solver", "thermal", "expect", "cases",
                             "uncertainty"})
    if (body[shared])
      throw doc.error(body[shared], what + "." + shared + ": a design case cannot override '" + shared +
                                        "': every case shares the geometry, its view factors and its one "
                                        "eigendecomposition; a case overrides orbit, attitude, environment, optics, "
                                        "dissipation_scale and dissipation");
  doc.expectMap(body, what, std::vector<std::string>(std::begin(kCaseKeys), std::end(kCaseKeys)));
}

int opticsIndex(const YamlDocument& doc, const YAML::Node& node, const std::string& what, const GeometryCase& c) {
  if (!node) return 0;
  const std::string name = doc.string(node, what);
  std::vector<std::string> names;
  for (size_t k = 0; k < c.optical_sets.size(); ++k) {
    if (c.optical_sets[k].name == name) return static_cast<int>(k);
    names.push_back(c.optical_sets[k].name);
  }
  std::string listed;
  for (const std::string& n : names) listed += (listed.empty() ? "'" : ", '") + n + "'";
  throw doc.error(node, what + ": unknown optical set '" + name + "'" + didYouMean(name, names) + "; the sets are " +
                            listed + " (from 'optics:')");
}

DesignCase parseCase(const YamlDocument& doc, const std::string& name, const YAML::Node& body, const GeometryCase& c) {
  const YAML::Node& root = doc.root();
  const std::string what = "cases." + name;
  DesignCase d;
  d.name = name;
  if (!body.IsNull()) {
    if (!body.IsMap()) throw doc.error(body, what + ": expected a mapping of the blocks the case overrides");
    checkCaseKeys(doc, body, what);
  }
  const YAML::Node none;
  const YAML::Node& b = body.IsMap() ? body : none;
  d.optics = opticsIndex(doc, b["optics"], what + ".optics", c);
  const YAML::Node orbit = overlay(root["orbit"], b["orbit"]), attitude = overlay(root["attitude"], b["attitude"]),
                   environment = overlay(root["environment"], b["environment"]);
  d.orbit = parseOrbitSettings(doc, orbit, attitude, environment);
  d.load_signature = loadSignature(orbit, attitude, environment);
  if (d.orbit)
    for (OrbitCase& oc : d.orbit->cases) oc.label = d.orbit->cases.size() == 1 ? name : name + "/" + oc.label;
  return d;
}


// The base optical set: the materials' ε, α and, in every set, ρs and τ per node and band
// (zeros where diffuse; applySpecularOptics empties them when nothing redirects).
OpticalSet baseOpticalSet(const GeometryCase& c) {
  OpticalSet set{"base", c.emissivity, c.absorptivity, c.emissivity, c.absorptivity, {}, {}, false};
  const Eigen::Index n = c.emissivity.size();
  set.specular_ir = {Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n)};
  set.specular_solar = set.specular_ir;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Material& m = c.materials.at(c.node_material[static_cast<size_t>(i)]);
    set.specular_ir.specular[i] = m.specular_ir, set.specular_ir.transmittance[i] = m.transmittance_ir;
    set.specular_solar.specular[i] = m.specular_solar, set.specular_solar.transmittance[i] = m.transmittance_solar;
  }
  return set;
}

constexpr const char* kSpecularKeys[] = {"specular_reflectance", "transmittance", "solar_specular_reflectance",
                                         "solar_transmittance"};

// optics.<set>.<material>: the material's ε, α, ρs, τ overridden in the set, on every node
// made of it. A solar ρs or τ not given keeps the material's, unless the material's own
// followed its IR value: then it follows the set's.
void overrideMaterial(const YamlDocument& doc, GeometryCase& c, const YAML::Node& key, const YAML::Node& value,
                      const std::string& what, OpticalSet& set) {
  const std::string m = key.Scalar(), mwhat = what + "." + m;
  const std::vector<std::string> materials = c.opticalMaterials();
  if (std::find(materials.begin(), materials.end(), m) == materials.end())
    throw doc.error(key, mwhat + ": unknown material '" + m + "'" + didYouMean(m, materials) +
                             (c.materials.count(m) ? "; it has no optical properties" : ""));
  doc.expectMap(value, mwhat, {"emissivity", "absorptivity", "specular_reflectance", "transmittance",
                               "solar_specular_reflectance", "solar_transmittance"});
  if (value.size() == 0) throw doc.error(value, mwhat + ": give emissivity, absorptivity, or specular reflectance or transmittance");
  const Material& mat = c.materials.at(m);
  for (const auto& [k, curve] : {std::pair{"emissivity", &mat.emissivity_curve}, std::pair{"absorptivity", &mat.absorptivity_curve}})
    if (value[k] && !curve->warming.temperature_k.empty())
      throw doc.error(value[k], mwhat + "." + k + ": '" + m + "' gives its " + k +
                                    " as a table against temperature, which every optical set follows; "
                                    "define a second material for the other coating");
  for (const char* k : kSpecularKeys)
    if (value[k] && mat.hasCurves())
      throw doc.error(value[k], mwhat + "." + k + ": '" + m + "' has ε or α against temperature; a specular or "
                                    "transmissive surface needs constant optics");
  const auto number = [&](const char* k, double fallback) {
    return value[k] ? doc.number(value[k], mwhat + "." + k + " (a fraction, –)", 0, 1) : fallback;
  };
  const double rs_ir = number("specular_reflectance", mat.specular_ir), tau_ir = number("transmittance", mat.transmittance_ir);
  const double rs_solar = number("solar_specular_reflectance", mat.solar_specular_given ? mat.specular_solar : rs_ir);
  const double tau_solar = number("solar_transmittance", mat.solar_transmittance_given ? mat.transmittance_solar : tau_ir);
  const double e = number("emissivity", mat.emissivity), a = number("absorptivity", mat.absorptivity);
  constexpr double kRounding = 1e-9;  // sums of values printed to 9 digits
  if (e + rs_ir + tau_ir > 1.0 + kRounding || a + rs_solar + tau_solar > 1.0 + kRounding)
    throw doc.error(value, mwhat + ": in the " + (e + rs_ir + tau_ir > 1.0 + kRounding ? "IR band emissivity" : "solar band absorptivity") +
                               " + specular reflectance + transmittance exceeds 1 (the diffuse reflectance is what remains of 1)");
  if (std::find(c.node_material.begin(), c.node_material.end(), m) == c.node_material.end())
    c.warnings.push_back(mwhat + ": no surface is made of '" + m + "', so the override changes nothing");
  for (size_t i = 0; i < c.node_material.size(); ++i) {
    if (c.node_material[i] != m) continue;
    const auto k = static_cast<Eigen::Index>(i);
    set.emissivity[k] = set.surface_emissivity[k] = e;
    set.absorptivity[k] = set.surface_absorptivity[k] = a;
    set.specular_ir.specular[k] = rs_ir, set.specular_ir.transmittance[k] = tau_ir;
    set.specular_solar.specular[k] = rs_solar, set.specular_solar.transmittance[k] = tau_solar;
  }
}

}  // namespace

bool isCaseName(const std::string& name) {
  // The first character not a '.' or '-': "." and ".." mean something in an HDF5 path.
  return !name.empty() && name.size() <= 64 && (std::isalnum(static_cast<unsigned char>(name[0])) || name[0] == '_') &&
         std::all_of(name.begin(), name.end(), [](char ch) {
           return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-' || ch == '.';
         });
}

std::vector<std::string> GeometryCase::opticalMaterials() const {
  std::vector<std::string> m;
  for (const auto& [name, props] : materials)  // a std::map: sorted
    if (props.has_optics) m.push_back(name);
  return m;
}

void parseOpticalSets(const YamlDocument& doc, GeometryCase& c) {
  c.optical_sets.push_back(baseOpticalSet(c));
  const YAML::Node sets = doc.root()["optics"];
  if (!sets) {
    applySpecularOptics(doc, c);
    return;
  }
  if (!sets.IsMap() || sets.size() == 0)
    throw doc.error(sets, "optics: expected a mapping of named optical sets, e.g. 'eol: {white_paint: "
                          "{absorptivity: 0.45}}'");
  std::set<std::string> seen = {"base"};
  for (const auto& kv : sets) {
    if (kv.first.Scalar() == "base")
      throw doc.error(kv.first, "optics.base: 'base' is the materials as given; name the set otherwise");
    OpticalSet set = c.optical_sets.front();
    set.name = caseName(doc, kv.first, "optics", seen);
    const std::string what = "optics." + set.name;
    if (!kv.second.IsMap() || kv.second.size() == 0)
      throw doc.error(kv.second, what + ": expected a mapping of materials to their overrides, e.g. "
                                        "'white_paint: {absorptivity: 0.45}'");
    for (const auto& mv : kv.second) overrideMaterial(doc, c, mv.first, mv.second, what, set);
    c.optical_sets.push_back(std::move(set));
  }
  applySpecularOptics(doc, c);  // every set's ε, α as the network's (ε/κ, α/κ) when a surface is specular
}

void parseDesignCases(const YamlDocument& doc, GeometryCase& c) {
  const YAML::Node cases = doc.root()["cases"];
  if (!cases) {
    DesignCase d;
    d.name = "base";
    d.orbit = parseOrbitSettings(doc);
    c.design_cases.push_back(std::move(d));
    return;
  }
  if (!cases.IsMap() || cases.size() == 0)
    throw doc.error(cases, "cases: expected a mapping of named design cases, e.g. 'hot: {environment: "
                           "{solar_constant: 1414}}'");
  std::set<std::string> seen;
  for (const auto& kv : cases) {
    const std::string name = caseName(doc, kv.first, "cases", seen);
    c.design_cases.push_back(parseCase(doc, name, kv.second, c));
    const DesignCase& first = c.design_cases.front();
    if (c.design_cases.back().orbit.has_value() != first.orbit.has_value())
      throw doc.error(kv.first, "cases." + name + ": " + (first.orbit ? "has no orbit while case '" + first.name +
                                                                            "' has one"
                                                                      : "has an orbit while case '" + first.name +
                                                                            "' has none") +
                                    "; give every case an orbit (or the base case one), or none");
  }
}

void parseCaseDissipations(const YamlDocument& doc, GeometryCase& c) {
  const YAML::Node cases = doc.root()["cases"];
  if (!cases) return;
  for (DesignCase& d : c.design_cases) {
    const YAML::Node body = cases[d.name];
    if (!body.IsMap()) continue;
    const std::string what = "cases." + d.name;
    for (const char* key : {"dissipation_scale", "dissipation"})
      if (body[key] && !c.thermal)
        throw doc.error(body[key], what + "." + key + ": dissipations need a 'thermal:' block");
    if (body["dissipation_scale"])
      d.dissipation_scale = doc.number(body["dissipation_scale"], what + ".dissipation_scale", 0, 1e3);
    const YAML::Node q = body["dissipation"];
    if (!q) continue;
    if (!q.IsMap() || q.size() == 0)
      throw doc.error(q, what + ".dissipation: expected a mapping of thermal nodes to powers, e.g. 'payload: 0.0' (W)");
    const std::vector<std::string>& names = c.thermal->node_names;
    for (const auto& kv : q) {
      const std::string node = kv.first.Scalar();
      const auto it = std::find(names.begin(), names.end(), node);
      if (it == names.end())
        throw doc.error(kv.first, what + ".dissipation: unknown thermal node '" + node + "'" + didYouMean(node, names));
      d.dissipation.emplace_back(static_cast<int>(it - names.begin()),
                                 doc.number(kv.second, what + ".dissipation." + node + " (W)", -1e9, 1e9));
    }
  }
}

void parseOpticalUncertainty(const YamlDocument& doc, GeometryCase& c) {
  const YAML::Node u = doc.root()["uncertainty"];
  if (!u) return;
  doc.expectMap(u, "uncertainty", {"absorptivity", "emissivity", "samples", "seed"});
  if (!u["absorptivity"] && !u["emissivity"])
    throw doc.error(u, "uncertainty: give the 1σ of absorptivity and/or emissivity (absolute, e.g. 0.03)");
  if (!c.thermal)
    throw doc.error(u, "uncertainty: the samples give temperature percentiles and need a 'thermal:' block");
  for (const OpticalSet& set : c.optical_sets)
    if (set.own_specular)
      throw doc.error(u, "uncertainty: optical set '" + set.name + "' changes specular reflectance or transmittance, "
                         "which gives it networks of its own; sampling ε and α around such a set is not supported");
  OpticalUncertainty o;
  if (u["absorptivity"]) o.absorptivity_sigma = doc.number(u["absorptivity"], "uncertainty.absorptivity (1σ)", 0, 0.5);
  if (u["emissivity"]) o.emissivity_sigma = doc.number(u["emissivity"], "uncertainty.emissivity (1σ)", 0, 0.5);
  if (u["samples"]) o.samples = static_cast<int>(doc.integer(u["samples"], "uncertainty.samples", 2, 100000));
  if (u["seed"]) o.seed = static_cast<std::uint64_t>(doc.integer(u["seed"], "uncertainty.seed", 0, 1LL << 62));
  c.optical_uncertainty = o;
}

void parseLimits(const YamlDocument& doc, GeometryCase& c) {
  const YAML::Node limits = doc.root()["limits"];
  if (!limits) return;
  if (!c.thermal) throw doc.error(limits, "limits: temperature limits need a 'thermal' block");
  if (!limits.IsMap()) throw doc.error(limits, "limits: expected a map {node: [min_K, max_K]}");
  const std::vector<std::string>& names = c.thermal->node_names;
  for (const auto& entry : limits) {
    const int index = doc.nodeIndex(entry.first, "limits", names);  // with a did-you-mean
    const std::string what = "limits." + names[static_cast<size_t>(index)];
    if (!entry.second.IsSequence() || entry.second.size() != 2)
      throw doc.error(entry.second, what + ": expected [min_K, max_K]");
    const double lo = doc.number(entry.second[0], what + "[0] (K)", 0.0, 1e5);
    const double hi = doc.number(entry.second[1], what + "[1] (K)", 0.0, 1e5);
    if (!(lo < hi)) throw doc.error(entry.second, what + ": the minimum must be below the maximum");
    warnIfCelsius(doc, entry.second[0], what + "[0]", lo, c.warnings);
    if (lo >= kSuspiciousKelvin) warnIfCelsius(doc, entry.second[1], what + "[1]", hi, c.warnings);
    c.limits.push_back({index, lo, hi});
  }
}

}  // namespace radnet::cases
