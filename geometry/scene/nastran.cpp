#include "geometry/scene/nastran.hpp"

#include "geometry/scene/mesh_checks.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace radnet::geometry {
namespace {

constexpr int kMaxIncludeDepth = 16;

// One card: its name and fields 1… (the name is field 0), where each came from.
struct Card {
  std::string name, file;
  size_t line = 0;
  std::vector<std::string> fields;
  std::string where() const { return file + ":" + std::to_string(line); }
};

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r"), b = s.find_last_not_of(" \t\r");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

std::string upper(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::toupper(c); });
  return s;
}

// Fixed-width fields of one line from column `from`, `count` of `width` characters.
void fixedFields(const std::string& line, size_t from, int count, size_t width, std::vector<std::string>& out) {
  for (int k = 0; k < count; ++k) {
    const size_t at = from + static_cast<size_t>(k) * width;
    out.push_back(at < line.size() ? trim(line.substr(at, width)) : "");
  }
}

// Free-field tokens after the first (the name or the continuation mark), at most `count`:
// a tenth field on a small-field line is the continuation mark and is dropped.
void freeFields(const std::string& line, int count, std::vector<std::string>& out) {
  std::stringstream ss(line);
  std::string token;
  std::getline(ss, token, ',');
  for (int k = 0; k < count && std::getline(ss, token, ','); ++k) out.push_back(trim(token));
}

bool isContinuation(const std::string& line) {
  return !line.empty() && (line[0] == '+' || line[0] == '*' || line[0] == ',' || line[0] == ' ' || line[0] == '\t');
}

class BulkReader {
 public:
  explicit BulkReader(std::vector<Card>& cards) : cards_(cards) {}

  void read(const std::string& path, int depth) {
    if (depth > kMaxIncludeDepth) throw GeometryError(path + ": INCLUDE nested deeper than 16 files");
    checkMeshFile(path);
    std::ifstream in(path);
    if (!in) throw GeometryError(path + ": NASTRAN file not found or unreadable");
    std::string line;
    size_t line_no = 0;
    bool bulk = !hasBeginBulk(path);
    while (std::getline(in, line)) {
      ++line_no;
      if (const size_t c = line.find('$'); c != std::string::npos) line.erase(c);
      if (trim(line).empty()) continue;
      const std::string head = upper(trim(line.substr(0, std::min<size_t>(line.size(), 10))));
      if (!bulk) {
        bulk = head.rfind("BEGIN", 0) == 0 && upper(line).find("BULK") != std::string::npos;
        continue;
      }
      if (head.rfind("ENDDATA", 0) == 0) break;
      if (head.rfind("INCLUDE", 0) == 0) {
        include(path, line, line_no, depth);
        continue;
      }
      if (isContinuation(line) && !cards_.empty() && cards_.back().file == path) {
        continuation(line);
        continue;
      }
      start(path, line, line_no);
    }
  }

 private:
  static bool hasBeginBulk(const std::string& path) {
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line))
      if (upper(trim(line)).rfind("BEGIN", 0) == 0 && upper(line).find("BULK") != std::string::npos) return true;
    return false;
  }

  void include(const std::string& path, const std::string& line, size_t line_no, int depth) {
    const size_t a = line.find('\''), b = line.rfind('\'');
    if (a == std::string::npos || b <= a)
      throw GeometryError(path + ":" + std::to_string(line_no) + ": expected INCLUDE 'file'");
    std::filesystem::path inc = line.substr(a + 1, b - a - 1);
    if (inc.is_relative()) inc = std::filesystem::path(path).parent_path() / inc;
    read(inc.string(), depth + 1);
  }

  void start(const std::string& path, const std::string& line, size_t line_no) {
    Card c;
    c.file = path, c.line = line_no;
    if (line.find(',') != std::string::npos) {
      c.name = upper(trim(line.substr(0, line.find(','))));
      large_ = !c.name.empty() && c.name.back() == '*';
      freeFields(line, large_ ? 4 : 8, c.fields);
    } else {
      c.name = upper(trim(line.substr(0, 8)));
      large_ = !c.name.empty() && c.name.back() == '*';
      fixedFields(line, 8, large_ ? 4 : 8, large_ ? 16 : 8, c.fields);
    }
    if (large_) c.name.pop_back();
    cards_.push_back(std::move(c));
  }

  void continuation(const std::string& line) {
    Card& c = cards_.back();
    const bool wide = large_ || line[0] == '*';
    if (line.find(',') != std::string::npos) freeFields(line, wide ? 4 : 8, c.fields);
    else fixedFields(line, 8, wide ? 4 : 8, wide ? 16 : 8, c.fields);
  }

  std::vector<Card>& cards_;
  bool large_ = false;  // the card being read is in large field
};

