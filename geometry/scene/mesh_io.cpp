#include "geometry/scene/mesh_io.hpp"

#include "geometry/scene/mesh_checks.hpp"

#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/IO/read_ply_points.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

namespace radnet::geometry {
namespace {

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

// A polygon fanned into triangles, each remembering the polygon (the file's face `element`).
void addPolygon(TriangleSoup& soup, const std::vector<int>& poly, const std::string& path, size_t index,
                int element) {
  if (poly.size() < 3) {
    std::ostringstream s;
    s << path << ": polygon " << index << " has " << poly.size() << " corners; expected at least 3";
    throw GeometryError(s.str());
  }
  for (size_t k = 1; k + 1 < poly.size(); ++k) {
    soup.triangles.push_back({poly[0], poly[k], poly[k + 1]});
    soup.element.push_back(element);
  }
}

void checkScale(double scale, const std::string& path) {
  if (!(std::isfinite(scale) && scale > 0)) throw GeometryError(path + ": scale must be a finite value > 0");
}

// A PLY header's vertex element must name its coordinates x, y and z: CGAL reads them by
// those names and takes any other (an exporter's "Z", or none) as 0, flattening the part
// without a word. The header is text in ASCII and binary PLY alike. Returns whether the
// vertices carry normals (nx, ny, nz).
bool checkPlyHeader(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line, element;
  std::vector<std::string> vertex_properties;
  bool has_vertex = false;
  for (int line_no = 1; std::getline(in, line) && line_no <= 10000; ++line_no) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word == "end_header") {
      if (!has_vertex) throw GeometryError(path + ": the PLY header declares no 'element vertex'");
      for (const char* axis : {"x", "y", "z"})
        if (std::find(vertex_properties.begin(), vertex_properties.end(), axis) == vertex_properties.end()) {
          std::string found;
          for (const std::string& p : vertex_properties) found += (found.empty() ? "" : ", ") + p;
          throw GeometryError(path + ": the PLY vertex element has no property '" + axis + "' (it has: " +
                              (found.empty() ? "none" : found) + "); coordinates must be named x, y and z");
        }
      const auto has = [&](const char* p) {
        return std::find(vertex_properties.begin(), vertex_properties.end(), p) != vertex_properties.end();
      };
      return has("nx") && has("ny") && has("nz");
    }
    if (word == "element") {
      ls >> element;
      has_vertex = has_vertex || element == "vertex";
    } else if (word == "property" && element == "vertex") {
      std::string last, token;
      while (ls >> token) last = token;
      vertex_properties.push_back(last);
    }
  }
  throw GeometryError(path + ": not a PLY file with a complete header (no end_header)");
}

// A PLY file's vertex normals (nx, ny, nz), in the file's vertex order, made unit (zero where
// one has no length); empty when they cannot be read or do not match the vertices.
std::vector<Vec3> plyVertexNormals(const std::string& path, size_t vertex_count) {
  using PointNormal = std::pair<Point3, Kernel::Vector_3>;
  std::vector<PointNormal> read;
  std::ifstream is(path, std::ios::binary);
  bool ok = false;
  try {
    ok = CGAL::IO::read_PLY_with_properties(
        is, std::back_inserter(read), CGAL::IO::make_ply_point_reader(CGAL::First_of_pair_property_map<PointNormal>()),
        CGAL::IO::make_ply_normal_reader(CGAL::Second_of_pair_property_map<PointNormal>()));
  } catch (const std::exception&) {
    ok = false;
  }
  if (!ok || read.size() != vertex_count) return {};
  std::vector<Vec3> normals;
  for (const auto& [point, normal] : read) {
    const Vec3 n(normal.x(), normal.y(), normal.z());
    normals.push_back(n.norm() > 0 && std::isfinite(n.norm()) ? Vec3(n.normalized()) : Vec3::Zero());
  }
  return normals;
}

