#include "geometry/scene/gmsh.hpp"

#include "geometry/scene/mesh_checks.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <unordered_map>

namespace radnet::geometry {
namespace {

// Nodes per element type (Gmsh's numbering, types 1–21); 0: unknown.
int nodesOf(int type) {
  static const int n[] = {0, 2, 3, 4, 4, 8, 6, 5, 3, 6, 9, 10, 27, 18, 14, 1, 8, 20, 15, 13, 9, 10};
  return type >= 1 && type <= 21 ? n[type] : 0;
}

// Corners of a surface element (triangles 2, 9, 20, 21; quadrangles 3, 10, 16), 0 otherwise.
int cornersOf(int type) {
  if (type == 2 || type == 9 || type == 20 || type == 21) return 3;
  if (type == 3 || type == 10 || type == 16) return 4;
  return 0;
}

const char* kindOf(int type) {
  if (type == 15) return "points";
  if (type == 1 || type == 8) return "lines";
  return "volume elements";
}

class Reader {
 public:
  Reader(const std::string& path, double scale) : path_(path), scale_(scale), in_(path, std::ios::binary) {
    if (!in_) throw GeometryError(path + ": Gmsh file not found or unreadable");
    in_.seekg(0, std::ios::end);
    size_ = static_cast<long long>(in_.tellg());
    in_.seekg(0);
  }

  GmshModel read() {
    std::string section;
    while (nextSection(section)) {
      if (section == "$MeshFormat") format();
      else if (section == "$PhysicalNames") physicalNames();
      else if (section == "$Entities") entities();
      else if (section == "$Nodes") version_ >= 4 ? nodes4() : nodes2();
      else if (section == "$Elements") version_ >= 4 ? elements4() : elements2();
      skipTo("$End" + section.substr(1));
    }
    if (version_ == 0) fail("no $MeshFormat section: not a Gmsh mesh");
    return finish();
  }

 private:
  [[noreturn]] void fail(const std::string& what) {
    if (binary_) throw GeometryError(path_ + ": " + what);
    // The line: newlines before where reading stopped (counted only when failing).
    in_.clear();
    const long long at = static_cast<long long>(in_.tellg());
    std::ifstream again(path_, std::ios::binary);
    long long line = 1;
    char ch;
    for (long long k = 0; k < (at < 0 ? size_ : at) && again.get(ch); ++k) line += ch == '\n';
    throw GeometryError(path_ + ":" + std::to_string(line) + ": " + what);
  }

  bool nextSection(std::string& section) {
    std::string l;
    while (std::getline(in_, l)) {
      while (!l.empty() && (l.back() == '\r' || l.back() == ' ')) l.pop_back();
      if (!l.empty() && l[0] == '$') {
        section = l;
        return true;
      }
    }
    return false;
  }

  void skipTo(const std::string& end) {
    std::string l;
    while (std::getline(in_, l)) {
      if (l.compare(0, end.size(), end) == 0) return;
    }
    fail("expected " + end);
  }

  // A count the file states, bounded by what the rest of the file can hold at
  // `bytes_each` bytes a record.
  long long bounded(long long count, long long bytes_each, const char* what) {
    const long long left = size_ - static_cast<long long>(in_.tellg());
    if (count < 0 || count > left / std::max(1LL, bytes_each))
      fail(std::string(what) + ": " + std::to_string(count) + " stated, more than the file's " +
           std::to_string(left) + " bytes left can hold");
    return count;
  }

  template <class T>
  T ascii(const char* what) {
    T v{};
    if (!(in_ >> v)) fail(std::string("expected ") + what);
    return v;
  }

  template <class T>
  T bin(const char* what) {
    T v{};
    if (!in_.read(reinterpret_cast<char*>(&v), sizeof v)) fail(std::string("binary data ends inside ") + what);
    return v;
  }

  // An integer field of either form: in binary, `Binary` bytes wide.
  template <class Binary>
  long long integer(const char* what) {
    return binary_ ? static_cast<long long>(bin<Binary>(what)) : ascii<long long>(what);
  }

  double real(const char* what) { return binary_ ? bin<double>(what) : ascii<double>(what); }

