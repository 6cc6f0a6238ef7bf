#include "cases/output/shared_matrices.hpp"

#include <algorithm>
#include <vector>

namespace radnet::cases {
namespace {

// Whether every rank's held rows of a and b have one pattern (then b links to a's).
bool samePatternEverywhere(const CsrRef& a, const CsrRef& b, const solver::RowShare& share) {
  const bool same = a.rows() == b.rows() && a.nonZeros() == b.nonZeros() && a.isCompressed() && b.isCompressed() &&
                    std::equal(a.outerIndexPtr(), a.outerIndexPtr() + a.rows() + 1, b.outerIndexPtr()) &&
                    std::equal(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros(), b.innerIndexPtr());
  return !share.any(!same);
}

// One CSR group from held rows (compressed): the row lengths joined into indptr, then
// `data` (and `indices` unless linked to pattern_from's) by blocks of kVectorBlock entries,
// each block's entries put at their places by their rows' holders and joined.
void writeSharedCsr(Hdf5Writer* h5, const std::string& group, const CsrRef& held, const std::string& units,
                    const Eigen::VectorXd& row_scale, const std::string& pattern_from,
                    const solver::RowShare& share) {
  const Eigen::Index n = held.rows();
  const int* outer = held.outerIndexPtr();
  Eigen::VectorXd length = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i)
    if (share.holds(i)) length[i] = outer[i + 1] - outer[i];
  share.joinRows(length.data(), static_cast<size_t>(n));
  std::vector<long long> indptr(static_cast<size_t>(n) + 1, 0);
  for (Eigen::Index i = 0; i < n; ++i)
    indptr[size_t(i) + 1] = indptr[size_t(i)] + static_cast<long long>(length[i]);
  const long long total = indptr.back();
  auto block = [&](long long first, long long count, double* out, bool indices) {
    std::fill(out, out + count, 0.0);
    auto r = static_cast<Eigen::Index>(std::upper_bound(indptr.begin(), indptr.end(), first) - indptr.begin()) - 1;
    for (; r < n && indptr[size_t(r)] < first + count; ++r) {
      if (!share.holds(r)) continue;
      for (int k = outer[r]; k < outer[r + 1]; ++k) {
        const long long at = indptr[size_t(r)] + (k - outer[r]) - first;
        if (at < 0 || at >= count) continue;
        out[at] = indices ? double(held.innerIndexPtr()[k])
                          : held.valuePtr()[k] * (row_scale.size() ? row_scale[r] : 1.0);
      }
    }
    share.joinRows(out, static_cast<size_t>(count));
  };
  auto write = [&](const std::string& path, bool indices) {
    const auto fill = [&](long long first, long long count, double* out) { block(first, count, out, indices); };
    if (h5 && indices) h5->writeIntegerBlocks(path, total, fill, "1");
    else if (h5) h5->writeVectorBlocks(path, total, fill, units);
    else {  // the same blocks, in the same order, as rank 0's writer asks for them
      std::vector<double> buffer(static_cast<size_t>(std::min(total, Hdf5Writer::kVectorBlock)));
      for (long long first = 0; first < total; first += Hdf5Writer::kVectorBlock)
        fill(first, std::min(Hdf5Writer::kVectorBlock, total - first), buffer.data());
    }
  };
  write(group + "/data", false);
  if (pattern_from.empty()) write(group + "/indices", true);
  if (!h5) return;
  if (pattern_from.empty()) {
    h5->writeLongs(group + "/indptr", indptr, "1");
  } else {
    h5->link(pattern_from + "/indices", group + "/indices");
    h5->link(pattern_from + "/indptr", group + "/indptr");
  }
  h5->attribute(group, "shape", std::vector<long long>{static_cast<long long>(n), static_cast<long long>(held.cols())});
  h5->attribute(group, "format", std::string("csr"));
  h5->attribute(group, "units", units);
}

const SparseRows& compressed(const SparseRows& m, SparseRows& copy) {
  if (m.isCompressed()) return m;
  copy = m;
  copy.makeCompressed();
  return copy;
}

void linkNetwork(Hdf5Writer* h5, const std::string& name) {
  if (h5) h5->link("/network/sparse/" + name, "/network/" + name);
}

}  // namespace

bool sharedRowsResult(const GeometryRunResult& r) {
  return r.radiative.network && !r.radiative.network->share().whole();
}

void writeSharedMatrices(Hdf5Writer* h5, const GeometryRunResult& r) {
  if (!sharedRowsResult(r)) return;
  const solver::Network& net = *r.radiative.network;
  const solver::RowShare& share = net.share();
  const Eigen::Map<const SparseRows> g = rowsOfSymmetric(net.sparseConductance());
  const std::string conductance = "/network/sparse/conductance";
  writeSharedCsr(h5, conductance, g, "m^2", {}, "", share);
  linkNetwork(h5, "conductance");
  writeSharedCsr(h5, "/network/sparse/view_factors", g, "1", net.area().cwiseInverse(), conductance, share);
  linkNetwork(h5, "view_factors");
  if (const auto& ex = r.radiative.exchange; ex && ex->factored())
    writeSharedCsr(h5, "/network/radiative_exchange_factors/direct", ex->direct, "m^2", {},
                   samePatternEverywhere(g, ex->direct, share) ? conductance : "", share);
  const std::string raw = "/network/sparse/view_factors_raw";
  SparseRows raw_copy, sigma_copy;  // compressed copies only of rows left uncompressed
  const SparseRows& raw_f = compressed(r.raw_view_factors, raw_copy);
  const SparseRows& sigma = compressed(r.view_factor_stderr, sigma_copy);
  writeSharedCsr(h5, raw, raw_f, "1", {}, "", share);
  linkNetwork(h5, "view_factors_raw");
  writeSharedCsr(h5, "/network/sparse/view_factor_stderr", sigma, "1", {},
                 samePatternEverywhere(raw_f, sigma, share) ? raw : "", share);
  linkNetwork(h5, "view_factor_stderr");
}

}  // namespace radnet::cases
