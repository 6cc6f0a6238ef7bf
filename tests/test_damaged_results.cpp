// Results damaged below the level of datasets (issue 38): a file whose bytes HDF5 itself cannot
// survive is exit 2 naming it, never a crash of radnet or of the report's Python.
#include "cli_support.hpp"

#include <catch2/catch.hpp>

#include <cstdint>
#include <fstream>
#include <string>

using namespace radnet::test;
using Catch::Contains;

namespace {

// The file offset of /nodes/name's raw data (contiguous: one 16-byte record per name, the
// length (4 bytes), then the global heap ID: collection address (8) and object index (4)).
long long namesOffset(const fs::path& result) {
  const hid_t f = H5Fopen(result.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(f >= 0);
  const hid_t ds = H5Dopen2(f, "/nodes/name", H5P_DEFAULT);
  const haddr_t offset = H5Dget_offset(ds);
  H5Dclose(ds);
  H5Fclose(f);
  REQUIRE(offset != HADDR_UNDEF);
  return static_cast<long long>(offset);
}

}  // namespace

TEST_CASE("a heap index out of range in the node names (HDF5 1.10 segfaults on it) is exit 2 'damaged'") {
  TempDir dir;
  REQUIRE(runRadnet("run '" + source("cases/examples/cubesat-3u.yaml") + "' -o r.h5 -q", dir).exit_code == 0);
  const long long at = namesOffset(dir.path / "r.h5");
  {  // The first name's object index becomes 0x00720007: the byte fuzz_outputs.py flipped
    // (seed 1001, mutant 131) when `export` and `report` first died of SIGSEGV in H5HG_read.
    std::fstream f(dir.path / "r.h5", std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(at + 12 + 2);
    f.put(static_cast<char>(0x72));
  }
  for (const char* format : {"esatan", "csv"}) {
    INFO(format);
    const Run ex = runRadnet(std::string("export r.h5 --format ") + format + " -o out", dir);
    // HDF5 1.10 (Debian 12) crashes here, and the guard says "damaged"; a library that
    // reports the bad index instead gives the reader's own "cannot read": exit 2 either way.
    CHECK(ex.exit_code == 2);
    CHECK_THAT(ex.err, Contains("r.h5") && (Contains("damaged") || Contains("cannot read")));
    CHECK_FALSE(fs::exists(dir.path / "out"));
  }
  const Run report = runRadnet("report r.h5 -o rep", dir);
  CHECK(report.exit_code == 2);
  CHECK_THAT(report.err, Contains("r.h5"));
  CHECK_FALSE(fs::exists(dir.path / "rep"));
  for (const auto& entry : fs::directory_iterator(dir.path))
    CHECK(entry.path().filename().string().find(".tmp-") == std::string::npos);
}
