#pragma once
// An HDF5 identifier closed by its own close function when it goes out of scope: the TMD
// reader (cases/config) and the result reader and writer (cases/output) share it.
#include <hdf5.h>

namespace radnet::cases {

struct Hdf5Handle {
  hid_t id;
  herr_t (*close)(hid_t);
  ~Hdf5Handle() {
    if (id >= 0) close(id);
  }
  Hdf5Handle(hid_t handle, herr_t (*closer)(hid_t)) : id(handle), close(closer) {}
  Hdf5Handle(const Hdf5Handle&) = delete;
  Hdf5Handle& operator=(const Hdf5Handle&) = delete;
};

}  // namespace radnet::cases
