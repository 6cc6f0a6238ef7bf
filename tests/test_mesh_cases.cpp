// Meshes through the whole command (issue 29): transforms, node partitions, one warning per
// kind of defect, unit warnings, no false coincidence, located refusals.
#include "cli_support.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>

using namespace radnet::test;
using Catch::Contains;

namespace {

using P = std::array<double, 3>;

// An axis-aligned box [0, sx] × [0, sy] × [0, sz] as an ASCII STL, each face two facets,
// fronts facing `inward` or out; one `solid` per face (named px, mx, py, my, pz, mz) or one
// for all (`one_solid`), the +z face lifted by `lift` (a crack), a degenerate facet added.
struct BoxStl {
  bool inward = false, one_solid = false, degenerate = false;
  double lift = 0.0;
};

std::string boxStl(double sx, double sy, double sz, const BoxStl& o) {
  const bool inward = o.inward;
  const auto corner = [&](int i, int j, int k) { return P{i * sx, j * sy, k * sz}; };
  struct FaceSpec {
    const char* name;
    std::array<P, 4> q;  // counter-clockwise seen from outside
  };
  const std::vector<FaceSpec> faces = {
      {"px", {corner(1, 0, 0), corner(1, 1, 0), corner(1, 1, 1), corner(1, 0, 1)}},
      {"mx", {corner(0, 0, 0), corner(0, 0, 1), corner(0, 1, 1), corner(0, 1, 0)}},
      {"py", {corner(0, 1, 0), corner(0, 1, 1), corner(1, 1, 1), corner(1, 1, 0)}},
      {"my", {corner(0, 0, 0), corner(1, 0, 0), corner(1, 0, 1), corner(0, 0, 1)}},
      {"pz", {corner(0, 0, 1), corner(1, 0, 1), corner(1, 1, 1), corner(0, 1, 1)}},
      {"mz", {corner(0, 0, 0), corner(0, 1, 0), corner(1, 1, 0), corner(1, 0, 0)}}};
  std::ostringstream s;
  s.precision(9);
  const auto facet = [&](const P& a, const P& b, const P& c) {
    const std::array<P, 3> t = inward ? std::array<P, 3>{a, c, b} : std::array<P, 3>{a, b, c};
    s << "facet normal 0 0 0\nouter loop\n";
    for (const P& v : t) s << "vertex " << v[0] << " " << v[1] << " " << v[2] << "\n";
    s << "endloop\nendfacet\n";
  };
  if (o.one_solid) s << "solid box\n";
  for (FaceSpec f : faces) {
    if (!o.one_solid) s << "solid " << f.name << "\n";
    if (std::string(f.name) == "pz")
      for (P& v : f.q) v[2] += o.lift;
    facet(f.q[0], f.q[1], f.q[2]);
    facet(f.q[0], f.q[2], f.q[3]);
    if (!o.one_solid) s << "endsolid " << f.name << "\n";
  }
  if (o.degenerate) facet(P{0, 0, 0}, P{0.5 * sx, 0, 0}, P{sx, 0, 0});
  if (o.one_solid) s << "endsolid box\n";
  return s.str();
}

std::map<std::string, int> nodeIndex(hid_t file) {
  std::map<std::string, int> index;
  const std::vector<std::string> names = readNodeNames(file);
  for (size_t i = 0; i < names.size(); ++i) index[names[i]] = static_cast<int>(i);
  return index;
}

}  // namespace