// A NASTRAN real: 1.5, .5, 1.5E3, 1.5D3, and the short forms 1.5+3 and -2.-4 (E implied).
double real(const Card& c, size_t k, const char* what, bool required = true, double fallback = 0.0) {
  const std::string f = k < c.fields.size() ? c.fields[k] : "";
  if (f.empty()) {
    if (!required) return fallback;
    throw GeometryError(c.where() + ": " + c.name + " field " + std::to_string(k + 1) + " (" + what + ") is empty");
  }
  std::string s = upper(f);
  std::replace(s.begin(), s.end(), 'D', 'E');
  if (s.find('E') == std::string::npos)
    for (size_t i = 1; i < s.size(); ++i)
      if ((s[i] == '+' || s[i] == '-') && s[i - 1] != 'E') {
        s.insert(i, "E");
        break;
      }
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || *end != '\0' || !std::isfinite(v))
    throw GeometryError(c.where() + ": " + c.name + " field " + std::to_string(k + 1) + " (" + what + "): '" + f +
                        "' is not a number");
  return v;
}

long integer(const Card& c, size_t k, const char* what, bool required = true, long fallback = 0) {
  const std::string f = k < c.fields.size() ? c.fields[k] : "";
  if (f.empty() && !required) return fallback;
  char* end = nullptr;
  const long v = std::strtol(f.c_str(), &end, 10);
  if (f.empty() || *end != '\0' || v < 0 || v > 999999999)
    throw GeometryError(c.where() + ": " + c.name + " field " + std::to_string(k + 1) + " (" + what + "): '" + f +
                        "' is not an id (a whole number from 0 to 999999999)");
  return v;
}

struct Frame {
  Vec3 origin = Vec3::Zero();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // columns: the system's x, y, z in basic
};

struct Model {
  std::map<long, Vec3> grid;          // id → position in its CP system
  std::map<long, long> grid_system;   // id → CP
  std::map<long, const Card*> cord2r;
  std::map<long, Frame> frames;       // resolved
  struct Element {
    long eid, pid;
    std::vector<long> grids;
    const Card* card;
  };
  std::vector<Element> elements;
};

Frame frameOf(Model& m, long cid, std::set<long>& visiting) {
  if (cid == 0) return {};
  if (const auto it = m.frames.find(cid); it != m.frames.end()) return it->second;
  const auto card = m.cord2r.find(cid);
  if (card == m.cord2r.end())
    throw GeometryError("coordinate system " + std::to_string(cid) +
                        " is not defined by a CORD2R (other systems are not read)");
  const Card& c = *card->second;
  if (!visiting.insert(cid).second)
    throw GeometryError(c.where() + ": CORD2R " + std::to_string(cid) + " refers to itself through its RID");
  const Frame ref = frameOf(m, integer(c, 1, "RID", false, 0), visiting);
  const auto point = [&](size_t k) {
    return Vec3(ref.origin + ref.axes * Vec3(real(c, k, "A/B/C"), real(c, k + 1, "A/B/C"), real(c, k + 2, "A/B/C")));
  };
  const Vec3 a = point(2), b = point(5), cpt = point(8);
  const Vec3 z = b - a, xz = cpt - a;
  if (!(z.norm() > 0) || !(z.cross(xz).norm() > 0))
    throw GeometryError(c.where() + ": CORD2R " + std::to_string(cid) + ": A, B and C must not be collinear");
  Frame f;
  f.origin = a;
  const Vec3 ez = z.normalized(), ey = z.cross(xz).normalized(), ex = ey.cross(ez);
  f.axes.col(0) = ex, f.axes.col(1) = ey, f.axes.col(2) = ez;
  m.frames[cid] = f;
  return f;
}

