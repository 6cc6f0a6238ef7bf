#pragma once
// Reads a radnet result back (radnet report, radnet export). Every failure (no such file, not
// an HDF5 file, a dataset missing or of another shape) is an InputError naming the file and
// the dataset, so the commands exit 2 with a message rather than crash.
#include <Eigen/Dense>

#include <map>
#include <string>
#include <vector>

namespace radnet::cases {

class Hdf5Reader {
 public:
  /// @throws InputError when the file cannot be opened as a radnet result (no /meta)
  explicit Hdf5Reader(const std::string& path);
  ~Hdf5Reader();
  Hdf5Reader(const Hdf5Reader&) = delete;
  Hdf5Reader& operator=(const Hdf5Reader&) = delete;

  bool has(const std::string& path) const;
  /// A 1-D or 2-D dataset as stored (rows, cols); a 1-D one is (size × 1). Integers are converted.
  Eigen::MatrixXd matrix(const std::string& path) const;
  Eigen::VectorXd vector(const std::string& path) const;
  /// The first dimension of a dataset, without reading it (0 for a scalar).
  Eigen::Index rows(const std::string& path) const;
  std::vector<std::string> strings(const std::string& path) const;
  /// A numeric or string attribute of an object; `fallback` when it is absent.
  double attribute(const std::string& object, const std::string& name, double fallback) const;
  std::string textAttribute(const std::string& object, const std::string& name, const std::string& fallback) const;
  const std::string& path() const { return path_; }
  /// Keeps every matrix read under these prefixes (e.g. "/solution/") for later reads: a
  /// history of P positions reads each (P × n) dataset once, not P times. Empty: none kept.
  void keepMatricesUnder(std::vector<std::string> prefixes) const {
    keep_prefixes_ = std::move(prefixes);
    kept_.clear();
  }
  /// Reads every dataset and attribute once and discards it: run in a child process
  /// (cases/config/damaged_file_guard.hpp) it shows whether the HDF5 library survives the file at all.
  void readEverything() const;
  /// InputError when dataset `path` declares more bytes than the file could hold.
  void checkLogicalSize(const std::string& path, double bytes) const;

 private:

  Eigen::MatrixXd readMatrix(const std::string& path) const;

  std::string path_;
  long long file_ = -1;
  mutable std::vector<std::string> keep_prefixes_;
  mutable std::map<std::string, Eigen::MatrixXd> kept_;
};

}  // namespace radnet::cases
