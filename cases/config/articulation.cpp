#include "cases/config/articulation.hpp"

#include "cases/config/geometry_case.hpp"
#include "geometry/scene/part_clearance.hpp"
#include "solver/thermal/network.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace radnet::cases {
namespace {

constexpr double kPi = 3.14159265358979323846;

// (−180, 180], deg.
double wrapDegrees(double a) {
  a = std::remainder(a, 360.0);
  return a <= -180.0 ? a + 360.0 : a;
}

// A part names a geometry item: its surface, or the surfaces radnet derived from it
// (<name>.<i>.<j> of a grid, a box's <name>.+x, a mesh's <name>.<part>).
std::vector<int> surfacesOf(const geometry::Scene& scene, const std::string& part) {
  std::vector<int> out;
  const std::vector<std::string>& names = scene.surfaceNames();
  for (size_t s = 0; s < names.size(); ++s)
    if (names[s] == part || names[s].rfind(part + ".", 0) == 0) out.push_back(static_cast<int>(s));
  return out;
}

// Every geometry item name the case has (the surfaces' names up to their first '.').
std::vector<std::string> itemNames(const geometry::Scene& scene) {
  std::set<std::string> items;
  for (const std::string& s : scene.surfaceNames()) items.insert(s.substr(0, s.find('.')));
  return {items.begin(), items.end()};
}

void parseParts(const YamlDocument& doc, const YAML::Node& parts, const std::string& what, const GeometryCase& c,
                std::set<int>& taken, Drive& d) {
  doc.expectSequence(parts, what);
  if (parts.size() == 0) throw doc.error(parts, what + ": the list is empty; expected the geometry items that turn");
  for (size_t k = 0; k < parts.size(); ++k) {
    const std::string name = doc.string(parts[k], what + "[" + std::to_string(k) + "]");
    const std::vector<int> surfaces = surfacesOf(c.scene, name);
    if (surfaces.empty()) {
      std::string msg = what + ": '" + name + "' is not a geometry item";
      if (auto near = nearestWord(name, itemNames(c.scene))) msg += " (did you mean '" + *near + "'?)";
      throw doc.error(parts[k], msg + "; parts name the `name:` of geometry entries");
    }
    for (int s : surfaces)
      if (!taken.insert(s).second)
        throw doc.error(parts[k], what + ": '" + name + "' already turns with another drive (or is listed twice)");
    d.parts.push_back(name);
    d.surfaces.insert(d.surfaces.end(), surfaces.begin(), surfaces.end());
  }
}

// The nodes on the drive's surfaces; a node with triangles on a fixed surface too would tear.
void collectNodes(const YamlDocument& doc, const YAML::Node& at, const std::string& what, const geometry::Scene& scene,
                  Drive& d) {
  std::vector<char> moving(scene.surfaceNames().size(), 0);
  for (int s : d.surfaces) moving[static_cast<size_t>(s)] = 1;
  for (size_t i = 0; i < scene.nodes().size(); ++i) {
    const geometry::Node& node = scene.nodes()[i];
    int on = 0;
    for (int f : node.faces) on += moving[static_cast<size_t>(scene.faces()[static_cast<size_t>(f)].surface)];
    if (on == 0) continue;
    if (on != static_cast<int>(node.faces.size()))
      throw doc.error(at, what + ": node '" + node.name + "' has triangles on a turning part and on a fixed one " +
                              "(`join: true` across them?): a node must move as one");
    d.nodes.push_back(static_cast<int>(i));
  }
}

// The parts' area-weighted front normal (their active front sides), for Sun tracking.
Eigen::Vector3d frontNormal(const YamlDocument& doc, const YAML::Node& at, const std::string& what,
                            const geometry::Scene& scene, const Drive& d) {
  std::vector<char> moving(scene.surfaceNames().size(), 0);
  for (int s : d.surfaces) moving[static_cast<size_t>(s)] = 1;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double area = 0.0;
  for (const geometry::Face& f : scene.faces())
    if (moving[static_cast<size_t>(f.surface)] && f.front_node >= 0) {
      sum += f.area_m2 * f.normal;
      area += f.area_m2;
    }
  const Eigen::Vector3d across = sum - sum.dot(d.direction) * d.direction;
  if (!(area > 0) || across.norm() < 1e-6 * area)
    throw doc.error(at, what + ": track: sun needs the parts' front sides to face one way across the axis (their "
                               "area-weighted front normal is " + (area > 0 ? "along the axis or zero" : "absent") +
                               "); give `angle:` or `angles:` instead");
  return sum.normalized();
}

void parseAngleTable(const YamlDocument& doc, const YAML::Node& table, const std::string& what, Drive& d) {
  doc.expectSequence(table, what);
  if (table.size() == 0) throw doc.error(table, what + ": the table is empty; expected [[t_s, deg], ...]");
  for (size_t k = 0; k < table.size(); ++k) {
    const std::string at = what + "[" + std::to_string(k) + "]";
    if (!table[k].IsSequence() || table[k].size() != 2)
      throw doc.error(table[k], at + ": expected [t_s, deg] (seconds since the orbit case's epoch, degrees)");
    const double t = doc.number(table[k][0], at + "[0] (s)", -1e12, 1e12);
    const double a = doc.number(table[k][1], at + "[1] (deg)", -1e6, 1e6);
    if (!d.table_t_s.empty() && !(t > d.table_t_s.back()))
      throw doc.error(table[k][0], at + ": times must increase (" + std::to_string(t) + " s after " +
                                       std::to_string(d.table_t_s.back()) + " s)");
    d.table_t_s.push_back(t);
    d.table_deg.push_back(a);
  }
}

Drive parseDrive(const YamlDocument& doc, const YAML::Node& entry, const std::string& what, GeometryCase& c,
                 std::set<int>& taken) {
  doc.expectMap(entry, what, {"name", "parts", "axis", "track", "angle", "angles", "step"});
  Drive d;
  d.name = doc.string(doc.required(entry, "name", what), what + ".name");
  if (d.name.empty()) throw doc.error(entry["name"], what + ".name: empty; expected the drive's name");
  parseParts(doc, doc.required(entry, "parts", what), what + ".parts", c, taken, d);
  collectNodes(doc, entry["parts"], what + ".parts", c.scene, d);
  const YAML::Node axis = doc.required(entry, "axis", what);
  doc.expectMap(axis, what + ".axis", {"point", "direction"});
  d.point = doc.vector3(doc.required(axis, "point", what + ".axis"), what + ".axis.point (m)");
  const YAML::Node dir = doc.required(axis, "direction", what + ".axis");
  const Eigen::Vector3d direction = doc.vector3(dir, what + ".axis.direction");
  if (!(direction.norm() > 1e-12))
    throw doc.error(dir, what + ".axis.direction: zero length; expected the axis' direction [x, y, z]");
  d.direction = direction.normalized();
  const int given = int(bool(entry["track"])) + int(bool(entry["angle"])) + int(bool(entry["angles"]));
  if (given != 1)
    throw doc.error(entry, what + ": expected exactly one of `track: sun`, `angle: deg` or `angles: [[t_s, deg], ...]`" +
                               (given ? " (several given)" : ""));
  if (entry["track"]) {
    doc.choice(entry["track"], what + ".track", {"sun"});
    d.track = Drive::Track::Sun;
    d.front_normal = frontNormal(doc, entry["track"], what, c.scene, d);
  } else if (entry["angle"]) {
    d.track = Drive::Track::Fixed;
    d.angle_deg = doc.number(entry["angle"], what + ".angle (deg)", -1e6, 1e6);
  } else {
    d.track = Drive::Track::Table;
    parseAngleTable(doc, entry["angles"], what + ".angles", d);
  }
  d.step_deg = entry["step"] ? doc.number(entry["step"], what + ".step (deg)", 1e-3, 180.0)
                             : defaultDriveStep(c.solver.accuracy);
  return d;
}

}  // namespace

