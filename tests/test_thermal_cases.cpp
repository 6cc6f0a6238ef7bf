// The thermal model through case files and the executable (issue 10's keys and HDF5 names),
// against closed forms: shells against 1-D conduction, a thermostat against its analytic
// cycle, schedules against the orbit's sunlit fraction, occluders, undetermined nodes.
#include "cli_support.hpp"

#include <catch2/catch.hpp>

#include <algorithm>

#include <cmath>
#include <string>
#include <vector>

using namespace radnet::test;

namespace {

// Runs `yaml` (written into dir as case.yaml) and opens the result, or fails the test.
hid_t runAndOpen(const TempDir& dir, const std::string& yaml) {
  dir.write("case.yaml", yaml);
  const Run r = runRadnet("run case.yaml -o out.h5 -q", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const hid_t file = H5Fopen((dir.path / "out.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(file >= 0);
  return file;
}

// Index of `name` in /nodes/name.
int nodeIndex(hid_t file, const std::string& name) {
  const std::vector<std::string> names = readNodeNames(file);
  const auto it = std::find(names.begin(), names.end(), name);
  REQUIRE(it != names.end());
  return static_cast<int>(it - names.begin());
}

const char* kStrip = R"(
name: strip
materials:
  bare: {emissivity: 0.0, absorptivity: 0.0}
  al: {conductivity: 167.0, density: 2700.0, specific_heat: 896.0}
geometry:
  - rectangle: {name: strip, origin: [0, 0, 0], u: [1, 0, 0], v: [0, 0.1, 0], front: bare, BACK
                nodes: [10, 1], subdivisions: [20, 2], shell: {material: al, thickness: 0.002}}
solver: {view_factors: {rays: 200, seed: 1}}
thermal:
  nodes:
    strip.0.0: {temperature: 300.0}
    strip.9.0: {dissipation: 1.0}
)";

}  // namespace

TEST_CASE("shell: a strip with one end held and heat put in at the other follows 1-D conduction") {
  // 1 m × 0.1 m, 2 mm aluminium in 10 nodes: G = k t w / Δx = 167 · 0.002 · 0.1 / 0.1 = 0.334 W/K
  // between neighbours, so T_i = 300 K + i · 1 W / 0.334 W/K (no radiation: ε = 0).
  for (const bool two_sided : {false, true}) {
    INFO((two_sided ? "two-sided" : "one-sided"));
    TempDir dir;
    std::string yaml = kStrip;
    yaml.replace(yaml.find("BACK"), 4, two_sided ? "back: bare," : "");
    const hid_t file = runAndOpen(dir, yaml);
    const H5Data t = readDataset(file, "/solution/temperature");
    const H5Data c = readDataset(file, "/nodes/capacitance");
    // ρ c t A of each 0.01 m² cell, half on each side of a two-sided strip.
    const double cell_capacitance = 2700.0 * 896.0 * 0.002 * 0.01;
    for (int i = 0; i < 10; ++i) {
      const std::string front = "strip." + std::to_string(i) + ".0";
      const double exact = 300.0 + i / 0.334;
      // One-sided: the discrete chain is exact; Newton's 1e-9 tolerance leaves < 1e-6 K.
      // Two-sided: each side carries half the plate (k t/2 L/d) and the heat crosses the
      // thickness through k A / t = 835 W/K per cell, 5000× the in-plane link: within 1e-3 K
      // (measured 6e-4 K, the two crossings at the ends).
      const double tol = two_sided ? 1e-3 : 1e-6;
      CHECK(t.values[static_cast<size_t>(nodeIndex(file, front))] == Approx(exact).margin(tol));
      CHECK(c.values[static_cast<size_t>(nodeIndex(file, front))] ==
            Approx(two_sided ? 0.5 * cell_capacitance : cell_capacitance).epsilon(1e-12));
      if (two_sided) {
        CHECK(t.values[static_cast<size_t>(nodeIndex(file, front + ".back"))] == Approx(exact).margin(tol));
        CHECK(c.values[static_cast<size_t>(nodeIndex(file, front + ".back"))] ==
              Approx(0.5 * cell_capacitance).epsilon(1e-12));
      }
    }
    H5Fclose(file);
  }
}

TEST_CASE("thermostat without an orbit: a battery heater cycles in its dead band with the analytic on-time") {
  // C = 1000 J/K on 1 W/K to a 250 K wall; 50 W heater on below 278.15 K, off above 283.15 K;
  // from 280.65 K (heater off). τ = 1000 s; off phases decay to 250 K, on phases to 300 K.
  TempDir dir;
  const hid_t file = runAndOpen(dir, R"(
name: thermostat
network:
  nodes:
    - {name: wall, area: 1.0, emissivity: 0.0}
  view_factors: [[0.0]]
thermal:
  nodes:
    wall: {temperature: 250.0}
  lumped:
    battery: {capacitance: 1000.0, initial_temperature: 280.65}
  conductors: [[battery, wall, 1.0]]
  heaters:
    - {name: bat_heater, node: battery, power: 50.0, on_below: 278.15, off_above: 283.15}
  transient: {duration: 20000.0, time_step: 10.0, output_step: 10.0}
)");
  // Closed form of the switching times, and the time on within [0, 20000 s].
  const double duration = 20000.0, tau = 1000.0;
  const double t_on = tau * std::log(21.85 / 16.85), t_off = tau * std::log(33.15 / 28.15);
  double clock = tau * std::log(30.65 / 28.15), on_time = 0.0;  // first cooling to 278.15 K
  for (bool on = true; clock < duration; on = !on) {
    const double phase = std::min(on ? t_on : t_off, duration - clock);
    if (on) on_time += phase;
    clock += phase;
  }
  const H5Data duty = readDataset(file, "/heaters/duty");
  REQUIRE(duty.values.size() == 1);
  // Switching located to 1e-3 K (0.05 s at 0.02 K/s) and BDF2's O(h²) error: within 1e-3.
  CHECK(duty.values[0] == Approx(on_time / duration).margin(1e-3));
  const H5Data time = readDataset(file, "/solution/time");
  CHECK(time.values.size() == 2001);
  CHECK(time.values.back() == 20000.0);
  const H5Data t = readDataset(file, "/solution/temperature");  // (P, 2): wall, battery
  const H5Data power = readDataset(file, "/heaters/power");       // (P, 1)
  const H5Data heater = readDataset(file, "/solution/heat/heater");
  for (size_t p = 0; p < time.values.size(); ++p) {
    CHECK(t.values[2 * p + 1] > 278.15 - 2e-3);
    CHECK(t.values[2 * p + 1] < 283.15 + 2e-3);
    CHECK((power.values[p] == 0.0 || power.values[p] == 50.0));
    CHECK(heater.values[2 * p + 1] == power.values[p]);
  }
  CHECK(readDoubleAttribute(file, "/report", "heat_balance_max_relative_imbalance") <= 1e-6);
  H5Fclose(file);
}

TEST_CASE("schedules on an orbit: an illumination schedule and a time table appear in /solution/heat/dissipation") {
  TempDir dir;
  const hid_t file = runAndOpen(dir, R"(
name: schedules
materials:
  black: {emissivity: 0.9, absorptivity: 0.9}
geometry:
  - rectangle: {name: radiator, origin: [0, 0, 0], u: [0.5, 0, 0], v: [0, 0.5, 0], front: black}
orbit: {altitude: 500.0e3, beta: 0.0, epoch: 2026-03-20T00:00:00Z, positions: 36}
attitude: {mode: nadir}
solver: {view_factors: {rays: 1000, seed: 1}}
thermal:
  nodes:
    radiator: {capacitance: 2000.0}
  lumped:
    payload: {capacitance: 1200.0, dissipation: {sunlit: 10.0, eclipse: 2.0}}
    radio: {capacitance: 300.0, dissipation: {table: [[0, 5.0], [600, 20.0], [900, 5.0]]}}
  conductors: [[radiator, payload, 0.5], [radiator, radio, 0.5]]
  transient: {orbits: 2, time_step: 10.0}
)");
  const H5Data sunlit = readDataset(file, "/orbit/sunlit_fraction");
  const H5Data time = readDataset(file, "/orbit/time");
  const H5Data period = readDataset(file, "/orbit/period");
  const H5Data dissipation = readDataset(file, "/solution/heat/dissipation");  // (P, 3)
  REQUIRE(period.values.size() == 1);
  const size_t P = time.values.size();
  REQUIRE(dissipation.values.size() == 3 * P);
  int dark = 0, radio_high = 0;
  for (size_t p = 0; p < P; ++p) {
    // At an output time the step that ends there has the sunlit fraction of that time.
    CHECK(dissipation.values[3 * p + 1] == Approx(2.0 + 8.0 * sunlit.values[p]).margin(1e-12));
    const double tau = std::fmod(time.values[p], period.values[0]);
    CHECK(dissipation.values[3 * p + 2] == (tau > 600.0 && tau <= 900.0 ? 20.0 : 5.0));
    dark += sunlit.values[p] == 0.0;
    radio_high += dissipation.values[3 * p + 2] == 20.0;
  }
  CHECK(dark > 5);  // β = 0 at 500 km: 36 % of the orbit in umbra
  CHECK(radio_high >= 2);
  CHECK(readDoubleAttribute(file, "/report", "heat_balance_max_relative_imbalance") <= 1e-6);
  H5Fclose(file);
}

TEST_CASE("periodic transient on the CubeSat: converges within max_orbits, with its heater's duty") {
  TempDir dir;
  const Run r = runRadnet("run '" + source("cases/examples/cubesat-3u.yaml") + "' -o out.h5", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("heater battery_heater: duty") != std::string::npos);
  const hid_t file = H5Fopen((dir.path / "out.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(file >= 0);
  const double orbits = readDoubleAttribute(file, "/solution/temperature", "orbits");
  CHECK(orbits >= 2);
  CHECK(orbits <= 60);
  CHECK(readDoubleAttribute(file, "/solution/temperature", "periodic_residual") <= 0.01);
  CHECK(readStringAttribute(file, "/solution/temperature", "kind") == "periodic transient");
  const H5Data duty = readDataset(file, "/heaters/duty");
  REQUIRE(duty.values.size() == 1);
  CHECK(duty.values[0] > 0.0);
  CHECK(duty.values[0] < 1.0);
  const H5Data power = readDataset(file, "/heaters/power");
  for (double w : power.values) CHECK((w == 0.0 || w == 3.0));
  const H5Data lumped = readDataset(file, "/nodes/lumped");
  CHECK(lumped.values.back() == 1.0);
  H5Fclose(file);
}

// Unit squares 1 m apart with a centred 0.5 m square halfway between that is no node.
const char* const kBlockedSquares = R"(
materials:
  black: {emissivity: 1.0, absorptivity: 1.0}
geometry:
  - rectangle: {name: a, origin: [0, 0, 0], u: [1, 0, 0], v: [0, 1, 0], front: black}
  - rectangle: {name: b, origin: [0, 0, 1], u: [0, 1, 0], v: [1, 0, 0], front: black}
  - rectangle: {name: shade, origin: [0.25, 0.25, 0.5], u: [0.5, 0, 0], v: [0, 0.5, 0]}
)";

TEST_CASE("occluder: a surface naming no material blocks rays and belongs to no node") {
  // Unit squares 1 m apart with a centred 0.5 m square halfway between that is no node.
  // Unoccluded F = 0.199825 (Howell C-11); with the blocker 0.0995063 (View3D, 1e-8).
  TempDir dir;
  const hid_t file =
      runAndOpen(dir, std::string("name: occluder\n") + kBlockedSquares + "solver: {view_factors: {rays: 400000, seed: 3}}\n");
  const H5Data f = readDataset(file, "/network/view_factors");
  const H5Data raw = readDataset(file, "/network/view_factors_raw");
  const H5Data se = readDataset(file, "/network/view_factor_stderr");
  const H5Data blocked = readDataset(file, "/network/blocked_view_factor");
  const H5Data tri = readDataset(file, "/geometry/triangle_node");
  REQUIRE(f.values.size() == 4);  // two nodes: the shade is none
  // 3.29 σ: the t(31) 99.73 % quantile of the 32-replica estimate.
  CHECK(std::abs(raw.values[1] - 0.0995063) <= 3.29 * se.values[1]);
  CHECK(blocked.values[0] > 0.0);
  int no_node = 0;
  for (double v : tri.values) no_node += v == -1.0;
  CHECK(no_node == 2);  // the shade's two triangles
  H5Fclose(file);
}

TEST_CASE("undetermined temperatures exit 3 naming the node, a stiff shell panel converges") {
  TempDir dir;
  dir.write("loose.yaml", R"(
name: loose
network:
  nodes:
    - {name: plate, area: 1.0, emissivity: 1.0}
    - {name: shiny, area: 1.0, emissivity: 0.0}
  view_factors: [[0.0, 0.0], [0.0, 0.0]]
thermal:
  lumped:
    box: {capacitance: 100.0, dissipation: 5.0}
  nodes:
    shiny: {dissipation: 1.0}
)");
  const Run r = runRadnet("run loose.yaml -o out.h5", dir);
  CHECK(r.exit_code == 3);
  CHECK(r.err.find("undetermined") != std::string::npos);
  CHECK(r.err.find("'shiny'") != std::string::npos);
  CHECK(r.err.find("'box'") != std::string::npos);
  CHECK(r.err.find("'plate'") == std::string::npos);
  CHECK_FALSE(fs::exists(dir.path / "out.h5"));
}

TEST_CASE("suspicious thermal input is run but warned about: a shell torn by a T-junction, a set point in °C") {
  TempDir dir;
  // Two OBJ groups meeting along x = 1, the right one split at (1, 0.5): no edge coincides.
  dir.write("t.obj",
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nv 1 0.5 0\n"
            "g left\nf 1 2 3\nf 1 3 4\ng right\nf 2 5 7\nf 7 5 6\nf 7 6 3\n");
  dir.write("case.yaml", R"(
name: suspicious
materials:
  black: {emissivity: 0.9, absorptivity: 0.9}
  al: {conductivity: 167.0, density: 2700.0, specific_heat: 896.0}
geometry:
  - mesh: {name: m, file: t.obj, groups: true, front: black, shell: {material: al, thickness: 0.002}}
solver: {view_factors: {rays: 500, seed: 1}}
thermal:
  heaters: [{name: h, node: m.left, power: 5.0, on_below: 5.0, off_above: 10.0}]
)");
  const Run r = runRadnet("run case.yaml -o out.h5", dir);
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(r.err.find("warning: geometry[0].mesh.shell: the front nodes fall into 2 pieces") != std::string::npos);
  CHECK(r.err.find(": thermal.heaters[0].on_below: 5 K is below 100 K") != std::string::npos);
}

TEST_CASE("view-factor methods end to end: auto and exact integrate the blocked squares, monte_carlo casts") {
  // The case of the occluder test above; View3D's F = 0.0995063 (7 digits).
  const std::string body = kBlockedSquares;
  for (const std::string method : {"auto", "exact", "contour", "monte_carlo"}) {
    TempDir dir;
    // Each method takes the keys that act on it: rays where rows are cast, a tolerance where
    // pairs are integrated (the others are refused: tests/data/bad).
    const std::string keys = method == "monte_carlo" ? "rays: 100000"
                             : method == "auto"      ? "rays: 100000, tolerance: 1.0e-7"
                                                     : "tolerance: 1.0e-7";
    const hid_t file = runAndOpen(dir, "name: methods\n" + body + "solver: {view_factors: {method: " + method + ", " +
                                           keys + "}}\n");
    INFO(method);
    const H5Data raw = readDataset(file, "/network/view_factors_raw");
    const H5Data se = readDataset(file, "/network/view_factor_stderr");
    const std::string written = readStringAttribute(file, "/network", "method");
    if (method == "monte_carlo") {
      CHECK(written == "monte_carlo");
      CHECK(readDoubleAttribute(file, "/network", "rays_total") > 0);
      CHECK(std::abs(raw.values[1] - 0.0995063) <= 3.29 * se.values[1]);  // t(31) 99.73 %
    } else {
      CHECK(written == (method == "auto" ? "auto" : "exact"));
      CHECK(readDoubleAttribute(file, "/network", "exact_pairs_occluded") == 1.0);
      CHECK(readDoubleAttribute(file, "/network", "rows_sampled") == 0.0);
      CHECK(std::abs(raw.values[1] - 0.0995063) <= 1e-7 + 5e-8);  // tolerance + the reference's rounding
      CHECK(se.values[1] <= 1e-7);
    }
    H5Fclose(file);
  }
}

namespace {

// A 10 cm plate in orbit and a lumped battery with a 3 W heater (5 K band, 300 J/K) on a 260 K
// wall: the plate's entry, the conductors, whether the heater is there, the transient.
std::string batteryOnPlate(const std::string& plate, const std::string& conductors, bool heater,
                           const std::string& transient) {
  std::string text = R"(name: battery-heater
materials:
  white: {emissivity: 0.88, absorptivity: 0.2}
geometry:
  - rectangle: {name: plate, origin: [0, 0, 0], u: [0.1, 0, 0], v: [0, 0.1, 0], front: white}
orbit: {altitude: 500.0e3, inclination: 51.6, positions: 36}
thermal:
  nodes:
    plate: )" + plate + R"(
  lumped:
    wall: {temperature: 260.0}
    battery: {capacitance: 300.0, initial_temperature: 280.0}
  conductors: )" + conductors + "\n";
  if (heater)
    text += "  heaters:\n    - {name: battery_heater, node: battery, power: 3.0, on_below: 273.15, off_above: 278.15}\n";
  return text + "  transient: " + transient + "\n";
}

const char* kPeriodic = "{periodic: true, periodic_tolerance: 0.01, max_orbits: 40, time_step: 10.0}";

}  // namespace

TEST_CASE("a thermostat cycling on its own period, not locked to the orbit: the last orbit with a warning") {
  // The battery (300 J/K, 0.05 W/K to a 260 K wall, 3 W heater with a 5 K band) cycles every
  // ~2,700 s whatever the orbit (~5,700 s) does: no periodic state exists, and the run ended
  // with exit 3 after max_orbits. Now the last orbit is reported with a warning; the plate,
  // which the cycle does not touch, must still be at its own periodic state (the same case
  // without the heater, which converges, is the second method), and the battery in its band.
  const auto variant = [](const std::string& plate, const std::string& conductors, bool heater) {
    return batteryOnPlate(plate, conductors, heater, kPeriodic);
  };
  TempDir dir;
  dir.write("case.yaml", variant("{capacitance: 50.0}", "[[battery, wall, 0.05]]", true));
  const Run run = runRadnet("run case.yaml -o out.h5", dir);
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.err, Catch::Contains("not locked to the orbit"));
  const hid_t file = H5Fopen((dir.path / "out.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(file >= 0);
  const int plate = nodeIndex(file, "plate"), battery = nodeIndex(file, "battery");
  const H5Data t = readDataset(file, "/solution/temperature");  // (P, n)
  const size_t n = t.dims[1];
  H5Fclose(file);
  for (size_t p = 0; p < t.dims[0]; ++p) {  // switching located to 1e-3 K
    CHECK(t.values[p * n + battery] > 273.15 - 2e-3);
    CHECK(t.values[p * n + battery] < 278.15 + 2e-3);
  }
  TempDir alone;
  const hid_t reference = runAndOpen(alone, variant("{capacitance: 50.0}", "[[battery, wall, 0.05]]", false));
  const H5Data t_ref = readDataset(reference, "/solution/temperature");
  H5Fclose(reference);
  REQUIRE(t_ref.values.size() == t.values.size());
  // Both settle to 0.01 K orbit to orbit; the plate's states agree to twice that.
  for (size_t p = 0; p < t.dims[0]; ++p) CHECK(t.values[p * n + plate] == Approx(t_ref.values[p * n + plate]).margin(0.02));
  // A node still far from its periodic state (a 2e6 J/K plate from 300 K, drifting ~0.01 K per
  // orbit one way) under the same wandering cycle is not taken for it: exit 3 as before.
  dir.write("slow.yaml", variant("{capacitance: 2.0e6, initial_temperature: 300.0}",
                                 "[[battery, wall, 0.05], [battery, plate, 0.01]]", true));
  const Run slow = runRadnet("run slow.yaml -o slow.h5 -q", dir);
  CHECK(slow.exit_code == 3);
  CHECK_THAT(slow.err, Catch::Contains("did not become periodic"));
  // The failure names the nodes still changing, by name: the wandering battery first, then the
  // slow plate; the boundary wall, which does not change, is not listed.
  CHECK_THAT(slow.err, Catch::Contains("still changing most: battery"));
  CHECK_THAT(slow.err, Catch::Contains(", plate 0.00"));
  CHECK_THAT(slow.err, !Catch::Contains("wall 0 K"));
}

TEST_CASE("a thermostat locked to several orbits: the period found and checked by plain transients") {
  // The battery now also sees the plate's orbital swing (0.2 W/K), which pulls its heater
  // cycle onto whole orbits: the history repeats every m > 1 orbits, not every orbit, and the
  // run ended with exit 3 before. The second method: plain transients of K and K + m orbits
  // from the same start end in the same orbit (to twice the tolerance), K + 1 in another one.
  const auto text = [](const std::string& transient) {
    return batteryOnPlate("{capacitance: 50.0}", "[[battery, wall, 0.02], [battery, plate, 0.2]]", true, transient);
  };
  TempDir dir;
  dir.write("case.yaml", text(kPeriodic));
  const Run run = runRadnet("run case.yaml -o out.h5", dir);
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  CHECK_THAT(run.err, Catch::Contains("the state repeats every"));
  hid_t file = H5Fopen((dir.path / "out.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(file >= 0);
  const long long orbits = static_cast<long long>(readDoubleAttribute(file, "/solution/temperature", "orbits"));
  const long long period = static_cast<long long>(readDoubleAttribute(file, "/solution/temperature", "orbits_per_period"));
  const double spread = readDoubleAttribute(file, "/solution/temperature", "periodic_residual");
  const H5Data periodic = readDataset(file, "/solution/temperature");
  H5Fclose(file);
  REQUIRE(period > 1);
  const auto lastOrbit = [&](long long n) {
    TempDir plain;
    const hid_t f = runAndOpen(plain, text("{orbits: " + std::to_string(n) + ", time_step: 10.0}"));
    const H5Data t = readDataset(f, "/solution/temperature");
    H5Fclose(f);
    return t.values;
  };
  const auto largestDifference = [](const std::vector<double>& a, const std::vector<double>& b) {
    double d = 0.0;
    for (size_t k = 0; k < a.size(); ++k) d = std::max(d, std::abs(a[k] - b[k]));
    return d;
  };
  const std::vector<double> at_k = lastOrbit(orbits), at_k_m = lastOrbit(orbits + period), at_k_1 = lastOrbit(orbits + 1);
  CHECK(largestDifference(at_k, periodic.values) < 1e-9);  // the same integration
  CHECK(largestDifference(at_k, at_k_m) < 0.02);
  CHECK(largestDifference(at_k, at_k_1) > 0.1);
  CHECK(spread > 0.1);
}
