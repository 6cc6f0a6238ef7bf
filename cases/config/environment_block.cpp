#include "cases/config/orbit_settings.hpp"

#include <cctype>
#include <limits>

namespace radnet::cases {
namespace {

// `albedo: [[latitude_deg, albedo], ...]`, latitudes increasing.
void parseAlbedoTable(const YamlDocument& doc, const YAML::Node& a, orbits::EnvironmentOptions& env) {
  double last = -1;
  for (size_t k = 0; k < a.size(); ++k) {
    const std::string what = "environment.albedo[" + std::to_string(k) + "]";
    if (!a[k].IsSequence() || a[k].size() != 2) throw doc.error(a[k], what + ": expected [latitude_deg, albedo]");
    const double lat = doc.number(a[k][0], what + " latitude (deg)", 0, 90);
    if (lat <= last) throw doc.error(a[k][0], what + ": latitudes must increase");
    last = lat;
    env.albedo_by_latitude.emplace_back(lat, doc.number(a[k][1], what + " albedo", 0, 1));
  }
  if (env.albedo_by_latitude.empty()) throw doc.error(a, "environment.albedo: the table is empty");
}

// Named planet IR models: a body's own day–night constants, usable about any body.
constexpr std::pair<const char*, const char*> kNamedIr[] = {
    {"lunar_day_night", "moon"}, {"martian_day_night", "mars"}, {"mercurian_day_night", "mercury"}};

// `{subsolar_temperature: K, night_temperature: K, reference_flux: W/m²}`: a surface in
// radiative balance, T = max(T_ss cos^¼ z, T_night), T_ss at the reference solar flux.
orbits::PlanetIr dayNightMapping(const YamlDocument& doc, const YAML::Node& m, const orbits::CentralBody& body) {
  doc.expectMap(m, "environment.planet_ir", {"subsolar_temperature", "night_temperature", "reference_flux"});
  for (const char* key : {"subsolar_temperature", "night_temperature"})
    if (!m[key]) throw doc.error(m, std::string("environment.planet_ir: missing '") + key + "' (K)");
  orbits::PlanetIr ir;
  ir.kind = orbits::PlanetIr::Kind::DayNight;
  ir.subsolar_temperature_k = doc.number(m["subsolar_temperature"], "environment.planet_ir.subsolar_temperature (K)", 0, 3000);
  ir.night_temperature_k = doc.number(m["night_temperature"], "environment.planet_ir.night_temperature (K)", 0, 3000);
  if (ir.night_temperature_k > ir.subsolar_temperature_k)
    throw doc.error(m["night_temperature"], "environment.planet_ir.night_temperature: above the subsolar temperature; "
                                            "the night side is the colder one");
  // By default T_ss holds at the flux of the body's mean distance from the Sun (1 au for the Earth and the Moon).
  const double a_au = body.heliocentric.a_au;
  ir.reference_flux_w_m2 = m["reference_flux"] ? doc.number(m["reference_flux"], "environment.planet_ir.reference_flux (W/m²)",
                                                            std::numeric_limits<double>::min(), 1e6)
                                               : 1361.0 / (a_au * a_au);
  return ir;
}

orbits::PlanetIr parsePlanetIr(const YamlDocument& doc, const YAML::Node& v, const orbits::CentralBody& body) {
  if (v.IsMap()) return dayNightMapping(doc, v, body);
  if (v.IsScalar()) {
    const std::string word = v.Scalar();
    if (word == "day_night") {
      if (body.ir.uniform())
        throw doc.error(v, "environment.planet_ir: " + body.name + " has no day–night model of its own (it emits "
                               "uniformly); give {subsolar_temperature: K, night_temperature: K} or a flux in W/m²");
      return body.ir;
    }
    for (const auto& [name, from] : kNamedIr)
      if (word == name) return orbits::CentralBody::named(from)->ir;
    if (!word.empty() && (std::isalpha(static_cast<unsigned char>(word[0])) || word[0] == '_'))
      throw doc.error(v, "environment.planet_ir: unknown model '" + word +
                             "'; expected a flux in W/m², day_night, lunar_day_night, martian_day_night, "
                             "mercurian_day_night or {subsolar_temperature: K, night_temperature: K}");
  }
  orbits::PlanetIr ir;
  ir.kind = orbits::PlanetIr::Kind::Uniform;
  ir.uniform_w_m2 = doc.number(v, "environment.planet_ir (W/m²)", 0, 1e5);
  return ir;
}

}  // namespace

void parseEnvironment(const YamlDocument& doc, const YAML::Node& e, const orbits::CentralBody& body,
                      orbits::SweepOptions& sweep, orbits::EnvironmentOptions& env) {
  env.albedo = body.bond_albedo;
  env.planet_ir = body.ir;
  if (!e) return;
  doc.expectMap(e, "environment", {"solar_constant", "albedo", "earth_ir", "planet_ir", "shadow_samples", "shadow_cell",
                                   "planet_rays", "planet_method"});
  if (e["solar_constant"])
    sweep.solar_constant_w_m2 = doc.number(e["solar_constant"], "environment.solar_constant (W/m²)", 0, 1e5);
  if (const YAML::Node a = e["albedo"]) {
    if (a.IsSequence())
      parseAlbedoTable(doc, a, env);
    else
      env.albedo = doc.number(a, "environment.albedo", 0, 1);
  }
  if (e["earth_ir"] && e["planet_ir"])
    throw doc.error(e["earth_ir"], "environment.earth_ir: give planet_ir or earth_ir (its older name), not both");
  if (e["earth_ir"] && !body.isEarth())
    throw doc.error(e["earth_ir"], "environment.earth_ir: the orbit is about " + body.name +
                                       ", not the Earth; give its emission as 'planet_ir'");
  if (e["earth_ir"]) {
    env.planet_ir.kind = orbits::PlanetIr::Kind::Uniform;
    env.planet_ir.uniform_w_m2 = doc.number(e["earth_ir"], "environment.earth_ir (W/m²)", 0, 1e4);
  }
  if (e["planet_ir"]) env.planet_ir = parsePlanetIr(doc, e["planet_ir"], body);
  if (e["shadow_samples"])
    env.shadow_samples = static_cast<int>(doc.integer(e["shadow_samples"], "environment.shadow_samples", 1, 1 << 24));
  if (e["shadow_cell"]) {
    if (e["shadow_samples"])
      throw doc.error(e["shadow_cell"], "environment: shadow_cell sizes the shadow grid and shadow_samples replaces "
                                        "it by per-node shadow rays; give one of them");
    env.shadow_cell_m = doc.number(e["shadow_cell"], "environment.shadow_cell (m)", 1e-6, 10.0);
  }
  if (e["planet_rays"]) env.planet_rays = doc.integer(e["planet_rays"], "environment.planet_rays", 32, 1LL << 30);
  if (const YAML::Node m = e["planet_method"]) {
    const std::string word = m.IsScalar() ? m.Scalar() : std::string();
    using Method = orbits::EnvironmentOptions::PlanetMethod;
    if (word != "auto" && word != "sky_kernel" && word != "rays")
      throw doc.error(m, "environment.planet_method: expected auto (the default: the sky kernel unless the planet is "
                         "fixed in the body frame on a model of fewer than 12 nodes a position), sky_kernel (each node's sky cast once) or rays (planet rays at "
                         "every position the planet moves in the body frame)");
    env.planet_method = word == "auto" ? Method::Auto : word == "rays" ? Method::Rays : Method::SkyKernel;
    if (env.planet_method == Method::SkyKernel && !env.albedo_by_latitude.empty())
      throw doc.error(m, "environment: the sky kernel carries one albedo (its radiance is per direction, a latitude "
                         "table per place); give planet_method: rays or auto with the albedo table, or one albedo");
    if (env.planet_method == Method::SkyKernel && e["planet_rays"])
      throw doc.error(m, "environment: planet_rays pins the planet rays per node, which the sky kernel does not cast; "
                         "give planet_method: rays with it, or leave planet_rays out");
  }
}

}  // namespace radnet::cases