// An OBJ index (1-based; negative counts back from the `count` read so far), 0-based.
int objIndex(const std::string& text, size_t count, const std::string& token, const std::string& path, size_t line_no) {
  long idx = 0;
  try {
    idx = std::stol(text);
  } catch (const std::exception&) {
    throw GeometryError(path + ":" + std::to_string(line_no) + ": malformed face index '" + token + "'");
  }
  if (idx == 0 || std::abs(idx) > 2000000000L)
    throw GeometryError(path + ":" + std::to_string(line_no) + ": face index " + token + " out of range");
  return static_cast<int>(idx > 0 ? idx - 1 : static_cast<long>(count) + idx);
}

// The vertex indices (0-based) of one OBJ face line's "v/vt/vn" tokens, and in `normals`
// each corner's normal index (−1: none given).
std::vector<int> objFace(std::istringstream& ls, size_t vertex_count, size_t normal_count, const std::string& path,
                         size_t line_no, std::vector<int>& normals) {
  std::vector<int> poly;
  normals.clear();
  std::string token;
  while (ls >> token) {
    poly.push_back(objIndex(token.substr(0, token.find('/')), vertex_count, token, path, line_no));
    const size_t second = token.find('/') == std::string::npos ? std::string::npos : token.find('/', token.find('/') + 1);
    const bool has_normal = second != std::string::npos && second + 1 < token.size();
    normals.push_back(has_normal ? objIndex(token.substr(second + 1), normal_count, token, path, line_no) : -1);
  }
  return poly;
}

// Per vertex, the one normal its corners give (OBJ `vn`): zero where none is given or where
// corners give it different ones (a hard edge: the facets keep their own normals there).
class VertexNormals {
 public:
  void corner(int vertex, int normal) {
    if (vertex < 0) return;
    const size_t v = static_cast<size_t>(vertex);
    if (v >= normal_of_.size()) normal_of_.resize(v + 1, kUnset);
    int& slot = normal_of_[v];
    if (normal < 0 || normal >= static_cast<int>(normals.size())) slot = kConflict;
    else if (slot == kUnset) slot = normal;
    else if (slot != kConflict && !(normals[static_cast<size_t>(slot)] - normals[static_cast<size_t>(normal)]).isZero(1e-9))
      slot = kConflict;
  }
  /// Per vertex of `count`; empty when the file gives no normals.
  std::vector<Vec3> perVertex(size_t count) const {
    if (normals.empty()) return {};
    std::vector<Vec3> out(count, Vec3::Zero());
    for (size_t v = 0; v < count && v < normal_of_.size(); ++v)
      if (normal_of_[v] >= 0) out[v] = normals[static_cast<size_t>(normal_of_[v])];
    return out;
  }
  std::vector<Vec3> normals;  ///< the file's `vn` lines, unit (zero: a zero-length one)

 private:
  static constexpr int kUnset = -1, kConflict = -2;
  std::vector<int> normal_of_;
};

// An OBJ `vn` line's normal, made unit (zero when it has no length).
Vec3 objNormal(std::istringstream& ls, const std::string& path, size_t line_no) {
  double x, y, z;
  if (!(ls >> x >> y >> z)) throw GeometryError(path + ":" + std::to_string(line_no) + ": malformed normal");
  const Vec3 n(x, y, z);
  return n.norm() > 0 && std::isfinite(n.norm()) ? Vec3(n.normalized()) : Vec3::Zero();
}

// The vertex normals of an OBJ file read by CGAL (which keeps the file's vertex order).
std::vector<Vec3> objVertexNormals(const std::string& path, size_t vertex_count) {
  std::ifstream in(path);
  VertexNormals normals;
  std::string line;
  size_t line_no = 0, vertices = 0;
  std::vector<int> corner_normals;
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream ls(line);
    std::string tag;
    if (!(ls >> tag)) continue;
    if (tag == "v") ++vertices;
    else if (tag == "vn") normals.normals.push_back(objNormal(ls, path, line_no));
    else if (tag == "f") {
      const std::vector<int> poly = objFace(ls, vertices, normals.normals.size(), path, line_no, corner_normals);
      for (size_t k = 0; k < poly.size(); ++k) normals.corner(poly[k], corner_normals[k]);
    }
  }
  return vertices == vertex_count ? normals.perVertex(vertex_count) : std::vector<Vec3>{};
}

}  // namespace

