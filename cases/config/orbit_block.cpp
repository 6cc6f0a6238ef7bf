#include "cases/config/orbit_settings.hpp"

#include "orbits/earth.hpp"
#include "orbits/sweep.hpp"
#include "solver/units.hpp"

#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

namespace radnet::cases {
namespace {

constexpr double kBig = std::numeric_limits<double>::max();
constexpr double kPositive = std::numeric_limits<double>::min();  // "> 0" in messages
constexpr const char* kDefaultEpoch = "2026-03-20T00:00:00Z";

// Reads the optional numbers of the `orbit:` mapping with their unit in messages.
struct OrbitKeys {
  const YamlDocument& doc;
  const YAML::Node& o;
  const orbits::CentralBody& body;
  double num(const char* key, const std::string& what, double lo, double hi, double fallback) const {
    return o[key] ? doc.number(o[key], "orbit." + std::string(key) + " " + what, lo, hi) : fallback;
  }
  // An angle reduced to (-360, 360) deg in degrees, where std::fmod is exact, before it becomes
  // radians: 1e20 deg reduced after the conversion keeps none of its digits.
  double deg(const char* key, double fallback = 0) const {
    return std::fmod(num(key, "(deg)", -kBig, kBig, fallback), 360.0);
  }
  double inclinationDeg() const { return num("inclination", "(deg)", 0, 180, 0); }
};

// Below a body's lowest altitude (the Earth's: 100 km) nothing orbits for long; such a value
// is almost always kilometres written where metres are meant (35786 for GEO). Refused unless
// `allow_low_altitude: true`. Beyond its highest (the Earth's: the Moon's mean distance;
// elsewhere the Hill sphere) the body does not hold the orbit, and such a value is almost
// always a unit slip the other way (35786.0e6 for GEO, an astronomical unit). Refused unless
// `allow_high_altitude: true`.

// `orbit.body`: the Earth unless named.
const orbits::CentralBody& centralBody(const YamlDocument& doc, const YAML::Node& o) {
  if (!o["body"]) return orbits::CentralBody::earth();
  return *orbits::CentralBody::named(doc.choice(o["body"], "orbit.body", orbits::CentralBody::names()));
}

bool allowed(const YamlDocument& doc, const YAML::Node& o, const char* key) {
  return o[key] && doc.boolean(o[key], std::string("orbit.") + key);
}

void checkAltitudes(const YamlDocument& doc, const YAML::Node& o, const orbits::CentralBody& body) {
  const bool allow_low = allowed(doc, o, "allow_low_altitude"), allow_high = allowed(doc, o, "allow_high_altitude");
  const double radius_m = body.equatorial_radius_m;
  for (const char* key : {"altitude", "perigee_altitude", "apogee_altitude", "semi_major_axis"}) {
    const YAML::Node v = o[key];
    if (!v) continue;
    const bool radius = std::string(key) == "semi_major_axis";
    const double value = doc.number(v, std::string("orbit.") + key + " (m)", -kBig, kBig);
    const double h = radius ? value - radius_m : value;
    std::ostringstream msg;
    if (!allow_low && !radius && h > 0 && h < body.lowest_altitude_m) {
      msg << "orbit." << key << ": " << h << " m is below " << body.lowest_altitude_m / 1e3 << " km, where no orbit about "
          << body.name << " lasts; altitudes are in metres (" << h << " km is " << h
          << ".0e3); give 'allow_low_altitude: true' if " << h << " m is meant";
      throw doc.error(v, msg.str());
    }
    if (!allow_high && h > body.highest_altitude_m) {
      msg << "orbit." << key << ": " << value << " m puts the spacecraft " << h << " m above "
          << (body.isEarth() ? "the Earth, beyond the Moon's distance (3.844e8 m)"
                             : body.name + ", beyond its Hill sphere (" + std::to_string(body.highest_altitude_m) + " m)")
          << "; lengths are in metres" << (body.isEarth() ? " (GEO's altitude is 35786.0e3)" : "")
          << "; give 'allow_high_altitude: true' if it is meant";
      throw doc.error(v, msg.str());
    }
  }
}

// A key the chosen form does not use would be dropped silently: refuse it, saying why.
void checkFormKeys(const YamlDocument& doc, const YAML::Node& o, bool kepler) {
  std::vector<std::pair<const char*, const char*>> unused;  // key, why
  if (kepler) {
    for (const char* key : {"altitude", "ltan", "sun_synchronous", "beta"})
      unused.emplace_back(key, "Keplerian elements give the orbit; remove it");
    if (o["semi_major_axis"])
      for (const char* key : {"perigee_altitude", "apogee_altitude"})
        unused.emplace_back(key, "give semi_major_axis/eccentricity or perigee/apogee altitudes, not both");
    else
      unused.emplace_back("eccentricity", "perigee and apogee altitudes set it; remove it");
  } else {
    for (const char* key : {"eccentricity", "arg_perigee", "apogee_altitude"})
      unused.emplace_back(key, "a circular orbit by altitude has none; give Keplerian elements for an eccentric one");
    if (o["beta"])
      for (const char* key : {"inclination", "raan", "true_anomaly"})
        unused.emplace_back(key, "the beta form sets the plane from beta and starts at the ascending node; remove it");
    if (o["ltan"] || o["sun_synchronous"]) unused.emplace_back("raan", "a sun-synchronous orbit's node follows from ltan");
  }
  for (const auto& [key, why] : unused)
    if (o[key]) throw doc.error(o[key], std::string("orbit.") + key + ": " + why);
}

// `epoch` and `beta` may be lists: one orbit per combination (seasons × betas).
std::vector<YAML::Node> listOf(const YamlDocument& doc, const YAML::Node& o, const char* key) {
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
}

std::vector<std::pair<double, std::string>> epochs(const YamlDocument& doc, const YAML::Node& o) {
  std::vector<std::pair<double, std::string>> out;  // (Julian date, as written)
  for (const YAML::Node& e : listOf(doc, o, "epoch")) {
    const std::string text = doc.string(e, "orbit.epoch");
    try {
      out.emplace_back(orbits::julianDateFromIso(text), text);
    } catch (const std::invalid_argument& err) {
      throw doc.error(e, std::string("orbit.epoch: ") + err.what());
    }
  }
  if (out.empty()) out.emplace_back(orbits::julianDateFromIso(kDefaultEpoch), kDefaultEpoch);
  return out;
}

orbits::KeplerElements keplerElements(const OrbitKeys& k) {
  if (!k.o["semi_major_axis"])
    return orbits::perigeeApogeeElements(
        k.num("perigee_altitude", "(m)", kPositive, kBig, 0), k.num("apogee_altitude", "(m)", kPositive, kBig, 0),
        k.inclinationDeg(), k.deg("raan"), k.deg("arg_perigee"), k.deg("true_anomaly"), k.body);
  orbits::KeplerElements el;
  el.semi_major_axis_m = k.num("semi_major_axis", "(m)", kPositive, kBig, 0);
  el.eccentricity = k.num("eccentricity", "", 0, kBig, 0);
  el.inclination_rad = units::degToRad(k.inclinationDeg());
  el.raan_rad = units::degToRad(k.deg("raan"));
  el.arg_perigee_rad = units::degToRad(k.deg("arg_perigee"));
  el.true_anomaly_rad = units::degToRad(k.deg("true_anomaly"));
  return el;
}

// A circular orbit by altitude: by beta, sun-synchronous by LTAN, or by inclination.
orbits::KeplerElements circularElements(const OrbitKeys& k, std::optional<double> beta, double epoch,
                                        std::string& description) {
  const YamlDocument& doc = k.doc;
  const YAML::Node& o = k.o;
  const double h = k.num("altitude", "(m)", kPositive, kBig, 0);
  if (beta) {
    description = "circular, by beta";
    return orbits::betaElements(h, *beta, epoch, k.body);
  }
  if (o["ltan"] || o["sun_synchronous"]) {
    if (o["sun_synchronous"] && !doc.boolean(o["sun_synchronous"], "orbit.sun_synchronous"))
      throw doc.error(o["sun_synchronous"],
                      "orbit.sun_synchronous: false makes no orbit; remove it or give 'inclination'");
    if (o["inclination"])
      throw doc.error(o["inclination"],
                      "orbit.inclination: a sun-synchronous orbit's inclination follows from J2; remove it");
    const double ltan = k.num("ltan", "(hours)", 0, 24, 12.0);
    std::ostringstream d;
    d << "sun-synchronous, LTAN " << ltan << " h";
    description = d.str();
    return orbits::circularElements(h, orbits::sunSynchronousInclinationDeg(h, k.body),
                                    orbits::raanForLocalTimeDeg(ltan, epoch, k.body), k.deg("true_anomaly"), k.body);
  }
  description = "circular";
  return orbits::circularElements(h, k.inclinationDeg(), k.deg("raan"), k.deg("true_anomaly"), k.body);
}

void parseSweepOptions(const YamlDocument& doc, const YAML::Node& o, orbits::SweepOptions& sweep) {
  if (o["positions"])
    sweep.positions_per_orbit = static_cast<int>(doc.integer(o["positions"], "orbit.positions", 1, 100000));
  if (o["orbits"]) sweep.orbits = doc.number(o["orbits"], "orbit.orbits", 1e-3, 10000);
  if (o["spacing"])
    sweep.spacing = doc.choice(o["spacing"], "orbit.spacing", {"time", "true_anomaly"}) == "time"
                        ? orbits::SweepOptions::Spacing::Time
                        : orbits::SweepOptions::Spacing::TrueAnomaly;
  if (o["eclipse_events"]) sweep.insert_eclipse_events = doc.boolean(o["eclipse_events"], "orbit.eclipse_events");
}

constexpr double kAttitudeCheckMaxPositions = 2.0e5;  // about 0.2 s of positions (sweepOrbit)

// A pointing whose two targets align at some position of the sweep (sun and nadir at the
// subsolar point of a noon orbit) has no roll there: refused at `attitude:` before any work,
// so `validate` says what `run` would. Positions only, no rays: milliseconds.
void checkAttitudeOnSweep(const YamlDocument& doc, const YAML::Node& attitude, const OrbitSettings& s) {
  using Mode = orbits::AttitudeSpec::Mode;
  if (!attitude || (s.attitude.mode != Mode::Pointing && s.attitude.mode != Mode::Sun)) return;
  // A sweep too long to check in a moment (1e9 positions: validate ran for minutes) is left to
  // the memory check, which refuses most such sweeps, and to the run, which names the time.
  if (s.sweep.positions_per_orbit * s.sweep.orbits * static_cast<double>(s.cases.size()) > kAttitudeCheckMaxPositions)
    return;
  for (const OrbitCase& oc : s.cases) {
    try {
      (void)orbits::sweepOrbit(*oc.orbit, s.attitude, s.sweep);
    } catch (const orbits::OrbitError& e) {
      const std::string what = e.what();
      if (what.rfind("attitude", 0) != 0) throw;  // not the attitude's: the run reports it as before
      throw doc.error(attitude, what + " (" + oc.label + ")");
    }
  }
}

}  // namespace

std::optional<OrbitSettings> parseOrbitSettings(const YamlDocument& doc) {
  const YAML::Node& root = doc.root();
  return parseOrbitSettings(doc, root["orbit"], root["attitude"], root["environment"]);
}

std::optional<OrbitSettings> parseOrbitSettings(const YamlDocument& doc, const YAML::Node& o,
                                                const YAML::Node& attitude, const YAML::Node& environment) {
  if (!o) {
    if (attitude) throw doc.error(attitude, "'attitude' needs an 'orbit:'");
    if (environment) throw doc.error(environment, "'environment' needs an 'orbit:'");
    return std::nullopt;
  }
  doc.expectMap(o, "orbit",
                {"altitude", "beta", "inclination", "raan", "ltan", "sun_synchronous", "semi_major_axis",
                 "eccentricity", "perigee_altitude", "apogee_altitude", "arg_perigee", "true_anomaly", "epoch",
                 "positions", "orbits", "eclipse_events", "spacing", "allow_low_altitude", "allow_high_altitude", "body"});
  OrbitSettings s;
  s.body = &centralBody(doc, o);
  checkAltitudes(doc, o, *s.body);
  const OrbitKeys keys{doc, o, *s.body};
  const auto epoch_list = epochs(doc, o);
  std::vector<std::optional<double>> betas;
  for (const YAML::Node& b : listOf(doc, o, "beta")) betas.push_back(doc.number(b, "orbit.beta (deg)", -90, 90));
  if (betas.empty()) betas.push_back(std::nullopt);

  const bool kepler = o["semi_major_axis"] || o["perigee_altitude"];
  const int forms = (o["beta"] ? 1 : 0) + (o["ltan"] || o["sun_synchronous"] ? 1 : 0) + (kepler ? 1 : 0);
  if (forms > 1)
    throw doc.error(o,
                    "orbit: give one form: 'beta', or 'ltan'/'sun_synchronous', or Keplerian elements "
                    "('semi_major_axis'/'perigee_altitude'), or 'altitude' with 'inclination' and 'raan'");
  if (!kepler && !o["altitude"]) throw doc.error(o, "orbit: missing 'altitude' (m)");
  checkFormKeys(doc, o, kepler);
  for (const auto& [epoch, epoch_text] : epoch_list) {
    for (const auto& beta : betas) {
      try {
        orbits::KeplerElements el;
        if (kepler) {
          el = keplerElements(keys);
          s.description = "Keplerian elements";
        } else {
          el = circularElements(keys, beta, epoch, s.description);
        }
        OrbitCase oc;
        oc.orbit = std::make_unique<orbits::Orbit>(el, epoch, *s.body);
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
  if (!s.body->isEarth()) s.description += " about " + s.body->name;
  parseSweepOptions(doc, o, s.sweep);
  s.attitude = parseAttitude(doc, attitude);
  parseEnvironment(doc, environment, *s.body, s.sweep, s.environment);
  checkAttitudeOnSweep(doc, attitude, s);
  return s;
}

}  // namespace radnet::cases
