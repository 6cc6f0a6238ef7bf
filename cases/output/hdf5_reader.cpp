#include "cases/output/hdf5_reader.hpp"

#include "cases/config/errors.hpp"
#include "cases/config/hdf5_handle.hpp"

#include <hdf5.h>

#include <filesystem>
#include <vector>

namespace radnet::cases {
namespace {

using Handle = Hdf5Handle;

// HDF5 prints its own error stack on stderr; the messages here say what is wrong instead.
void quiet() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

// Reads a value of `type` `count` times through its native type, as a reader of it would,
// then frees what HDF5 allocated (variable-length strings and sequences).
template <class Read>
void readAsNative(hid_t type, hid_t space, hssize_t count, Read read) {
  if (count <= 0) return;
  Handle mem{H5Tget_native_type(type, H5T_DIR_ASCEND), H5Tclose};
  if (mem.id < 0) return;
  std::vector<unsigned char> buffer(static_cast<size_t>(count) * H5Tget_size(mem.id));
  if (read(mem.id, buffer.data()) >= 0 && (H5Tdetect_class(mem.id, H5T_VLEN) > 0 || H5Tis_variable_str(mem.id) > 0))
    H5Dvlen_reclaim(mem.id, space, H5P_DEFAULT, buffer.data());
}

herr_t readAttribute(hid_t object, const char* name, const H5A_info_t*, void*) {
  Handle a{H5Aopen(object, name, H5P_DEFAULT), H5Aclose};
  Handle type{H5Aget_type(a.id), H5Tclose};
  Handle space{H5Aget_space(a.id), H5Sclose};
  readAsNative(type.id, space.id, H5Sget_simple_extent_npoints(space.id),
               [&](hid_t mem, void* out) { return H5Aread(a.id, mem, out); });
  return 0;
}

herr_t readObject(hid_t group, const char* name, const H5L_info_t*, void* reader) {
  Handle object{H5Oopen(group, name, H5P_DEFAULT), H5Oclose};
  if (object.id < 0) return 0;
  H5Aiterate2(object.id, H5_INDEX_NAME, H5_ITER_NATIVE, nullptr, readAttribute, nullptr);
  if (H5Iget_type(object.id) != H5I_DATASET) return 0;
  Handle type{H5Dget_type(object.id), H5Tclose};
  Handle space{H5Dget_space(object.id), H5Sclose};
  const hssize_t count = H5Sget_simple_extent_npoints(space.id);
  static_cast<const Hdf5Reader*>(reader)->checkLogicalSize(name, static_cast<double>(count) * H5Tget_size(type.id));
  readAsNative(type.id, space.id, count,
               [&](hid_t mem, void* out) { return H5Dread(object.id, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, out); });
  return 0;
}

}  // namespace

void Hdf5Reader::readEverything() const {
  H5Aiterate2(static_cast<hid_t>(file_), H5_INDEX_NAME, H5_ITER_NATIVE, nullptr, readAttribute, nullptr);
  H5Lvisit(static_cast<hid_t>(file_), H5_INDEX_NAME, H5_ITER_NATIVE, readObject, const_cast<Hdf5Reader*>(this));
}

Hdf5Reader::Hdf5Reader(const std::string& path) : path_(path) {
  quiet();
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw InputError(path, 0, 0, "not a regular file (a FIFO, device or directory cannot be a result)");
  if (H5Fis_hdf5(path.c_str()) <= 0) throw InputError(path, 0, 0, "not an HDF5 file (or it does not exist)");
  file_ = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file_ < 0) throw InputError(path, 0, 0, "cannot open the HDF5 file");
  if (!has("/meta")) throw InputError(path, 0, 0, "not a radnet result: it has no /meta group");
}

Hdf5Reader::~Hdf5Reader() {
  if (file_ >= 0) H5Fclose(static_cast<hid_t>(file_));
}

bool Hdf5Reader::has(const std::string& path) const {
  // Each part of the path must exist before the next is asked for.
  for (size_t end = path.find('/', 1);; end = path.find('/', end + 1)) {
    const std::string part = path.substr(0, end);
    if (H5Lexists(static_cast<hid_t>(file_), part.c_str(), H5P_DEFAULT) <= 0) return false;
    if (end == std::string::npos) return true;
  }
}

Eigen::MatrixXd Hdf5Reader::matrix(const std::string& path) const {
  if (const auto it = kept_.find(path); it != kept_.end()) return it->second;
  Eigen::MatrixXd m = readMatrix(path);
  for (const std::string& prefix : keep_prefixes_)
    if (path.rfind(prefix, 0) == 0) return kept_.emplace(path, std::move(m)).first->second;
  return m;
}

