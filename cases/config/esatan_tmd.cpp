#include "cases/config/esatan_tmd.hpp"

#include "cases/config/errors.hpp"
#include "cases/config/hdf5_handle.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <type_traits>

namespace radnet::cases {
namespace {

using Handle = Hdf5Handle;

constexpr const char* kAnalysis = "/AnalysisSet1";
constexpr const char* kData = "/AnalysisSet1/DataGroup1";
// Beyond any thermal model (ESATAN's largest are ~1e5 nodes), and small enough that the
// products below stay far inside 64 bits.
constexpr double kMaxEntries = 4e9;

class TmdReader {
 public:
  explicit TmdReader(std::string path) : path_(std::move(path)) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // the messages here say what is wrong instead
    std::error_code ec;
    if (!std::filesystem::exists(path_, ec)) fail("no such file (expected an ESATAN-TMS .TMD file)");
    if (!std::filesystem::is_regular_file(path_, ec)) fail("not a regular file (expected an ESATAN-TMS .TMD file)");
    file_bytes_ = static_cast<double>(std::filesystem::file_size(path_, ec));
    if (H5Fis_hdf5(path_.c_str()) <= 0) fail("not an HDF5 file, so not an ESATAN-TMS TMD");
    file_ = H5Fopen(path_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    if (file_ < 0) fail("cannot be opened as HDF5");
  }
  ~TmdReader() {
    if (file_ >= 0) H5Fclose(file_);
  }
  TmdReader(const TmdReader&) = delete;
  TmdReader& operator=(const TmdReader&) = delete;

  [[noreturn]] void fail(const std::string& what) const { throw InputError(path_, 0, 0, what); }

  bool has(const std::string& path) const {
    for (size_t end = path.find('/', 1);; end = path.find('/', end + 1)) {
      if (H5Lexists(file_, path.substr(0, end).c_str(), H5P_DEFAULT) <= 0) return false;
      if (end == std::string::npos) return true;
    }
  }

  // The dimensions of dataset `path`, checked to be of one of the ranks allowed and to fit the file.
  std::vector<hsize_t> dims(const std::string& path, int min_rank, int max_rank, double bytes_each) const {
    if (!has(path)) fail("not an ESATAN-TMS TMD: it has no " + path);
    Handle ds{H5Dopen2(file_, path.c_str(), H5P_DEFAULT), H5Dclose};
    Handle space{H5Dget_space(ds.id), H5Sclose};
    const int rank = H5Sget_simple_extent_ndims(space.id);
    if (ds.id < 0 || rank < min_rank || rank > max_rank)
      fail(path + ": expected a dataset of rank " + std::to_string(min_rank) +
           (max_rank > min_rank ? "–" + std::to_string(max_rank) : std::string()));
    std::vector<hsize_t> d(static_cast<size_t>(rank));
    H5Sget_simple_extent_dims(space.id, d.data(), nullptr);
    double count = 1.0;
    for (hsize_t v : d) count *= static_cast<double>(v);
    // Deflate compresses at most ~1000:1: a dataset declared larger than that is malformed.
    if (count > kMaxEntries || count * bytes_each > 1100.0 * file_bytes_ + 16.0 * (1 << 20))
      fail(path + " declares " + std::to_string(static_cast<long long>(count)) + " values, more than the " +
           std::to_string(static_cast<long long>(file_bytes_)) + "-byte file can hold");
    return d;
  }

