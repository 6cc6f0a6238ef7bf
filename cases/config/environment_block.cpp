#include "cases/config/orbit_settings.hpp"

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

}  // namespace

void parseEnvironment(const YamlDocument& doc, const YAML::Node& e, orbits::SweepOptions& sweep,
                      orbits::EnvironmentOptions& env) {
  if (!e) return;
  doc.expectMap(e, "environment", {"solar_constant", "albedo", "earth_ir", "shadow_samples", "shadow_cell", "planet_rays"});
  if (e["solar_constant"])
    sweep.solar_constant_w_m2 = doc.number(e["solar_constant"], "environment.solar_constant (W/m²)", 0, 1e5);
  if (const YAML::Node a = e["albedo"]) {
    if (a.IsSequence())
      parseAlbedoTable(doc, a, env);
    else
      env.albedo = doc.number(a, "environment.albedo", 0, 1);
  }
  if (e["earth_ir"]) env.earth_ir_w_m2 = doc.number(e["earth_ir"], "environment.earth_ir (W/m²)", 0, 1e4);
  if (e["shadow_samples"])
    env.shadow_samples = static_cast<int>(doc.integer(e["shadow_samples"], "environment.shadow_samples", 1, 1 << 24));
  if (e["shadow_cell"]) {
    if (e["shadow_samples"])
      throw doc.error(e["shadow_cell"], "environment: shadow_cell sizes the shadow grid and shadow_samples replaces "
                                        "it by per-node shadow rays; give one of them");
    env.shadow_cell_m = doc.number(e["shadow_cell"], "environment.shadow_cell (m)", 1e-6, 10.0);
  }
  if (e["planet_rays"]) env.planet_rays = doc.integer(e["planet_rays"], "environment.planet_rays", 32, 1LL << 30);
}

}  // namespace radnet::cases
