#include "cases/config/primitive_specs.hpp"

#include "cases/config/mesh_block.hpp"
#include "cases/config/work_estimate.hpp"

#include <unistd.h>
#include <limits>
#include <sstream>

namespace radnet::cases {
namespace {

using geometry::Vec3;
constexpr double kBig = std::numeric_limits<double>::max();

Vec3 point(const PrimitiveInput& in, const char* key) {
  return in.doc.vector3(in.doc.required(in.params, key, in.what), in.what + "." + key);
}

double length(const PrimitiveInput& in, const char* key) {
  return in.doc.number(in.doc.required(in.params, key, in.what), in.what + "." + key + " (m)", 0, kBig);
}

double optionalLength(const PrimitiveInput& in, const char* key, double fallback) {
  return in.params[key] ? in.doc.number(in.params[key], in.what + "." + key, 0.0, kBig) : fallback;
}

// `angles: [start, end]` (deg) and `reference` of the curved primitives.
geometry::Sweep sweep(const PrimitiveInput& in) {
  geometry::Sweep s;
  if (in.params["angles"]) {
    const YAML::Node a = in.params["angles"];
    if (!a.IsSequence() || a.size() != 2) throw in.doc.error(a, in.what + ".angles: expected [start, end] in degrees");
    s.start_deg = in.doc.number(a[0], in.what + ".angles[0] (deg)", -360, 360);
    s.end_deg = in.doc.number(a[1], in.what + ".angles[1] (deg)", -360, 720);
  }
  if (in.params["reference"]) s.reference = in.doc.vector3(in.params["reference"], in.what + ".reference");
  return s;
}

void add(const PrimitiveInput& in, const geometry::TriangleSoup& soup) { in.add(in.name, in.name, soup, ""); }

void buildRectangle(const PrimitiveInput& in) {
  const auto [sa, sb] = in.subdivisions;
  if (!in.params["nodes"]) {
    add(in, geometry::rectangle(point(in, "origin"), point(in, "u"), point(in, "v"), sa, sb));
    return;
  }
  // A grid of thermal nodes <name>.<i>.<j>, each with its share of the subdivisions.
  const auto [na, nb] = parseCounts(in.doc, in.params["nodes"], in.what + ".nodes", {1, 1});
  checkNodeMemory(in.doc, in.params["nodes"], in.what + ".nodes",
                  static_cast<double>(in.existing_nodes) + in.active_sides * double(na) * double(nb));
  const Vec3 o = point(in, "origin"), u = point(in, "u"), v = point(in, "v");
  const int ca = std::max(1, (sa + na - 1) / na), cb = std::max(1, (sb + nb - 1) / nb);
  for (int i = 0; i < na; ++i)
    for (int j = 0; j < nb; ++j) {
      const std::string cell = in.name + "." + std::to_string(i) + "." + std::to_string(j);
      in.add(cell, cell, geometry::rectangle(o + (double(i) / na) * u + (double(j) / nb) * v, u / na, v / nb, ca, cb),
             "");
    }
}

std::vector<Vec3> corners(const PrimitiveInput& in, size_t want) {
  const YAML::Node cs = in.doc.required(in.params, "corners", in.what);
  if (!cs.IsSequence() || cs.size() != want)
    throw in.doc.error(cs, in.what + ".corners: expected " + std::to_string(want) + " points [x, y, z]");
  std::vector<Vec3> pts;
  for (size_t q = 0; q < want; ++q)
    pts.push_back(in.doc.vector3(cs[q], in.what + ".corners[" + std::to_string(q) + "]"));
  return pts;
}

void buildQuadrilateral(const PrimitiveInput& in) {
  const auto p = corners(in, 4);
  add(in, geometry::quadrilateral({p[0], p[1], p[2], p[3]}, in.subdivisions.first, in.subdivisions.second));
}

void buildTriangle(const PrimitiveInput& in) {
  const auto p = corners(in, 3);
  add(in, geometry::triangle(p[0], p[1], p[2], in.subdivisions.first));
}

void buildDisc(const PrimitiveInput& in) {
  const double r = length(in, "radius");
  add(in, geometry::disc(point(in, "center"), point(in, "normal"), r, optionalLength(in, "inner_radius", 0.0),
                         sweep(in), in.subdivisions.first, in.subdivisions.second));
}

void buildCylinder(const PrimitiveInput& in) {
  add(in, geometry::cylinder(point(in, "base"), point(in, "axis"), length(in, "radius"), sweep(in),
                             in.subdivisions.first, in.subdivisions.second));
}

void buildCone(const PrimitiveInput& in) {
  add(in,
      geometry::cone(point(in, "base"), point(in, "axis"), length(in, "base_radius"),
                     optionalLength(in, "top_radius", 0.0), sweep(in), in.subdivisions.first, in.subdivisions.second));
}

void buildSphere(const PrimitiveInput& in) {
  double t0 = 0, t1 = 180;
  if (in.params["polar"]) {
    const YAML::Node pr = in.params["polar"];
    if (!pr.IsSequence() || pr.size() != 2) throw in.doc.error(pr, in.what + ".polar: expected [min, max] in degrees");
    t0 = in.doc.number(pr[0], in.what + ".polar[0] (deg)", 0, 180);
    t1 = in.doc.number(pr[1], in.what + ".polar[1] (deg)", 0, 180);
  }
  const Vec3 center = point(in, "center");
  const double radius = length(in, "radius");
  const Vec3 axis = in.params["axis"] ? in.doc.vector3(in.params["axis"], in.what + ".axis") : Vec3(0, 0, 1);
  add(in, geometry::sphere(center, radius, axis, t0, t1, sweep(in), in.subdivisions.first, in.subdivisions.second));
}

void buildBox(const PrimitiveInput& in) {
  const auto faces = geometry::boxFaces(point(in, "origin"), point(in, "size"), in.subdivisions.first);
  const std::string mode =
      in.params["nodes"] ? in.doc.choice(in.params["nodes"], in.what + ".nodes", {"per_face", "single"}) : "per_face";
  for (int f = 0; f < 6; ++f)
    in.add(in.name + geometry::kBoxFaceNames[f],
           mode == "single" ? in.name : in.name + "." + geometry::kBoxFaceNames[f], faces[static_cast<size_t>(f)], "");
}

}  // namespace

const std::vector<PrimitiveSpec>& primitiveSpecs() {
  static const std::vector<PrimitiveSpec> specs = {
      {"rectangle", {"origin", "u", "v", "nodes"}, {1, 1}, buildRectangle},
      {"quadrilateral", {"corners"}, {1, 1}, buildQuadrilateral},
      {"triangle", {"corners"}, {1, 1}, buildTriangle},
      {"disc", {"center", "normal", "radius", "inner_radius", "angles", "reference"}, {1, 32}, buildDisc},
      {"cylinder", {"base", "axis", "radius", "angles", "reference"}, {1, 32}, buildCylinder},
      {"cone", {"base", "axis", "base_radius", "top_radius", "angles", "reference"}, {1, 32}, buildCone},
      {"sphere", {"center", "radius", "axis", "polar", "angles", "reference"}, {12, 24}, buildSphere},
      {"box", {"origin", "size", "nodes"}, {1, 1}, buildBox},
      {"mesh", {"file", "scale", "groups", "nodes", "feature_angle", "rotation", "position", "flip", "properties",
                "mesh_size"}, {1, 1},
       buildMesh},
  };
  return specs;
}

const PrimitiveSpec* findPrimitive(std::string_view kind) {
  for (const auto& spec : primitiveSpecs())
    if (spec.kind == kind) return &spec;
  return nullptr;
}

std::pair<int, int> parseCounts(const YamlDocument& doc, const YAML::Node& node, const std::string& what,
                                std::pair<int, int> fallback) {
  if (!node) return fallback;
  if (node.IsScalar()) {
    const int n = static_cast<int>(doc.integer(node, what, 1, 10000));
    return {n, n};
  }
  if (!node.IsSequence() || node.size() != 2) throw doc.error(node, what + ": expected [count, count] or a count");
  return {static_cast<int>(doc.integer(node[0], what + "[0]", 1, 10000)),
          static_cast<int>(doc.integer(node[1], what + "[1]", 1, 10000))};
}

void checkNodeMemory(const YamlDocument& doc, const YAML::Node& where, const std::string& what, double nodes) {
  const MemoryLimit memory = memoryLimit();
  const double need = kMinBytesPerNode * nodes;
  if (memory.bytes > 0 && need > 0.75 * memory.bytes) {
    std::ostringstream s;
    s << what << ": " << nodes << " thermal nodes need at least " << need / 1073741824.0
      << " GiB even with sparse view factors, more than 75 % of " << memory.source
      << ". Use fewer nodes (subdivisions refine the mesh, not the node count)";
    throw doc.error(where, s.str());
  }
}

}  // namespace radnet::cases
