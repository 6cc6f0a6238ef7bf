// The command-line contract (docs/design.md, "Contracts") through the real executable: exit codes,
// located error messages, atomic output, and the HDF5 layout read back with the HDF5 API.
#include "cli_support.hpp"

#include <hdf5.h>
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace radnet::test;

TEST_CASE("cli: run the seed room writes the HDF5 layout with units, and the paper's M'_2") {
  TempDir dir;
  const Run r = runRadnet("run '" + source("cases/examples/seed-room.yaml") + "' -o out.h5", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("ceiling") != std::string::npos);
  const fs::path h5 = dir.path / "out.h5";
  REQUIRE(fs::exists(h5));
  for (const auto& e : fs::directory_iterator(dir.path)) CHECK(e.path().string().find(".tmp-") == std::string::npos);

  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  hid_t file = H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(file >= 0);
  struct Expect {
    const char* name;
    std::vector<hsize_t> dims;
    const char* units;
  };
  const std::vector<Expect> layout = {
      {"/nodes/name", {6}, ""},
      {"/nodes/area", {6}, "m^2"},
      {"/network/view_factors", {6, 6}, "1"},
      {"/network/space_view_factor", {6}, "1"},
      {"/network/conductance", {6, 6}, "m^2"},
      {"/eigen/values", {2}, "m^2"},
      {"/eigen/vectors", {6, 2}, "1"},
      {"/solution/exitance", {6}, "W/m^2"},
      {"/meta/case_yaml", {}, ""},
  };
  for (const auto& e : layout) {
    INFO(e.name);
    const H5Data d = readDataset(file, e.name);
    CHECK(d.dims == e.dims);
    CHECK(d.units == e.units);
  }
  const H5Data m = readDataset(file, "/solution/exitance");
  const double paper[6] = {1.2431, 0.3695, 0.3695, 0.3484, 0.3484, 0.1322};
  for (int i = 0; i < 6; ++i) CHECK(std::abs(m.values[static_cast<size_t>(i)] - paper[i]) <= 5e-5);
  // G symmetric as stored (row-major on disk).
  const H5Data g = readDataset(file, "/network/conductance");
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      CHECK(g.values[static_cast<size_t>(i * 6 + j)] == g.values[static_cast<size_t>(j * 6 + i)]);
  CHECK(H5Aexists_by_name(file, "/report", "truncation_residual", H5P_DEFAULT) > 0);
  CHECK(H5Aexists_by_name(file, "/eigen", "rank", H5P_DEFAULT) > 0);
  CHECK(H5Aexists_by_name(file, "/meta", "created_utc", H5P_DEFAULT) > 0);
  H5Fclose(file);
}

TEST_CASE("cli: check passes the shipped examples and fails a wrong expectation with exit 1") {
  TempDir dir;
  const Run ok = runRadnet("check '" + source("cases/examples/seed-room.yaml") + "' '" +
                               source("cases/examples/random-network.yaml") + "' '" +
                               source("cases/examples/parallel-plates.yaml") + "'",
                           dir);
  INFO(ok.out << ok.err);
  CHECK(ok.exit_code == 0);
  CHECK(ok.out.find("FAIL") == std::string::npos);

  std::string text = slurp(source("cases/examples/seed-room.yaml"));
  text.replace(text.find("value: 1.2431"), 13, "value: 1.3431");
  std::ofstream(dir.path / "wrong.yaml") << text;
  const Run bad = runRadnet("check wrong.yaml", dir);
  INFO(bad.out << bad.err);
  CHECK(bad.exit_code == 1);
  CHECK(bad.out.find("FAIL exitance ceiling") != std::string::npos);
}

