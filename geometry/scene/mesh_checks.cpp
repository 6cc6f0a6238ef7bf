#include "geometry/scene/mesh_checks.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

namespace radnet::geometry {
namespace {

std::string count(double v) { return std::to_string(static_cast<long long>(v)); }

// --- PLY -------------------------------------------------------------------------------

struct PlyProperty {
  bool list = false;
  int count_bytes = 0;  ///< a list's count type
  int item_bytes = 0;   ///< the scalar, or a list's item type
};

struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  std::string format;
  std::size_t header_bytes = 0;
  std::vector<PlyElement> elements;
};

int plyTypeBytes(const std::string& t) {
  static const std::vector<std::pair<std::string, int>> types = {
      {"char", 1},  {"uchar", 1},  {"short", 2},  {"ushort", 2}, {"int", 4},    {"uint", 4},
      {"float", 4}, {"double", 8}, {"int8", 1},   {"uint8", 1},  {"int16", 2},  {"uint16", 2},
      {"int32", 4}, {"uint32", 4}, {"float32", 4}, {"float64", 8}};
  for (const auto& [name, bytes] : types)
    if (name == t) return bytes;
  return 0;
}

// CGAL's PLY reader dereferences a null element when a header is malformed (a property
// before any element, say): the header's structure is checked first.
PlyHeader readPlyHeader(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  int line_no = 0;
  auto fail = [&](const std::string& what) {
    throw GeometryError(path + ":" + std::to_string(line_no) + ": malformed PLY header: " + what);
  };
  if (!std::getline(in, line) || (++line_no, line.rfind("ply", 0) != 0)) fail("the first line must be 'ply'");
  PlyHeader h;
  const double file_bytes = static_cast<double>(std::filesystem::file_size(path));
  double min_bytes = 0.0;  // every property of every element takes at least one byte
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string word;
    if (!(ls >> word)) continue;
    if (word == "end_header") {
      if (h.format.empty()) fail("no 'format' line");
      if (h.elements.empty()) fail("no 'element' line");
      if (min_bytes > file_bytes)
        fail("its elements need at least " + count(min_bytes) + " bytes but the file has " + count(file_bytes) +
             " (truncated, or a wrong count)");
      h.header_bytes = static_cast<std::size_t>(in.tellg());
      return h;
    }
    if (word == "comment" || word == "obj_info") continue;
    if (word == "format") {
      std::string version;
      if (!(ls >> h.format >> version) ||
          (h.format != "ascii" && h.format != "binary_little_endian" && h.format != "binary_big_endian"))
        fail("'format' must be ascii, binary_little_endian or binary_big_endian");
    } else if (word == "element") {
      PlyElement e;
      e.count = -1;
      if (!(ls >> e.name >> e.count) || e.count < 0) fail("'element' needs a name and a count >= 0");
      h.elements.push_back(e);
    } else if (word == "property") {
      if (h.elements.empty()) fail("'property' before any 'element'");
      min_bytes += static_cast<double>(h.elements.back().count);
      std::string type, a, b;
      PlyProperty p;
      if (!(ls >> type)) fail("'property' without a type");
      if (type == "list") {
        p.list = true;
        if (!(ls >> a >> b) || !plyTypeBytes(a) || !plyTypeBytes(b)) fail("'property list' needs two valid types");
        p.count_bytes = plyTypeBytes(a), p.item_bytes = plyTypeBytes(b);
      } else if (!(p.item_bytes = plyTypeBytes(type))) {
        fail("unknown property type '" + type + "'");
      }
      h.elements.back().properties.push_back(p);
    } else {
      fail("unexpected keyword '" + word + "'");
    }
  }
  fail("no 'end_header' line");
  return h;
}

// A binary PLY walked element by element: every list's count must fit in what is left of
// the file (CGAL resizes a face to its count before reading it).
void checkPlyLists(const std::string& path, const PlyHeader& h) {
  if (h.format == "ascii") return;  // CGAL reads ASCII lists token by token
  bool any_list = false;
  for (const PlyElement& e : h.elements)
    for (const PlyProperty& p : e.properties) any_list |= p.list;
  if (!any_list) return;
  std::ifstream in(path, std::ios::binary);
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const bool big = h.format == "binary_big_endian";
  std::size_t at = h.header_bytes;
  auto unsignedAt = [&](int bytes) {
    std::uint64_t v = 0;
    for (int k = 0; k < bytes; ++k) {
      const auto byte = static_cast<unsigned char>(data[at + static_cast<std::size_t>(big ? k : bytes - 1 - k)]);
      v = (v << 8) | byte;
    }
    return v;
  };
  for (const PlyElement& e : h.elements)
    for (long long item = 0; item < e.count; ++item)
      for (const PlyProperty& p : e.properties) {
        const std::size_t head = static_cast<std::size_t>(p.list ? p.count_bytes : p.item_bytes);
        if (at + head > data.size())
          throw GeometryError(path + ": binary PLY ends inside " + e.name + " " + count(double(item)) +
                              " (truncated, or a wrong count)");
        if (!p.list) {
          at += head;
          continue;
        }
        const std::uint64_t n = unsignedAt(p.count_bytes);
        at += head;
        const double need = double(n) * p.item_bytes, left = double(data.size() - at);
        if (need > left)
          throw GeometryError(path + ": " + e.name + " " + count(double(item)) + " lists " + count(double(n)) +
                              " entries (" + count(need) + " bytes) with " + count(left) +
                              " bytes left in the file (a wrong count)");
        at += static_cast<std::size_t>(need);
      }
}