void collect(const std::vector<Card>& cards, Model& m, NastranModel& out, std::map<long, long>& pshell_mid,
             std::map<long, NastranModel::Mat4>& mat4) {
  for (const Card& c : cards) {
    if (c.name == "GRID") {
      const long id = integer(c, 0, "ID");
      m.grid[id] = Vec3(real(c, 2, "X1", false), real(c, 3, "X2", false), real(c, 4, "X3", false));
      m.grid_system[id] = integer(c, 1, "CP", false, 0);
    } else if (c.name == "CORD2R") {
      m.cord2r[integer(c, 0, "CID")] = &c;
    } else if (c.name == "CTRIA3" || c.name == "CQUAD4") {
      const size_t corners = c.name == "CTRIA3" ? 3 : 4;
      Model::Element e{integer(c, 0, "EID"), integer(c, 1, "PID"), {}, &c};
      for (size_t k = 0; k < corners; ++k) e.grids.push_back(integer(c, 2 + k, "G"));
      m.elements.push_back(std::move(e));
    } else if (c.name == "PSHELL") {
      const long pid = integer(c, 0, "PID");
      pshell_mid[pid] = integer(c, 1, "MID1", false, 0);
      out.thickness_m[static_cast<int>(pid)] = real(c, 2, "T", false, 0.0);
    } else if (c.name == "MAT4") {
      const long mid = integer(c, 0, "MID");
      mat4[mid] = {mid, real(c, 1, "K", false, 0.0), real(c, 2, "CP", false, 0.0), real(c, 3, "RHO", false, 0.0)};
    } else {
      ++out.skipped[c.name];
    }
  }
}

// The element's corners in basic coordinates × scale; a CQUAD4 checked for warp.
std::vector<Vec3> corners(Model& m, const Model::Element& e, double scale) {
  std::vector<Vec3> p;
  for (long g : e.grids) {
    const auto it = m.grid.find(g);
    if (it == m.grid.end())
      throw GeometryError(e.card->where() + ": " + e.card->name + " " + std::to_string(e.eid) + " refers to GRID " +
                          std::to_string(g) + ", which the file does not define");
    std::set<long> visiting;
    const Frame f = frameOf(m, m.grid_system[g], visiting);
    p.push_back(scale * (f.origin + f.axes * it->second));
  }
  if (p.size() == 4) {
    const Vec3 n = (p[1] - p[0]).cross(p[2] - p[0]);
    const double diagonal = std::max((p[2] - p[0]).norm(), (p[3] - p[1]).norm());
    const double warp = n.norm() > 0 ? std::abs(n.normalized().dot(p[3] - p[0])) : 0.0;
    if (warp > kMaxQuadWarp * diagonal) {
      std::ostringstream s;
      s << e.card->where() << ": CQUAD4 " << e.eid << " is not flat: its fourth corner lies " << warp / diagonal
        << " of its diagonal off the plane of the other three (at most " << kMaxQuadWarp << "); split it into CTRIA3s";
      throw GeometryError(s.str());
    }
  }
  return p;
}

}  // namespace

NastranModel readNastran(const std::string& path, double scale) {
  if (!(std::isfinite(scale) && scale > 0)) throw GeometryError(path + ": scale must be a finite value > 0");
  std::vector<Card> cards;
  BulkReader(cards).read(path, 0);
  NastranModel out;
  Model m;
  std::map<long, long> pshell_mid;
  std::map<long, NastranModel::Mat4> mat4;
  collect(cards, m, out, pshell_mid, mat4);
  for (auto& [pid, t] : out.thickness_m) t *= scale;
  for (const auto& [pid, mid] : pshell_mid)
    if (const auto k = mat4.find(mid); k != mat4.end()) out.material[static_cast<int>(pid)] = k->second;
  std::map<long, MeshGroup> by_pid;
  for (const Model::Element& e : m.elements) {
    const std::vector<Vec3> p = corners(m, e, scale);
    MeshGroup& g = by_pid[e.pid];
    g.name = std::to_string(e.pid);
    const int base = static_cast<int>(g.soup.vertices.size());
    g.soup.vertices.insert(g.soup.vertices.end(), p.begin(), p.end());
    g.soup.triangles.push_back({base, base + 1, base + 2});
    g.soup.element.push_back(static_cast<int>(e.eid));
    if (p.size() == 4) {
      g.soup.triangles.push_back({base, base + 2, base + 3});
      g.soup.element.push_back(static_cast<int>(e.eid));
    }
  }
  for (auto& [pid, g] : by_pid) out.groups.push_back(std::move(g));
  if (out.groups.empty()) throw GeometryError(path + ": no CTRIA3 or CQUAD4 elements");
  return out;
}

}  // namespace radnet::geometry
