#pragma once
// The writer's HDF5 call checks, shared by its files (hdf5_writer.cpp, hdf5_writer_matrices.cpp):
// a failed call becomes an OutputError (exit 4) naming what failed.
#include "cases/config/errors.hpp"
#include "cases/config/hdf5_handle.hpp"

#include <hdf5.h>

#include <string>

namespace radnet::cases::hdf5_detail {

/// Closes an HDF5 identifier at scope exit.
using Handle = Hdf5Handle;

inline void check(herr_t status, const std::string& what) {
  if (status < 0) throw OutputError("HDF5: " + what + " failed");
}

inline hid_t checkId(hid_t id, const std::string& what) {
  if (id < 0) throw OutputError("HDF5: " + what + " failed");
  return id;
}

/// Link creation properties that create intermediate groups ("/a/b/c" with only "/" there).
inline hid_t createLinkProps() {
  hid_t lcpl = checkId(H5Pcreate(H5P_LINK_CREATE), "link property list");
  H5Pset_create_intermediate_group(lcpl, 1);
  return lcpl;
}

}  // namespace radnet::cases::hdf5_detail
