#include "cases/orbit_settings.hpp"

#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

namespace radnet::cases {
namespace {

constexpr double kBig = std::numeric_limits<double>::max();
constexpr double kPositive = std::numeric_limits<double>::min();  // "> 0" in messages

Eigen::Vector3d vec3(const YamlDocument& doc, const YAML::Node& node, const std::string& what) {
  if (!node.IsSequence() || node.size() != 3) throw doc.error(node, what + ": expected [x, y, z]");
  Eigen::Vector3d v(doc.number(node[0], what + "[0]", -kBig, kBig), doc.number(node[1], what + "[1]", -kBig, kBig),
                    doc.number(node[2], what + "[2]", -kBig, kBig));
  if (!(v.norm() > 0)) throw doc.error(node, what + ": expected a non-zero vector");
  return v;
}

orbits::Target target(const YamlDocument& doc, const YAML::Node& node, const std::string& what, Eigen::Vector3d& fixed) {
  if (node.IsSequence()) {
    fixed = vec3(doc, node, what);
    return orbits::Target::Inertial;
  }
  const std::string t = doc.string(node, what);
  if (t == "sun") return orbits::Target::Sun;
  if (t == "nadir") return orbits::Target::Nadir;
  if (t == "zenith") return orbits::Target::Zenith;
  if (t == "velocity") return orbits::Target::Velocity;
  if (t == "orbit_normal") return orbits::Target::OrbitNormal;
  std::string msg = what + ": unknown target '" + t + "'";
  if (auto near = nearestWord(t, {"sun", "nadir", "zenith", "velocity", "orbit_normal"})) msg += " (did you mean '" + *near + "'?)";
  throw doc.error(node, msg + "; expected sun, nadir, zenith, velocity, orbit_normal or an ECI vector [x, y, z]");
}

orbits::AttitudeSpec parseAttitude(const YamlDocument& doc, const YAML::Node& node) {
  orbits::AttitudeSpec a;
  if (!node) return a;
  doc.expectMap(node, "attitude", {"mode", "quaternion", "spin_axis", "spin_rate", "primary", "secondary"});
  const std::string mode = node["mode"] ? doc.string(node["mode"], "attitude.mode") : "nadir";
  using Mode = orbits::AttitudeSpec::Mode;
  if (mode == "nadir") a.mode = Mode::Nadir;
  else if (mode == "sun") a.mode = Mode::Sun;
  else if (mode == "inertial") a.mode = Mode::Inertial;
  else if (mode == "spin") a.mode = Mode::Spin;
  else if (mode == "pointing") a.mode = Mode::Pointing;
  else {
    std::string msg = "attitude.mode: unknown mode '" + mode + "'";
    if (auto near = nearestWord(mode, {"nadir", "sun", "inertial", "spin", "pointing"})) msg += " (did you mean '" + *near + "'?)";
    throw doc.error(node["mode"], msg + "; expected nadir, sun, inertial, spin or pointing");
  }
  if (node["quaternion"]) {
    const YAML::Node q = node["quaternion"];
    if (!q.IsSequence() || q.size() != 4) throw doc.error(q, "attitude.quaternion: expected [w, x, y, z] (bodyFromEci)");
    Eigen::Quaterniond quat(doc.number(q[0], "attitude.quaternion[0]", -kBig, kBig), doc.number(q[1], "attitude.quaternion[1]", -kBig, kBig),
                            doc.number(q[2], "attitude.quaternion[2]", -kBig, kBig), doc.number(q[3], "attitude.quaternion[3]", -kBig, kBig));
    if (!(quat.norm() > 0)) throw doc.error(q, "attitude.quaternion: must not be zero");
    a.body_from_eci = quat.normalized();
  } else if (a.mode == Mode::Inertial || a.mode == Mode::Spin) {
    throw doc.error(node, "attitude: mode '" + mode + "' needs 'quaternion: [w, x, y, z]' (bodyFromEci at t = 0)");
  }
  if (node["spin_axis"]) a.spin_axis_body = vec3(doc, node["spin_axis"], "attitude.spin_axis");
  if (node["spin_rate"]) a.spin_rate_deg_s = doc.number(node["spin_rate"], "attitude.spin_rate (deg/s)", -1e4, 1e4);
  if (a.mode == Mode::Pointing) {
    for (const char* which : {"primary", "secondary"}) {
      const YAML::Node p = doc.required(node, which, "attitude (pointing)");
      const std::string what = std::string("attitude.") + which;
      doc.expectMap(p, what, {"axis", "target"});
      const Eigen::Vector3d axis = vec3(doc, doc.required(p, "axis", what), what + ".axis");
      Eigen::Vector3d fixed = Eigen::Vector3d::UnitZ();
      const orbits::Target t = target(doc, doc.required(p, "target", what), what + ".target", fixed);
      if (std::string(which) == "primary") {
        a.pointing.primary_body = axis;
        a.pointing.primary = t;
        a.pointing.primary_eci = fixed;
      } else {
        a.pointing.secondary_body = axis;
        a.pointing.secondary = t;
        a.pointing.secondary_eci = fixed;
      }
    }
    if (a.pointing.primary_body.normalized().cross(a.pointing.secondary_body.normalized()).norm() < 1e-9)
      throw doc.error(node, "attitude: the primary and secondary body axes are parallel");
  }
  return a;
}

}  // namespace

std::optional<OrbitSettings> parseOrbitSettings(const YamlDocument& doc) {
  const YAML::Node& root = doc.root();
  if (!root["orbit"]) {
    for (const char* k : {"attitude", "environment"})
      if (root[k]) throw doc.error(root[k], std::string("'") + k + "' needs an 'orbit:'");
    return std::nullopt;
  }
  const YAML::Node o = root["orbit"];
  doc.expectMap(o, "orbit",
                {"altitude", "beta", "inclination", "raan", "ltan", "sun_synchronous", "semi_major_axis", "eccentricity",
                 "perigee_altitude", "apogee_altitude", "arg_perigee", "true_anomaly", "epoch", "positions", "orbits",
                 "eclipse_events", "spacing"});
  OrbitSettings s;
  auto num = [&](const char* key, const std::string& what, double lo, double hi, double fallback) {
    return o[key] ? doc.number(o[key], "orbit." + std::string(key) + " " + what, lo, hi) : fallback;
  };
  // `epoch` and `beta` may be lists: one orbit per combination (seasons × betas).
  auto listOf = [&](const char* key) {
    std::vector<YAML::Node> items;
    const YAML::Node v = o[key];
    if (!v) return items;
    if (v.IsSequence()) {
      if (v.size() == 0) throw doc.error(v, std::string("orbit.") + key + ": the list is empty");
      for (size_t k = 0; k < v.size(); ++k) items.push_back(v[k]);
    } else {
      items.push_back(v);
    }
    return items;
  };
  std::vector<std::pair<double, std::string>> epochs;
  for (const YAML::Node& e : listOf("epoch")) {
    const std::string text = doc.string(e, "orbit.epoch");
    try {
      epochs.emplace_back(orbits::julianDateFromIso(text), text);
    } catch (const std::invalid_argument& err) {
      throw doc.error(e, std::string("orbit.epoch: ") + err.what());
    }
  }
  if (epochs.empty()) epochs.emplace_back(orbits::julianDateFromIso("2026-03-20T00:00:00Z"), "2026-03-20T00:00:00Z");
  std::vector<std::optional<double>> betas;
  for (const YAML::Node& b : listOf("beta")) betas.push_back(doc.number(b, "orbit.beta (deg)", -90, 90));
  if (betas.empty()) betas.push_back(std::nullopt);

  const bool kepler = o["semi_major_axis"] || o["perigee_altitude"];
  const int forms = (o["beta"] ? 1 : 0) + (o["ltan"] || o["sun_synchronous"] ? 1 : 0) + (kepler ? 1 : 0);
  if (forms > 1)
    throw doc.error(o, "orbit: give one form: 'beta', or 'ltan'/'sun_synchronous', or Keplerian elements "
                       "('semi_major_axis'/'perigee_altitude'), or 'altitude' with 'inclination' and 'raan'");
  if (!kepler && !o["altitude"]) throw doc.error(o, "orbit: missing 'altitude' (m)");
  for (const auto& [epoch, epoch_text] : epochs) {
    for (const auto& beta : betas) {
      try {
        orbits::KeplerElements el;
        if (kepler) {
          if (o["semi_major_axis"]) {
            el.semi_major_axis_m = num("semi_major_axis", "(m)", kPositive, kBig, 0);
            el.eccentricity = num("eccentricity", "", 0, kBig, 0);
            el.inclination_rad = num("inclination", "(deg)", -kBig, kBig, 0) * M_PI / 180;
            el.raan_rad = num("raan", "(deg)", -kBig, kBig, 0) * M_PI / 180;
            el.arg_perigee_rad = num("arg_perigee", "(deg)", -kBig, kBig, 0) * M_PI / 180;
            el.true_anomaly_rad = num("true_anomaly", "(deg)", -kBig, kBig, 0) * M_PI / 180;
          } else {
            el = orbits::perigeeApogeeElements(num("perigee_altitude", "(m)", kPositive, kBig, 0),
                                               num("apogee_altitude", "(m)", kPositive, kBig, 0),
                                               num("inclination", "(deg)", -kBig, kBig, 0), num("raan", "(deg)", -kBig, kBig, 0),
                                               num("arg_perigee", "(deg)", -kBig, kBig, 0),
                                               num("true_anomaly", "(deg)", -kBig, kBig, 0));
          }
          s.description = "Keplerian elements";
        } else {
          const double h = num("altitude", "(m)", kPositive, kBig, 0);
          if (beta) {
            el = orbits::betaElements(h, *beta, epoch);
            s.description = "circular, by beta";
          } else if (o["ltan"] || o["sun_synchronous"]) {
            if (o["sun_synchronous"] && !doc.boolean(o["sun_synchronous"], "orbit.sun_synchronous"))
              throw doc.error(o["sun_synchronous"], "orbit.sun_synchronous: false makes no orbit; remove it or give 'inclination'");
            if (o["inclination"]) throw doc.error(o["inclination"], "orbit.inclination: a sun-synchronous orbit's inclination follows from J2; remove it");
            const double ltan = num("ltan", "(hours)", 0, 24, 12.0);
            el = orbits::circularElements(h, orbits::sunSynchronousInclinationDeg(h), orbits::raanForLocalTimeDeg(ltan, epoch));
            std::ostringstream d;
            d << "sun-synchronous, LTAN " << ltan << " h";
            s.description = d.str();
          } else {
            el = orbits::circularElements(h, num("inclination", "(deg)", 0, 180, 0), num("raan", "(deg)", -kBig, kBig, 0),
                                          num("true_anomaly", "(deg)", -kBig, kBig, 0));
            s.description = "circular";
          }
        }
        OrbitCase oc;
        oc.orbit = std::make_unique<orbits::Orbit>(el, epoch);
        std::ostringstream label;
        label << "epoch " << epoch_text;
        if (beta) label << ", beta " << *beta << " deg";
        oc.label = label.str();
        s.cases.push_back(std::move(oc));
      } catch (const orbits::OrbitError& e) {
        throw doc.error(o, std::string("orbit: ") + e.what());
      }
    }
  }
  if (o["positions"]) s.sweep.positions_per_orbit = static_cast<int>(doc.integer(o["positions"], "orbit.positions", 1, 100000));
  if (o["orbits"]) s.sweep.orbits = doc.number(o["orbits"], "orbit.orbits", 1e-3, 10000);
  if (o["spacing"]) {
    const std::string sp = doc.string(o["spacing"], "orbit.spacing");
    if (sp == "time") s.sweep.spacing = orbits::SweepOptions::Spacing::Time;
    else if (sp == "true_anomaly") s.sweep.spacing = orbits::SweepOptions::Spacing::TrueAnomaly;
    else throw doc.error(o["spacing"], "orbit.spacing: '" + sp + "'; expected time or true_anomaly");
  }
  if (o["eclipse_events"]) s.sweep.insert_eclipse_events = doc.boolean(o["eclipse_events"], "orbit.eclipse_events");

  s.attitude = parseAttitude(doc, root["attitude"]);
  if (const YAML::Node e = root["environment"]) {
    doc.expectMap(e, "environment", {"solar_constant", "albedo", "earth_ir", "shadow_samples", "planet_rays"});
    if (e["solar_constant"]) s.sweep.solar_constant_w_m2 = doc.number(e["solar_constant"], "environment.solar_constant (W/m²)", 0, 1e5);
    if (e["albedo"]) {
      const YAML::Node a = e["albedo"];
      if (a.IsSequence()) {
        double last = -1;
        for (size_t k = 0; k < a.size(); ++k) {
          const std::string what = "environment.albedo[" + std::to_string(k) + "]";
          if (!a[k].IsSequence() || a[k].size() != 2) throw doc.error(a[k], what + ": expected [latitude_deg, albedo]");
          const double lat = doc.number(a[k][0], what + " latitude (deg)", 0, 90);
          if (lat <= last) throw doc.error(a[k][0], what + ": latitudes must increase");
          last = lat;
          s.environment.albedo_by_latitude.emplace_back(lat, doc.number(a[k][1], what + " albedo", 0, 1));
        }
        if (s.environment.albedo_by_latitude.empty()) throw doc.error(a, "environment.albedo: the table is empty");
      } else {
        s.environment.albedo = doc.number(a, "environment.albedo", 0, 1);
      }
    }
    if (e["earth_ir"]) s.environment.earth_ir_w_m2 = doc.number(e["earth_ir"], "environment.earth_ir (W/m²)", 0, 1e4);
    if (e["shadow_samples"]) s.environment.shadow_samples = static_cast<int>(doc.integer(e["shadow_samples"], "environment.shadow_samples", 1, 1 << 24));
    if (e["planet_rays"]) s.environment.planet_rays = doc.integer(e["planet_rays"], "environment.planet_rays", 32, 1LL << 30);
  }
  return s;
}

}  // namespace radnet::cases
