#include "cases/output/hdf5_writer.hpp"

#include "cases/config/errors.hpp"
#include "cases/config/hdf5_handle.hpp"
#include "cases/output/hdf5_checks.hpp"
#include "cases/output/hdf5_chunks.hpp"
#include "cases/output/output_guard.hpp"

#include <algorithm>

#include <hdf5.h>

#include <sys/stat.h>
#include <unistd.h>
#include <cstdio>
#include <stdexcept>

namespace radnet::cases {
namespace {

using namespace hdf5_detail;  // check, checkId, createLinkProps, Handle

void writeStringAttribute(hid_t obj, const std::string& name, const std::string& value) {
  // Variable-length UTF-8, so that h5py returns str rather than bytes.
  Handle type{checkId(H5Tcopy(H5T_C_S1), "string type"), H5Tclose};
  check(H5Tset_size(type.id, H5T_VARIABLE), "variable string");
  check(H5Tset_cset(type.id, H5T_CSET_UTF8), "string charset");
  Handle space{checkId(H5Screate(H5S_SCALAR), "scalar space"), H5Sclose};
  if (H5Aexists(obj, name.c_str()) > 0) H5Adelete(obj, name.c_str());
  Handle attr{checkId(H5Acreate2(obj, name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT), "attribute " + name),
              H5Aclose};
  const char* ptr = value.c_str();
  check(H5Awrite(attr.id, type.id, &ptr), "write attribute " + name);
}

}  // namespace

void Hdf5Writer::noLibraryExitHandler() { H5dont_atexit(); }

Hdf5Writer::Hdf5Writer(std::string final_path) : final_path_(std::move(final_path)) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are reported by exceptions, not printed
  // Created exclusively (H5F_ACC_EXCL is O_CREAT | O_EXCL, which follows no symlink): a name
  // planted in a shared folder, a symlink to someone's file included, is passed over, never
  // written through. The next name is tried; 100 taken names in a row is refused.
  for (int attempt = 0; attempt < 100 && file_ < 0; ++attempt) {
    temp_path_ = final_path_ + ".tmp-" + std::to_string(::getpid()) + (attempt ? "-" + std::to_string(attempt) : "");
    registerTemporary(temp_path_);  // a signal removes it (cases/output/output_guard.hpp)
    file_ = H5Fcreate(temp_path_.c_str(), H5F_ACC_EXCL, H5P_DEFAULT, H5P_DEFAULT);
    if (file_ >= 0) break;
    unregisterTemporary(temp_path_);
    struct stat taken{};
    if (::lstat(temp_path_.c_str(), &taken) != 0) break;  // not a name clash: the folder refuses
  }
  if (file_ < 0) throw OutputError("cannot create the output file '" + temp_path_ + "'");
}

Hdf5Writer::~Hdf5Writer() {
  if (!committed_) {
    if (file_ >= 0) H5Fclose(static_cast<hid_t>(file_));
    std::remove(temp_path_.c_str());
    unregisterTemporary(temp_path_);
  }
}

long long Hdf5Writer::ensureGroup(const std::string& path) {
  if (path.empty() || path == "/") return H5Gopen2(static_cast<hid_t>(file_), "/", H5P_DEFAULT);
  if (H5Lexists(static_cast<hid_t>(file_), path.c_str(), H5P_DEFAULT) > 0)
    return H5Oopen(static_cast<hid_t>(file_), path.c_str(), H5P_DEFAULT);
  Handle lcpl{createLinkProps(), H5Pclose};
  return checkId(H5Gcreate2(static_cast<hid_t>(file_), path.c_str(), lcpl.id, H5P_DEFAULT, H5P_DEFAULT),
                 "create group " + path);
}

void Hdf5Writer::addUnits(long long dataset, const std::string& units) {
  writeStringAttribute(static_cast<hid_t>(dataset), "units", units);
}

