#include "cases/output/hdf5_writer.hpp"

#include "cases/output/hdf5_checks.hpp"
#include "cases/output/hdf5_chunks.hpp"

#include <algorithm>

#include <hdf5.h>

namespace radnet::cases {
namespace {

using namespace hdf5_detail;  // check, checkId, createLinkProps, Handle

}  // namespace

void Hdf5Writer::writeMatrix(const std::string& path, const Eigen::Ref<const Eigen::MatrixXd>& m,
                             const std::string& units, const Eigen::VectorXd& row_scale) {
  if (m.rows() >= 2 * kMatrixChunk && m.cols() >= 2 * kMatrixChunk && H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0) {
    writeChunkedMatrix(
        path, m.rows(), m.cols(),
        [&](Eigen::Index row0, Eigen::Index col0, auto& block) {
          const Eigen::Index rows = std::min<Eigen::Index>(kMatrixChunk, m.rows() - row0);
          const Eigen::Index cols = std::min<Eigen::Index>(kMatrixChunk, m.cols() - col0);
          block.topLeftCorner(rows, cols) = m.block(row0, col0, rows, cols);
          if (row_scale.size())
            for (Eigen::Index r = 0; r < rows; ++r) block.row(r).head(cols) *= row_scale[row0 + r];
        },
        units);
    return;
  }
  // HDF5 is row-major: (rows, cols) as a reader indexes it. The transposition goes by
  // 64 × 64 tiles that stay in cache.
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> data(m.rows(), m.cols());
  constexpr Eigen::Index kTile = 64;
  for (Eigen::Index j = 0; j < m.cols(); j += kTile)
    for (Eigen::Index i = 0; i < m.rows(); i += kTile) {
      const Eigen::Index rows = std::min(kTile, m.rows() - i), cols = std::min(kTile, m.cols() - j);
      data.block(i, j, rows, cols) = m.block(i, j, rows, cols);
    }
  if (row_scale.size())
    for (Eigen::Index r = 0; r < data.rows(); ++r) data.row(r) *= row_scale[r];
  const unsigned long long dims[2] = {static_cast<unsigned long long>(m.rows()),
                                      static_cast<unsigned long long>(m.cols())};
  writeArray(path, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 2, dims, data.data(), units);
}

void Hdf5Writer::writeMatrix(const std::string& path, const SparseRowsRef& m, const std::string& units,
                             const Eigen::VectorXd& row_scale) {
  writeSparseRows(path, m, units, row_scale);
}

void Hdf5Writer::writeFloatMatrix(const std::string& path, const FloatRowsRef& m, const std::string& units) {
  writeSparseRows(path, m, units, {});
}

template <class Rows>
void Hdf5Writer::writeSparseRows(const std::string& path, const Rows& m, const std::string& units,
                                 const Eigen::VectorXd& row_scale) {
  const auto scale = [&](Eigen::Index r) { return row_scale.size() ? row_scale[r] : 1.0; };
  if (!(m.rows() >= 2 * kMatrixChunk && m.cols() >= 2 * kMatrixChunk && H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0)) {
    Eigen::MatrixXd dense = Eigen::MatrixXd(m.template cast<double>());  // small: the ordinary path
    for (Eigen::Index r = 0; r < dense.rows(); ++r) dense.row(r) *= scale(r);
    writeMatrix(path, dense, units);
    return;
  }
  writeChunkedMatrix(
      path, m.rows(), m.cols(),
      [&](Eigen::Index row0, Eigen::Index col0, auto& block) {
        const Eigen::Index rows = std::min<Eigen::Index>(kMatrixChunk, m.rows() - row0);
        for (Eigen::Index r = 0; r < rows; ++r)
          for (typename Rows::InnerIterator it(m, row0 + r); it; ++it)
            if (it.col() >= col0 && it.col() < col0 + kMatrixChunk)
              block(r, it.col() - col0) = double(it.value()) * scale(row0 + r);
      },
      units);
}

// The layout writeArray gives a large matrix (256 × 256 chunks, shuffle and deflate level 1),
// but each chunk filled (from a dense or a sparse matrix), compressed here on all cores, and
// handed to HDF5 ready (H5Dwrite_chunk): HDF5 1.10 runs its filters on one core, which made
// writing the five n × n matrices the largest stage of a 6,402-node run (14 s), and no
// row-major copy of the whole matrix is needed. Readers see an ordinary shuffled and deflated
// dataset (mostly-zero chunks skip the shuffle, hdf5_chunks.hpp); chunks are written in
// order, so the file does not depend on the thread count.
void Hdf5Writer::writeChunkedMatrix(const std::string& path, Eigen::Index rows, Eigen::Index cols,
                                    const ChunkFill& fill, const std::string& units) {
  const hsize_t dims[2] = {static_cast<hsize_t>(rows), static_cast<hsize_t>(cols)};
  const hsize_t chunk[2] = {kMatrixChunk, kMatrixChunk};
  Handle space{checkId(H5Screate_simple(2, dims, nullptr), "dataspace"), H5Sclose};
  Handle dcpl{checkId(H5Pcreate(H5P_DATASET_CREATE), "dataset properties"), H5Pclose};
  check(H5Pset_chunk(dcpl.id, 2, chunk), "chunking");
  check(H5Pset_shuffle(dcpl.id), "shuffle");
  check(H5Pset_deflate(dcpl.id, 1), "deflate");
  Handle lcpl{createLinkProps(), H5Pclose};
  Handle ds{checkId(H5Dcreate2(static_cast<hid_t>(file_), path.c_str(), H5T_IEEE_F64LE, space.id, lcpl.id, dcpl.id,
                               H5P_DEFAULT),
                    "create dataset " + path),
            H5Dclose};
  const Eigen::Index col_chunks = (cols + kMatrixChunk - 1) / kMatrixChunk;
  const long long chunks = static_cast<long long>((rows + kMatrixChunk - 1) / kMatrixChunk * col_chunks);
  deflateChunks(
      chunks, sizeof(double) * kMatrixChunk * kMatrixChunk, sizeof(double),
      [&](long long k, unsigned char* bytes) {
        ChunkBlock block(reinterpret_cast<double*>(bytes), kMatrixChunk, kMatrixChunk);
        fill(k / col_chunks * kMatrixChunk, k % col_chunks * kMatrixChunk, block);
      },
      [&](long long k, const std::vector<unsigned char>& bytes, unsigned filter_mask) {
        const hsize_t offset[2] = {static_cast<hsize_t>(k / col_chunks * kMatrixChunk),
                                   static_cast<hsize_t>(k % col_chunks * kMatrixChunk)};
        check(H5Dwrite_chunk(ds.id, H5P_DEFAULT, filter_mask, offset, bytes.size(), bytes.data()), "write " + path);
      },
      path);
  addUnits(ds.id, units);
}

// Stored contiguous, as writeVector's undeflated vectors, and written by hyperslabs of
// kVectorBlock entries (8 MB): the 100,002-node F's 2e8 scaled non-zeros never exist whole.
void Hdf5Writer::writeVectorBlocks(const std::string& path, long long size, const VectorFill& fill,
                                   const std::string& units) {
  writeBlocks(path, size, fill, units, false);
}

void Hdf5Writer::writeIntegerBlocks(const std::string& path, long long size, const VectorFill& fill,
                                    const std::string& units) {
  writeBlocks(path, size, fill, units, true);
}

void Hdf5Writer::writeBlocks(const std::string& path, long long size, const VectorFill& fill, const std::string& units,
                             bool integers) {
  const hsize_t dims[1] = {static_cast<hsize_t>(size)};
  Handle space{checkId(H5Screate_simple(1, dims, nullptr), "dataspace"), H5Sclose};
  Handle lcpl{createLinkProps(), H5Pclose};
  Handle ds{checkId(H5Dcreate2(static_cast<hid_t>(file_), path.c_str(), integers ? H5T_STD_I32LE : H5T_IEEE_F64LE,
                               space.id, lcpl.id, H5P_DEFAULT, H5P_DEFAULT),
                    "create dataset " + path),
            H5Dclose};
  std::vector<double> block(static_cast<size_t>(std::min(size, kVectorBlock)));
  std::vector<int> as_int(integers ? block.size() : 0);
  for (long long first = 0; first < size; first += kVectorBlock) {
    const long long count = std::min(kVectorBlock, size - first);
    fill(first, count, block.data());
    const hsize_t offset[1] = {static_cast<hsize_t>(first)}, extent[1] = {static_cast<hsize_t>(count)};
    check(H5Sselect_hyperslab(space.id, H5S_SELECT_SET, offset, nullptr, extent, nullptr), "select " + path);
    Handle memory{checkId(H5Screate_simple(1, extent, nullptr), "memory space"), H5Sclose};
    if (integers) {
      for (long long k = 0; k < count; ++k) as_int[size_t(k)] = static_cast<int>(block[size_t(k)]);
      check(H5Dwrite(ds.id, H5T_NATIVE_INT, memory.id, space.id, H5P_DEFAULT, as_int.data()), "write " + path);
    } else {
      check(H5Dwrite(ds.id, H5T_NATIVE_DOUBLE, memory.id, space.id, H5P_DEFAULT, block.data()), "write " + path);
    }
  }
  addUnits(ds.id, units);
}

}  // namespace radnet::cases