TEST_CASE("cli: every malformed case exits 2 with file:line:column and writes nothing") {
  const std::regex located(R"(\.yaml:[0-9]+:[0-9]+: )");
  int count = 0;
  for (const auto& entry : fs::directory_iterator(source("tests/data/bad"))) {
    if (entry.path().extension() != ".yaml") continue;  // meshes/ holds the broken mesh files
    TempDir dir;
    const std::string text = slurp(entry.path());
    const std::string expected = text.substr(10, text.find('\n') - 10);  // after "# expect: " on the first line
    const Run r = runRadnet("run '" + entry.path().string() + "' -o out.h5", dir);
    INFO(entry.path().filename().string() << "\nstderr: " << r.err);
    CHECK(r.exit_code == 2);
    CHECK(std::regex_search(r.err, located));
    CHECK(r.err.find(expected) != std::string::npos);
    CHECK(r.err.find(entry.path().filename().string()) != std::string::npos);
    CHECK_FALSE(fs::exists(dir.path / "out.h5"));
    CHECK(std::distance(fs::directory_iterator(dir.path), fs::directory_iterator{}) == 2);  // stdout.txt, stderr.txt
    const Run v = runRadnet("validate '" + entry.path().string() + "'", dir);
    CHECK(v.exit_code == 2);
    ++count;
  }
  CHECK(count >= 40);
}

TEST_CASE("cli: a missing file and bad arguments exit 2, a numerical failure exits 3 with no output") {
  TempDir dir;
  const Run missing = runRadnet("run no-such-case.yaml -o out.h5", dir);
  CHECK(missing.exit_code == 2);
  CHECK(missing.err.find("no-such-case.yaml:0:0: cannot open") != std::string::npos);
  CHECK(runRadnet("frobnicate", dir).exit_code == 2);
  const Run no_dir = runRadnet("run '" + source("cases/examples/seed-room.yaml") + "' -o missing/out.h5", dir);
  CHECK(no_dir.exit_code == 2);
  CHECK(no_dir.err.find("does not exist") != std::string::npos);
  CHECK(runRadnet("run", dir).exit_code == 2);
  const Run bad_seed = runRadnet("run '" + source("cases/examples/seed-room.yaml") + "' -o out.h5 --seed -5", dir);
  CHECK(bad_seed.exit_code == 2);  // refused, not ignored
  CHECK(bad_seed.err.find("a seed is a whole number >= 0") != std::string::npos);
  CHECK_FALSE(fs::exists(dir.path / "out.h5"));

  const Run num = runRadnet("run '" + source("tests/data/numerical/lossless-cavity.yaml") + "' -o out.h5", dir);
  INFO(num.err);
  CHECK(num.exit_code == 3);
  CHECK(num.err.find("numerical failure") != std::string::npos);
  CHECK_FALSE(fs::exists(dir.path / "out.h5"));
}

