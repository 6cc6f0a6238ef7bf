// Output under attack (issue 38): names planted in a shared output folder are passed over,
// never written through; a full disk is exit 4 with the old files intact and no crash.
#include "cli_support.hpp"

#include <catch2/catch.hpp>

#include <sys/mount.h>
#include <unistd.h>

#include <limits>
#include <string>
#include <vector>

using namespace radnet::test;
using Catch::Contains;

namespace {

const std::string kCase = source("cases/examples/cubesat-3u.yaml");

}  // namespace

TEST_CASE("symlinks planted at the temporaries' names are not followed: the victim keeps its text") {
  TempDir dir;
  dir.write("victim.txt", "precious\n");
  // The next pids' temporary names, as an attacker sharing the folder would plant them.
  const int from = static_cast<int>(::getpid());
  for (int pid = from + 1; pid < from + 3000; ++pid)
    for (const char* name : {"out.h5.tmp-", "out.xmf.tmp-"})
      fs::create_symlink("victim.txt", dir.path / (name + std::to_string(pid)));
  const Run run = runRadnet("run '" + kCase + "' -o out.h5 -q", dir);
  INFO(run.err);
  CHECK(run.exit_code == 0);
  CHECK(slurp(dir.path / "victim.txt") == "precious\n");
  CHECK(fs::is_regular_file(dir.path / "out.h5"));
  CHECK(fs::is_regular_file(dir.path / "out.xmf"));
  const hid_t f = H5Fopen((dir.path / "out.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  CHECK(f >= 0);
  if (f >= 0) H5Fclose(f);
}

TEST_CASE("a full disk is exit 4, no crash, the old result untouched and nothing left behind") {
  TempDir dir;
  const fs::path full = dir.path / "full";
  fs::create_directory(full);
  // A 200 kB tmpfs: the CubeSat's result does not fit. Mounting needs root (CI runs as
  // root); elsewhere the test says so and checks nothing.
  if (::mount("tmpfs", full.c_str(), "tmpfs", 0, "size=200k") != 0) {
    WARN("cannot mount a tmpfs here (not root?): the full-disk case is not exercised");
    return;
  }
  struct Unmount {
    fs::path at;
    ~Unmount() { ::umount(at.c_str()); }
  } unmount{full};
  std::ofstream(full / "out.h5") << "the old result\n";
  const Run run = runRadnet("run '" + kCase + "' -o full/out.h5 -q", dir);
  INFO(run.err);
  CHECK(run.exit_code == 4);  // not 139 (HDF5's exit handler closing the failed file again)
  CHECK_THAT(run.err, Contains("output not written"));
  CHECK(slurp(full / "out.h5") == "the old result\n");
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(full)) ++entries;
  CHECK(entries == 1);  // no temporary, no sidecar
}

namespace {

// Replaces dataset `path` of an HDF5 file by a doubles array of the given shape.
void replaceDataset(const fs::path& file, const std::string& path, const std::vector<hsize_t>& dims,
                    const std::vector<double>& values) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  REQUIRE(f >= 0);
  H5Ldelete(f, path.c_str(), H5P_DEFAULT);
  const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  const hid_t ds = H5Dcreate2(f, path.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  REQUIRE(ds >= 0);
  H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  H5Dclose(ds);
  H5Sclose(space);
  H5Fclose(f);
}

/// A dataset of the CubeSat result rewritten with other dimensions or values.
struct Damage {
  const char* dataset;
  std::vector<hsize_t> dims;
  std::vector<double> values;
};

}  // namespace

TEST_CASE("export refuses a malformed result naming the dataset (exit 2, nothing written), never a crash") {
  TempDir dir;
  REQUIRE(runRadnet("run '" + kCase + "' -o good.h5 -q", dir).exit_code == 0);
  // The CubeSat: 13 nodes (11 radiative), 20 conductors, 76 positions.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> temperatures(76 * 13, 290.0);
  temperatures[5] = nan;
  std::vector<double> pairs(40, 0.0);
  pairs[7] = 1000.0;  // a node that does not exist
  const std::vector<Damage> damages = {
      // GR as export reads it: the base optics set's (more nodes than the result has; too long)
      {"/optics/base/radiative_exchange", {20, 20}, std::vector<double>(400, 0.01)},
      {"/optics/base/gr_space", {50}, std::vector<double>(50, 0.01)},
      {"/thermal/conductor_nodes", {20, 2}, pairs},
      {"/thermal/conductance", {76, 3}, std::vector<double>(76 * 3, 1.0)},  // short of the 20 conductors
      {"/thermal/fixed", {2}, {1.0, 0.0}},                                   // short of the 13 nodes
      {"/solution/temperature", {76, 13}, temperatures},                     // a NaN
  };
  for (const Damage& d : damages) {
    INFO(d.dataset);
    fs::copy_file(dir.path / "good.h5", dir.path / "bad.h5", fs::copy_options::overwrite_existing);
    replaceDataset(dir.path / "bad.h5", d.dataset, d.dims, d.values);
    for (const char* format : {"esatan", "sinda", "csv"}) {
      INFO(format);
      fs::remove_all(dir.path / (std::string("out.") + format));
      const Run run = runRadnet(std::string("export bad.h5 --format ") + format + " -o out." + format, dir);
      CHECK(run.exit_code == 2);
      CHECK_THAT(run.err, Contains(d.dataset));
      CHECK_FALSE(fs::exists(dir.path / (std::string("out.") + format)));
    }
  }
  // The undamaged file still exports.
  CHECK(runRadnet("export good.h5 --format esatan -o good.d", dir).exit_code == 0);
}

TEST_CASE("the .xmf sidecar escapes the file name: -o 'a&b<c>.h5' gives well-formed XML") {
  TempDir dir;
  const Run run = runRadnet("run '" + kCase + "' -o 'a&b<c>.h5' -q", dir);
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  const std::string xmf = slurp(dir.path / "a&b<c>.xmf");
  CHECK_THAT(xmf, Contains(">a&amp;b&lt;c&gt;.h5:/xdmf/"));
  CHECK(xmf.find("a&b<c>") == std::string::npos);
}

TEST_CASE("filesystem failures are exit 4: a name over 255 bytes, a read-only folder") {
  TempDir dir;
  const std::string small = source("cases/examples/parallel-plates.yaml");
  const Run long_name = runRadnet("run '" + small + "' -o " + std::string(300, 'a') + ".h5 -q", dir);
  CHECK(long_name.exit_code == 4);
  CHECK_THAT(long_name.err, Contains("output not written"));
  const fs::path ro = dir.path / "ro";
  fs::create_directory(ro);
  if (::mount("tmpfs", ro.c_str(), "tmpfs", MS_RDONLY, "size=64k") != 0) {
    WARN("cannot mount a read-only tmpfs here (not root?): that case is not exercised");
    return;
  }
  const Run read_only = runRadnet("run '" + small + "' -o ro/out.h5 -q", dir);
  ::umount(ro.c_str());
  CHECK(read_only.exit_code == 4);
  CHECK_THAT(read_only.err, Contains("not writable"));
}

TEST_CASE("a 10 µm square 1 m above a 10 m plate: the exact method's work stays bounded (no hang)") {
  // Once sat at "view factors 50 %" for over 300 s; the planner now bounds each pair's cost.
  // 120 s is a hang guard, not a timing (it takes milliseconds).
  TempDir dir;
  dir.write("hang.yaml", R"(name: hang
materials: {w: {emissivity: 0.8, absorptivity: 0.3}}
geometry:
  - rectangle: {name: tiny, origin: [0, 0, 1], u: [1.0e-5, 0, 0], v: [0, -1.0e-5, 0], front: w}
  - rectangle: {name: plate, origin: [-5, -5, 0], u: [10, 0, 0], v: [0, 10, 0], front: w}
)");
  const std::string cmd = "cd '" + dir.path.string() + "' && timeout 120 '" + RADNET_EXE + "' run hang.yaml -o h.h5 -q > /dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);
  // F from a differential area 1 m above the centre of a 10 m square: four a × a rectangles
  // with a corner below it (Howell's catalogue, element to a parallel rectangle:
  // F = (1/2π)[A/√(1+A²) atan(B/√(1+A²)) + B/√(1+B²) atan(A/√(1+B²))], A = B = a/c = 5);
  // checked to 1e-6 (the 10 µm square is a point to 1e-5 of its distance).
  const hid_t f = H5Fopen((dir.path / "h.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(f >= 0);
  const H5Data space = readDataset(f, "/network/space_view_factor");
  H5Fclose(f);
  const double a = 5.0, c = 1.0, r = a / std::sqrt(a * a + c * c);
  const double f_quarter = (1.0 / (2.0 * M_PI)) * (2.0 * r * std::atan(r));  // corner of an a × a rectangle, A = B
  CHECK(space.values[0] == Approx(1.0 - 4.0 * f_quarter).margin(1e-6));
}

TEST_CASE("a thermostat dead band too narrow to resolve is refused at its line, one that chatters is exit 3") {
  // 50 W into 1000 J/K: a band of 1e-12 K would switch every 2e-11 s (it ran without end):
  // refused at off_above, as is anything below twice the switch tolerance (1e-3 K). 60 kW
  // against 1000 W/K to a 250 K wall across a 0.002 K band (±30 K/s) switches every 7e-5 s,
  // over 10,000 times between two outputs: the run stops naming the heater. 120 s is a hang
  // guard, not a timing.
  TempDir dir;
  const auto thermostat = [&](const std::string& off_above, const std::string& power,
                              const std::string& conductance = "1.0") {
    dir.write("band.yaml", R"(name: thermostat
network:
  nodes:
    - {name: wall, area: 1.0, emissivity: 0.0}
  view_factors: [[0.0]]
thermal:
  nodes:
    wall: {temperature: 250.0}
  lumped:
    battery: {capacitance: 1000.0, initial_temperature: 280.65}
  conductors: [[battery, wall, )" + conductance + R"(]]
  heaters:
    - {name: bat_heater, node: battery, power: )" + power + R"(, on_below: 278.15, off_above: )" + off_above + R"(}
  transient: {duration: 2000.0, time_step: 10.0, output_step: 10.0}
)");
    fs::remove(dir.path / "b.h5");
    const std::string cmd = "cd '" + dir.path.string() + "' && timeout 120 '" + RADNET_EXE +
                            "' run band.yaml -o b.h5 -q > out.txt 2> err.txt";
    const int status = std::system(cmd.c_str());
    REQUIRE(WIFEXITED(status));
    return WEXITSTATUS(status);
  };
  CHECK(thermostat("278.150000000001", "50.0") == 2);
  CHECK_THAT(slurp(dir.path / "err.txt"), Contains("band.yaml:13:") && Contains("widen it to at least 0.002 K"));
  CHECK(thermostat("278.1505", "50.0") == 2);
  CHECK(thermostat("278.152", "60000.0", "1000.0") == 3);
  CHECK_THAT(slurp(dir.path / "err.txt"), Contains("heater 'bat_heater'") && Contains("widen the band"));
  CHECK_FALSE(fs::exists(dir.path / "b.h5"));
  CHECK(thermostat("278.16", "50.0") == 0);
}

namespace {

// A chunked dataset of the given shape with no chunk written: a huge logical size in a tiny
// file, as a hostile or truncated result may declare.
void declareEmptyDataset(const fs::path& file, const std::string& path, const std::vector<hsize_t>& dims) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  REQUIRE(f >= 0);
  H5Ldelete(f, path.c_str(), H5P_DEFAULT);
  const hid_t space = H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr);
  const hid_t props = H5Pcreate(H5P_DATASET_CREATE);
  std::vector<hsize_t> chunk(dims.size(), 1);
  chunk.back() = dims.back();
  H5Pset_chunk(props, static_cast<int>(chunk.size()), chunk.data());
  const hid_t ds = H5Dcreate2(f, path.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, props, H5P_DEFAULT);
  REQUIRE(ds >= 0);
  H5Dclose(ds);
  H5Pclose(props);
  H5Sclose(space);
  H5Fclose(f);
}

bool hasReportPython() { return std::system("/usr/bin/python3 -c 'import h5py, matplotlib' 2>/dev/null") == 0; }

}  // namespace

TEST_CASE("report refuses a malformed result naming the dataset (exit 2, no traceback, nothing written)") {
  if (!hasReportPython()) {
    WARN("Debian's python3-h5py/matplotlib are missing: the report is not exercised");
    return;
  }
  TempDir dir;
  REQUIRE(runRadnet("run '" + kCase + "' -o good.h5 -q", dir).exit_code == 0);
  // The CubeSat: 13 nodes, 11 radiative, 76 positions, one design case, one heater.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> temperatures(76 * 13, 290.0);
  temperatures[40] = nan;
  const std::vector<Damage> damages = {
      {"/solution/temperature", {76, 13}, temperatures},                          // a NaN
      {"/solution/temperature", {76, 7}, std::vector<double>(76 * 7, 290.0)},     // too few nodes
      {"/orbit/time", {5}, std::vector<double>(5, 0.0)},                          // too few positions
      {"/loads/solar", {76, 40}, std::vector<double>(76 * 40, 1.0)},              // more nodes than the result
      {"/cases/position_start", {2}, {0.0, 1000.0}},                              // beyond the positions
      {"/solution/envelope/temperature_max_case", {13}, std::vector<double>(13, 9.0)},  // no case 9
      {"/heaters/power", {3, 1}, {1.0, 2.0, 3.0}},
      {"/solution/heat/radiative", {76, 13}, std::vector<double>(76 * 13, nan)},
      {"/network/conductance", {3, 5}, std::vector<double>(15, 1.0)},
  };
  for (const Damage& d : damages) {
    INFO(d.dataset);
    fs::copy_file(dir.path / "good.h5", dir.path / "bad.h5", fs::copy_options::overwrite_existing);
    replaceDataset(dir.path / "bad.h5", d.dataset, d.dims, d.values);
    const Run run = runRadnet("report bad.h5 -o rep", dir);
    INFO(run.err);
    CHECK(run.exit_code == 2);
    CHECK_THAT(run.err, Contains(d.dataset));
    CHECK(run.err.find("Traceback") == std::string::npos);
    CHECK_FALSE(fs::exists(dir.path / "rep"));
  }
  // 400 million positions declared in a 2 MB file: refused by its size before it is read.
  fs::copy_file(dir.path / "good.h5", dir.path / "bad.h5", fs::copy_options::overwrite_existing);
  declareEmptyDataset(dir.path / "bad.h5", "/solution/temperature", {400000000, 13});
  const Run huge = runRadnet("report bad.h5 -o rep", dir);
  CHECK(huge.exit_code == 2);
  CHECK_THAT(huge.err, Contains("/solution/temperature"));
  // Bad limits files and targets: located, exit 2, no traceback.
  dir.write("binary.yaml", std::string("\xff\xfe\x00\x01 node", 9));
  for (const char* args : {"--limits missing.yaml", "--limits binary.yaml", "--limits ."}) {
    INFO(args);
    const Run run = runRadnet(std::string("report good.h5 -o rep ") + args, dir);
    CHECK(run.exit_code == 2);
    CHECK(run.err.find("Traceback") == std::string::npos);
    CHECK_FALSE(fs::exists(dir.path / "rep"));
  }
  dir.write("plain.txt", "not a folder\n");
  CHECK(runRadnet("report good.h5 -o plain.txt", dir).exit_code == 2);
  CHECK(slurp(dir.path / "plain.txt") == "not a folder\n");
  // The undamaged file gives its report; a second report into the same folder replaces its
  // files and leaves a user's own file there alone.
  REQUIRE(runRadnet("report good.h5 -o rep", dir).exit_code == 0);
  dir.write("rep/notes.txt", "mine\n");
  REQUIRE(runRadnet("report good.h5 -o rep", dir).exit_code == 0);
  CHECK(fs::exists(dir.path / "rep" / "report.md"));
  CHECK(slurp(dir.path / "rep" / "notes.txt") == "mine\n");
  for (const auto& entry : fs::directory_iterator(dir.path))
    CHECK(entry.path().filename().string().find(".tmp-") == std::string::npos);
}

TEST_CASE("report on a full disk is exit 4 with no partial report") {
  if (!hasReportPython()) return;
  TempDir dir;
  REQUIRE(runRadnet("run '" + kCase + "' -o good.h5 -q", dir).exit_code == 0);
  const fs::path full = dir.path / "full";
  fs::create_directory(full);
  if (::mount("tmpfs", full.c_str(), "tmpfs", 0, "size=100k") != 0) {
    WARN("cannot mount a tmpfs here (not root?): the full-disk report is not exercised");
    return;
  }
  struct Unmount {
    fs::path at;
    ~Unmount() { ::umount(at.c_str()); }
  } unmount{full};
  const Run run = runRadnet("report good.h5 -o full/rep", dir);
  INFO(run.err);
  CHECK(run.exit_code == 4);
  CHECK(run.err.find("Traceback") == std::string::npos);
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(full)) ++entries;
  CHECK(entries == 0);  // no report folder, no scratch folder
}

