#pragma once
// Atomic HDF5 output (docs/hdf5-layout.md): everything is written to a temporary file beside the
// requested one and renamed at commit(); a run that fails never leaves a half-written
// file under the requested name. Every dataset carries a `units` attribute.
#include <Eigen/Dense>
#include <Eigen/Sparse>

#include <functional>
#include <string>
#include <vector>

namespace radnet::cases {

class Hdf5Writer {
 public:
  /// Chunk edge of large matrices (docs/hdf5-layout.md).
  static constexpr long kMatrixChunk = 256;
  /// @throws std::runtime_error when the temporary file cannot be created
  explicit Hdf5Writer(std::string final_path);
  ~Hdf5Writer();
  /// Call first in main: HDF5 then installs no exit handler. Every file is closed explicitly;
  /// a file whose close failed (a full disk) stays in HDF5's table, and 1.10's handler crashes
  /// closing it again at exit (signal 11 after "closing … failed").
  static void noLibraryExitHandler();
  Hdf5Writer(const Hdf5Writer&) = delete;
  Hdf5Writer& operator=(const Hdf5Writer&) = delete;

  /// (rows×cols) dataset in row-major order as HDF5 expects; intermediate groups are created.
  /// Matrices of more than 4096 entries are chunked and deflate-compressed; from 512 × 512
  /// on, chunks are compressed on all cores (solver/parallel.hpp threads).
  /// `row_scale` (empty: 1) multiplies each row as it is written (F = A⁻¹ G from the dense G
  /// itself, without an n × n copy).
  void writeMatrix(const std::string& path, const Eigen::Ref<const Eigen::MatrixXd>& m, const std::string& units,
                   const Eigen::VectorXd& row_scale = {});
  /// The same dataset from a sparse matrix, each row scaled by `row_scale` (empty: 1), never
  /// formed densely (F = A⁻¹ G of a 6,402-node network is 3.7 % non-zero: 330 MB dense).
  /// A compressed row-major matrix or a Map of one (a symmetric column-major matrix's arrays
  /// read as rows) is read in place.
  using SparseRowsRef = Eigen::Ref<const Eigen::SparseMatrix<double, Eigen::RowMajor>>;
  void writeMatrix(const std::string& path, const SparseRowsRef& m, const std::string& units,
                   const Eigen::VectorXd& row_scale = {});
  /// The same from single-precision values (σ_F of the exact method, kept on F's pattern),
  /// stored as doubles as every matrix of the file.
  using FloatRowsRef = Eigen::Ref<const Eigen::SparseMatrix<float, Eigen::RowMajor>>;
  void writeFloatMatrix(const std::string& path, const FloatRowsRef& m, const std::string& units);
  /// `deflate` false: stored whole (values that do not compress, e.g. a sparse matrix's non-zeros).
  void writeVector(const std::string& path, const Eigen::Ref<const Eigen::VectorXd>& v, const std::string& units,
                   bool deflate = true);
  /// fill(first, count, out): entries first … first + count − 1 of a vector.
  using VectorFill = std::function<void(long long first, long long count, double* out)>;
  /// A vector of `size` doubles stored whole (as writeVector's undeflated ones) but made and
  /// written block by block: values that exist only as a product (a matrix's scaled non-zeros).
  /// fill is called for the blocks [k kVectorBlock, (k + 1) kVectorBlock) in order.
  void writeVectorBlocks(const std::string& path, long long size, const VectorFill& fill, const std::string& units);
  /// The same as 32-bit integers (fill gives them as doubles: exact below 2⁵³).
  void writeIntegerBlocks(const std::string& path, long long size, const VectorFill& fill, const std::string& units);
  static constexpr long long kVectorBlock = 1LL << 20;  ///< entries a block (8 MB of doubles)
  /// (slices, rows, cols) dataset of equally sized matrices.
  void writeStack(const std::string& path, const std::vector<Eigen::MatrixXd>& slices, const std::string& units);
  /// True when `path` exists (its parent groups must: "/a/b" with "/a" written).
  bool has(const std::string& path) const;
  /// A second name for an existing dataset (an HDF5 hard link: no copy).
  void link(const std::string& existing, const std::string& path);
  /// Integer (row-major) dataset, e.g. triangle corner indices.
  void writeIntegers(const std::string& path, const Eigen::Ref<const Eigen::MatrixXi>& m, const std::string& units);
  /// Booleans as HDF5's enum {FALSE = 0, TRUE = 1} of int8, which h5py reads as numpy bool.
  void writeBooleans(const std::string& path, const std::vector<bool>& values);
  void writeStrings(const std::string& path, const std::vector<std::string>& values, const std::string& units = "");
  void writeText(const std::string& path, const std::string& text);
  /// Fixed-length ASCII strings padded with spaces to `width` bytes (longer ones cut), of shape
  /// `dims` (rank 1–3, row-major): the layout of ESATAN's TMD files. Its units attribute is empty.
  void writeFixedStrings(const std::string& path, const std::vector<unsigned long long>& dims,
                         const std::vector<std::string>& values, size_t width);
  /// A one-element fixed-length string attribute (as ESATAN writes Description and Date).
  void fixedStringAttribute(const std::string& object, const std::string& name, const std::string& value);

  /// Attributes on an object (group or dataset); groups are created as needed.
  void attribute(const std::string& object, const std::string& name, const std::string& value);
  void attribute(const std::string& object, const std::string& name, double value);
  void attribute(const std::string& object, const std::string& name, long long value);
  /// A 1-D integer attribute (e.g. a sparse matrix's `shape`).
  void attribute(const std::string& object, const std::string& name, const std::vector<long long>& values);
  /// 64-bit integer vector (e.g. a CSR matrix's `indptr`), chunked and deflated as writeVector.
  void writeLongs(const std::string& path, const std::vector<long long>& values, const std::string& units);

  /// Closes the file, writes each (path, text) sidecar to a temporary, then renames them all
  /// to their names together (PendingFiles): a failure or a signal leaves the old set or the
  /// new one, never a mix.
  void commit(const std::vector<std::pair<std::string, std::string>>& sidecars = {});

 private:
  /// One kMatrixChunk² row-major block of the chunk's bytes (zeroed): filled up to the edge.
  using ChunkBlock = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;
  /// Fills the block whose top-left entry is (row0, col0).
  using ChunkFill = std::function<void(Eigen::Index row0, Eigen::Index col0, ChunkBlock& block)>;
  void writeChunkedMatrix(const std::string& path, Eigen::Index rows, Eigen::Index cols, const ChunkFill& fill,
                          const std::string& units);
  template <class Rows>
  void writeSparseRows(const std::string& path, const Rows& m, const std::string& units,
                       const Eigen::VectorXd& row_scale);
  long long ensureGroup(const std::string& path);
  void writeBlocks(const std::string& path, long long size, const VectorFill& fill, const std::string& units,
                   bool integers);
  // HDF5 ids and sizes passed as plain integers so this header needs no <hdf5.h>.
  void writeArray(const std::string& path, long long file_type, long long memory_type, int rank,
                  const unsigned long long* dims, const void* data, const std::string& units, bool deflate = true);
  void addUnits(long long dataset, const std::string& units);
  void writeScalarAttribute(const std::string& object, const std::string& name, long long file_type,
                            long long memory_type, const void* value, size_t count = 0);

  std::string final_path_;
  std::string temp_path_;
  long long file_ = -1;
  bool committed_ = false;
};

}  // namespace radnet::cases