TriangleSoup readMesh(const std::string& path, double scale) {
  checkScale(scale, path);
  const std::string ext = lowerExtension(path);
  if (ext != ".off" && ext != ".obj" && ext != ".stl" && ext != ".ply")
    throw GeometryError(path + ": unknown mesh format '" + ext +
                        "'; expected .off, .obj, .stl, .ply, NASTRAN .bdf/.nas/.dat/.blk, Gmsh .msh or STEP .step/.stp");
  checkMeshFile(path);
  const bool ply_normals = ext == ".ply" && checkPlyHeader(path);
  std::vector<Point3> points;
  std::vector<std::vector<std::size_t>> polygons;
  bool ok = false;
  try {
    ok = CGAL::IO::read_polygon_soup(path, points, polygons, CGAL::parameters::verbose(false));
  } catch (const std::exception& e) {
    throw GeometryError(path + ": cannot read the mesh (" + e.what() + ")");
  }
  if (!ok) throw GeometryError(path + ": cannot read the mesh: malformed or truncated " + ext.substr(1) + " file");
  if (polygons.empty()) throw GeometryError(path + ": the mesh has no faces");
  TriangleSoup soup;
  for (const auto& p : points) soup.vertices.push_back(scale * Vec3(p.x(), p.y(), p.z()));
  for (size_t i = 0; i < polygons.size(); ++i) {
    std::vector<int> poly;
    for (std::size_t v : polygons[i]) {
      if (v >= points.size()) {
        std::ostringstream s;
        s << path << ": polygon " << i << " refers to vertex " << v << " of " << points.size();
        throw GeometryError(s.str());
      }
      poly.push_back(static_cast<int>(v));
    }
    addPolygon(soup, poly, path, i, static_cast<int>(i));
  }
  if (ext == ".obj") soup.normals = objVertexNormals(path, points.size());
  if (ply_normals) soup.normals = plyVertexNormals(path, points.size());
  return soup;
}

namespace {

// One group's polygons as a soup that keeps only the vertices it uses, renumbered.
MeshGroup objGroup(const std::string& name, const std::vector<std::pair<int, std::vector<int>>>& polys,
                   const std::vector<Vec3>& vertices, const std::vector<Vec3>& normals, const std::string& path) {
  MeshGroup g{name, {}};
  std::vector<int> remap(vertices.size(), -1);
  for (size_t i = 0; i < polys.size(); ++i) {
    std::vector<int> poly;
    for (int v : polys[i].second) {
      if (v < 0 || v >= static_cast<int>(vertices.size())) {
        std::ostringstream s;
        s << path << ": group '" << name << "' face " << i << " refers to a missing vertex";
        throw GeometryError(s.str());
      }
      if (remap[static_cast<size_t>(v)] < 0) {
        remap[static_cast<size_t>(v)] = static_cast<int>(g.soup.vertices.size());
        g.soup.vertices.push_back(vertices[static_cast<size_t>(v)]);
        if (!normals.empty()) g.soup.normals.push_back(normals[static_cast<size_t>(v)]);
      }
      poly.push_back(remap[static_cast<size_t>(v)]);
    }
    addPolygon(g.soup, poly, path + " group '" + name + "'", i, polys[i].first);
  }
  return g;
}

}  // namespace

