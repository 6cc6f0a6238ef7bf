#pragma once
// Running the real executable from tests and reading its HDF5 output back with the HDF5 C
// API (RADNET_EXE and RADNET_SOURCE_DIR come from tests/CMakeLists.txt).
#include "temp_dir.hpp"

#include <hdf5.h>
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace radnet::test {

namespace fs = std::filesystem;

struct Run {
  int exit_code;
  std::string out, err;
};

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// @param shell_before  shell commands run first in the same shell (e.g. "ulimit -v 2000000 && ")
inline Run runRadnet(const std::string& args, const TempDir& dir, const std::string& shell_before = "") {
  const fs::path out = dir.path / "stdout.txt", err = dir.path / "stderr.txt";
  // `timeout`: a hang (a FIFO read, an endless loop) fails the test as exit 124, not the suite.
  const std::string cmd = "cd '" + dir.path.string() + "' && " + shell_before + "timeout -k 5 600 '" + RADNET_EXE + "' " + args + " > '" + out.string() +
                          "' 2> '" + err.string() + "'";
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

inline std::string source(const std::string& rel) { return std::string(RADNET_SOURCE_DIR) + "/" + rel; }

struct H5Data {
  std::vector<hsize_t> dims;
  std::vector<double> values;
  std::string units;
};

inline H5Data readDataset(hid_t file, const std::string& name) {
  H5Data d;
  hid_t ds = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  REQUIRE(ds >= 0);
  hid_t space = H5Dget_space(ds);
  const int rank = H5Sget_simple_extent_ndims(space);
  d.dims.resize(static_cast<size_t>(rank));
  H5Sget_simple_extent_dims(space, d.dims.data(), nullptr);
  hid_t type = H5Dget_type(ds);
  if (H5Tget_class(type) == H5T_FLOAT || H5Tget_class(type) == H5T_INTEGER) {
    hsize_t count = 1;
    for (auto x : d.dims) count *= x;
    d.values.resize(count);
    H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, d.values.data());
  } else if (H5Tget_class(type) == H5T_ENUM && H5Tget_size(type) == 1) {  // booleans: enum {FALSE, TRUE} of int8
    hsize_t count = 1;
    for (auto x : d.dims) count *= x;
    std::vector<signed char> raw(count);
    hid_t native = H5Tget_native_type(type, H5T_DIR_ASCEND);
    H5Dread(ds, native, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data());
    H5Tclose(native);
    d.values.assign(raw.begin(), raw.end());
  }
  if (H5Aexists(ds, "units") > 0) {
    hid_t attr = H5Aopen(ds, "units", H5P_DEFAULT);
    hid_t atype = H5Aget_type(attr);
    REQUIRE(H5Tis_variable_str(atype) > 0);
    char* text = nullptr;
    H5Aread(attr, atype, &text);
    d.units = text ? text : "";
    H5free_memory(text);
    H5Tclose(atype);
    H5Aclose(attr);
  } else {
    d.units = "<missing>";
  }
  H5Tclose(type);
  H5Sclose(space);
  H5Dclose(ds);
  return d;
}

/// /nodes/name (variable-length strings), in node order.
inline std::vector<std::string> readNodeNames(hid_t file) {
  const hid_t ds = H5Dopen2(file, "/nodes/name", H5P_DEFAULT);
  const hid_t space = H5Dget_space(ds);
  hsize_t n = 0;
  H5Sget_simple_extent_dims(space, &n, nullptr);
  std::vector<char*> raw(n);
  const hid_t type = H5Dget_type(ds);
  H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data());
  std::vector<std::string> names;
  for (hsize_t k = 0; k < n; ++k) names.emplace_back(raw[k] ? raw[k] : "");
  H5Dvlen_reclaim(type, space, H5P_DEFAULT, raw.data());
  H5Tclose(type);
  H5Sclose(space);
  H5Dclose(ds);
  return names;
}

inline double readDoubleAttribute(hid_t file, const char* object, const char* name) {
  double value = -1.0;
  const hid_t attr = H5Aopen_by_name(file, object, name, H5P_DEFAULT, H5P_DEFAULT);
  REQUIRE(attr >= 0);
  H5Aread(attr, H5T_NATIVE_DOUBLE, &value);
  H5Aclose(attr);
  return value;
}


/// A variable-length string attribute.
inline std::string readStringAttribute(hid_t file, const char* object, const char* name) {
  const hid_t attr = H5Aopen_by_name(file, object, name, H5P_DEFAULT, H5P_DEFAULT);
  REQUIRE(attr >= 0);
  const hid_t type = H5Aget_type(attr);
  char* text = nullptr;
  H5Aread(attr, type, &text);
  std::string value = text ? text : "";
  H5free_memory(text);
  H5Tclose(type);
  H5Aclose(attr);
  return value;
}

}  // namespace radnet::test
