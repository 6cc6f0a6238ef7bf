// The reported uncertainty against the error it claims to bound: each case is run at the
// default error budget (and few view-factor rays, so that their noise shows) and again as
// a reference with hundreds of times the rays, shadows by the second method (each node's
// own shadow rays instead of the grid) and another seed. The difference of the two must lie
// within 2 σ (both runs' σ combined) for ≥ 90 % of the (node, position) pairs, as a normal
// error would for 95 %; and σ must not be so wide that it says nothing.
#include "cli_support.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <regex>

using namespace radnet::test;

namespace {

struct Coverage {
  int pairs = 0, within_2 = 0, within_half = 0;
};

// A shipped example with fewer positions and the given solver and environment lines.
std::string variant(const std::string& example, const std::string& vf, const std::string& env) {
  std::string text = slurp(source("cases/examples/" + example));
  text = std::regex_replace(text, std::regex("positions: 72"), "positions: 12");
  text = std::regex_replace(text, std::regex("  view_factors: \\{[^}]*\\}"), "  view_factors: " + vf);
  text = std::regex_replace(text, std::regex("environment: \\{"), "environment: {" + env);
  return text;
}

std::vector<double> absorbed(hid_t f) {
  std::vector<double> q = readDataset(f, "/loads/solar").values;
  const std::vector<double> a = readDataset(f, "/loads/albedo").values, e = readDataset(f, "/loads/earth_ir").values;
  for (size_t k = 0; k < q.size(); ++k) q[k] += a[k] + e[k];
  return q;
}

Coverage compare(const std::string& example, const std::string& vf_test, const std::string& vf_ref,
                 const std::string& dataset, const std::string& sigma_dataset, const std::string& attitude = "") {
  TempDir dir;
  std::filesystem::create_directories(dir.path / "materials");
  dir.write("materials/common.yaml", slurp(source("cases/examples/materials/common.yaml")));
  const auto turned = [&](std::string text) {
    return attitude.empty() ? text : std::regex_replace(text, std::regex("attitude: \\{mode: nadir\\}"), attitude);
  };
  dir.write("test.yaml", turned(variant(example, vf_test, "")));
  dir.write("ref.yaml", turned(variant(example, vf_ref, "shadow_samples: 16384, planet_rays: 131072, ")));
  REQUIRE(runRadnet("run test.yaml -o test.h5", dir).exit_code == 0);
  REQUIRE(runRadnet("run ref.yaml -o ref.h5", dir).exit_code == 0);
  const hid_t t = H5Fopen((dir.path / "test.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t r = H5Fopen((dir.path / "ref.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const std::vector<double> qt = dataset.empty() ? absorbed(t) : readDataset(t, dataset).values;
  const std::vector<double> qr = dataset.empty() ? absorbed(r) : readDataset(r, dataset).values;
  const std::vector<double> st = readDataset(t, sigma_dataset).values, sr = readDataset(r, sigma_dataset).values;
  H5Fclose(t);
  H5Fclose(r);
  Coverage c;
  for (size_t k = 0; k < qt.size(); ++k) {
    if (qt[k] == 0 && qr[k] == 0) continue;  // lumped nodes, nodes that never absorb
    const double sigma = std::hypot(st[k], sr[k]), err = std::abs(qt[k] - qr[k]);
    // 1e-9 relative: round-off of exact parts (a fully lit node's direct load has σ = 0).
    const double slack = 1e-9 * std::abs(qr[k]);
    ++c.pairs;
    c.within_2 += err <= 2 * sigma + slack;
    c.within_half += err <= 0.5 * sigma + slack;
  }
  return c;
}

void checkCoverage(const Coverage& c) {
  INFO(c.pairs << " pairs: " << c.within_2 << " within 2σ, " << c.within_half << " within σ/2");
  REQUIRE(c.pairs > 50);
  CHECK(c.within_2 >= 0.90 * c.pairs);
  // A normal error lies within σ/2 38 % of the time: far more says σ is inflated. The
  // exact parts (unshadowed direct Sun) agree to round-off, so allow up to 90 %.
  CHECK(c.within_half <= 0.90 * c.pairs);
}

}  // namespace

TEST_CASE("uncertainty: the CubeSat's absorbed power lies within its reported 2σ of a high-ray reference") {
  checkCoverage(compare("cubesat-3u.yaml", "{method: monte_carlo, rays: 4000, seed: 1}",
                        "{method: monte_carlo, rays: 1000000, seed: 7}", "", "/uncertainty/absorbed_power"));
}

TEST_CASE("uncertainty: the satellite (mast, dish and wings shadowing each other) within its 2σ") {
  checkCoverage(compare("satellite.yaml", "{method: monte_carlo, rays: 4000, seed: 1}",
                        "{method: monte_carlo, rays: 400000, seed: 7}", "", "/uncertainty/absorbed_power"));
}

TEST_CASE("uncertainty: the Sun-pointing satellite's sky-kernel loads within 2σ of 131,072 planet rays a node") {
  // The kernel's targets are shares of each node's absorbed power (direct sunlight
  // included, orbits/sky_loads.hpp): what it reports must still cover its error, against
  // the second method (planet rays into the cone, cast at every position).
  checkCoverage(compare("satellite.yaml", "{method: monte_carlo, rays: 4000, seed: 1}",
                        "{method: monte_carlo, rays: 400000, seed: 7}", "", "/uncertainty/absorbed_power",
                        "attitude: {mode: sun}"));
}

TEST_CASE("error budget: design cases that reuse the kernel's loads under other optics stay within the loads' share") {
  // The hot case reuses the cold case's irradiances scaled (same orbit and attitude) under
  // end-of-life optics: the kernel's targets take every optical set's α/ε and the cases'
  // scale factors, so neither case's loads exceed their share of the budget.
  TempDir dir;
  std::filesystem::create_directories(dir.path / "materials");
  dir.write("materials/common.yaml", slurp(source("cases/examples/materials/common.yaml")));
  std::string text = variant("satellite.yaml", "{method: monte_carlo, rays: 4000, seed: 1}", "");
  text = std::regex_replace(text, std::regex("attitude: \\{mode: nadir\\}"), "attitude: {mode: inertial, quaternion: [1, 0, 0, 0]}");
  text += "optics:\n  eol: {white_paint: {absorptivity: 0.45}, solar_cell: {absorptivity: 0.94, emissivity: 0.80}}\n"
          "cases:\n  cold: {environment: {solar_constant: 1322, albedo: 0.25, earth_ir: 218}}\n"
          "  hot: {environment: {solar_constant: 1414, albedo: 0.35, earth_ir: 258}, optics: eol}\n";
  dir.write("cases.yaml", text);
  const Run run = runRadnet("run cases.yaml -o cases.h5", dir);
  REQUIRE(run.exit_code == 0);
  CHECK(run.err.find("no rays cast") != std::string::npos);  // the hot case did reuse the loads
  const hid_t f = H5Fopen((dir.path / "cases.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const double loads = readDoubleAttribute(f, "/report", "absorbed_uncertainty_loads_max_relative");
  const double share = readDoubleAttribute(f, "/report", "budget_load_relative_error");
  const double over = readDoubleAttribute(f, "/report", "nodes_over_budget");
  H5Fclose(f);
  CHECK(loads > 0);
  CHECK(loads <= share);
  CHECK(over == 0);
}

TEST_CASE("uncertainty: the CubeSat's temperatures lie within their reported 2σ of the reference's") {
  checkCoverage(compare("cubesat-3u.yaml", "{method: monte_carlo, rays: 4000, seed: 1}",
                        "{method: monte_carlo, rays: 1000000, seed: 7}", "/solution/temperature",
                        "/uncertainty/temperature"));
}

TEST_CASE("error budget: solver.accuracy sets the shares, a tighter one buys a smaller reported σ, too few rays warn") {
  TempDir dir;
  std::filesystem::create_directories(dir.path / "materials");
  dir.write("materials/common.yaml", slurp(source("cases/examples/materials/common.yaml")));
  auto withAccuracy = [](std::string text, const std::string& accuracy) {
    return std::regex_replace(text, std::regex("\nsolver:\n"), "\nsolver:\n  accuracy: " + accuracy + "\n");
  };
  const std::string base = variant("cubesat-3u.yaml", "{method: monte_carlo, seed: 1}", "");
  dir.write("loose.yaml", withAccuracy(base, "0.05"));
  dir.write("tight.yaml", withAccuracy(base, "0.002"));
  dir.write("few.yaml", variant("cubesat-3u.yaml", "{method: monte_carlo, rays: 4000, seed: 1}", "planet_rays: 64, "));
  REQUIRE(runRadnet("run loose.yaml -o loose.h5", dir).exit_code == 0);
  REQUIRE(runRadnet("run tight.yaml -o tight.h5", dir).exit_code == 0);
  const Run few = runRadnet("run few.yaml -o few.h5", dir);
  REQUIRE(few.exit_code == 0);
  auto report = [&](const char* file, const char* name) {
    const hid_t f = H5Fopen((dir.path / file).c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const double v = readDoubleAttribute(f, "/report", name);
    H5Fclose(f);
    return v;
  };
  for (const auto& [file, accuracy] : {std::pair{"loose.h5", 0.05}, std::pair{"tight.h5", 0.002}}) {
    CHECK(report(file, "accuracy") == accuracy);
    CHECK(report(file, "budget_load_relative_error") == Approx(accuracy / 2));
    CHECK(report(file, "budget_view_factor_target_error") == Approx(accuracy / 10));
    CHECK(report(file, "budget_solver_tolerance") <= accuracy / 10);
    CHECK(report(file, "budget_solver_tolerance") >= 1e-10);
    CHECK(report(file, "absorbed_uncertainty_max_relative") <= accuracy);  // met on this small case
  }
  CHECK(report("tight.h5", "planet_rays") > report("loose.h5", "planet_rays"));
  CHECK(report("tight.h5", "absorbed_uncertainty_max_relative") < report("loose.h5", "absorbed_uncertainty_max_relative"));
  // 64 planet rays per node, pinned: the run still answers, and says it missed the budget.
  CHECK(report("few.h5", "nodes_over_budget") > 0);
  CHECK(few.err.find("uncertain by more than solver.accuracy") != std::string::npos);
}

TEST_CASE("uncertainty: a truncated rank's temperature error is covered (band and GR truncation in σ_T)") {
  // Same case, seeds and rays; one run at rank 2 (band answers and GR from 2 pairs), one at
  // the budget's rank (exact GR). Their difference is the truncation alone. Of the 112
  // pairs it moves by more than 0.05 K, 75 % were within 2σ without its two terms in σ_T
  // (the absorbed power's truncation part, GR's probe error), 94 % with the first alone,
  // 100 % with both; ≥ 90 % is asked (this CubeSat cannot single out the GR term).
  TempDir dir;
  std::filesystem::create_directories(dir.path / "materials");
  dir.write("materials/common.yaml", slurp(source("cases/examples/materials/common.yaml")));
  const std::string text = variant("cubesat-3u.yaml", "{rays: 50000, seed: 1}", "");
  dir.write("exact.yaml", text);
  dir.write("rank2.yaml", std::regex_replace(text, std::regex("\nsolver:\n"), "\nsolver:\n  rank: 2\n"));
  REQUIRE(runRadnet("run exact.yaml -o exact.h5", dir).exit_code == 0);
  const Run low = runRadnet("run rank2.yaml -o rank2.h5", dir);
  REQUIRE(low.exit_code == 0);
  CHECK(low.err.find("solver.rank = 2 leaves the exchange factors GR off") != std::string::npos);
  const hid_t e = H5Fopen((dir.path / "exact.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t r = H5Fopen((dir.path / "rank2.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const std::vector<double> te = readDataset(e, "/solution/temperature").values;
  const std::vector<double> tr = readDataset(r, "/solution/temperature").values;
  const std::vector<double> sr = readDataset(r, "/uncertainty/temperature").values;
  H5Fclose(e);
  H5Fclose(r);
  int moved = 0, covered = 0;
  for (size_t k = 0; k < te.size(); ++k) {
    const double err = std::abs(tr[k] - te[k]);
    if (err <= 0.05) continue;
    ++moved;
    covered += err <= 2 * sr[k];
  }
  INFO(moved << " pairs moved by more than 0.05 K, " << covered << " within 2σ");
  REQUIRE(moved >= 30);
  CHECK(covered >= 0.9 * moved);
}
