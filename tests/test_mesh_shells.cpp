// A NASTRAN model's shells from its own cards (issue 29): PSHELL thickness and MAT4 K, CP,
// RHO per PID feed `shell:` where the case leaves them out; checked against 1-D conduction.
#include "cli_support.hpp"

#include <catch2/catch.hpp>

#include <map>
#include <string>

using namespace radnet::test;
using Catch::Contains;

namespace {

// A 1000 × 100 mm strip along x in ten CQUAD4s of 100 mm (EID 1 … 10, normal +z), free field.
// Elements 1–5: PID 10, PSHELL T = 2 mm of MAT4 1 (aluminium: K 167, CP 896, RHO 2700);
// elements 6–10: PID 20, T = 1 mm of MAT4 2 (copper: K 400, CP 385, RHO 8960). `mat4_2`
// replaces MAT4 2's card (for unit-system refusals); `pid20_t` its PSHELL thickness field.
std::string stripBdf(const std::string& mat4_2 = "MAT4,2,400.,385.,8960.", const std::string& pid20_t = "1.0") {
  std::string out = "BEGIN BULK\n";
  for (int i = 0; i <= 10; ++i) {
    out += "GRID," + std::to_string(i + 1) + ",," + std::to_string(100 * i) + ".,0.,0.\n";
    out += "GRID," + std::to_string(i + 12) + ",," + std::to_string(100 * i) + ".,100.,0.\n";
  }
  for (int e = 1; e <= 10; ++e)
    out += "CQUAD4," + std::to_string(e) + "," + (e <= 5 ? "10" : "20") + "," + std::to_string(e) + "," +
           std::to_string(e + 1) + "," + std::to_string(e + 12) + "," + std::to_string(e + 11) + "\n";
  out += "PSHELL,10,1,2.0\nPSHELL,20,2," + pid20_t + "\nMAT4,1,167.,896.,2700.\n" + mat4_2 + "\nENDDATA\n";
  return out;
}

std::string stripCase(const std::string& shell, const std::string& nodes, const std::string& held,
                      const std::string& heated) {
  return R"(name: strip
materials:
  bare: {emissivity: 0.0, absorptivity: 0.0}
  al: {conductivity: 167.0, density: 2700.0, specific_heat: 896.0}
geometry:
  - mesh: {name: s, file: strip.bdf, scale: 0.001, front: bare, nodes: )" +
         nodes + ", shell: " + shell + R"(}
solver: {view_factors: {rays: 200, seed: 1}}
thermal:
  nodes:
    )" + held + R"(: {temperature: 300.0}
    )" + heated + R"(: {dissipation: 1.0}
)";
}

std::map<std::string, double> byName(hid_t file, const std::string& dataset) {
  const std::vector<std::string> names = readNodeNames(file);
  const H5Data d = readDataset(file, dataset);
  std::map<std::string, double> out;
  for (size_t i = 0; i < names.size(); ++i) out[names[i]] = d.values[i];
  return out;
}

}  // namespace

