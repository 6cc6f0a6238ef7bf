#include "geometry/scene/mesh_io.hpp"

#include "geometry/scene/mesh_checks.hpp"

#include <CGAL/IO/polygon_soup_io.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace radnet::geometry {
namespace {

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

void addPolygon(TriangleSoup& soup, const std::vector<int>& poly, const std::string& path, size_t index) {
  if (poly.size() < 3) {
    std::ostringstream s;
    s << path << ": polygon " << index << " has " << poly.size() << " corners; expected at least 3";
    throw GeometryError(s.str());
  }
  for (size_t k = 1; k + 1 < poly.size(); ++k) soup.triangles.push_back({poly[0], poly[k], poly[k + 1]});
}

void checkScale(double scale, const std::string& path) {
  if (!(std::isfinite(scale) && scale > 0)) throw GeometryError(path + ": scale must be a finite value > 0");
}

}  // namespace

TriangleSoup readMesh(const std::string& path, double scale) {
  checkScale(scale, path);
  const std::string ext = lowerExtension(path);
  if (ext != ".off" && ext != ".obj" && ext != ".stl" && ext != ".ply")
    throw GeometryError(path + ": unknown mesh format '" + ext + "'; expected .off, .obj, .stl or .ply");
  checkMeshFile(path);
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
    addPolygon(soup, poly, path, i);
  }
  return soup;
}

namespace {

// The vertex indices (0-based) of one OBJ face line's "v/vt/vn" tokens; negative indices
// count back from the vertices read so far.
std::vector<int> objFace(std::istringstream& ls, size_t vertex_count, const std::string& path, size_t line_no) {
  std::vector<int> poly;
  std::string token;
  while (ls >> token) {
    long idx = 0;  // "v/vt/vn": the vertex
    try {
      idx = std::stol(token.substr(0, token.find('/')));
    } catch (const std::exception&) {
      throw GeometryError(path + ":" + std::to_string(line_no) + ": malformed face index '" + token + "'");
    }
    if (idx == 0 || std::abs(idx) > 2000000000L)
      throw GeometryError(path + ":" + std::to_string(line_no) + ": face index " + token + " out of range");
    poly.push_back(static_cast<int>(idx > 0 ? idx - 1 : static_cast<long>(vertex_count) + idx));
  }
  return poly;
}

// One group's polygons as a soup that keeps only the vertices it uses, renumbered.
MeshGroup objGroup(const std::string& name, const std::vector<std::vector<int>>& polys,
                   const std::vector<Vec3>& vertices, const std::string& path) {
  MeshGroup g{name, {}};
  std::vector<int> remap(vertices.size(), -1);
  for (size_t i = 0; i < polys.size(); ++i) {
    std::vector<int> poly;
    for (int v : polys[i]) {
      if (v < 0 || v >= static_cast<int>(vertices.size())) {
        std::ostringstream s;
        s << path << ": group '" << name << "' face " << i << " refers to a missing vertex";
        throw GeometryError(s.str());
      }
      if (remap[static_cast<size_t>(v)] < 0) {
        remap[static_cast<size_t>(v)] = static_cast<int>(g.soup.vertices.size());
        g.soup.vertices.push_back(vertices[static_cast<size_t>(v)]);
      }
      poly.push_back(remap[static_cast<size_t>(v)]);
    }
    addPolygon(g.soup, poly, path + " group '" + name + "'", i);
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
  std::vector<std::pair<std::string, std::vector<std::vector<int>>>> groups;
  std::string line, current = "default";
  size_t line_no = 0;
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
    } else if (tag == "f") {
      std::vector<int> poly = objFace(ls, vertices.size(), path, line_no);
      auto it = std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.first == current; });
      if (it == groups.end()) {
        groups.push_back({current, {}});
        it = groups.end() - 1;
      }
      it->second.push_back(std::move(poly));
    }
  }
  std::vector<MeshGroup> out;
  for (const auto& [name, polys] : groups) out.push_back(objGroup(name, polys, vertices, path));
  if (out.empty()) throw GeometryError(path + ": the mesh has no faces");
  return out;
}

}  // namespace radnet::geometry