TEST_CASE("export: a FIFO is refused at once, a dataset declared larger than the file is refused unread") {
  TempDir dir;
  REQUIRE(std::system(("mkfifo '" + (dir.path / "fifo.h5").string() + "'").c_str()) == 0);
  const Run fifo = runRadnet("export fifo.h5 --format esatan -o x.d", dir);  // bounded by `timeout`
  CHECK(fifo.exit_code == 2);
  CHECK_THAT(fifo.err, Contains("not a regular file"));
  REQUIRE(runRadnet("run '" + kCase + "' -o good.h5 -q", dir).exit_code == 0);
  fs::copy_file(dir.path / "good.h5", dir.path / "bad.h5");
  declareEmptyDataset(dir.path / "bad.h5", "/solution/temperature", {400000000, 13});  // 41.6 GB
  const Run huge = runRadnet("export bad.h5 --format esatan -o x.d", dir);
  CHECK(huge.exit_code == 2);
  CHECK_THAT(huge.err, Contains("/solution/temperature"));
  CHECK_FALSE(fs::exists(dir.path / "x.d"));
}

TEST_CASE("warnings are kept in /report/warnings and counted on stderr even under -q") {
  TempDir dir;
  // A 300 mm square written in mm and read without `scale`: the 300 m model is warned.
  dir.write("sq.off", "OFF\n4 2 0\n0 0 0\n300 0 0\n300 300 0\n0 300 0\n3 0 1 2\n3 0 2 3\n");
  dir.write("mm.yaml", R"(name: mm-plate
materials: {black: {emissivity: 0.9, absorptivity: 0.9}}
geometry:
  - mesh: {name: plate, file: sq.off, front: black}
)");
  const Run quiet = runRadnet("run mm.yaml -o m.h5 -q", dir);
  REQUIRE(quiet.exit_code == 0);
  CHECK(quiet.err.find("scale: 0.001") == std::string::npos);  // -q: the warning itself is not shown
  CHECK_THAT(quiet.err, Contains("1 warning(s)"));
  CHECK_THAT(quiet.err, Contains("/report/warnings"));
  const hid_t f = H5Fopen((dir.path / "m.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(f >= 0);
  const hid_t ds = H5Dopen2(f, "/report/warnings", H5P_DEFAULT);
  REQUIRE(ds >= 0);
  const hid_t space = H5Dget_space(ds);
  CHECK(H5Sget_simple_extent_npoints(space) == 1);
  H5Sclose(space);
  H5Dclose(ds);
  H5Fclose(f);
  // A case without warnings has the dataset, empty, and no count line.
  const Run clean = runRadnet("run '" + source("cases/analytic/lumped-nodes.yaml") + "' -o l.h5 -q", dir);
  REQUIRE(clean.exit_code == 0);
  CHECK(clean.err.find("warning") == std::string::npos);
}

TEST_CASE("run with several cases reads them all first: a bad one among good ones writes nothing") {
  TempDir dir;
  fs::create_directory(dir.path / "out");
  dir.write("good.yaml", slurp(source("cases/analytic/lumped-nodes.yaml")));
  dir.write("bad.yaml", "name: bad\nnodes: [\n");
  const Run run = runRadnet("run good.yaml bad.yaml -o out -q", dir);
  CHECK(run.exit_code == 2);
  CHECK_THAT(run.err, Contains("bad.yaml:"));
  CHECK_THAT(run.err, Contains("no case was run"));
  CHECK(fs::is_empty(dir.path / "out"));
  CHECK(runRadnet("run good.yaml -o out -q", dir).exit_code == 0);
}

// Issue 38: a transient reaching 1e6 K said nothing. 1e7 W into 10 J/K on a 0.001 W/K link
// heats the box by about 1e6 K/s, so it reaches ~1e8 K by 100 s.
TEST_CASE("a node heated beyond what any material survives is warned, naming it and when") {
  TempDir dir;
  dir.write("hot.yaml", R"(name: hot
network:
  nodes:
    - {name: plate, area: 1.0, emissivity: 1.0}
  view_factors:
    - [0.0]
thermal:
  nodes:
    plate: {capacitance: 1000.0}
  lumped:
    box: {dissipation: 1.0e7, capacitance: 10.0, initial_temperature: 293.15}
  conductors: [[box, plate, 0.001]]
  transient: {duration: 100.0, output_step: 10.0}
)");
  const Run hot = runRadnet("run hot.yaml -o hot.h5", dir);
  INFO(hot.err);
  CHECK(hot.exit_code == 0);
  CHECK_THAT(hot.err, Contains("warning: thermal: node 'box' reaches 9.95"));
  CHECK_THAT(hot.err, Contains("e+07 K at t = 100 s"));
  CHECK_THAT(hot.out, Contains("9.95e+07"));  // the summary's maximum, not its first output
  // The plate, at 1142 K, is hot but not impossible: not named.
  CHECK(hot.err.find("'plate'") == std::string::npos);
}