TEST_CASE("a box written as an STL in mm, turned and placed, gives the box primitive's nodes, areas and view factors") {
  TempDir dir;
  // The file: 200 × 100 × 300 mm at its own origin, fronts inward. Turned +90° about z it is
  // 100 × 200 × 300 mm, placed so that it fills the primitive's box at [1, 2, 3].
  dir.write("box.stl", boxStl(200, 100, 300, {true, false, false, 0.0}));
  const std::string head = R"(
materials: {black: {emissivity: 0.9, absorptivity: 0.9}}
solver: {view_factors: {method: exact}}
)";
  dir.write("primitive.yaml", "name: p" + head + R"(geometry:
  - box: {name: b, origin: [1.0, 2.0, 3.0], size: [0.1, 0.2, 0.3], back: black}
)");
  dir.write("mesh.yaml", "name: m" + head + R"(geometry:
  - mesh: {name: m, file: box.stl, scale: 0.001, rotation: {axis: [0, 0, 1], angle: 90.0},
           position: [1.1, 2.0, 3.0], nodes: groups, front: black}
)");
  const Run p = runRadnet("run primitive.yaml -o p.h5", dir), m = runRadnet("run mesh.yaml -o m.h5", dir);
  INFO(p.err << m.err);
  REQUIRE(p.exit_code == 0);
  REQUIRE(m.exit_code == 0);
  CHECK(m.err.find("warning") == std::string::npos);  // a clean file says nothing
  // +90° about z: the file's +x face looks along +y, its +y face along −x.
  const std::map<std::string, std::string> same = {{"m.px", "b.+y.back"}, {"m.mx", "b.-y.back"},
                                                   {"m.py", "b.-x.back"}, {"m.my", "b.+x.back"},
                                                   {"m.pz", "b.+z.back"}, {"m.mz", "b.-z.back"}};
  const hid_t pf = H5Fopen((dir.path / "p.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t mf = H5Fopen((dir.path / "m.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const auto pi = nodeIndex(pf), mi = nodeIndex(mf);
  const H5Data pa = readDataset(pf, "/nodes/area"), ma = readDataset(mf, "/nodes/area");
  const H5Data pF = readDataset(pf, "/network/view_factors"), mF = readDataset(mf, "/network/view_factors");
  H5Fclose(pf);
  H5Fclose(mf);
  REQUIRE(mi.size() == 6);
  for (const auto& [mn, pn] : same) {
    INFO(mn << " ~ " << pn);
    // The float coordinates of an STL: areas to 1e-7.
    CHECK(ma.values[static_cast<size_t>(mi.at(mn))] == Approx(pa.values[static_cast<size_t>(pi.at(pn))]).epsilon(1e-7));
    for (const auto& [mn2, pn2] : same) {
      const double fm = mF.values[static_cast<size_t>(mi.at(mn) * 6 + mi.at(mn2))];
      const double fp = pF.values[static_cast<size_t>(pi.at(pn) * 6 + pi.at(pn2))];
      CHECK(fm == Approx(fp).margin(1e-6));  // both exact; the STL's float rounding, 1e-7 relative
    }
  }
}

TEST_CASE("a mesh in mm without scale warns, an inward cracked mesh warns, defects warn once per kind") {
  TempDir dir;
  dir.write("outward.stl", boxStl(200, 100, 300, {false, true, false, 0.0}));
  // Inward, with a degenerate facet, its +z face lifted by 0.05 mm (a crack).
  dir.write("cracked.stl", boxStl(0.2, 0.1, 0.3, {true, true, true, 5e-5}));
  dir.write("case.yaml", R"(
name: defects
materials: {white: {emissivity: 0.8, absorptivity: 0.2}}
geometry:
  - mesh: {name: big, file: outward.stl, front: white}
  - mesh: {name: a, file: cracked.stl, front: white, position: [1.0, 0, 0]}
  - mesh: {name: b, file: cracked.stl, front: white, position: [2.0, 0, 0]}
)");
  const Run r = runRadnet("validate case.yaml", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.err, Contains("meshes larger than 100 m") && Contains("did you mean `scale: 0.001`") &&
                        Contains("mesh 'big' from"));
  CHECK_THAT(r.err, Contains("fronts face inward") && Contains("flip: true"));
  CHECK_THAT(r.err, Contains("cracks left open") && Contains("8 open edges"));
  // One line per kind, naming both meshes.
  const auto count = [&](const std::string& what) {
    size_t n = 0;
    for (size_t at = r.err.find(what); at != std::string::npos; at = r.err.find(what, at + 1)) ++n;
    return n;
  };
  CHECK(count("degenerate triangles") == 1);
  CHECK(count("cracks left open") == 1);
  CHECK(count("fronts face inward") == 1);
  CHECK_THAT(r.err, Contains("mesh 'a' from") && Contains("mesh 'b' from"));
  // flip: true turns them out: the inward warning goes.
  dir.write("flipped.yaml", R"(
name: flipped
materials: {white: {emissivity: 0.8, absorptivity: 0.2}}
geometry:
  - mesh: {name: a, file: cracked.stl, front: white, flip: true}
)");
  const Run f = runRadnet("validate flipped.yaml", dir);
  CHECK(f.exit_code == 0);
  CHECK(f.err.find("fronts face inward") == std::string::npos);
  CHECK(f.err.find("cracks left open") != std::string::npos);
}

TEST_CASE("meshes: no false coincidence on fine bodies, true coincidence named by triangle and file, located refusals") {
  TempDir dir;
  // A UV sphere of 19,998 triangles, 150 mm, 1.5 m off the origin (refused before as "two
  // coincident triangles").
  std::ostringstream off;
  off.precision(10);
  const int np = 100, na = 101;
  off << "OFF\n" << 2 + (np - 1) * na << " " << 2 * na * (np - 1) << " 0\n";
  const double c[3] = {1500.0, -1050.0, 450.0}, r = 150.0;
  off << c[0] << " " << c[1] << " " << c[2] + r << "\n";
  for (int i = 1; i < np; ++i)
    for (int j = 0; j < na; ++j) {
      const double th = M_PI * i / np, ph = 2 * M_PI * j / na;
      off << c[0] + r * std::sin(th) * std::cos(ph) << " " << c[1] + r * std::sin(th) * std::sin(ph) << " "
          << c[2] + r * std::cos(th) << "\n";
    }
  off << c[0] << " " << c[1] << " " << c[2] - r << "\n";
  const auto at = [&](int i, int j) { return 1 + (i - 1) * na + (j % na); };
  for (int j = 0; j < na; ++j) off << "3 0 " << at(1, j) << " " << at(1, j + 1) << "\n";
  for (int i = 1; i < np - 1; ++i)
    for (int j = 0; j < na; ++j)
      off << "3 " << at(i, j) << " " << at(i + 1, j) << " " << at(i + 1, j + 1) << "\n3 " << at(i, j) << " "
          << at(i + 1, j + 1) << " " << at(i, j + 1) << "\n";
  for (int j = 0; j < na; ++j) off << "3 " << at(np - 1, j) << " " << 2 + (np - 1) * na - 1 << " " << at(np - 1, j + 1) << "\n";
  dir.write("ball.off", off.str());
  dir.write("plate.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  const std::string head = "materials: {white: {emissivity: 0.8, absorptivity: 0.2}}\ngeometry:\n";
  dir.write("ball.yaml", "name: ball\n" + head + "  - mesh: {name: ball, file: ball.off, scale: 0.001, front: white}\n");
  const Run b = runRadnet("validate ball.yaml", dir);
  INFO(b.err);
  CHECK(b.exit_code == 0);
  dir.write("twice.yaml", "name: twice\n" + head +
                              "  - mesh: {name: p, file: plate.obj, front: white}\n"
                              "  - mesh: {name: q, file: plate.obj, front: white}\n");
  const Run t = runRadnet("validate twice.yaml", dir);
  CHECK(t.exit_code == 2);
  CHECK_THAT(t.err, Contains("twice.yaml:") && Contains("coincide") && Contains("triangle 0 of mesh 'p' from") &&
                        Contains("plate.obj") && Contains("of mesh 'q' from"));
  dir.write("subdivided.yaml", "name: s\n" + head + "  - mesh: {name: p, file: plate.obj, front: white, subdivisions: 4}\n");
  const Run s = runRadnet("validate subdivided.yaml", dir);
  CHECK(s.exit_code == 2);
  CHECK_THAT(s.err, Contains("subdivided.yaml:4:") && Contains("subdivisions apply to primitives only"));
  dir.write("groups.yaml", "name: g\n" + head + "  - mesh: {name: p, file: ball.off, nodes: groups, front: white}\n");
  const Run g = runRadnet("validate groups.yaml", dir);
  CHECK(g.exit_code == 2);
  CHECK_THAT(g.err, Contains("groups.yaml:4:") && Contains("has no groups"));
  dir.write("faces.yaml", "name: f\n" + head +
                              "  - mesh: {name: p, file: plate.obj, nodes: elements, front: white, "
                              "rotation: {axis: [0, 0, 0], angle: 10.0}}\n");
  const Run f = runRadnet("validate faces.yaml", dir);
  CHECK(f.exit_code == 2);
  CHECK_THAT(f.err, Contains("faces.yaml:4:") && Contains("rotation.axis"));
}

namespace {

// Small field: 8 characters a field.
std::string small(const std::vector<std::string>& fields) {
  std::string line;
  for (const std::string& f : fields) {
    std::string cell = f.substr(0, 8);
    line += cell + std::string(8 - cell.size(), ' ');
  }
  return line + "\n";
}

// A number in at most 8 characters, in NASTRAN's short form where it helps (1.5-3 = 1.5e-3).
std::string num8(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  std::string t = s.str();
  if (t.size() > 8) {
    std::ostringstream e;
    e.precision(2);
    e << std::scientific << v;  // 1.23e-05 → 1.23-5
    t = e.str();
    const size_t at = t.find('e');
    const std::string mant = t.substr(0, at);
    const int ex = std::stoi(t.substr(at + 1));
    t = mant + (ex < 0 ? "-" : "+") + std::to_string(std::abs(ex));
  }
  return t;
}

// The box [1, 1.1] × [2, 2.2] × [3, 3.3] in mm as NASTRAN bulk data, one CQUAD4 per face, each
// face its own PID (1 … 6 for +x, −x, +y, −y, +z, −z), fronts inward. `form`: "small",
// "large" (GRID* in a CORD2R turned 90° about z and shifted, with continuations) or "free"
// (commas, the grids in an INCLUDE file, short-form reals).
std::string boxBdf(const std::string& form) {
  const double lo[3] = {1000, 2000, 3000}, hi[3] = {1100, 2200, 3300};
  std::vector<std::array<double, 3>> grid;
  for (int k = 0; k < 8; ++k) grid.push_back({k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]});
  // Corners of each face, wound inward (clockwise seen from outside).
  const int quads[6][4] = {{1, 5, 7, 3}, {0, 2, 6, 4}, {2, 3, 7, 6}, {0, 4, 5, 1}, {4, 6, 7, 5}, {0, 1, 3, 2}};
  std::string out = "$ a box written by hand\nBEGIN BULK\n";
  std::string grids;
  for (int k = 0; k < 8; ++k) {
    const auto& g = grid[static_cast<size_t>(k)];
    if (form == "small") {
      out += small({"GRID", std::to_string(k + 1), "", num8(g[0]), num8(g[1]), num8(g[2])});
    } else if (form == "large") {
      // System 5: origin (500, 0, 0) mm, axes x' = +y, y' = −x, z' = z: x = 500 − y', y = x'.
      char line[200];
      std::snprintf(line, sizeof line, "GRID*   %-16d%-16d%-16.9g%-16.9g*G%d\n*G%-6d%-16.9g\n", k + 1, 5, g[1],
                    500.0 - g[0], k, k, g[2]);
      out += line;
    } else {
      // Short-form reals: 1.1+3 is 1100.
      const auto shortForm = [](double v) {
        std::ostringstream m;
        m << v / 1000.0 << "+3";
        return m.str();
      };
      grids += "GRID," + std::to_string(k + 1) + ",," + shortForm(g[0]) + "," + shortForm(g[1]) + "," + shortForm(g[2]) + "\n";
    }
  }
  if (form == "large")
    out += small({"CORD2R", "5", "0", "500.", "0.", "0.", "500.", "0.", "1.", "+C5"}) + small({"+C5", "500.", "1.", "0."});
  if (form == "free") out += "INCLUDE 'grids.inc'\n";
  for (int f = 0; f < 6; ++f) {
    std::vector<std::string> q = {"CQUAD4", std::to_string(100 + f), std::to_string(f + 1)};
    for (int c = 0; c < 4; ++c) q.push_back(std::to_string(quads[f][c] + 1));
    if (form == "free") {
      for (size_t k = 0; k < q.size(); ++k) out += (k ? "," : "") + q[k];
      out += "\n";
    } else {
      out += small(q);
    }
    out += form == "free" ? "PSHELL," + std::to_string(f + 1) + ",7,1.5\n" : small({"PSHELL", std::to_string(f + 1), "7", "1.5"});
  }
  out += small({"MAT4", "7", "167."}) + small({"RBE2", "900", "1", "123", "2"}) + "ENDDATA\n";
  return form == "free" ? out + "\x1f" + grids : out;  // the grids go to their own file
}

}  // namespace

TEST_CASE("NASTRAN: a box in small, large (CORD2R) and free field (INCLUDE) gives the box primitive's nodes, areas and view factors") {
  TempDir dir;
  const std::string head = "materials: {black: {emissivity: 0.9, absorptivity: 0.9}}\n"
                           "solver: {view_factors: {method: exact}}\ngeometry:\n";
  dir.write("primitive.yaml",
            "name: p\n" + head + "  - box: {name: b, origin: [1.0, 2.0, 3.0], size: [0.1, 0.2, 0.3], back: black}\n");
  const Run p = runRadnet("run primitive.yaml -o p.h5", dir);
  REQUIRE(p.exit_code == 0);
  const hid_t pf = H5Fopen((dir.path / "p.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const auto pi = nodeIndex(pf);
  const H5Data pa = readDataset(pf, "/nodes/area"), pF = readDataset(pf, "/network/view_factors");
  H5Fclose(pf);
  const std::vector<std::string> faces = {"b.+x.back", "b.-x.back", "b.+y.back", "b.-y.back", "b.+z.back", "b.-z.back"};
  for (const std::string form : {"small", "large", "free"}) {
    INFO(form);
    std::string bdf = boxBdf(form);
    if (const size_t split = bdf.find('\x1f'); split != std::string::npos) {
      dir.write("grids.inc", bdf.substr(split + 1));
      bdf.erase(split);
    }
    dir.write("box.bdf", bdf);
    dir.write("n.yaml", "name: n\n" + head + "  - mesh: {name: n, file: box.bdf, scale: 0.001, front: black}\n");
    const Run n = runRadnet("run n.yaml -o n.h5", dir);
    INFO(n.err);
    REQUIRE(n.exit_code == 0);
    CHECK_THAT(n.err, Contains("NASTRAN cards not read") && Contains("RBE2 ×1"));
    const hid_t nf = H5Fopen((dir.path / "n.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const auto ni = nodeIndex(nf);
    const H5Data na = readDataset(nf, "/nodes/area"), nF = readDataset(nf, "/network/view_factors");
    H5Fclose(nf);
    REQUIRE(ni.size() == 6);
    for (int a = 0; a < 6; ++a) {
      const std::string an = "n." + std::to_string(a + 1);
      REQUIRE(ni.count(an));
      CHECK(na.values[static_cast<size_t>(ni.at(an))] ==
            Approx(pa.values[static_cast<size_t>(pi.at(faces[static_cast<size_t>(a)]))]).epsilon(1e-9));
      for (int b = 0; b < 6; ++b) {
        const double fn = nF.values[static_cast<size_t>(ni.at(an) * 6 + ni.at("n." + std::to_string(b + 1)))];
        const double fp = pF.values[static_cast<size_t>(pi.at(faces[static_cast<size_t>(a)]) * 6 +
                                                        pi.at(faces[static_cast<size_t>(b)]))];
        CHECK(fn == Approx(fp).margin(1e-9));
      }
    }
  }
  // Located errors: a missing grid names the element and the line; a bad number its field.
  dir.write("bad.bdf", small({"GRID", "1", "", "0.", "0.", "0."}) + small({"CTRIA3", "7", "1", "1", "2", "3"}));
  dir.write("bad.yaml", "name: bad\n" + head + "  - mesh: {name: n, file: bad.bdf, front: black}\n");
  const Run bad = runRadnet("validate bad.yaml", dir);
  CHECK(bad.exit_code == 2);
  CHECK_THAT(bad.err, Contains("bad.yaml:") && Contains("bad.bdf:2: CTRIA3 7 refers to GRID 2"));
  dir.write("num.bdf", small({"GRID", "1", "", "0.", "1.x", "0."}));
  dir.write("num.yaml", "name: num\n" + head + "  - mesh: {name: n, file: num.bdf, front: black}\n");
  const Run num = runRadnet("validate num.yaml", dir);
  CHECK(num.exit_code == 2);
  CHECK_THAT(num.err, Contains("num.bdf:1: GRID field 4 (X2): '1.x' is not a number"));
}

namespace {

// Appends the bytes of a value (Gmsh binary: native endianness, checked by the file's int 1).
template <class T>
void put(std::string& out, T v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

// The box [1, 1.1] × [2, 2.2] × [3, 3.3] in mm as a Gmsh mesh: one quadrangle per face, each
// face its own physical surface (1 … 6, named px … mz), fronts inward; a point and a line
// element besides (read past). `version` 2.2 or 4.1, ASCII or binary.
std::string boxMsh(const std::string& version, bool binary) {
  const double lo[3] = {1000, 2000, 3000}, hi[3] = {1100, 2200, 3300};
  const int quads[6][4] = {{1, 5, 7, 3}, {0, 2, 6, 4}, {2, 3, 7, 6}, {0, 4, 5, 1}, {4, 6, 7, 5}, {0, 1, 3, 2}};
  const char* names[6] = {"px", "mx", "py", "my", "pz", "mz"};
  std::ostringstream a;
  a.precision(10);
  std::string out = "$MeshFormat\n" + version + (binary ? " 1 8\n" : " 0 8\n");
  if (binary) put<int32_t>(out, 1), out += "\n";
  out += "$EndMeshFormat\n$PhysicalNames\n6\n";
  for (int f = 0; f < 6; ++f) out += "2 " + std::to_string(f + 1) + " \"" + names[f] + "\"\n";
  out += "$EndPhysicalNames\n";
  const auto corner = [&](int k, int axis) { return (k >> axis) & 1 ? hi[axis] : lo[axis]; };
  if (version == "2.2") {
    out += "$Nodes\n8\n";
    for (int k = 0; k < 8; ++k) {
      if (binary) {
        put<int32_t>(out, k + 1);
        for (int ax = 0; ax < 3; ++ax) put<double>(out, corner(k, ax));
      } else {
        a.str("");
        a << k + 1 << " " << corner(k, 0) << " " << corner(k, 1) << " " << corner(k, 2) << "\n";
        out += a.str();
      }
    }
    out += std::string(binary ? "\n" : "") + "$EndNodes\n$Elements\n8\n";
    if (binary) {
      put<int32_t>(out, 15), put<int32_t>(out, 1), put<int32_t>(out, 2);  // a point
      put<int32_t>(out, 1), put<int32_t>(out, 0), put<int32_t>(out, 9), put<int32_t>(out, 1);
      put<int32_t>(out, 1), put<int32_t>(out, 1), put<int32_t>(out, 2);  // a line
      put<int32_t>(out, 2), put<int32_t>(out, 0), put<int32_t>(out, 9), put<int32_t>(out, 1), put<int32_t>(out, 2);
      put<int32_t>(out, 3), put<int32_t>(out, 6), put<int32_t>(out, 2);  // six quadrangles, 2 tags each
      for (int f = 0; f < 6; ++f) {
        put<int32_t>(out, 101 + f), put<int32_t>(out, f + 1), put<int32_t>(out, 11 + f);
        for (int c = 0; c < 4; ++c) put<int32_t>(out, quads[f][c] + 1);
      }
      out += "\n";
    } else {
      out += "1 15 2 0 9 1\n2 1 2 0 9 1 2\n";
      for (int f = 0; f < 6; ++f) {
        out += std::to_string(101 + f) + " 3 2 " + std::to_string(f + 1) + " " + std::to_string(11 + f);
        for (int c = 0; c < 4; ++c) out += " " + std::to_string(quads[f][c] + 1);
        out += "\n";
      }
    }
    return out + "$EndElements\n";
  }
  // 4.1: the surfaces' physical tags come from $Entities.
  out += "$Entities\n";
  if (binary) {
    for (uint64_t c : {0, 0, 6, 0}) put<uint64_t>(out, c);
    for (int f = 0; f < 6; ++f) {
      put<int32_t>(out, 11 + f);
      for (int b = 0; b < 6; ++b) put<double>(out, 0.0);
      put<uint64_t>(out, 1), put<int32_t>(out, f + 1), put<uint64_t>(out, 0);
    }
    out += "\n";
  } else {
    out += "0 0 6 0\n";
    for (int f = 0; f < 6; ++f) out += std::to_string(11 + f) + " 0 0 0 1 1 1 1 " + std::to_string(f + 1) + " 0\n";
  }
  out += "$EndEntities\n$Nodes\n";
  if (binary) {
    for (uint64_t c : {1, 8, 1, 8}) put<uint64_t>(out, c);
    put<int32_t>(out, 3), put<int32_t>(out, 1), put<int32_t>(out, 0), put<uint64_t>(out, 8);
    for (uint64_t k = 1; k <= 8; ++k) put<uint64_t>(out, k);
    for (int k = 0; k < 8; ++k)
      for (int ax = 0; ax < 3; ++ax) put<double>(out, corner(k, ax));
    out += "\n";
  } else {
    out += "1 8 1 8\n3 1 0 8\n1\n2\n3\n4\n5\n6\n7\n8\n";
    for (int k = 0; k < 8; ++k) {
      a.str("");
      a << corner(k, 0) << " " << corner(k, 1) << " " << corner(k, 2) << "\n";
      out += a.str();
    }
  }
  out += "$EndNodes\n$Elements\n";
  if (binary) {
    for (uint64_t c : {7, 7, 1, 201}) put<uint64_t>(out, c);
    put<int32_t>(out, 1), put<int32_t>(out, 1), put<int32_t>(out, 1), put<uint64_t>(out, 1);  // a line
    put<uint64_t>(out, 201), put<uint64_t>(out, 1), put<uint64_t>(out, 2);
    for (int f = 0; f < 6; ++f) {
      put<int32_t>(out, 2), put<int32_t>(out, 11 + f), put<int32_t>(out, 3), put<uint64_t>(out, 1);
      put<uint64_t>(out, static_cast<uint64_t>(101 + f));
      for (int c = 0; c < 4; ++c) put<uint64_t>(out, static_cast<uint64_t>(quads[f][c] + 1));
    }
    out += "\n";
  } else {
    out += "7 7 1 201\n1 1 1 1\n201 1 2\n";
    for (int f = 0; f < 6; ++f) {
      out += "2 " + std::to_string(11 + f) + " 3 1\n" + std::to_string(101 + f);
      for (int c = 0; c < 4; ++c) out += " " + std::to_string(quads[f][c] + 1);
      out += "\n";
    }
  }
  return out + "$EndElements\n";
}

}  // namespace

TEST_CASE("Gmsh: a box in MSH 2.2 and 4.1, ASCII and binary, gives the box primitive's nodes, areas and view factors") {
  TempDir dir;
  const std::string head = "materials: {black: {emissivity: 0.9, absorptivity: 0.9}}\n"
                           "solver: {view_factors: {method: exact}}\ngeometry:\n";
  dir.write("primitive.yaml",
            "name: p\n" + head + "  - box: {name: b, origin: [1.0, 2.0, 3.0], size: [0.1, 0.2, 0.3], back: black}\n");
  REQUIRE(runRadnet("run primitive.yaml -o p.h5", dir).exit_code == 0);
  const hid_t pf = H5Fopen((dir.path / "p.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const auto pi = nodeIndex(pf);
  const H5Data pF = readDataset(pf, "/network/view_factors");
  H5Fclose(pf);
  const std::map<std::string, std::string> same = {{"g.px", "b.+x.back"}, {"g.mx", "b.-x.back"},
                                                   {"g.py", "b.+y.back"}, {"g.my", "b.-y.back"},
                                                   {"g.pz", "b.+z.back"}, {"g.mz", "b.-z.back"}};
  for (const std::string version : {"2.2", "4.1"})
    for (const bool binary : {false, true}) {
      INFO(version << (binary ? " binary" : " ASCII"));
      dir.write("box.msh", boxMsh(version, binary));
      dir.write("g.yaml", "name: g\n" + head + "  - mesh: {name: g, file: box.msh, scale: 0.001, front: black}\n");
      const Run g = runRadnet("run g.yaml -o g.h5", dir);
      INFO(g.err);
      REQUIRE(g.exit_code == 0);
      CHECK_THAT(g.err, Contains("Gmsh elements not read") && Contains("lines ×1"));
      const hid_t gf = H5Fopen((dir.path / "g.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
      const auto gi = nodeIndex(gf);
      const H5Data gF = readDataset(gf, "/network/view_factors");
      H5Fclose(gf);
      REQUIRE(gi.size() == 6);
      for (const auto& [gn, pn] : same)
        for (const auto& [gn2, pn2] : same)
          CHECK(gF.values[static_cast<size_t>(gi.at(gn) * 6 + gi.at(gn2))] ==
                Approx(pF.values[static_cast<size_t>(pi.at(pn) * 6 + pi.at(pn2))]).margin(1e-9));
    }
  // A count beyond what the file can hold is refused before anything is allocated.
  dir.write("huge.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n900000000000\n1 0 0 0\n$EndNodes\n");
  dir.write("huge.yaml", "name: h\n" + head + "  - mesh: {name: g, file: huge.msh, front: black}\n");
  const Run h = runRadnet("validate huge.yaml", dir);
  CHECK(h.exit_code == 2);
  CHECK_THAT(h.err, Contains("huge.msh:5: nodes: 900000000000 stated"));
}

TEST_CASE("a node that falls below 10 K is warned by name, a boundary node is not") {
  TempDir dir;
  // Three plates facing +x: `lit` dissipates 10 W and sees only the inactive back of `dark`,
  // which has nothing and no conductor, so in steady state it sits at the 3 K of space;
  // `sky` is held at 3 K.
  dir.write("plates.obj", "v 0 0 0\nv 0 1 0\nv 0 1 1\nv 0 0 1\nv 2 0 0\nv 2 0 1\nv 2 1 1\nv 2 1 0\n"
                          "v 5 0 0\nv 5 1 0\nv 5 1 1\nv 5 0 1\ng lit\nf 1 2 3 4\ng dark\nf 5 8 7 6\ng sky\nf 9 10 11 12\n");
  dir.write("case.yaml", R"(
name: dark
materials: {white: {emissivity: 0.8, absorptivity: 0.3}}
geometry:
  - mesh: {name: p, file: plates.obj, nodes: groups, front: white}
thermal:
  nodes: {p.lit: {dissipation: 10.0}, p.sky: {temperature: 3.0}}
)");
  const Run r = runRadnet("run case.yaml -o out.h5", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.err, Contains("node 'p.dark' falls to"));
  CHECK(r.err.find("node 'p.lit' falls to") == std::string::npos);
  CHECK(r.err.find("node 'p.sky' falls to") == std::string::npos);
}

TEST_CASE("STEP: a box's CAD faces are its nodes with exact areas, a cylinder's within the tessellation's bound") {
  TempDir dir;
  const std::string head = "materials: {black: {emissivity: 0.9, absorptivity: 0.9}}\n"
                           "solver: {view_factors: {method: exact}}\ngeometry:\n";
  const std::string data = source("tests/data/meshes/");
  dir.write("box.yaml", "name: b\n" + head + "  - mesh: {name: box, file: " + data + "box.step, front: black}\n");
  const Run b = runRadnet("run box.yaml -o b.h5", dir);
  INFO(b.err);
  REQUIRE(b.exit_code == 0);
  hid_t f = H5Fopen((dir.path / "b.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  std::vector<std::string> names = readNodeNames(f);
  H5Data area = readDataset(f, "/nodes/area"), space = readDataset(f, "/network/space_view_factor");
  H5Fclose(f);
  REQUIRE(names.size() == 6);
  std::vector<double> sorted = area.values;
  std::sort(sorted.begin(), sorted.end());
  const std::vector<double> faces = {0.02, 0.02, 0.03, 0.03, 0.06, 0.06};  // the file's mm, read as m
  for (size_t k = 0; k < 6; ++k) {
    CHECK(names[k] == "box." + std::to_string(k));
    CHECK(sorted[k] == Approx(faces[k]).epsilon(1e-12));
    CHECK(space.values[k] == Approx(1.0).margin(1e-9));  // a convex solid's outward faces see only space
  }
  // The file's face labels name the nodes, made fit for names ("lid top" → lid_top); a label
  // two faces share, and an empty one, leave those faces their index.
  {
    std::ifstream in(data + "box.step");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::vector<std::string> labels = {"lid top", "floor", "wall-a", "wall-b", "wall-a", ""};
    size_t at = 0;
    for (const std::string& label : labels) {
      at = text.find("ADVANCED_FACE(''", at);
      REQUIRE(at != std::string::npos);
      text.replace(at, 16, "ADVANCED_FACE('" + label + "'");
      at += 16;
    }
    dir.write("named.step", text);
    dir.write("named.yaml", "name: n\n" + head + "  - mesh: {name: box, file: named.step, front: black}\n");
    const Run n = runRadnet("run named.yaml -o n.h5", dir);
    INFO(n.err);
    REQUIRE(n.exit_code == 0);
    f = H5Fopen((dir.path / "n.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    CHECK(readNodeNames(f) == std::vector<std::string>{"box.lid_top", "box.floor", "box.2", "box.wall-b", "box.4", "box.5"});
    H5Fclose(f);
  }
  // A cylinder (r = 50 mm, h = 120 mm) at a chord deflection d = 0.5 mm: the tessellation is
  // inscribed, so each face is smaller than the true one, the wall by at most d/(3r) (its rim
  // polygon's perimeter), a lid by at most (4/3) d/r (its polygon's area).
  dir.write("can.yaml", "name: c\n" + head + "  - mesh: {name: can, file: " + data +
                            "cylinder.step, front: black, mesh_size: 0.0005}\n");
  const Run c = runRadnet("run can.yaml -o c.h5", dir);
  INFO(c.err);
  REQUIRE(c.exit_code == 0);
  f = H5Fopen((dir.path / "c.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  area = readDataset(f, "/nodes/area");
  H5Fclose(f);
  REQUIRE(area.values.size() == 3);
  const double r = 0.05, h = 0.12, d = 0.0005;
  int walls = 0, lids = 0;
  for (double a : area.values) {
    if (a > 0.02) {
      ++walls;
      CHECK(a <= 2 * M_PI * r * h);
      CHECK(a >= 2 * M_PI * r * h * (1 - d / (3 * r)));
    } else {
      ++lids;
      CHECK(a <= M_PI * r * r);
      CHECK(a >= M_PI * r * r * (1 - 4 * d / (3 * r)));
    }
  }
  CHECK(walls == 1);
  CHECK(lids == 2);
  // The habit of `scale: 0.001` on a CAD export in mm is warned: the file states its unit.
  dir.write("scaled.yaml", "name: s\n" + head + "  - mesh: {name: box, file: " + data +
                               "box.step, front: black, scale: 0.001}\n");
  const Run scaled = runRadnet("validate scaled.yaml", dir);
  CHECK(scaled.exit_code == 0);
  CHECK_THAT(scaled.err, Contains("STEP files with a scale") && Contains("scale 0.001"));
  CHECK(b.err.find("STEP files with a scale") == std::string::npos);
  // Other formats take no mesh_size.
  dir.write("plate.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n");
  dir.write("bad.yaml", "name: x\n" + head + "  - mesh: {name: p, file: plate.obj, front: black, mesh_size: 0.1}\n");
  const Run bad = runRadnet("validate bad.yaml", dir);
  CHECK(bad.exit_code == 2);
  CHECK_THAT(bad.err, Contains("bad.yaml:5:") && Contains("applies to STEP files only"));
}

TEST_CASE("specular meshes: facetted mirrors and one-sided windows are warned, smooth normals and two-sided glass not") {
  TempDir dir;
  // A trough mirror written in mm: 8 strips over 80° of a 500 mm radius arc, 10° creases.
  std::string bent, normals;
  for (int k = 0; k <= 8; ++k) {
    const double a = (-40.0 + 10.0 * k) * M_PI / 180.0, x = 500.0 * std::sin(a), z = 500.0 * (1.0 - std::cos(a));
    bent += "v " + std::to_string(x) + " 0 " + std::to_string(z) + "\nv " + std::to_string(x) + " 300 " +
            std::to_string(z) + "\n";
    normals += "vn " + std::to_string(-std::sin(a)) + " 0 " + std::to_string(std::cos(a)) + "\n";
  }
  std::string faces, smooth_faces;
  for (int k = 0; k < 8; ++k) {
    const int a = 2 * k + 1, b = a + 1, c = a + 2, d = a + 3, na = k + 1, nc = k + 2;
    faces += "f " + std::to_string(a) + " " + std::to_string(c) + " " + std::to_string(d) + "\nf " + std::to_string(a) +
             " " + std::to_string(d) + " " + std::to_string(b) + "\n";
    const auto corner = [](int v, int n) { return std::to_string(v) + "//" + std::to_string(n); };
    smooth_faces += "f " + corner(a, na) + " " + corner(c, nc) + " " + corner(d, nc) + "\nf " + corner(a, na) + " " +
                    corner(d, nc) + " " + corner(b, na) + "\n";
  }
  dir.write("trough.obj", bent + faces);
  dir.write("smooth.obj", bent + normals + smooth_faces);
  const std::string head = "materials:\n  mirror: {emissivity: 0.05, absorptivity: 0.08, specular_reflectance: 0.9}\n"
                           "  glass: {emissivity: 0.84, absorptivity: 0.05, solar_transmittance: 0.9}\n"
                           "  black: {emissivity: 0.9, absorptivity: 0.9}\ngeometry:\n"
                           "  - rectangle: {name: plate, origin: [0, 0, 0.2], u: [0.1, 0, 0], v: [0, 0.1, 0], "
                           "front: black}\n";
  dir.write("facetted.yaml", "name: f\n" + head + "  - mesh: {name: trough, file: trough.obj, scale: 0.001, "
                                                   "front: mirror}\n");
  const Run facetted = runRadnet("validate facetted.yaml", dir);
  CHECK(facetted.exit_code == 0);
  // 10° creases × 1.2 %/deg × ρs 0.9 ≈ 11 %: far above solver.accuracy 0.01.
  CHECK_THAT(facetted.err, Contains("node 'trough' reflects specularly") && Contains("up to 10"));
  dir.write("smooth.yaml", "name: s\n" + head + "  - mesh: {name: trough, file: smooth.obj, scale: 0.001, "
                                               "front: mirror}\n");
  const Run smooth = runRadnet("validate smooth.yaml", dir);
  CHECK(smooth.exit_code == 0);
  CHECK(smooth.err.find("reflects specularly") == std::string::npos);  // the file's normals are followed
  const std::string glass = "  - rectangle: {name: window, origin: [-0.1, -0.1, 0.5], u: [0.3, 0, 0], "
                            "v: [0, 0.3, 0], front: glass";
  dir.write("one.yaml", "name: o\n" + head + glass + "}\n");
  const Run one = runRadnet("validate one.yaml", dir);
  CHECK(one.exit_code == 0);
  CHECK_THAT(one.err, Contains("node 'window' transmits") && Contains("no node on their other side"));
  dir.write("two.yaml", "name: t\n" + head + glass + ", back: glass}\n");
  const Run two = runRadnet("validate two.yaml", dir);
  CHECK(two.exit_code == 0);
  CHECK(two.err.find("transmits") == std::string::npos);
}