void Hdf5Writer::writeArray(const std::string& path, long long file_type, long long memory_type, int rank,
                            const unsigned long long* dims, const void* data, const std::string& units, bool deflate) {
  hsize_t hdims[3] = {0, 0, 0};
  hsize_t count = 1;
  for (int k = 0; k < rank; ++k) count *= (hdims[k] = static_cast<hsize_t>(dims[k]));
  Handle space{checkId(H5Screate_simple(rank, hdims, nullptr), "dataspace"), H5Sclose};
  Handle dcpl{checkId(H5Pcreate(H5P_DATASET_CREATE), "dataset properties"), H5Pclose};
  // Large matrices: 256 × 256 chunks, long vectors 65,536 entries (/xdmf's per-triangle
  // copies of node values repeat each value over a node's triangles and shrink tenfold),
  // deflate level 1 (docs/hdf5-layout.md).
  hsize_t chunk[2] = {0, 0};
  deflate = deflate && H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0;
  if (deflate && rank == 2 && count > 4096) {
    chunk[0] = std::min<hsize_t>(hdims[0], kMatrixChunk), chunk[1] = std::min<hsize_t>(hdims[1], kMatrixChunk);
  } else if (deflate && rank == 1 && count > 512) {
    chunk[0] = std::min<hsize_t>(hdims[0], 65536);
  }
  if (chunk[0] > 0) {
    check(H5Pset_chunk(dcpl.id, rank, chunk), "chunking");
    check(H5Pset_deflate(dcpl.id, 1), "deflate");
  }
  Handle lcpl{createLinkProps(), H5Pclose};
  Handle ds{checkId(H5Dcreate2(static_cast<hid_t>(file_), path.c_str(), static_cast<hid_t>(file_type), space.id,
                               lcpl.id, dcpl.id, H5P_DEFAULT),
                    "create dataset " + path),
            H5Dclose};
  const size_t element = H5Tget_size(static_cast<hid_t>(file_type));
  // A numeric array of more than 1 MB whose memory layout is the file's: its chunks deflated
  // on all cores (hdf5_chunks.hpp); HDF5's own filter runs on one. Not shuffled: the (n, P)
  // series and eigenvectors, whose equal nodes repeat whole doubles, grew by up to 22 % on
  // the 6,402-node satellite when their chunks were.
  if (chunk[0] > 0 && count * element > (1u << 20) && H5Tequal(static_cast<hid_t>(file_type), static_cast<hid_t>(memory_type)) > 0) {
    const unsigned long long chunk_dims[2] = {chunk[0], chunk[1]};
    long long chunks = 1;
    for (int k = 0; k < rank; ++k) chunks *= static_cast<long long>((hdims[k] + chunk[k] - 1) / chunk[k]);
    const size_t chunk_bytes = element * chunk[0] * (rank == 2 ? chunk[1] : 1);
    const long long col_chunks = rank == 2 ? static_cast<long long>((hdims[1] + chunk[1] - 1) / chunk[1]) : 1;
    deflateChunks(
        chunks, chunk_bytes, 0,
        [&](long long k, unsigned char* bytes) {
          copyChunk(static_cast<const unsigned char*>(data), rank, dims, chunk_dims, element, k, bytes);
        },
        [&](long long k, const std::vector<unsigned char>& bytes, unsigned filter_mask) {
          const hsize_t offset[2] = {static_cast<hsize_t>(k / col_chunks) * chunk[0],
                                     static_cast<hsize_t>(k % col_chunks) * chunk[1]};
          check(H5Dwrite_chunk(ds.id, H5P_DEFAULT, filter_mask, offset, bytes.size(), bytes.data()), "write " + path);
        },
        path);
  } else if (count > 0) {
    check(H5Dwrite(ds.id, static_cast<hid_t>(memory_type), H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "write " + path);
  }
  addUnits(ds.id, units);
}

void Hdf5Writer::writeStack(const std::string& path, const std::vector<Eigen::MatrixXd>& slices,
                            const std::string& units) {
  const Eigen::Index rows = slices.empty() ? 0 : slices.front().rows(), cols = slices.empty() ? 0 : slices.front().cols();
  std::vector<double> data;
  data.reserve(slices.size() * static_cast<size_t>(rows * cols));
  for (const Eigen::MatrixXd& m : slices)
    for (Eigen::Index i = 0; i < rows; ++i)
      for (Eigen::Index j = 0; j < cols; ++j) data.push_back(m(i, j));
  const unsigned long long dims[3] = {slices.size(), static_cast<unsigned long long>(rows),
                                      static_cast<unsigned long long>(cols)};
  writeArray(path, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 3, dims, data.data(), units);
}

bool Hdf5Writer::has(const std::string& path) const {
  return H5Lexists(static_cast<hid_t>(file_), path.c_str(), H5P_DEFAULT) > 0;
}

void Hdf5Writer::link(const std::string& existing, const std::string& path) {
  Handle lcpl{createLinkProps(), H5Pclose};
  check(H5Lcreate_hard(static_cast<hid_t>(file_), existing.c_str(), static_cast<hid_t>(file_), path.c_str(), lcpl.id,
                       H5P_DEFAULT),
        "link " + path + " to " + existing);
}

void Hdf5Writer::writeIntegers(const std::string& path, const Eigen::Ref<const Eigen::MatrixXi>& m,
                               const std::string& units) {
  const Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> data = m;
  const unsigned long long dims[2] = {static_cast<unsigned long long>(m.rows()),
                                      static_cast<unsigned long long>(m.cols())};
  writeArray(path, H5T_STD_I32LE, H5T_NATIVE_INT, m.cols() == 1 ? 1 : 2, dims, data.data(), units);
}

void Hdf5Writer::writeVector(const std::string& path, const Eigen::Ref<const Eigen::VectorXd>& v,
                             const std::string& units, bool deflate) {
  const Eigen::VectorXd data = v;
  const unsigned long long dims[1] = {static_cast<unsigned long long>(v.size())};
  writeArray(path, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, dims, data.data(), units, deflate);
}

void Hdf5Writer::writeBooleans(const std::string& path, const std::vector<bool>& values) {
  Handle type{checkId(H5Tenum_create(H5T_NATIVE_INT8), "boolean type"), H5Tclose};
  const signed char no = 0, yes = 1;
  check(H5Tenum_insert(type.id, "FALSE", &no), "boolean FALSE");
  check(H5Tenum_insert(type.id, "TRUE", &yes), "boolean TRUE");
  std::vector<signed char> data(values.begin(), values.end());
  const unsigned long long dims[1] = {static_cast<unsigned long long>(values.size())};
  writeArray(path, type.id, type.id, 1, dims, data.data(), "1");
}

void Hdf5Writer::writeStrings(const std::string& path, const std::vector<std::string>& values,
                              const std::string& units) {
  // Variable-length UTF-8 strings: h5py reads them as str/bytes without padding.
  std::vector<const char*> ptrs;
  for (const auto& s : values) ptrs.push_back(s.c_str());
  Handle type{checkId(H5Tcopy(H5T_C_S1), "string type"), H5Tclose};
  check(H5Tset_size(type.id, H5T_VARIABLE), "variable string");
  check(H5Tset_cset(type.id, H5T_CSET_UTF8), "string charset");
  const hsize_t dims[1] = {values.size()};
  Handle space{checkId(H5Screate_simple(1, dims, nullptr), "dataspace"), H5Sclose};
  Handle lcpl{createLinkProps(), H5Pclose};
  Handle ds{
      checkId(H5Dcreate2(static_cast<hid_t>(file_), path.c_str(), type.id, space.id, lcpl.id, H5P_DEFAULT, H5P_DEFAULT),
              "create dataset " + path),
      H5Dclose};
  if (!values.empty()) check(H5Dwrite(ds.id, type.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, ptrs.data()), "write " + path);
  addUnits(ds.id, units);
}

void Hdf5Writer::writeText(const std::string& path, const std::string& text) {
  Handle type{checkId(H5Tcopy(H5T_C_S1), "string type"), H5Tclose};
  check(H5Tset_size(type.id, H5T_VARIABLE), "variable string");
  check(H5Tset_cset(type.id, H5T_CSET_UTF8), "string charset");
  Handle space{checkId(H5Screate(H5S_SCALAR), "scalar space"), H5Sclose};
  Handle lcpl{createLinkProps(), H5Pclose};
  Handle ds{
      checkId(H5Dcreate2(static_cast<hid_t>(file_), path.c_str(), type.id, space.id, lcpl.id, H5P_DEFAULT, H5P_DEFAULT),
              "create dataset " + path),
      H5Dclose};
  const char* ptr = text.c_str();
  check(H5Dwrite(ds.id, type.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, &ptr), "write " + path);
  addUnits(ds.id, "");
}

namespace {
hid_t fixedStringType(size_t width) {
  const hid_t type = H5Tcopy(H5T_C_S1);
  if (type < 0 || H5Tset_size(type, std::max<size_t>(width, 1)) < 0 || H5Tset_strpad(type, H5T_STR_SPACEPAD) < 0)
    throw OutputError("HDF5: fixed-length string type of " + std::to_string(width) + " bytes");
  return type;
}
}  // namespace

void Hdf5Writer::writeFixedStrings(const std::string& path, const std::vector<unsigned long long>& dims,
                                   const std::vector<std::string>& values, size_t width) {
  Handle type{fixedStringType(width), H5Tclose};
  std::string data(values.size() * width, ' ');
  for (size_t k = 0; k < values.size(); ++k) data.replace(k * width, std::min(width, values[k].size()), values[k], 0, width);
  writeArray(path, type.id, type.id, static_cast<int>(dims.size()), dims.data(), data.data(), "");
}

void Hdf5Writer::fixedStringAttribute(const std::string& object, const std::string& name, const std::string& value) {
  Handle type{fixedStringType(value.size()), H5Tclose};
  Handle obj{static_cast<hid_t>(ensureGroup(object)), H5Oclose};
  const hsize_t one[1] = {1};
  Handle space{checkId(H5Screate_simple(1, one, nullptr), "attribute space"), H5Sclose};
  if (H5Aexists(obj.id, name.c_str()) > 0) H5Adelete(obj.id, name.c_str());
  Handle attr{checkId(H5Acreate2(obj.id, name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT), name), H5Aclose};
  const std::string padded = value.empty() ? " " : value;
  check(H5Awrite(attr.id, type.id, padded.data()), "write attribute " + name);
}

void Hdf5Writer::attribute(const std::string& object, const std::string& name, const std::string& value) {
  Handle obj{static_cast<hid_t>(ensureGroup(object)), H5Oclose};
  writeStringAttribute(obj.id, name, value);
}

void Hdf5Writer::attribute(const std::string& object, const std::string& name, double value) {
  writeScalarAttribute(object, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &value);
}

void Hdf5Writer::attribute(const std::string& object, const std::string& name, long long value) {
  writeScalarAttribute(object, name, H5T_STD_I64LE, H5T_NATIVE_LLONG, &value);
}

void Hdf5Writer::attribute(const std::string& object, const std::string& name, const std::vector<long long>& values) {
  if (values.empty()) throw OutputError("HDF5: empty attribute " + name + " of " + object);
  writeScalarAttribute(object, name, H5T_STD_I64LE, H5T_NATIVE_LLONG, values.data(), values.size());
}

void Hdf5Writer::writeLongs(const std::string& path, const std::vector<long long>& values, const std::string& units) {
  const unsigned long long dims[1] = {values.size()};
  writeArray(path, H5T_STD_I64LE, H5T_NATIVE_LLONG, 1, dims, values.data(), units);
}

void Hdf5Writer::writeScalarAttribute(const std::string& object, const std::string& name, long long file_type,
                                      long long memory_type, const void* value, size_t count) {
  Handle obj{static_cast<hid_t>(ensureGroup(object)), H5Oclose};
  const hsize_t dims[1] = {count};
  Handle space{checkId(count == 0 ? H5Screate(H5S_SCALAR) : H5Screate_simple(1, dims, nullptr), "attribute space"),
               H5Sclose};
  if (H5Aexists(obj.id, name.c_str()) > 0) H5Adelete(obj.id, name.c_str());
  Handle attr{
      checkId(H5Acreate2(obj.id, name.c_str(), static_cast<hid_t>(file_type), space.id, H5P_DEFAULT, H5P_DEFAULT),
              name),
      H5Aclose};
  check(H5Awrite(attr.id, static_cast<hid_t>(memory_type), value), "write attribute " + name);
}

void Hdf5Writer::commit(const std::vector<std::pair<std::string, std::string>>& sidecars) {
  // The id is released whether or not the close succeeds: the destructor must not close it again.
  const herr_t closed = H5Fclose(static_cast<hid_t>(file_));
  file_ = -1;
  if (closed < 0) throw OutputError("HDF5: closing '" + temp_path_ + "' failed");
  PendingFiles pending;  // removes the temporaries, the .h5's too, if anything below fails
  pending.adopt(temp_path_, final_path_);
  for (const auto& [path, text] : sidecars) pending.addText(path, text);
  pending.publish();
  committed_ = true;
}

}  // namespace radnet::cases