std::vector<MeshGroup> readObjGroups(const std::string& path, double scale) {
  checkScale(scale, path);
  checkMeshFile(path);
  std::ifstream in(path);
  if (!in) throw GeometryError(path + ": mesh file not found or unreadable");
  std::vector<Vec3> vertices;
  std::vector<std::pair<std::string, std::vector<std::pair<int, std::vector<int>>>>> groups;
  std::string line, current = "default";
  size_t line_no = 0;
  int faces = 0;  // the file's face count so far: each face's element number
  VertexNormals normals;
  std::vector<int> corner_normals;
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream ls(line);
    std::string tag;
    if (!(ls >> tag) || tag[0] == '#') continue;
    if (tag == "v") {
      double x, y, z;
      if (!(ls >> x >> y >> z)) throw GeometryError(path + ":" + std::to_string(line_no) + ": malformed vertex");
      vertices.push_back(scale * Vec3(x, y, z));
    } else if (tag == "g" || tag == "o") {
      std::string name;
      ls >> name;
      current = name.empty() ? "default" : name;
    } else if (tag == "vn") {
      normals.normals.push_back(objNormal(ls, path, line_no));
    } else if (tag == "f") {
      std::vector<int> poly = objFace(ls, vertices.size(), normals.normals.size(), path, line_no, corner_normals);
      for (size_t k = 0; k < poly.size(); ++k) normals.corner(poly[k], corner_normals[k]);
      auto it = std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.first == current; });
      if (it == groups.end()) {
        groups.push_back({current, {}});
        it = groups.end() - 1;
      }
      it->second.push_back({faces++, std::move(poly)});
    }
  }
  std::vector<MeshGroup> out;
  const std::vector<Vec3> per_vertex = normals.perVertex(vertices.size());
  for (const auto& [name, polys] : groups) out.push_back(objGroup(name, polys, vertices, per_vertex, path));
  if (out.empty()) throw GeometryError(path + ": the mesh has no faces");
  return out;
}

namespace {

std::string stlError(const std::string& path, size_t line_no, const std::string& what) {
  return path + ":" + std::to_string(line_no) + ": " + what;
}

// The next "vertex x y z" of an ASCII STL facet.
Vec3 stlVertex(std::istream& in, const std::string& path, size_t& line_no, double scale) {
  std::string line, tag;
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream ls(line);
    if (!(ls >> tag)) continue;
    double x, y, z;
    if (tag != "vertex" || !(ls >> x >> y >> z)) break;
    return scale * Vec3(x, y, z);
  }
  throw GeometryError(stlError(path, line_no, "expected 'vertex x y z' of a facet"));
}

}  // namespace

std::vector<MeshGroup> readStlSolids(const std::string& path, double scale) {
  checkScale(scale, path);
  checkMeshFile(path);
  std::ifstream in(path);
  if (!in) throw GeometryError(path + ": mesh file not found or unreadable");
  std::vector<MeshGroup> out;
  std::string line, tag;
  size_t line_no = 0;
  int faces = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream ls(line);
    if (!(ls >> tag)) continue;
    if (tag == "solid") {
      std::string name;
      std::getline(ls >> std::ws, name);
      while (!name.empty() && std::isspace(static_cast<unsigned char>(name.back()))) name.pop_back();
      out.push_back({name.empty() ? "solid" + std::to_string(out.size()) : name, {}});
    } else if (tag == "facet") {
      if (out.empty()) throw GeometryError(stlError(path, line_no, "a facet before any 'solid'"));
      TriangleSoup& soup = out.back().soup;
      const int base = static_cast<int>(soup.vertices.size());
      std::getline(in, line), ++line_no;  // "outer loop"
      for (int k = 0; k < 3; ++k) soup.vertices.push_back(stlVertex(in, path, line_no, scale));
      soup.triangles.push_back({base, base + 1, base + 2});
      soup.element.push_back(faces++);
    } else if (tag != "endloop" && tag != "endfacet" && tag != "endsolid") {
      throw GeometryError(stlError(path, line_no, "'" + tag.substr(0, 40) +
                                                      "' is no ASCII STL statement; a binary STL holds one solid "
                                                      "and no names (use nodes: components or faces)"));
    }
  }
  out.erase(std::remove_if(out.begin(), out.end(), [](const MeshGroup& g) { return g.soup.triangles.empty(); }),
            out.end());
  if (out.empty()) throw GeometryError(path + ": the mesh has no faces");
  return out;
}

std::vector<MeshGroup> readMeshGroups(const std::string& path, double scale) {
  const std::string ext = lowerExtension(path);
  if (ext == ".obj") return readObjGroups(path, scale);
  if (ext == ".stl") return readStlSolids(path, scale);
  throw GeometryError(path + ": a " + ext + " file has no groups (OBJ 'g'/'o' groups and ASCII STL 'solid' names "
                                            "have); use nodes: components, faces or elements");
}

}  // namespace radnet::geometry
