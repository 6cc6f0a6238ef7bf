#include "geometry/mesh_io.hpp"

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

// CGAL's PLY reader dereferences a null element when a header is malformed (a property
// before any element, say): check the header's structure first, so a broken file is an
// error message and never a crash.
void checkPlyHeader(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  int line_no = 0;
  auto fail = [&](const std::string& what) {
    throw GeometryError(path + ":" + std::to_string(line_no) + ": malformed PLY header: " + what);
  };
  if (!std::getline(in, line) || (++line_no, line.rfind("ply", 0) != 0)) fail("the first line must be 'ply'");
  bool format = false, element = false;
  const double file_bytes = static_cast<double>(std::filesystem::file_size(path));
  double min_bytes = 0.0;  // every property of every element takes at least one byte
  long long count = 0;
  static const std::vector<std::string> types = {"char",  "uchar",  "short",   "ushort", "int",   "uint",
                                                 "float", "double", "int8",    "uint8",  "int16", "uint16",
                                                 "int32", "uint32", "float32", "float64"};
  auto isType = [&](const std::string& t) { return std::find(types.begin(), types.end(), t) != types.end(); };
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string word;
    if (!(ls >> word)) continue;
    if (word == "end_header") {
      if (!format) fail("no 'format' line");
      if (!element) fail("no 'element' line");
      if (min_bytes > file_bytes)
        fail("its elements need at least " + std::to_string(static_cast<long long>(min_bytes)) +
             " bytes but the file has " + std::to_string(static_cast<long long>(file_bytes)) +
             " (truncated, or a wrong count)");
      return;
    }
    if (word == "comment" || word == "obj_info") continue;
    if (word == "format") {
      std::string kind, version;
      if (!(ls >> kind >> version) ||
          (kind != "ascii" && kind != "binary_little_endian" && kind != "binary_big_endian"))
        fail("'format' must be ascii, binary_little_endian or binary_big_endian");
      format = true;
    } else if (word == "element") {
      std::string name;
      count = -1;
      if (!(ls >> name >> count) || count < 0) fail("'element' needs a name and a count >= 0");
      element = true;
    } else if (word == "property") {
      if (!element) fail("'property' before any 'element'");
      min_bytes += static_cast<double>(count);
      std::string type, a, b;
      if (!(ls >> type)) fail("'property' without a type");
      if (type == "list") {
        if (!(ls >> a >> b) || !isType(a) || !isType(b)) fail("'property list' needs two valid types");
      } else if (!isType(type)) {
        fail("unknown property type '" + type + "'");
      }
    } else {
      fail("unexpected keyword '" + word + "'");
    }
  }
  fail("no 'end_header' line");
}

// An OFF header's counts are trusted by CGAL's reader, which reserves memory for them: a
// corrupt count of 1e9 vertices would take 20+ GB. Compare them with the file size first
// (an ASCII vertex takes at least 6 bytes, "0 0 0\n"; a face at least 8).
void checkOffCounts(const std::string& path) {
  std::ifstream in(path);
  std::string token;
  std::vector<double> numbers;
  bool binary = false;
  while (numbers.size() < 2 && in >> token) {
    if (token[0] == '#') {
      std::getline(in, token);
      continue;
    }
    if (token.find("OFF") != std::string::npos) continue;
    if (token == "BINARY") {
      binary = true;
      break;
    }
    try {
      numbers.push_back(std::stod(token));
    } catch (const std::exception&) {
      throw GeometryError(path + ": malformed OFF header: expected vertex and face counts, found '" + token + "'");
    }
  }
  if (binary || numbers.size() < 2) return;  // CGAL reports what is missing
  if (numbers[0] < 0 || numbers[1] < 0) throw GeometryError(path + ": malformed OFF header: negative counts");
  const double need = 6.0 * numbers[0] + 8.0 * numbers[1];
  const double have = static_cast<double>(std::filesystem::file_size(path));
  if (need > have)
    throw GeometryError(path + ": the OFF header promises " + std::to_string(static_cast<long long>(numbers[0])) +
                        " vertices and " + std::to_string(static_cast<long long>(numbers[1])) +
                        " faces, which need at least " + std::to_string(static_cast<long long>(need)) +
                        " bytes; the file has " + std::to_string(static_cast<long long>(have)) +
                        " (truncated, or a wrong count)");
}

// A binary STL is an 80-byte header, a triangle count and 50 bytes per triangle: a count
// that disagrees with the size would make the reader drop (or invent) triangles silently.
// An ASCII STL starts with "solid" and has "facet" soon after.
void checkStlCount(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(1024, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  if (head.rfind("solid", 0) == 0 && head.find("facet") != std::string::npos) return;
  const auto size = static_cast<unsigned long long>(std::filesystem::file_size(path));
  if (size < 84) throw GeometryError(path + ": binary STL shorter than its 84-byte header");
  const unsigned char* c = reinterpret_cast<const unsigned char*>(head.data()) + 80;
  const unsigned long long count = c[0] | (c[1] << 8) | (c[2] << 16) | (static_cast<unsigned long long>(c[3]) << 24);
  if (84 + 50 * count != size)
    throw GeometryError(path + ": the binary STL header counts " + std::to_string(count) + " triangles, which take " +
                        std::to_string(84 + 50 * count) + " bytes; the file has " + std::to_string(size) +
                        " (truncated, or a wrong count)");
}

// Only regular files: a FIFO would block the run forever and a device such as /dev/zero
// would be read without end.
void checkRegularFile(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw GeometryError(path + ": mesh file not found");
  if (!std::filesystem::is_regular_file(path, ec))
    throw GeometryError(path + ": not a regular file (a FIFO, device or directory cannot be a mesh)");
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
  checkRegularFile(path);
  if (ext == ".ply") checkPlyHeader(path);
  if (ext == ".off") checkOffCounts(path);
  if (ext == ".stl") checkStlCount(path);
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
  checkRegularFile(path);
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