  // A whole numeric dataset as T (double or int), its dims in `d`; doubles must be finite.
  template <class T>
  std::vector<T> numbers(const std::string& path, std::vector<hsize_t>& d, int min_rank, int max_rank) const {
    d = dims(path, min_rank, max_rank, sizeof(T));
    size_t count = 1;
    for (hsize_t v : d) count *= static_cast<size_t>(v);
    std::vector<T> out(count);
    Handle ds{H5Dopen2(file_, path.c_str(), H5P_DEFAULT), H5Dclose};
    const hid_t type = std::is_same_v<T, double> ? H5T_NATIVE_DOUBLE : H5T_NATIVE_INT;
    if (count && H5Dread(ds.id, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
      fail(path + ": cannot be read as numbers");
    if constexpr (std::is_same_v<T, double>)
      for (double v : out)
        if (!std::isfinite(v)) fail(path + " holds a value that is not finite");
    return out;
  }

  // Fixed-length (ESATAN's, space padded) or variable-length strings, trailing blanks cut.
  std::vector<std::string> strings(const std::string& path, std::vector<hsize_t>& d, int max_rank) const {
    if (!has(path)) fail("not an ESATAN-TMS TMD: it has no " + path);
    Handle ds{H5Dopen2(file_, path.c_str(), H5P_DEFAULT), H5Dclose};
    Handle type{H5Dget_type(ds.id), H5Tclose};
    if (H5Tget_class(type.id) != H5T_STRING) fail(path + ": expected strings");
    // What reading takes: the fixed width of each string, or a pointer and a short text.
    d = dims(path, 1, max_rank, H5Tis_variable_str(type.id) > 0 ? 16.0 : std::max(16.0, double(H5Tget_size(type.id))));
    size_t count = 1;
    for (hsize_t v : d) count *= static_cast<size_t>(v);
    std::vector<std::string> out;
    if (H5Tis_variable_str(type.id) > 0) {
      Handle mem{H5Tcopy(H5T_C_S1), H5Tclose};
      H5Tset_size(mem.id, H5T_VARIABLE);
      std::vector<char*> raw(count, nullptr);
      if (count && H5Dread(ds.id, mem.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data()) < 0) fail(path + ": unreadable");
      for (char* s : raw) out.emplace_back(s ? s : "");
      Handle space{H5Dget_space(ds.id), H5Sclose};
      if (count) H5Dvlen_reclaim(mem.id, space.id, H5P_DEFAULT, raw.data());
    } else {
      const size_t width = H5Tget_size(type.id);
      if (width == 0 || width > 4096) fail(path + ": strings of " + std::to_string(width) + " bytes");
      Handle mem{H5Tcopy(H5T_C_S1), H5Tclose};
      H5Tset_size(mem.id, width);
      std::vector<char> raw(count * width);
      if (count && H5Dread(ds.id, mem.id, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data()) < 0) fail(path + ": unreadable");
      for (size_t k = 0; k < count; ++k) out.emplace_back(raw.data() + k * width, width);
    }
    for (std::string& s : out) s.erase(std::find(s.begin(), s.end(), '\0'), s.end()), s.erase(s.find_last_not_of(' ') + 1);
    return out;
  }

  double attribute(const std::string& object, const char* name, double fallback) const {
    if (!has(object) || H5Aexists_by_name(file_, object.c_str(), name, H5P_DEFAULT) <= 0) return fallback;
    Handle a{H5Aopen_by_name(file_, object.c_str(), name, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
    double v = fallback;
    if (H5Aread(a.id, H5T_NATIVE_DOUBLE, &v) < 0 || !std::isfinite(v)) fail(object + " attribute " + name + ": not a number");
    return v;
  }

 private:
  std::string path_;
  hid_t file_ = -1;
  double file_bytes_ = 0.0;
};

// Which column of the file's real data holds each of kTmdRealAttributes (−1: absent, zeros).
std::array<int, 16> realColumns(const TmdReader& r, size_t& stored) {
  std::vector<hsize_t> d;
  const std::vector<std::string> names = r.strings(std::string(kAnalysis) + "/thermalNodesRealAttributes", d, 1);
  stored = names.size();
  std::array<int, 16> column{};
  for (size_t k = 0; k < kTmdRealAttributes.size(); ++k) {
    const auto it = std::find(names.begin(), names.end(), kTmdRealAttributes[k]);
    column[k] = it == names.end() ? -1 : static_cast<int>(it - names.begin());
  }
  for (int required : {kTmdTemperature, kTmdCapacitance})
    if (column[static_cast<size_t>(required)] < 0)
      r.fail(std::string(kAnalysis) + "/thermalNodesRealAttributes: no '" + kTmdRealAttributes[static_cast<size_t>(required)] + "'");
  return column;
}

void readNodes(const TmdReader& r, TmdFile& f) {
  std::vector<hsize_t> d;
  const std::vector<int> numbers = r.numbers<int>(std::string(kAnalysis) + "/thermalNodes", d, 1, 2);
  const size_t n = static_cast<size_t>(d[0]), stride = d.size() == 2 ? static_cast<size_t>(d[1]) : 1;
  if (n == 0 || stride == 0) r.fail(std::string(kAnalysis) + "/thermalNodes: no node");
  for (size_t i = 0; i < n; ++i) f.node_number.push_back(numbers[i * stride]);
  std::vector<int> sorted = f.node_number;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
    r.fail(std::string(kAnalysis) + "/thermalNodes: a node number is used twice");
  const std::vector<double> times = r.numbers<double>(std::string(kData) + "/times", d, 1, 1);
  if (times.empty()) r.fail(std::string(kData) + "/times: no output time");
  for (size_t k = 1; k < times.size(); ++k)
    if (!(times[k] > times[k - 1])) r.fail(std::string(kData) + "/times: not increasing at entry " + std::to_string(k));
  f.times_s = times;
  const std::string text_path = std::string(kData) + "/thermalNodesStringData";
  const std::vector<std::string> text = r.strings(text_path, d, 3);
  if (d.size() != 3 || d[0] != times.size() || d[1] != n || d[2] < 2)
    r.fail(text_path + ": expected (" + std::to_string(times.size()) + ", " + std::to_string(n) + ", 2)");
  for (size_t t = 0; t < times.size(); ++t)
    for (size_t i = 0; i < n; ++i) {
      const std::string& type = text[(t * n + i) * d[2]];
      if (type != "D" && type != "B" && type != "X")
        r.fail(text_path + ": node " + std::to_string(f.node_number[i]) + " has type '" + type + "' (expected D, B or X)");
      if (t == 0) f.type.push_back(type), f.label.push_back(text[i * d[2] + 1]);
      else if (type != f.type[i])
        r.fail(text_path + ": node " + std::to_string(f.node_number[i]) + " changes type from " + f.type[i] + " to " +
               type + " during the run (not supported)");
    }
}

void readRealData(const TmdReader& r, TmdFile& f) {
  size_t stored = 0;
  const std::array<int, 16> column = realColumns(r, stored);
  std::vector<hsize_t> d;
  const std::string path = std::string(kData) + "/thermalNodesRealData";
  const std::vector<double> data = r.numbers<double>(path, d, 3, 3);
  const size_t nt = f.times_s.size(), n = f.node_number.size();
  if (d[0] != nt || d[1] != n || d[2] != stored)
    r.fail(path + ": expected (" + std::to_string(nt) + ", " + std::to_string(n) + ", " + std::to_string(stored) + ")");
  for (size_t t = 0; t < nt; ++t) {
    Eigen::MatrixXd m = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n), 16);
    for (size_t i = 0; i < n; ++i)
      for (size_t k = 0; k < 16; ++k)
        if (column[k] >= 0) m(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) = data[(t * n + i) * stored + static_cast<size_t>(column[k])];
    f.real.push_back(std::move(m));
  }
}

// conductorsG? (M, ≥2) 1-based node rows and conductorDataG? (nt, M, ≥1) values; absent: none.
TmdConductors readConductors(const TmdReader& r, const TmdFile& f, const char* kind) {
  TmdConductors c;
  const std::string pairs_path = std::string(kAnalysis) + "/conductors" + kind;
  const std::string data_path = std::string(kData) + "/conductorData" + kind;
  const size_t nt = f.times_s.size();
  if (!r.has(pairs_path)) {
    c.nodes.resize(0, 2), c.value.resize(static_cast<Eigen::Index>(nt), 0);
    return c;
  }
  std::vector<hsize_t> d;
  const std::vector<int> pairs = r.numbers<int>(pairs_path, d, 1, 2);
  const size_t m = d[0], stride = d.size() == 2 ? d[1] : 1;
  if (m > 0 && stride < 2) r.fail(pairs_path + ": expected (M, 4) node rows");
  c.nodes.resize(static_cast<Eigen::Index>(m), 2);
  for (size_t k = 0; k < m; ++k)
    for (size_t s = 0; s < 2; ++s) {
      const int row = pairs[k * stride + s];
      if (row < 1 || row > static_cast<int>(f.node_number.size()))
        r.fail(pairs_path + ": conductor " + std::to_string(k + 1) + " names node row " + std::to_string(row) +
               ", not one of the " + std::to_string(f.node_number.size()) + " (1-based)");
      c.nodes(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(s)) = row - 1;
    }
  const std::vector<double> values = r.numbers<double>(data_path, d, 2, 3);
  const size_t width = d.size() == 3 ? d[2] : 1;
  if (d[0] != nt || d[1] != m || width == 0)
    r.fail(data_path + ": expected (" + std::to_string(nt) + ", " + std::to_string(m) + ", 2)");
  c.value.resize(static_cast<Eigen::Index>(nt), static_cast<Eigen::Index>(m));
  for (size_t t = 0; t < nt; ++t)
    for (size_t k = 0; k < m; ++k) c.value(static_cast<Eigen::Index>(t), static_cast<Eigen::Index>(k)) = values[(t * m + k) * width];
  return c;
}

}  // namespace

TmdFile readTmd(const std::string& path) {
  const TmdReader r(path);
  TmdFile f;
  f.celsius_offset_k = r.attribute(kAnalysis, "TAbs", 273.15);
  f.stefan_boltzmann = r.attribute(kAnalysis, "StefanBoltzmann", 5.670374419e-8);
  if (!(f.celsius_offset_k >= 0 && f.celsius_offset_k < 1e4)) r.fail(std::string(kAnalysis) + " attribute TAbs: not an offset in K");
  readNodes(r, f);
  readRealData(r, f);
  f.gl = readConductors(r, f, "GL");
  f.gr = readConductors(r, f, "GR");
  return f;
}

}  // namespace radnet::cases