double defaultDriveStep(double accuracy) {
  // Divisors of 360° (so that 0 and ±180 are bins), then finer.
  for (double step : {180.0, 120.0, 90.0, 72.0, 60.0, 45.0, 40.0, 36.0, 30.0, 24.0, 20.0, 18.0, 15.0, 12.0, 10.0, 9.0,
                      8.0, 6.0, 5.0, 4.0, 3.0, 2.0, 1.0, 0.5, 0.25, 0.1, 0.05, 0.025, 0.01})
    if (1.0 - std::cos(0.5 * step * kPi / 180.0) <= 0.1 * accuracy) return step;
  return 0.01;
}

std::vector<std::string> Articulation::names() const {
  std::vector<std::string> out;
  for (const Drive& d : drives) out.push_back(d.name);
  for (const auto& [name, angle] : fixed_drives) out.push_back(name);
  return out;
}

Eigen::MatrixXd Articulation::movingAngles(const std::vector<orbits::SweepPosition>& positions) const {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(positions.size()), static_cast<Eigen::Index>(drives.size()));
  for (size_t d = 0; d < drives.size(); ++d)
    out.col(static_cast<Eigen::Index>(d)) = Eigen::Map<const Eigen::VectorXd>(drives[d].angles(positions).data(), out.rows());
  return out;
}