  void format() {
    std::string l;
    std::getline(in_, l);
    std::istringstream ls(l);
    int file_type = 0, data_size = 0;
    if (!(ls >> version_ >> file_type >> data_size)) fail("expected 'version file-type data-size'");
    if (!(version_ == 2.2 || version_ == 4.1)) fail("MSH version " + std::to_string(version_) + " (expected 2.2 or 4.1)");
    if (data_size != 8) fail("data size " + std::to_string(data_size) + " (expected 8)");
    binary_ = file_type == 1;
    if (binary_ && bin<int32_t>("the endianness check") != 1) fail("binary mesh of the other endianness");
  }

  void physicalNames() {
    const long long n = bounded(ascii<long long>("the number of physical names"), 6, "physical names");
    for (long long k = 0; k < n; ++k) {
      const int dim = ascii<int>("a physical name's dimension");
      const long long tag = ascii<long long>("a physical tag");
      std::string rest;
      std::getline(in_, rest);
      const size_t a = rest.find('"'), b = rest.rfind('"');
      if (dim == 2 && a != std::string::npos && b > a) names_[tag] = rest.substr(a + 1, b - a - 1);
    }
  }

  // $Entities (4.1): the physical tag of each surface.
  void entities() {
    long long count[4];
    for (long long& c : count) c = bounded(integer<uint64_t>("entity counts"), 8, "entities");
    for (int dim = 0; dim < 4; ++dim)
      for (long long k = 0; k < count[dim]; ++k) {
        const long long tag = integer<int32_t>("an entity tag");
        for (int b = 0; b < (dim == 0 ? 3 : 6); ++b) real("an entity's coordinates");
        const long long phys = bounded(integer<uint64_t>("physical tags"), 4, "physical tags");
        for (long long p = 0; p < phys; ++p) {
          const long long t = integer<int32_t>("a physical tag");
          if (dim == 2 && p == 0) surface_physical_[tag] = std::llabs(t);
        }
        if (dim > 0) {
          const long long bounding = bounded(integer<uint64_t>("bounding entities"), 4, "bounding entities");
          for (long long p = 0; p < bounding; ++p) integer<int32_t>("a bounding entity");
        }
      }
  }

  Vec3 point(const char* what) {
    const double x = real(what), y = real(what), z = real(what);
    if (!(std::isfinite(x) && std::isfinite(y) && std::isfinite(z))) fail(std::string(what) + " is not finite");
    return scale_ * Vec3(x, y, z);
  }

  void nodes2() {
    const long long n = bounded(ascii<long long>("the number of nodes"), binary_ ? 28 : 8, "nodes");
    if (binary_) in_.get();  // the newline after the count
    for (long long k = 0; k < n; ++k) {
      const long long id = integer<int32_t>("a node tag");
      node_[id] = point("a node's coordinates");
    }
  }

  void nodes4() {
    const long long blocks = bounded(integer<uint64_t>("node blocks"), 8, "node blocks");
    for (int k = 0; k < 3; ++k) integer<uint64_t>("the node counts");
    for (long long b = 0; b < blocks; ++b) {
      const long long dim = integer<int32_t>("a block's dimension");
      integer<int32_t>("a block's entity");
      const long long parametric = integer<int32_t>("a block's parametric flag");
      const long long n = bounded(integer<uint64_t>("nodes in a block"), binary_ ? 32 : 8, "nodes in a block");
      std::vector<long long> tags(static_cast<size_t>(n));
      for (long long& t : tags) t = integer<uint64_t>("a node tag");
      for (long long t : tags) {
        node_[t] = point("a node's coordinates");
        for (long long p = 0; p < (parametric ? dim : 0); ++p) real("a node's parameters");
      }
    }
  }

  void addElement(long long id, int type, long long physical, const std::vector<long long>& nodes) {
    const int corners = cornersOf(type);
    if (corners == 0) {
      ++skipped_[kindOf(type)];
      return;
    }
    std::vector<Vec3> p;
    for (int c = 0; c < corners; ++c) {
      const auto it = node_.find(nodes[static_cast<size_t>(c)]);
      if (it == node_.end()) fail("element " + std::to_string(id) + " refers to node " + std::to_string(nodes[static_cast<size_t>(c)]) + ", which the file does not define");
      p.push_back(it->second);
    }
    TriangleSoup& s = group_[physical];
    const int base = static_cast<int>(s.vertices.size());
    s.vertices.insert(s.vertices.end(), p.begin(), p.end());
    s.triangles.push_back({base, base + 1, base + 2});
    s.element.push_back(static_cast<int>(id));
    if (corners == 4) {
      s.triangles.push_back({base, base + 2, base + 3});
      s.element.push_back(static_cast<int>(id));
    }
  }

