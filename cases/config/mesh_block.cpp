// The `mesh` primitive (docs/case-files.md, "Meshes"): a file read in its own units, scaled,
// turned and placed, flipped if asked, cleaned (geometry/scene/mesh_repair.hpp) and split
// into nodes (geometry/scene/mesh_partition.hpp); what cleaning found becomes one warning
// per kind of defect for the whole case.
#include "cases/config/mesh_block.hpp"

#include "geometry/scene/gmsh.hpp"
#include "geometry/scene/mesh_partition.hpp"
#include "geometry/scene/mesh_repair.hpp"
#include "geometry/scene/nastran.hpp"
#include "geometry/scene/step.hpp"
#include "solver/units.hpp"

#include <algorithm>
#include <cctype>
#include <iomanip>
#include <limits>
#include <sstream>

namespace radnet::cases {
namespace {

using geometry::MeshNodes;
using geometry::Vec3;

// Beyond these a mesh is likely in the wrong unit: no spacecraft part is 100 m across, and
// no CAD export resolves below a micrometre.
constexpr double kLargestLikelyMeshM = 100.0;
constexpr double kShortestLikelyEdgeM = 1e-6;

std::string number(double v) {
  std::ostringstream s;
  s << std::setprecision(4) << v;
  return s.str();
}

// `rotation: {axis: [x, y, z], angle: deg}` about the origin, after the scale.
Eigen::Matrix3d rotation(const PrimitiveInput& in) {
  const YAML::Node r = in.params["rotation"];
  if (!r) return Eigen::Matrix3d::Identity();
  const std::string what = in.what + ".rotation";
  in.doc.expectMap(r, what, {"axis", "angle"});
  const Vec3 axis = in.doc.vector3(in.doc.required(r, "axis", what), what + ".axis", true);
  const double angle = in.doc.number(in.doc.required(r, "angle", what), what + ".angle (deg)", -360.0, 360.0);
  return Eigen::AngleAxisd(units::degToRad(angle), axis.normalized()).toRotationMatrix();
}

// The formats whose own unit is a group (NASTRAN PIDs, Gmsh physical surfaces, STEP faces),
// by extension.
enum class Format { Plain, Nastran, Gmsh, Step };

Format formatOf(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".bdf" || ext == ".nas" || ext == ".dat" || ext == ".blk") return Format::Nastran;
  if (ext == ".msh") return Format::Gmsh;
  if (ext == ".step" || ext == ".stp") return Format::Step;
  return Format::Plain;
}

// `nodes:` (or its older form `groups: true`); by default per group where the format has
// them as its own unit (NASTRAN PIDs), else one node.
MeshNodes nodeMode(const PrimitiveInput& in, Format format) {
  const YAML::Node nodes = in.params["nodes"], groups = in.params["groups"];
  if (nodes && groups)
    throw in.doc.error(groups, in.what + ".groups: give either nodes or groups (groups: true is nodes: groups)");
  if (groups) return in.doc.boolean(groups, in.what + ".groups") ? MeshNodes::Groups : MeshNodes::Single;
  if (!nodes) return format == Format::Plain ? MeshNodes::Single : MeshNodes::Groups;
  const std::string mode =
      in.doc.choice(nodes, in.what + ".nodes", {"single", "groups", "components", "faces", "elements"});
  return mode == "groups"       ? MeshNodes::Groups
         : mode == "components" ? MeshNodes::Components
         : mode == "faces"      ? MeshNodes::Faces
         : mode == "elements"   ? MeshNodes::Elements
                                : MeshNodes::Single;
}

// What cleaning found, as the case's defect notes (one warning per kind over all meshes).
void noteDefects(const PrimitiveInput& in, const geometry::MeshReport& r, const std::string& label) {
  const auto count = [&](int n, const char* what, int first) {
    return label + ": " + std::to_string(n) + what + (first >= 0 ? ", first at face " + std::to_string(first) : "");
  };
  if (r.degenerate > 0)
    in.note("degenerate triangles (no area), dropped", count(r.degenerate, "", r.first_degenerate));
  if (r.duplicate > 0)
    in.note("repeated triangles (the same corners, wound the same way), dropped",
            count(r.duplicate, "", r.first_duplicate));
  if (r.welded_vertices > 0)
    in.note("vertices within the weld tolerance (1e-6 of the mesh's diagonal) of another, welded: cracks that narrow "
            "are closed",
            count(r.welded_vertices, " vertices", -1));
  if (r.wound_against > 0)
    in.note("edges whose two triangles are wound against each other (one of them faces the wrong way)",
            count(r.wound_against, " edges", r.first_wound_against));
  if (r.non_manifold_edges > 0)
    in.note("edges shared by three or more triangles", count(r.non_manifold_edges, " edges", -1));
  if (r.nearly_closed && r.open_edges > 0)
    in.note("cracks left open in nearly closed meshes (wider than the weld tolerance: rays leak through them)",
            label + ": " + std::to_string(r.open_edges) + " open edges, " + number(r.open_length_m) +
                " m long in all, holes of " + number(r.hole_area_m2) + " m²");
  if (r.nearly_closed && r.enclosed_volume_m3 < 0 && in.front_active)
    in.note("nearly closed meshes whose fronts face inward, so their front nodes see only the inside (a solid: "
            "flip: true turns them out; a cavity: name its material as the back side)",
            label + ": encloses " + number(-r.enclosed_volume_m3) + " m³ wound inward");
}

// The unit warnings of one whole mesh file, after its transform.
void noteScale(const PrimitiveInput& in, double extent_m, double shortest_edge_m, const std::string& label) {
  if (extent_m > kLargestLikelyMeshM)
    in.note("meshes larger than 100 m: is the file in millimetres (did you mean `scale: 0.001`?)",
            label + ": " + number(extent_m) + " m across");
  if (shortest_edge_m < kShortestLikelyEdgeM)
    in.note("meshes with edges shorter than 1 µm: is the scale right?",
            label + ": shortest edge " + number(shortest_edge_m) + " m");
}

// The groups of a NASTRAN or Gmsh file as one soup (`nodes: single`), elements kept.
geometry::MeshGroup merged(const std::vector<geometry::MeshGroup>& groups) {
  geometry::MeshGroup all{"", {}};
  for (const geometry::MeshGroup& g : groups) {
    const int base = static_cast<int>(all.soup.vertices.size());
    all.soup.vertices.insert(all.soup.vertices.end(), g.soup.vertices.begin(), g.soup.vertices.end());
    for (const auto& t : g.soup.triangles) all.soup.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    all.soup.element.insert(all.soup.element.end(), g.soup.element.begin(), g.soup.element.end());
  }
  return all;
}

template <class Count>
void noteSkipped(const PrimitiveInput& in, const std::string& kind, const std::string& path,
                 const std::map<std::string, Count>& skipped) {
  if (skipped.empty()) return;
  std::string list;
  for (const auto& [name, count] : skipped) list += (list.empty() ? "" : ", ") + name + " ×" + std::to_string(count);
  in.note(kind, path + ": " + list);
}

using FileBulk = PrimitiveInput::FileBulk;

// What a NASTRAN file says of each PID's shell (PSHELL T, MAT4 K, CP, RHO), by group name;
// for `nodes: single` (group ""), the PIDs' common values, or none where they differ.
std::map<std::string, FileBulk> nastranBulk(const geometry::NastranModel& model) {
  std::map<std::string, FileBulk> out;
  for (const geometry::MeshGroup& g : model.groups) {
    const int pid = std::stoi(g.name);
    FileBulk& b = out[g.name];
    b.group = "PID " + g.name;
    if (const auto t = model.thickness_m.find(pid); t != model.thickness_m.end()) b.thickness_m = t->second;
    if (const auto m = model.material.find(pid); m != model.material.end()) {
      b.conductivity = m->second.conductivity;
      b.density = m->second.density;
      b.specific_heat = m->second.specific_heat;
      b.group += " (MAT4 " + std::to_string(m->second.mid) + ")";
    }
  }
  FileBulk all;
  all.group = "the PIDs merged by nodes: single";
  bool first = true;
  for (const auto& [name, b] : out) {
    auto same = [&](double FileBulk::*field) {
      if (first) all.*field = b.*field;
      else if (all.*field != b.*field) all.*field = 0.0;  // they differ: the file gives no one value
    };
    for (double FileBulk::*field : {&FileBulk::thickness_m, &FileBulk::conductivity, &FileBulk::density,
                                   &FileBulk::specific_heat})
      same(field);
    first = false;
  }
  out[""] = all;
  return out;
}

// The file's parts: one, its groups, or a NASTRAN or Gmsh model's groups (merged into one
// for `nodes: single`); what those readers read past is noted, and a NASTRAN file's shell
// data kept in `bulk`.
std::vector<geometry::MeshGroup> readParts(const PrimitiveInput& in, const std::string& path, double scale,
                                           MeshNodes mode, Format format, std::map<std::string, FileBulk>& bulk) {
  std::vector<geometry::MeshGroup> groups;
  if (format == Format::Step) {
    const double size = in.params["mesh_size"] ? in.doc.number(in.params["mesh_size"], in.what + ".mesh_size (m)",
                                                               1e-9, 1e3)
                                               : 0.0;
    groups = geometry::readStep(path, scale, size);
  } else if (format == Format::Nastran) {
    geometry::NastranModel model = geometry::readNastran(path, scale);
    noteSkipped(in, "NASTRAN cards not read (radnet reads GRID, CORD2R, CTRIA3, CQUAD4, PSHELL, MAT4)", path,
                model.skipped);
    bulk = nastranBulk(model);
    groups = std::move(model.groups);
  } else if (format == Format::Gmsh) {
    geometry::GmshModel model = geometry::readGmsh(path, scale);
    noteSkipped(in, "Gmsh elements not read (radnet reads triangles and quadrangles)", path, model.skipped);
    groups = std::move(model.groups);
  } else if (mode == MeshNodes::Groups) {
    return geometry::readMeshGroups(path, scale);
  } else {
    return {geometry::MeshGroup{"", geometry::readMesh(path, scale)}};
  }
  if (mode != MeshNodes::Single) return groups;
  return {merged(groups)};
}

// `properties: {PID: {front, back}}` of a NASTRAN mesh, checked against the file's PIDs.
std::map<std::string, YAML::Node> properties(const PrimitiveInput& in, const std::vector<geometry::MeshGroup>& parts,
                                             Format format, MeshNodes mode) {
  std::map<std::string, YAML::Node> out;
  const YAML::Node props = in.params["properties"];
  if (!props) return out;
  const std::string what = in.what + ".properties";
  if (format != Format::Nastran)
    throw in.doc.error(props, what + ": properties (by PID) apply to NASTRAN files only");
  if (mode == MeshNodes::Single) throw in.doc.error(props, what + ": one node has one material; give nodes: groups");
  if (!props.IsMap()) throw in.doc.error(props, what + ": expected a mapping PID: {front, back}");
  for (const auto& kv : props) {
    const std::string pid = std::to_string(in.doc.integer(kv.first, what + " (a PID)", 1, 99999999));
    if (std::none_of(parts.begin(), parts.end(), [&](const geometry::MeshGroup& g) { return g.name == pid; }))
      throw in.doc.error(kv.first, what + ": the file has no elements of PID " + pid);
    out[pid] = kv.second;
  }
  return out;
}

// The keys that belong to one format or node mode only; a STEP scale is warned. Returns the
// feature angle (deg) for nodes: faces.
double checkFormatKeys(const PrimitiveInput& in, Format format, MeshNodes mode, double scale,
                       const std::filesystem::path& path) {
  // A STEP file states its unit and is read in metres: the habit of `scale: 0.001` for a CAD
  // export in mm would shrink it a thousandfold without a word.
  if (format == Format::Step && scale != 1.0)
    in.note("STEP files with a scale: a STEP file states its own unit and is read in metres already, so the "
            "scale multiplies on top (drop it unless the part is to be resized)",
            "mesh '" + in.name + "' from " + path.string() + ": scale " + number(scale));
  if (in.params["mesh_size"] && format != Format::Step)
    throw in.doc.error(in.params["mesh_size"], in.what + ".mesh_size: applies to STEP files only (other meshes are "
                                                         "used as their file has them)");
  if (in.params["feature_angle"] && mode != MeshNodes::Faces)
    throw in.doc.error(in.params["feature_angle"], in.what + ".feature_angle: applies to nodes: faces only");
  return in.params["feature_angle"]
             ? in.doc.number(in.params["feature_angle"], in.what + ".feature_angle (deg)", 0, 180)
             : geometry::kDefaultFeatureAngleDeg;
}

}  // namespace