// --- OFF -------------------------------------------------------------------------------

std::int64_t bigEndianInt32(const unsigned char* c) {
  return std::int32_t(std::uint32_t(c[0]) << 24 | std::uint32_t(c[1]) << 16 | std::uint32_t(c[2]) << 8 | c[3]);
}

// A plain binary OFF after its counts, as CGAL reads it: vertices of three float32, then per
// face an int32 corner count and the int32 corners. Each corner count must fit in what is
// left of the file.
void checkBinaryOffFaces(const std::string& path, std::ifstream& in, double vertices, double faces, double have) {
  in.seekg(static_cast<std::streamoff>(4 + 12.0 * vertices), std::ios::cur);  // the edge count, the vertices
  unsigned char c[4];
  for (long long face = 0; face < static_cast<long long>(faces); ++face) {
    if (!in.read(reinterpret_cast<char*>(c), 4)) return;
    const std::int64_t corners = bigEndianInt32(c);
    const double left = have - static_cast<double>(in.tellg());
    if (corners < 0 || 4.0 * static_cast<double>(corners) > left)
      throw GeometryError(path + ": binary face " + std::to_string(face) + " claims " + std::to_string(corners) +
                          " corners, more than the " + count(left) + " bytes left in the file could hold");
    in.seekg(4 * corners, std::ios::cur);
  }
}

// The header's counts against the file size, and (for a plain ASCII OFF, one face a line
// as every exporter writes it) each face's corner count against the bytes left: each
// corner takes at least two ("0 ").
void checkOff(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const double have = static_cast<double>(std::filesystem::file_size(path));
  std::string keyword;
  if (!(in >> keyword)) throw GeometryError(path + ": empty OFF file");
  bool binary = false;
  std::vector<double> numbers;
  std::string token;
  while (numbers.size() < 2 && in >> token) {
    if (token[0] == '#') {
      std::getline(in, token);
      continue;
    }
    if (token == "BINARY") {
      binary = true;
      break;
    }
    if (token.find("OFF") != std::string::npos) continue;
    try {
      numbers.push_back(std::stod(token));
    } catch (const std::exception&) {
      throw GeometryError(path + ": malformed OFF header: expected vertex and face counts, found '" + token + "'");
    }
  }
  if (binary) {  // "OFF BINARY\n", then big-endian int32 vertex, face and edge counts
    in.ignore(1);
    unsigned char c[8];
    if (!in.read(reinterpret_cast<char*>(c), 8)) throw GeometryError(path + ": binary OFF shorter than its counts");
    for (int k = 0; k < 2; ++k) numbers.push_back(double(bigEndianInt32(c + 4 * k)));
  }
  if (numbers.size() < 2) return;  // CGAL reports what is missing
  if (numbers[0] < 0 || numbers[1] < 0) throw GeometryError(path + ": malformed OFF header: negative counts");
  // A vertex takes at least 6 bytes in ASCII ("0 0 0\n"), 12 in binary; a face 8 or 16.
  const double need = binary ? 12.0 * numbers[0] + 16.0 * numbers[1] : 6.0 * numbers[0] + 8.0 * numbers[1];
  if (need > have)
    throw GeometryError(path + ": the OFF header promises " + count(numbers[0]) + " vertices and " + count(numbers[1]) +
                        " faces, which need at least " + count(need) + " bytes; the file has " + count(have) +
                        " (truncated, or a wrong count)");
  if (binary && keyword == "OFF") checkBinaryOffFaces(path, in, numbers[0], numbers[1], have);
  if (binary || keyword != "OFF") return;  // COFF, NOFF, ...: per-vertex extras; counts only
  std::string line;
  std::getline(in, line);  // the rest of the counts line
  long long skipped = 0;
  while (skipped < static_cast<long long>(numbers[0]) && std::getline(in, line)) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first != std::string::npos && line[first] != '#') ++skipped;
  }
  for (long long face = 0; face < static_cast<long long>(numbers[1]);) {
    const double line_start = static_cast<double>(in.tellg());
    if (line_start < 0 || !std::getline(in, line)) break;
    std::istringstream ls(line);
    long long corners = 0;
    if (!(ls >> corners)) continue;  // blank, a comment, or not one face a line: CGAL judges it
    const double left = have - line_start;
    if (corners < 0 || 2.0 * static_cast<double>(corners) > left)
      throw GeometryError(path + ": face " + std::to_string(face) + " claims " + std::to_string(corners) +
                          " corners, more than the " + count(left) + " bytes left in the file could hold");
    ++face;
  }
}

// --- STL -------------------------------------------------------------------------------

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
  const unsigned long long n = c[0] | (c[1] << 8) | (c[2] << 16) | (static_cast<unsigned long long>(c[3]) << 24);
  if (84 + 50 * n != size)
    throw GeometryError(path + ": the binary STL header counts " + std::to_string(n) + " triangles, which take " +
                        std::to_string(84 + 50 * n) + " bytes; the file has " + std::to_string(size) +
                        " (truncated, or a wrong count)");
}

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return std::tolower(ch); });
  return ext;
}

}  // namespace

void checkMeshFile(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw GeometryError(path + ": mesh file not found");
  if (!std::filesystem::is_regular_file(path, ec))
    throw GeometryError(path + ": not a regular file (a FIFO, device or directory cannot be a mesh)");
  const std::string ext = lowerExtension(path);
  if (ext == ".ply") checkPlyLists(path, readPlyHeader(path));
  if (ext == ".off") checkOff(path);
  if (ext == ".stl") checkStlCount(path);
}

}  // namespace radnet::geometry
