#include "cases/config/orbit_settings.hpp"

#include <limits>

namespace radnet::cases {
namespace {

constexpr double kBig = std::numeric_limits<double>::max();

orbits::Target target(const YamlDocument& doc, const YAML::Node& node, const std::string& what,
                      Eigen::Vector3d& fixed) {
  if (node.IsSequence()) {
    fixed = doc.vector3(node, what, true);
    return orbits::Target::Inertial;
  }
  const std::string t = doc.string(node, what);
  if (t == "sun") return orbits::Target::Sun;
  if (t == "nadir") return orbits::Target::Nadir;
  if (t == "zenith") return orbits::Target::Zenith;
  if (t == "velocity") return orbits::Target::Velocity;
  if (t == "orbit_normal") return orbits::Target::OrbitNormal;
  std::string msg = what + ": unknown target '" + t + "'";
  if (auto near = nearestWord(t, {"sun", "nadir", "zenith", "velocity", "orbit_normal"}))
    msg += " (did you mean '" + *near + "'?)";
  throw doc.error(node, msg + "; expected sun, nadir, zenith, velocity, orbit_normal or an ECI vector [x, y, z]");
}

orbits::AttitudeSpec::Mode attitudeMode(const YamlDocument& doc, const YAML::Node& node, const std::string& mode) {
  using Mode = orbits::AttitudeSpec::Mode;
  if (mode == "nadir") return Mode::Nadir;
  if (mode == "sun") return Mode::Sun;
  if (mode == "inertial") return Mode::Inertial;
  if (mode == "spin") return Mode::Spin;
  if (mode == "pointing") return Mode::Pointing;
  std::string msg = "attitude.mode: unknown mode '" + mode + "'";
  if (auto near = nearestWord(mode, {"nadir", "sun", "inertial", "spin", "pointing"}))
    msg += " (did you mean '" + *near + "'?)";
  throw doc.error(node, msg + "; expected nadir, sun, inertial, spin or pointing");
}

Eigen::Quaterniond quaternion(const YamlDocument& doc, const YAML::Node& q) {
  if (!q.IsSequence() || q.size() != 4) throw doc.error(q, "attitude.quaternion: expected [w, x, y, z] (bodyFromEci)");
  Eigen::Quaterniond quat(
      doc.number(q[0], "attitude.quaternion[0]", -kBig, kBig), doc.number(q[1], "attitude.quaternion[1]", -kBig, kBig),
      doc.number(q[2], "attitude.quaternion[2]", -kBig, kBig), doc.number(q[3], "attitude.quaternion[3]", -kBig, kBig));
  if (!(quat.norm() > 0)) throw doc.error(q, "attitude.quaternion: must not be zero");
  return quat.normalized();
}

// `primary` and `secondary` of the two-axis pointing mode (TRIAD).
void parsePointing(const YamlDocument& doc, const YAML::Node& node, orbits::AttitudeSpec& a) {
  for (const char* which : {"primary", "secondary"}) {
    const YAML::Node p = doc.required(node, which, "attitude (pointing)");
    const std::string what = std::string("attitude.") + which;
    doc.expectMap(p, what, {"axis", "target"});
    const Eigen::Vector3d axis = doc.vector3(doc.required(p, "axis", what), what + ".axis", true);
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
  // Targets parallel at every instant leave the roll undefined everywhere; those that align
  // only at some instants are found on the sweep's positions (parseOrbitSettings).
  using orbits::Target;
  const Target t1 = a.pointing.primary, t2 = a.pointing.secondary;
  const bool same = t1 == t2 && t1 != Target::Inertial;
  const bool opposite = (t1 == Target::Nadir && t2 == Target::Zenith) || (t1 == Target::Zenith && t2 == Target::Nadir);
  const bool fixed = t1 == Target::Inertial && t2 == Target::Inertial &&
                     a.pointing.primary_eci.normalized().cross(a.pointing.secondary_eci.normalized()).norm() < 1e-9;
  if (same || opposite || fixed)
    throw doc.error(node["secondary"]["target"], "attitude.secondary.target: parallel to the primary target at every instant "
                                       "(the roll about the primary axis is undefined); choose a target across it");
}

}  // namespace

orbits::AttitudeSpec parseAttitude(const YamlDocument& doc, const YAML::Node& node) {
  orbits::AttitudeSpec a;
  if (!node) return a;
  doc.expectMap(node, "attitude", {"mode", "quaternion", "spin_axis", "spin_rate", "primary", "secondary"});
  const std::string mode = node["mode"] ? doc.string(node["mode"], "attitude.mode") : "nadir";
  using Mode = orbits::AttitudeSpec::Mode;
  a.mode = attitudeMode(doc, node["mode"], mode);
  if (node["quaternion"]) {
    a.body_from_eci = quaternion(doc, node["quaternion"]);
  } else if (a.mode == Mode::Inertial || a.mode == Mode::Spin) {
    throw doc.error(node, "attitude: mode '" + mode + "' needs 'quaternion: [w, x, y, z]' (bodyFromEci at t = 0)");
  }
  if (node["spin_axis"]) a.spin_axis_body = doc.vector3(node["spin_axis"], "attitude.spin_axis", true);
  if (node["spin_rate"]) a.spin_rate_deg_s = doc.number(node["spin_rate"], "attitude.spin_rate (deg/s)", -1e4, 1e4);
  if (a.mode == Mode::Pointing) parsePointing(doc, node, a);
  return a;
}

}  // namespace radnet::cases