void buildMesh(const PrimitiveInput& in) {
  const YAML::Node fnode = in.doc.required(in.params, "file", in.what);
  std::filesystem::path path = in.doc.string(fnode, in.what + ".file");
  if (path.is_relative()) path = in.folder / path;
  if (in.params["subdivisions"])
    throw in.doc.error(in.params["subdivisions"], in.what + ".subdivisions: a mesh is used as its file has it; "
                                                            "subdivisions apply to primitives only");
  const double scale = in.params["scale"] ? in.doc.number(in.params["scale"], in.what + ".scale",
                                                          std::numeric_limits<double>::min(), 1e300)
                                          : 1.0;
  const Eigen::Matrix3d turn = rotation(in);
  const Vec3 position = in.params["position"] ? in.doc.vector3(in.params["position"], in.what + ".position (m)")
                                              : Vec3::Zero();
  const bool flip = in.params["flip"] && in.doc.boolean(in.params["flip"], in.what + ".flip");
  const Format format = formatOf(path);
  const MeshNodes mode = nodeMode(in, format);
  const double feature_angle = checkFormatKeys(in, format, mode, scale, path);
  try {
    std::map<std::string, FileBulk> bulk;
    std::vector<geometry::MeshGroup> parts = readParts(in, path.string(), scale, mode, format, bulk);
    const std::map<std::string, YAML::Node> sides = properties(in, parts, format, mode);
    double extent = 0.0, shortest = std::numeric_limits<double>::infinity(), nodes_so_far = 0.0;
    for (geometry::MeshGroup& part : parts) {
      // NASTRAN, Gmsh and STEP elements are named by their id alone (unique across groups).
      const bool by_id = format != Format::Plain && mode == MeshNodes::Elements;
      const std::string node = part.name.empty() || by_id ? in.name : in.name + "." + part.name;
      const std::string label = "mesh '" + (by_id ? in.name + "' group '" + part.name : node) + "' from " + path.string();
      geometry::transformMesh(part.soup, turn, position);
      if (flip) geometry::flipWinding(part.soup);
      const geometry::MeshReport report = geometry::cleanMesh(part.soup);
      if (part.soup.triangles.empty()) throw geometry::GeometryError(label + ": no triangle with an area");
      noteDefects(in, report, label);
      extent = std::max(extent, report.extent_m);
      shortest = std::min(shortest, report.shortest_edge_m);
      const auto pieces = geometry::splitMesh(part.soup, mode, feature_angle);
      nodes_so_far += in.active_sides * double(pieces.size());  // this file's earlier groups count too
      checkNodeMemory(in.doc, fnode, in.what + ".nodes", static_cast<double>(in.existing_nodes) + nodes_so_far);
      const auto own = sides.find(part.name);
      const auto file_bulk = bulk.find(part.name);
      for (const geometry::MeshGroup& piece : pieces) {
        if (in.file_bulk) in.file_bulk->push_back(file_bulk != bulk.end() ? file_bulk->second : FileBulk{label});
        const std::string name = piece.name.empty() ? node : node + "." + piece.name;
        if (own == sides.end()) in.add(name, name, piece.soup, path.string());
        else in.add_with_sides(name, name, piece.soup, path.string(), own->second, in.what + ".properties." + part.name);
      }
    }
    noteScale(in, extent, shortest, "mesh '" + in.name + "' from " + path.string());
  } catch (const geometry::GeometryError& e) {
    throw in.doc.error(fnode, in.what + ".file: " + e.what());
  }
}

}  // namespace radnet::cases