Eigen::MatrixXd Hdf5Reader::readMatrix(const std::string& path) const {
  if (!has(path)) throw InputError(path_, 0, 0, "the result has no " + path);
  Handle ds{H5Dopen2(static_cast<hid_t>(file_), path.c_str(), H5P_DEFAULT), H5Dclose};
  Handle space{H5Dget_space(ds.id), H5Sclose};
  const int rank = H5Sget_simple_extent_ndims(space.id);
  hsize_t dims[2] = {1, 1};
  if (rank < 1 || rank > 2 || H5Sget_simple_extent_dims(space.id, dims, nullptr) < 0)
    throw InputError(path_, 0, 0, path + " is not a 1-D or 2-D dataset");
  checkLogicalSize(path, static_cast<double>(dims[0]) * static_cast<double>(rank == 2 ? dims[1] : 1) * 8.0);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> m(dims[0], rank == 2 ? dims[1] : 1);
  if (m.size() && H5Dread(ds.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, m.data()) < 0)
    throw InputError(path_, 0, 0, "cannot read " + path + " as numbers");
  return m;
}

void Hdf5Reader::checkLogicalSize(const std::string& path, double bytes) const {
  // Deflate compresses at most ~1000:1 and unwritten chunks take no room: a dataset declared
  // far larger than the file could hold is malformed, refused before memory is taken for it.
  std::error_code ec;
  const double file_bytes = static_cast<double>(std::filesystem::file_size(path_, ec));
  if (!ec && bytes > 1100.0 * file_bytes + 16.0 * (1 << 20))
    throw InputError(path_, 0, 0, path + " declares " + std::to_string(static_cast<long long>(bytes)) +
                                      " bytes, more than a " + std::to_string(static_cast<long long>(file_bytes)) +
                                      "-byte file can hold");
}

Eigen::Index Hdf5Reader::rows(const std::string& path) const {
  if (!has(path)) throw InputError(path_, 0, 0, "the result has no " + path);
  Handle ds{H5Dopen2(static_cast<hid_t>(file_), path.c_str(), H5P_DEFAULT), H5Dclose};
  Handle space{H5Dget_space(ds.id), H5Sclose};
  hsize_t dims[H5S_MAX_RANK] = {0};
  if (H5Sget_simple_extent_dims(space.id, dims, nullptr) < 0) throw InputError(path_, 0, 0, "cannot read " + path);
  return H5Sget_simple_extent_ndims(space.id) > 0 ? static_cast<Eigen::Index>(dims[0]) : 0;
}

Eigen::VectorXd Hdf5Reader::vector(const std::string& path) const {
  const Eigen::MatrixXd m = matrix(path);
  if (m.cols() != 1) throw InputError(path_, 0, 0, path + " is not 1-D");
  return m.col(0);
}

std::vector<std::string> Hdf5Reader::strings(const std::string& path) const {
  if (!has(path)) throw InputError(path_, 0, 0, "the result has no " + path);
  Handle ds{H5Dopen2(static_cast<hid_t>(file_), path.c_str(), H5P_DEFAULT), H5Dclose};
  Handle space{H5Dget_space(ds.id), H5Sclose};
  const hssize_t count = H5Sget_simple_extent_npoints(space.id);
  checkLogicalSize(path, static_cast<double>(count) * 16.0);  // a pointer and a short name a string
  Handle type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type.id, H5T_VARIABLE);
  H5Tset_cset(type.id, H5T_CSET_UTF8);
  std::vector<char*> raw(static_cast<size_t>(std::max<hssize_t>(count, 0)), nullptr);
  if (count > 0 && H5Dread(ds.id, type.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data()) < 0)
    throw InputError(path_, 0, 0, "cannot read " + path + " as strings");
  std::vector<std::string> out;
  for (char* s : raw) out.emplace_back(s ? s : "");
  if (count > 0) H5Dvlen_reclaim(type.id, space.id, H5P_DEFAULT, raw.data());
  return out;
}

double Hdf5Reader::attribute(const std::string& object, const std::string& name, double fallback) const {
  if (!has(object) || H5Aexists_by_name(static_cast<hid_t>(file_), object.c_str(), name.c_str(), H5P_DEFAULT) <= 0)
    return fallback;
  Handle a{H5Aopen_by_name(static_cast<hid_t>(file_), object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT),
           H5Aclose};
  double v = fallback;
  if (H5Aread(a.id, H5T_NATIVE_DOUBLE, &v) < 0) return fallback;
  return v;
}

std::string Hdf5Reader::textAttribute(const std::string& object, const std::string& name,
                                      const std::string& fallback) const {
  if (!has(object) || H5Aexists_by_name(static_cast<hid_t>(file_), object.c_str(), name.c_str(), H5P_DEFAULT) <= 0)
    return fallback;
  Handle a{H5Aopen_by_name(static_cast<hid_t>(file_), object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT),
           H5Aclose};
  Handle type{H5Aget_type(a.id), H5Tclose};
  if (H5Tget_class(type.id) != H5T_STRING) return fallback;
  if (H5Tis_variable_str(type.id) > 0) {
    char* s = nullptr;
    Handle mem{H5Tget_native_type(type.id, H5T_DIR_ASCEND), H5Tclose};
    if (H5Aread(a.id, mem.id, &s) < 0 || !s) return fallback;
    std::string out(s);
    H5free_memory(s);
    return out;
  }
  std::string out(H5Tget_size(type.id), '\0');
  if (H5Aread(a.id, type.id, out.data()) < 0) return fallback;
  return out.substr(0, out.find('\0'));
}

}  // namespace radnet::cases