  int elementType(long long type) {
    if (nodesOf(static_cast<int>(type)) == 0) fail("element type " + std::to_string(type) + " is not a Gmsh type 1–21");
    return static_cast<int>(type);
  }

  void elements2() {
    const long long n = bounded(ascii<long long>("the number of elements"), 8, "elements");
    if (binary_) in_.get();
    for (long long done = 0; done < n;) {
      // Binary: blocks of one type and tag count; ASCII: one element a line.
      const int type = binary_ ? elementType(bin<int32_t>("an element block")) : 0;
      const long long follow = binary_ ? bounded(bin<int32_t>("an element block"), 8, "elements in a block") : 1;
      const long long tags_binary = binary_ ? bin<int32_t>("an element block") : 0;
      for (long long e = 0; e < follow && done < n; ++e, ++done) {
        const long long id = integer<int32_t>("an element tag");
        const int t = binary_ ? type : elementType(ascii<long long>("an element type"));
        const long long ntags = binary_ ? tags_binary : ascii<long long>("an element's tag count");
        if (ntags < 0 || ntags > 64) fail("element " + std::to_string(id) + " has " + std::to_string(ntags) + " tags");
        long long physical = 0;
        for (long long k = 0; k < ntags; ++k) {
          const long long tag = integer<int32_t>("an element's tags");
          if (k == 0) physical = tag;
        }
        std::vector<long long> nodes(static_cast<size_t>(nodesOf(t)));
        for (long long& v : nodes) v = integer<int32_t>("an element's nodes");
        addElement(id, t, physical, nodes);
      }
    }
  }

  void elements4() {
    const long long blocks = bounded(integer<uint64_t>("element blocks"), 8, "element blocks");
    for (int k = 0; k < 3; ++k) integer<uint64_t>("the element counts");
    for (long long b = 0; b < blocks; ++b) {
      const long long dim = integer<int32_t>("a block's dimension");
      const long long entity = integer<int32_t>("a block's entity");
      const int type = elementType(integer<int32_t>("a block's element type"));
      const long long n = bounded(integer<uint64_t>("elements in a block"), 8, "elements in a block");
      const auto phys = surface_physical_.find(entity);
      const long long physical = dim == 2 && phys != surface_physical_.end() ? phys->second : 0;
      std::vector<long long> nodes(static_cast<size_t>(nodesOf(type)));
      for (long long e = 0; e < n; ++e) {
        const long long id = integer<uint64_t>("an element tag");
        for (long long& v : nodes) v = integer<uint64_t>("an element's nodes");
        addElement(id, type, physical, nodes);
      }
    }
  }

  GmshModel finish() {
    GmshModel out;
    out.skipped = skipped_;
    for (auto& [physical, soup] : group_) {
      const auto name = names_.find(physical);
      out.groups.push_back({name != names_.end() ? name->second : std::to_string(physical), std::move(soup)});
    }
    if (out.groups.empty()) fail("no triangles or quadrangles");
    return out;
  }

  std::string path_;
  double scale_;
  std::ifstream in_;
  long long size_ = 0;
  double version_ = 0;
  bool binary_ = false;
  std::map<long long, std::string> names_;             // physical surface tag → name
  std::map<long long, long long> surface_physical_;    // surface entity → its physical tag (4.1)
  std::unordered_map<long long, Vec3> node_;
  std::map<long long, TriangleSoup> group_;            // physical tag → its elements
  std::map<std::string, long> skipped_;
};

}  // namespace

GmshModel readGmsh(const std::string& path, double scale) {
  if (!(std::isfinite(scale) && scale > 0)) throw GeometryError(path + ": scale must be a finite value > 0");
  checkMeshFile(path);
  return Reader(path, scale).read();
}

}  // namespace radnet::geometry