TEST_CASE("NASTRAN shells: PSHELL thickness and MAT4 per PID conduct and store heat as 1-D conduction says") {
  // Per element (nodes: elements) a one-sided plate link k t w / Δx = k t (w = Δx = 0.1 m):
  // 167 · 0.002 = 0.334 W/K within PID 10, 400 · 0.001 = 0.4 W/K within PID 20, and across
  // the PID boundary the two half-cells in series, 0.1 / (0.05 / 0.334 + 0.05 / 0.4). One watt
  // in at element 10, element 1 held at 300 K, no radiation (ε = 0): T_i = 300 K + Σ 1 / G.
  // Tolerance: the chain is exact; Newton's 1e-9 tolerance leaves < 1e-6 K.
  struct Variant {
    const char* shell;
    double kt10, kt20, rho_c10, rho_c20;  // W/K per unit width ratio, J/(m³ K)
  };
  for (const Variant& v : {Variant{"{}", 167 * 0.002, 400 * 0.001, 2700.0 * 896, 8960.0 * 385},
                           Variant{"{material: al}", 167 * 0.002, 167 * 0.001, 2700.0 * 896, 2700.0 * 896}}) {
    INFO(v.shell);
    TempDir dir;
    dir.write("strip.bdf", stripBdf());
    dir.write("case.yaml", stripCase(v.shell, "elements", "s.1", "s.10"));
    const Run run = runRadnet("run case.yaml -o out.h5", dir);
    INFO(run.err);
    REQUIRE(run.exit_code == 0);
    const hid_t file = H5Fopen((dir.path / "out.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const auto t = byName(file, "/solution/temperature");
    const auto c = byName(file, "/nodes/capacitance");
    H5Fclose(file);
    double expected = 300.0;
    for (int e = 1; e <= 10; ++e) {
      const std::string node = "s." + std::to_string(e);
      REQUIRE(t.count(node));
      CHECK(t.at(node) == Approx(expected).margin(1e-6));
      // ρ c t A of the 0.01 m² element
      const double capacitance = e <= 5 ? v.rho_c10 * 0.002 * 0.01 : v.rho_c20 * 0.001 * 0.01;
      CHECK(c.at(node) == Approx(capacitance).epsilon(1e-12));
      const double g = e < 5 ? v.kt10 : e == 5 ? 0.1 / (0.05 / v.kt10 + 0.05 / v.kt20) : v.kt20;
      expected += 1.0 / g;
    }
  }
}

TEST_CASE("NASTRAN shells per PID (nodes: groups): two half-strips joined in series") {
  // Node s.10 (centroid x = 0.25 m) and s.20 (x = 0.75 m) meet along 0.1 m at x = 0.5 m:
  // G = 0.1 / (0.25 / 0.334 + 0.25 / 0.4); s.10 held at 300 K, 1 W into s.20.
  TempDir dir;
  dir.write("strip.bdf", stripBdf());
  dir.write("case.yaml", stripCase("{}", "groups", "s.10", "s.20"));
  const Run run = runRadnet("run case.yaml -o out.h5", dir);
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  const hid_t file = H5Fopen((dir.path / "out.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const auto t = byName(file, "/solution/temperature");
  H5Fclose(file);
  CHECK(t.at("s.20") == Approx(300.0 + (0.25 / 0.334 + 0.25 / 0.4) / 0.1).margin(1e-6));
}

TEST_CASE("NASTRAN shells: what the file lacks, or gives in another unit system, is refused at the shell") {
  TempDir dir;
  const auto refused = [&](const std::string& bdf, const std::string& shell, const std::string& nodes) {
    dir.write("strip.bdf", bdf);
    dir.write("case.yaml", stripCase(shell, nodes, "s.1", "s.10"));
    return runRadnet("run case.yaml -o out.h5", dir);
  };
  // PID 20's PSHELL has no thickness.
  Run r = refused(stripBdf("MAT4,2,400.,385.,8960.", ""), "{}", "elements");
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("case.yaml:") && Contains("shell.thickness: not given") && Contains("PID 20"));
  // MAT4 2 in mm-tonne-s (RHO in t/mm³): not a density in kg/m³.
  r = refused(stripBdf("MAT4,2,400.,3.85e8,8.96e-9"), "{}", "elements");
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("PID 20 (MAT4 2) has RHO = 8.96e-09") && Contains("give shell.material"));
  // MAT4 2 without CP and RHO, no material in the case.
  r = refused(stripBdf("MAT4,2,400."), "{thickness: 0.001}", "elements");
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("shell.material: not given") && Contains("PID 20"));
  // nodes: single merges PIDs of different thickness: no one value to take.
  r = refused(stripBdf(), "{}", "single");
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Contains("the PIDs merged by nodes: single"));
  CHECK_FALSE(std::filesystem::exists(dir.path / "out.h5"));
}