TEST_CASE("cli: a geometry case writes /geometry, view factors with errors, and closed exchange factors") {
  TempDir dir;
  const Run r = runRadnet("run '" + source("cases/analytic/cube-interior.yaml") + "' -o cube.h5 --threads 1", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.err.find("view factors 100 %") != std::string::npos);  // progress on stderr
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  hid_t file = H5Fopen((dir.path / "cube.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(file >= 0);
  const H5Data v = readDataset(file, "/geometry/vertices");
  const H5Data t = readDataset(file, "/geometry/triangles");
  const H5Data tn = readDataset(file, "/geometry/triangle_node");
  CHECK(v.dims[1] == 3);
  CHECK(v.units == "m");
  CHECK(t.dims == std::vector<hsize_t>{48, 3});  // 6 faces × 2 × 2 cells × 2 triangles
  CHECK(tn.dims == std::vector<hsize_t>{48});
  for (double node : tn.values) CHECK(node >= 0.0);  // inner (back) sides: every triangle has its node
  CHECK(readDataset(file, "/geometry/triangle_front_node").values.front() == -1.0);
  const H5Data f = readDataset(file, "/network/view_factors");
  const H5Data e = readDataset(file, "/network/view_factor_stderr");
  const H5Data gr = readDataset(file, "/network/radiative_exchange");
  const H5Data grs = readDataset(file, "/network/gr_space");
  REQUIRE(f.dims == std::vector<hsize_t>{6, 6});
  CHECK(e.dims == f.dims);
  for (int i = 0; i < 6; ++i) {
    double row = 0.0;
    for (int j = 0; j < 6; ++j) row += f.values[static_cast<size_t>(6 * i + j)];
    CHECK(std::abs(row - 1.0) < 1e-12);                          // closed after the correction
    CHECK(std::abs(grs.values[static_cast<size_t>(i)]) < 1e-9);  // nothing reaches space
    CHECK(e.values[static_cast<size_t>(6 * i + (i ^ 1))] > 0);   // errors reported
  }
  CHECK(gr.units == "m^2");
  const H5Data emis = readDataset(file, "/nodes/emissivity");
  CHECK(emis.values[0] == 0.5);
  H5Fclose(file);
  // Same seed, one thread or two: the same bits.
  const Run r2 = runRadnet("run '" + source("cases/analytic/cube-interior.yaml") + "' -o cube2.h5 --threads 2 -q", dir);
  REQUIRE(r2.exit_code == 0);
  hid_t f2 = H5Fopen((dir.path / "cube2.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  CHECK(readDataset(f2, "/network/view_factors").values == f.values);
  H5Fclose(f2);
}

TEST_CASE("cli: orbit sweep of a Sun-facing plate: absorbed α S A in sunlight, 0 in eclipse, shadowed plate 0") {
  TempDir dir;
  // Body +z points at the Sun; the plate's front faces +z; a second plate sits in the
  // shadow of a black roof (which reflects nothing back). β = 0: the orbit passes through
  // the Earth's shadow.
  std::ofstream(dir.path / "plate.yaml") << R"(name: sun-plate
materials:
  cells: {emissivity: 0.85, absorptivity: 0.92}
  black: {emissivity: 1.0, absorptivity: 1.0}
geometry:
  - rectangle: {name: plate, origin: [0, 0, 0], u: [1, 0, 0], v: [0, 2, 0], front: cells}
  - rectangle: {name: shaded, origin: [5, 0, 0], u: [1, 0, 0], v: [0, 1, 0], front: cells}
  - rectangle: {name: roof, origin: [4.5, -0.5, 1], u: [2, 0, 0], v: [0, 2, 0], back: black}
orbit: {altitude: 600.0e3, beta: 0.0, epoch: 2026-06-21T00:00:00Z, positions: 24}
attitude: {mode: sun}
solver: {view_factors: {rays: 20000}}
)";
  const Run r = runRadnet("run plate.yaml -o plate.h5 -q", dir);
  INFO(r.err << r.out);
  REQUIRE(r.exit_code == 0);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  hid_t file = H5Fopen((dir.path / "plate.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(file >= 0);
  const H5Data solar = readDataset(file, "/loads/solar"), sunlit = readDataset(file, "/orbit/sunlit_fraction");
  const H5Data flux = readDataset(file, "/orbit/solar_flux"), ev = readDataset(file, "/orbit/eclipse_event");
  REQUIRE(solar.dims.size() == 2);
  const size_t P = solar.dims[0], n = solar.dims[1];
  CHECK(n == 3);  // plate, shaded, roof.back (the roof's front names no material)
  CHECK(P == 24 + 4);
  int dark = 0, events = 0;
  for (size_t p = 0; p < P; ++p) {
    const double expected = 0.92 * flux.values[p] * sunlit.values[p] * 2.0;  // α S A × sunlit fraction
    CHECK(solar.values[p * n + 0] == Approx(expected).epsilon(1e-9));
    CHECK(std::abs(solar.values[p * n + 1]) < 1e-9);  // behind the roof: no direct Sun (rounding of the band solve)
    dark += sunlit.values[p] == 0.0;
    events += ev.values[p] == 1.0;
    if (sunlit.values[p] == 0.0) CHECK(std::abs(solar.values[p * n + 0]) < 1e-9);
  }
  CHECK(dark > 0);
  CHECK(events == 4);
  CHECK(readDoubleAttribute(file, "/report", "solar_energy_balance_error") < 1e-12);
  const H5Data tri = readDataset(file, "/geometry/triangles");
  CHECK(tri.dims[1] == 3);
  H5Fclose(file);
}

TEST_CASE("cli: the 3U CubeSat example runs end to end with every orbit dataset") {
  TempDir dir;
  const Run r = runRadnet("run '" + source("cases/examples/cubesat-3u.yaml") + "' -o cubesat.h5 -q", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  hid_t file = H5Fopen((dir.path / "cubesat.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(file >= 0);
  const H5Data t = readDataset(file, "/orbit/time");
  const size_t P = t.dims[0];
  CHECK(P == 72 + 4);
  // 11 surface nodes and 2 lumped ones (electronics, battery), which absorb nothing.
  const H5Data lumped = readDataset(file, "/nodes/lumped");
  REQUIRE(lumped.values.size() == 13);
  for (size_t i = 0; i < 13; ++i) CHECK(lumped.values[i] == (i >= 11 ? 1.0 : 0.0));
  for (const char* name : {"/loads/solar", "/loads/albedo", "/loads/earth_ir", "/solution/exitance_solar"}) {
    INFO(name);
    const H5Data d = readDataset(file, name);
    CHECK(d.dims == std::vector<hsize_t>{P, 13});
    for (size_t k = 0; k < d.values.size(); ++k)
      if (k % 13 >= 11) CHECK(d.values[k] == 0.0);
    for (double v : d.values) CHECK(std::isfinite(v));
    for (double v : d.values) CHECK(v >= -1e-9);
  }
  CHECK(readDataset(file, "/orbit/sun_body").dims == std::vector<hsize_t>{P, 3});
  {  // The orbit as data: a 500 km circular orbit, |r| = a and |v| = √(μ/a) (μ: WGS84's GM;
     // 0.2 % allows J2's mean-motion correction, about 1e-3 at 500 km).
    const H5Data r = readDataset(file, "/orbit/position_eci"), v = readDataset(file, "/orbit/velocity_eci");
    const H5Data a = readDataset(file, "/orbit/semi_major_axis");
    REQUIRE(r.dims == std::vector<hsize_t>{P, 3});
    REQUIRE(v.dims == std::vector<hsize_t>{P, 3});
    CHECK(r.units == "m");
    CHECK(v.units == "m/s");
    for (hsize_t p = 0; p < P; ++p) {
      const double rn = std::hypot(r.values[3 * p], r.values[3 * p + 1], r.values[3 * p + 2]);
      const double vn = std::hypot(v.values[3 * p], v.values[3 * p + 1], v.values[3 * p + 2]);
      CHECK(rn == Approx(a.values[p]).epsilon(1e-6));
      CHECK(a.values[p] == Approx(6378137.0 + 500e3).epsilon(1e-6));
      CHECK(vn == Approx(std::sqrt(3.986004418e14 / a.values[p])).epsilon(2e-3));
    }
    CHECK(readDataset(file, "/orbit/inclination").units == "deg");
  }
  CHECK(readDataset(file, "/orbit/beta").units == "deg");
  const H5Data temp = readDataset(file, "/solution/temperature");  // transient, last of 3 orbits
  CHECK(temp.dims == std::vector<hsize_t>{P, 13});
  CHECK(temp.units == "K");
  for (double v : temp.values) {
    CHECK(v > 150.0);  // a 3U CubeSat in LEO stays between about −120 °C and +130 °C
    CHECK(v < 400.0);
  }
  // The XDMF sidecar refers only to datasets that exist, with the dimensions it states.
  const std::string xmf = slurp(dir.path / "cubesat.xmf");
  REQUIRE_FALSE(xmf.empty());
  const std::regex item(R"re(<DataItem Dimensions="([0-9 ]+)"[^>]*Format="HDF">cubesat\.h5:([^<]+)</DataItem>)re");
  int items = 0;
  for (auto it = std::sregex_iterator(xmf.begin(), xmf.end(), item); it != std::sregex_iterator(); ++it, ++items) {
    const std::string path = (*it)[2];
    INFO(path);
    REQUIRE(H5Lexists(file, path.c_str(), H5P_DEFAULT) > 0);
    std::vector<hsize_t> stated;
    std::istringstream dims((*it)[1]);
    for (hsize_t d; dims >> d;) stated.push_back(d);
    CHECK(readDataset(file, path).dims == stated);
  }
  CHECK(items >= 4 * static_cast<int>(P));
  CHECK(xmf.find("<Time Value=") != std::string::npos);
  H5Fclose(file);
}

TEST_CASE("cli: the larger satellite runs end to end: shapes, closed energy balance, no Sun in umbra") {
  TempDir dir;
  const Run r = runRadnet("run '" + source("cases/examples/satellite.yaml") + "' -o sat.h5 -q", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  hid_t file = H5Fopen((dir.path / "sat.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(file >= 0);
  const H5Data tri = readDataset(file, "/geometry/triangles");
  CHECK(tri.dims[0] > 4000);
  const H5Data solar = readDataset(file, "/loads/solar"), sunlit = readDataset(file, "/orbit/sunlit_fraction");
  const size_t P = solar.dims[0], n = solar.dims[1];
  CHECK(n == 16);
  for (size_t p = 0; p < P; ++p)
    if (sunlit.values[p] == 0.0)
      for (size_t i = 0; i < n; ++i) CHECK(std::abs(solar.values[p * n + i]) < 1e-6);  // no direct Sun in the umbra
  const double balance = readDoubleAttribute(file, "/report", "solar_energy_balance_error");
  CHECK(balance >= 0.0);
  CHECK(balance < 1e-12);  // in = absorbed + lost to space, every position
  H5Fclose(file);
}

TEST_CASE("cli: hot and cold cases in one run: a list of betas and epochs, one orbit case each") {
  TempDir dir;
  std::ofstream(dir.path / "hotcold.yaml") << R"(name: hot-cold
materials:
  cells: {emissivity: 0.85, absorptivity: 0.92}
geometry:
  - rectangle: {name: plate, origin: [0, 0, 0], u: [1, 0, 0], v: [0, 1, 0], front: cells}
orbit: {altitude: 500.0e3, beta: [0.0, 75.0], epoch: [2026-06-21T00:00:00Z, 2026-12-21T00:00:00Z], positions: 24}
attitude: {mode: sun}
thermal: {nodes: {plate: {capacitance: 2000.0}}, transient: {orbits: 2}}
solver: {view_factors: {rays: 2000}}
)";
  const Run r = runRadnet("run hotcold.yaml -o hc.h5 -q", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  hid_t file = H5Fopen((dir.path / "hc.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const H5Data which = readDataset(file, "/orbit/case"), sunlit = readDataset(file, "/orbit/sunlit_fraction");
  const H5Data temp = readDataset(file, "/solution/temperature");
  // 4 cases; β = 0 has an eclipse (4 events), β = 75° is above the critical 68.0° (none).
  REQUIRE(which.dims[0] == 2 * (24 + 4) + 2 * 24);
  CHECK(which.values.front() == 0.0);
  CHECK(which.values.back() == 3.0);
  std::vector<double> coldest(4, 1e9);  // per case, K
  for (size_t p = 0; p < which.values.size(); ++p) {
    const size_t k = static_cast<size_t>(which.values[p]);
    if (k == 1 || k == 3) CHECK(sunlit.values[p] == 1.0);  // β = 75°: always in the Sun
    coldest[k] = std::min(coldest[k], temp.values[p]);
  }
  CHECK(coldest[0] < coldest[1] - 10.0);  // the eclipsing orbit (β = 0) cools down
  CHECK(coldest[2] < coldest[3] - 10.0);
  H5Fclose(file);
}

TEST_CASE("cli: includes of materials and surfaces, errors located in the included file") {
  TempDir dir;
  fs::create_directories(dir.path / "lib" / "parts");
  std::ofstream(dir.path / "lib" / "materials.yaml") << "white: {emissivity: 0.88, absorptivity: 0.2}\n"
                                                        "black: {emissivity: 1.0, absorptivity: 1.0}\n";
  std::ofstream(dir.path / "lib" / "panels.yaml")
      << "- rectangle: {name: a, origin: [0, 0, 0], u: [1, 0, 0], v: [0, 1, 0], front: white}\n"
         "- mesh: {name: m, file: parts/tri.off, front: black}\n";
  std::ofstream(dir.path / "lib" / "parts" / "tri.off") << "OFF\n3 1 0\n0 0 1\n0 1 1\n1 0 1\n3 0 1 2\n";
  std::ofstream(dir.path / "case.yaml") << "name: inc\nmaterials: {include: lib/materials.yaml}\n"
                                           "geometry:\n  - include: lib/panels.yaml\n"
                                           "solver: {view_factors: {rays: 1000}}\n";
  const Run ok = runRadnet("run case.yaml -o inc.h5 -q", dir);
  INFO(ok.err);
  REQUIRE(ok.exit_code == 0);
  hid_t file = H5Fopen((dir.path / "inc.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  CHECK(H5Lexists(file, "/meta/included/0", H5P_DEFAULT) > 0);  // the included files travel with the result
  CHECK(H5Lexists(file, "/meta/included/1", H5P_DEFAULT) > 0);
  H5Fclose(file);
  // An error inside an included file names that file, its line and column.
  std::ofstream(dir.path / "lib" / "panels.yaml")
      << "- rectangle: {name: a, origin: [0, 0, 0], u: [1, 0, 0], v: [0, 1, 0], front: white}\n"
         "- rectangle: {name: b, origin: [0, 0, 1], u: [1, 0, 0], v: [0, 1, 0], front: grey}\n";
  const Run bad = runRadnet("run case.yaml -o bad.h5", dir);
  CHECK(bad.exit_code == 2);
  CHECK(bad.err.find("panels.yaml:2:") != std::string::npos);
  CHECK(bad.err.find("unknown material 'grey'") != std::string::npos);
  CHECK_FALSE(fs::exists(dir.path / "bad.h5"));
}

TEST_CASE("cli: validate accepts the shipped examples") {
  TempDir dir;
  for (const char* ex : {"seed-room", "random-network", "parallel-plates", "cubesat-3u", "satellite"}) {
    const Run r = runRadnet(std::string("validate '") + source("cases/examples/") + ex + ".yaml'", dir);
    INFO(ex << ": " << r.err);
    CHECK(r.exit_code == 0);
  }
}

TEST_CASE("cli: heat flows per node and position close the balance on every case with temperatures") {
  // Every shipped case with temperatures: the CubeSat's periodic transient (stored heat, a
  // heater, shells, schedules), the sunlit plate's steady state (environment loads), the
  // plates between boundary nodes (boundary supply) and the lumped nodes (couplings, MLI).
  for (const char* c : {"examples/cubesat-3u", "analytic/sunlit-plate-temperature",
                        "analytic/parallel-plates-temperature", "analytic/lumped-nodes"}) {
    INFO(c);
    TempDir dir;
    const Run r = runRadnet("run '" + source(std::string("cases/") + c + ".yaml") + "' -o out.h5 -q", dir);
    REQUIRE(r.exit_code == 0);
    hid_t file = H5Fopen((dir.path / "out.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    REQUIRE(file >= 0);
    const H5Data temperature = readDataset(file, "/solution/temperature");
    std::vector<double> sum(temperature.values.size(), 0.0), largest(temperature.values.size(), 0.0);
    for (const char* kind : {"solar", "albedo", "earth_ir", "emitted", "radiative", "conducted", "dissipation",
                             "heater", "stored", "boundary"}) {
      const H5Data d = readDataset(file, std::string("/solution/heat/") + kind);
      CHECK(d.dims == temperature.dims);  // (P, n)
      CHECK(d.units == "W");
      for (size_t k = 0; k < d.values.size() && k < sum.size(); ++k) {
        sum[k] += d.values[k];
        largest[k] = std::max(largest[k], std::abs(d.values[k]));
      }
    }
    // Issue 10's contract: every node and position balances to 1e-6 of its largest term
    // (Newton's tolerance is 1e-9 of the node's scale, so this has three digits to spare).
    for (size_t k = 0; k < sum.size(); ++k) CHECK(std::abs(sum[k]) <= 1e-6 * largest[k] + 1e-12);
    CHECK(readDoubleAttribute(file, "/report", "heat_balance_max_relative_imbalance") <= 1e-6);
    H5Fclose(file);
  }
}
