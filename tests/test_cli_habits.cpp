// The command line's habits (issue 14): --version, several files, refused output clashes,
// progress a log can hold, the summary of a large model, exit 4.
#include "cli_support.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <fstream>

using namespace radnet::test;

TEST_CASE("cli: --version names the program and its version") {
  TempDir dir;
  const Run r = runRadnet("--version", dir);
  CHECK(r.exit_code == 0);
  CHECK(r.out.rfind("radnet ", 0) == 0);
}

TEST_CASE("cli: validate and run take several files; the worst outcome decides the exit code") {
  TempDir dir;
  const std::string good = source("cases/analytic/lumped-nodes.yaml"), other = source("cases/analytic/parallel-plates-temperature.yaml");
  const Run v = runRadnet("validate '" + good + "' '" + other + "' '" + source("tests/data/bad/accuracy-too-large.yaml") + "'", dir);
  CHECK(v.exit_code == 2);  // the bad one is reported, the good ones still validated
  CHECK(v.out.find("lumped-nodes.yaml: valid") != std::string::npos);
  CHECK(v.out.find("parallel-plates-temperature.yaml: valid") != std::string::npos);
  const Run r = runRadnet("run '" + good + "' '" + other + "' -q", dir);
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(fs::exists(dir.path / "lumped-nodes.h5"));
  CHECK(fs::exists(dir.path / "parallel-plates-temperature.h5"));
  // -o naming one file for two cases is refused before anything runs.
  const Run one = runRadnet("run '" + good + "' '" + other + "' -o both.h5 -q", dir);
  CHECK(one.exit_code == 2);
  CHECK_FALSE(fs::exists(dir.path / "both.h5"));
}

TEST_CASE("cli: two cases with the same file name into one directory are refused, not overwritten") {
  TempDir dir;
  fs::create_directories(dir.path / "a");
  fs::create_directories(dir.path / "b");
  fs::create_directories(dir.path / "out");
  fs::copy_file(source("cases/analytic/lumped-nodes.yaml"), dir.path / "a" / "x.yaml");
  fs::copy_file(source("cases/analytic/parallel-plates-temperature.yaml"), dir.path / "b" / "x.yaml");
  const Run r = runRadnet("run a/x.yaml b/x.yaml -o out -q", dir);
  CHECK(r.exit_code == 2);
  CHECK(r.err.find("as a/x.yaml does") != std::string::npos);
  CHECK_FALSE(fs::exists(dir.path / "out" / "x.h5"));
}

TEST_CASE("cli: progress into a file is a few plain lines, no carriage returns") {
  TempDir dir;
  const Run r = runRadnet("run '" + source("cases/examples/cubesat-3u.yaml") + "' -o c.h5", dir);
  REQUIRE(r.exit_code == 0);
  CHECK(r.err.find('\r') == std::string::npos);
  const auto lines = std::count(r.err.begin(), r.err.end(), '\n');
  CHECK(lines < 40);  // 5 lines per stage (0, 25, 50, 75, 100 %) and a few notes
  CHECK(r.err.find("view factors 100 %") != std::string::npos);
}

TEST_CASE("cli: the summary of a large model shows extremes and primitives, --all every node") {
  TempDir dir;
  // Two 8 × 8 node grids (128 nodes) facing each other: above the 40 rows a table shows in full.
  std::ofstream(dir.path / "grid.yaml") << R"(name: grid
materials: {black: {emissivity: 0.9, absorptivity: 0.9}}
geometry:
  - rectangle: {name: top, origin: [0, 0, 1], u: [0, 1, 0], v: [1, 0, 0], front: black, nodes: [8, 8]}
  - rectangle: {name: bottom, origin: [0, 0, 0], u: [1, 0, 0], v: [0, 1, 0], front: black, nodes: [8, 8]}
solver: {view_factors: {rays: 2000, seed: 3}}
)";
  const Run r = runRadnet("run grid.yaml -o g.h5 -q", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("by primitive (128 nodes in 2 groups") != std::string::npos);
  CHECK(r.out.find("top (64)") != std::string::npos);
  CHECK(r.out.find("largest area") != std::string::npos);
  const Run all = runRadnet("run grid.yaml -o g.h5 -q --all", dir);
  REQUIRE(all.exit_code == 0);
  CHECK(all.out.find("by primitive") == std::string::npos);
  CHECK(all.out.find("top.7.7") != std::string::npos);
  CHECK(std::count(all.out.begin(), all.out.end(), '\n') > 128);
  CHECK(std::count(r.out.begin(), r.out.end(), '\n') < 40);
}

TEST_CASE("cli: round-off is not printed as a heat flow") {
  TempDir dir;
  const Run r = runRadnet("run '" + source("cases/examples/cubesat-3u.yaml") + "' -o c.h5 -q", dir);
  REQUIRE(r.exit_code == 0);
  const size_t from = r.out.find("heat flows, W"), to = r.out.find("heat balance:");
  REQUIRE(from != std::string::npos);
  REQUIRE(to > from);
  const std::string table = r.out.substr(from, to - from);
  // A node without conduction or heaters shows 0, not −2.3e-15 W (1e-12 of the column's scale).
  for (const char* tiny : {"e-13", "e-14", "e-15", "e-16", "e-17", "e-18"}) CHECK(table.find(tiny) == std::string::npos);
}

TEST_CASE("cli: output that cannot be written exits 4 and leaves nothing") {
  TempDir dir;
  const Run run = runRadnet("run '" + source("cases/analytic/lumped-nodes.yaml") + "' -o r.h5 -q", dir);
  REQUIRE(run.exit_code == 0);
  const Run r = runRadnet("export r.h5 --format esatan -o missing-dir/r.d", dir);
  CHECK(r.exit_code == 4);
  CHECK(r.err.find("output not written") != std::string::npos);
  CHECK_FALSE(fs::exists(dir.path / "missing-dir"));
}