std::vector<double> Drive::angles(const std::vector<orbits::SweepPosition>& positions) const {
  const size_t P = positions.size();
  std::vector<double> out(P, angle_deg);
  if (track == Track::Table) {
    for (size_t p = 0; p < P; ++p)
      out[p] = solver::interpolateHeld(table_t_s, table_deg, positions[p].t_s);
  } else if (track == Track::Sun) {
    // Turn the front towards the Sun about the axis; in eclipse (or with the Sun on the axis)
    // hold the last sunlit angle, the sweep taken as periodic (its start holds its end's).
    const Eigen::Vector3d n = (front_normal - front_normal.dot(direction) * direction).normalized();
    std::vector<char> known(P, 0);
    for (size_t p = 0; p < P; ++p) {
      const Eigen::Vector3d& s = positions[p].sun_body;
      const Eigen::Vector3d across = s - s.dot(direction) * direction;
      if (positions[p].sunlit_fraction <= 0.0 || across.norm() < 1e-9) continue;
      out[p] = std::atan2(direction.dot(n.cross(across)), n.dot(across)) * 180.0 / kPi;
      known[p] = 1;
    }
    double held = 0.0;
    for (size_t p = 0; p < P; ++p)  // the last known angle of the sweep holds its start
      if (known[p]) held = out[p];
    for (size_t p = 0; p < P; ++p) {
      if (known[p]) held = out[p];
      else out[p] = held;
    }
  }
  if (step_deg > 0 && track != Track::Fixed)
    for (double& a : out) a = step_deg * std::round(wrapDegrees(a) / step_deg);
  for (double& a : out) a = wrapDegrees(a) + 0.0;  // + 0.0: no −0 in the output
  return out;
}

void parseArticulation(const YamlDocument& doc, GeometryCase& c) {
  const YAML::Node node = doc.root()["articulation"];
  if (!node) return;
  doc.expectSequence(node, "articulation");
  if (node.size() == 0) throw doc.error(node, "articulation: the list is empty; expected drives {name, parts, axis, ...}");
  std::set<int> taken;
  std::set<std::string> names;
  for (size_t k = 0; k < node.size(); ++k) {
    const std::string what = "articulation[" + std::to_string(k) + "]";
    Drive d = parseDrive(doc, node[k], what, c, taken);
    if (!names.insert(d.name).second)
      throw doc.error(node[k]["name"], what + ".name: '" + d.name + "' names two drives");
    if (d.track != Drive::Track::Fixed && !c.hasOrbit())
      throw doc.error(node[k], what + ": `track` and `angles` follow the orbit, and the case has none; give `angle:`");
    if (d.track == Drive::Track::Fixed) {
      const std::vector<std::pair<int, int>> written = geometry::meetingSurfaces(c.scene, d.surfaces);
      c.scene.rotateSurfaces(d.surfaces, d.point, d.direction, d.angle_deg * kPi / 180.0);
      if (geometry::meetingSurfaces(c.scene, d.surfaces).size() > written.size())
        c.warnings.push_back(doc.located(node[k]["angle"], what + ": at " + std::to_string(d.angle_deg) +
                                                                "° the parts run into the spacecraft (they meet a fixed "
                                                                "surface they did not meet as written)"));
      c.articulation.fixed_drives.emplace_back(d.name, d.angle_deg);
    } else {
      c.articulation.drives.push_back(std::move(d));
    }
  }
  if (c.articulation.drives.empty()) return;
  // What the moving configurations do not support yet: said, never run silently wrong.
  const auto refuse = [&](const std::string& why) {
    throw doc.error(node, "articulation: parts that turn during the orbit " + why +
                              " (not supported yet); a fixed `angle:` works with it");
  };
  if (c.hasSpecular()) refuse("cannot be combined with specular or transmissive surfaces");
  for (const OpticalSet& set : c.optical_sets)
    if (set.own_specular) refuse("cannot be combined with optical sets that change ρs or τ");
  for (const auto& [name, m] : c.materials)
    if (m.hasCurves()) refuse("cannot be combined with optics tabulated against temperature (material '" + name + "')");
  if (doc.root()["uncertainty"]) refuse("cannot be combined with `uncertainty:` sampling");
}

}  // namespace radnet::cases
