#include "cases/pipeline/distributed.hpp"

#include "cases/cluster/cluster.hpp"
#include "cases/config/errors.hpp"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <iterator>

namespace radnet::cases {
namespace {

using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// Appends [count, (row, col, value)…] of the stored entries (explicit zeros too: the
// joined matrix must have the single-process structure).
void pack(const RowSparse& m, std::vector<double>& out) {
  out.push_back(static_cast<double>(m.nonZeros()));
  for (Eigen::Index i = 0; i < m.outerSize(); ++i)
    for (RowSparse::InnerIterator it(m, i); it; ++it) {
      out.push_back(static_cast<double>(i));
      out.push_back(static_cast<double>(it.col()));
      out.push_back(it.value());
    }
}

// Reads one pack() at `at` into `triplets`; returns the position after it.
std::size_t unpack(const std::vector<double>& in, std::size_t at, std::vector<Eigen::Triplet<double>>& triplets) {
  const auto count = static_cast<std::size_t>(in[at++]);
  for (std::size_t k = 0; k < count; ++k, at += 3)
    triplets.emplace_back(static_cast<int>(in[at]), static_cast<int>(in[at + 1]), in[at + 2]);
  return at;
}

void joinVector(Eigen::VectorXd& v) { cluster::join(v.data(), static_cast<std::size_t>(v.size())); }

}  // namespace

void checkSameCase(const std::string& case_path, const LoadedCase& c) {
  if (!cluster::distributed()) return;
  std::vector<std::string> texts;
  std::vector<double> node_areas;
  if (c.geometry) {
    for (const auto& [file, text] : c.geometry->included) texts.push_back(text);
    for (const auto& node : c.geometry->scene.nodes()) node_areas.push_back(node.area_m2);
  }
  // FNV-1a (64 bit) over every byte, split into two exact 32-bit halves for the gather.
  std::uint64_t h = 1469598103934665603ULL;
  const auto mix = [&h](const void* data, std::size_t bytes) {
    for (std::size_t k = 0; k < bytes; ++k) h = (h ^ static_cast<const unsigned char*>(data)[k]) * 1099511628211ULL;
  };
  std::ifstream in(case_path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  mix(bytes.data(), bytes.size());
  for (const std::string& t : texts) mix(t.data(), t.size());
  mix(node_areas.data(), node_areas.size() * sizeof(double));
  const std::vector<double> all = cluster::gatherAll({double(h >> 32), double(h & 0xffffffffULL)});
  for (std::size_t r = 2; r < all.size(); r += 2)
    if (all[r] != all[0] || all[r + 1] != all[1])
      throw InputError(case_path, 0, 0,
                       "MPI rank " + std::to_string(r / 2) + " read a different case than rank 0 (the case file, an "
                       "included file or a mesh differs): start every rank in the same directory on the same files");
}

void joinViewFactorRows(geometry::ViewFactorResult& vf) {
  if (!cluster::distributed()) return;
  std::vector<double> mine;
  pack(vf.view_factors, mine);
  pack(vf.standard_error, mine);
  const std::vector<double> all = cluster::gatherAll(mine);
  // Rank segments in rank order; the triplets of a row all come from its one owner, and
  // setFromTriplets sorts each row's columns: the same matrix as one process builds.
  std::vector<Eigen::Triplet<double>> f, e;
  for (std::size_t at = 0; at < all.size();) {
    at = unpack(all, at, f);
    at = unpack(all, at, e);
  }
  const Eigen::Index n = vf.view_factors.rows();
  vf.view_factors.resize(n, n);
  vf.view_factors.setFromTriplets(f.begin(), f.end());
  vf.standard_error.resize(n, n);
  vf.standard_error.setFromTriplets(e.begin(), e.end());
  for (Eigen::VectorXd* v : {&vf.space, &vf.space_error, &vf.blocked, &vf.blocked_error}) joinVector(*v);
  cluster::sum(vf.rays.data(), vf.rays.size());
  vf.total_rays = 0;
  for (std::int64_t r : vf.rays) vf.total_rays += r;
  cluster::max(&vf.seconds, 1);
}

void joinLoads(orbits::EnvironmentLoads& e) {
  if (!cluster::distributed()) return;
  joinOverRanks({&e.direct, &e.albedo, &e.earth_ir, &e.earth_view_factor, &e.direct_stderr, &e.albedo_stderr,
                &e.earth_ir_stderr});
  std::int64_t counts[4] = {e.planet_rays, e.shadow_rays, e.kernel_rays, e.kernel_fallbacks};
  cluster::sum(counts, 4);
  e.planet_rays = counts[0];
  e.shadow_rays = counts[1];
  e.kernel_rays = counts[2];
  e.kernel_fallbacks = counts[3];
  // Every rank casts its planet nodes as often as one process would cast them all.
  double largest[3] = {static_cast<double>(e.planet_casts), e.shadow_cell_m, e.seconds};
  cluster::max(largest, 3);
  e.planet_casts = static_cast<int>(largest[0]);
  e.shadow_cell_m = largest[1];
  e.seconds = largest[2];
}

void shareEigenPairs(solver::EigenPairs& pairs) {
  if (!cluster::distributed()) return;
  double header[9] = {static_cast<double>(pairs.values.size()), static_cast<double>(pairs.vectors.rows()),
                      static_cast<double>(pairs.method),        static_cast<double>(pairs.status),
                      pairs.tolerance,                           pairs.dropped_bound,
                      static_cast<double>(pairs.iterations),     pairs.probe_residual,
                      pairs.probe_exchange_error};
  cluster::broadcast(header, 9);
  const auto k = static_cast<Eigen::Index>(header[0]), n = static_cast<Eigen::Index>(header[1]);
  pairs.values.resize(k);
  pairs.vectors.resize(n, k);
  pairs.method = static_cast<solver::EigenMethod>(static_cast<int>(header[2]));
  pairs.status = static_cast<solver::Status>(static_cast<int>(header[3]));
  pairs.tolerance = header[4];
  pairs.dropped_bound = header[5];
  pairs.iterations = static_cast<int>(header[6]);
  pairs.probe_residual = header[7];
  pairs.probe_exchange_error = header[8];
  cluster::broadcast(pairs.values.data(), static_cast<std::size_t>(k));
  cluster::broadcast(pairs.vectors.data(), static_cast<std::size_t>(n * k));
  cluster::broadcast(pairs.message);
  cluster::broadcast(pairs.rank_rule, 0);
}

void shareThermal(ThermalOutcome& outcome, int owner) {
  if (!cluster::distributed()) return;
  std::string bytes = cluster::rank() == owner ? packThermal(outcome) : std::string();
  cluster::broadcast(bytes, owner);
  if (cluster::rank() != owner) outcome = unpackThermal(bytes);
}

void joinOverRanks(const std::vector<Eigen::MatrixXd*>& matrices) {
  if (!cluster::distributed()) return;
  std::vector<double> packed;
  for (const Eigen::MatrixXd* m : matrices) packed.insert(packed.end(), m->data(), m->data() + m->size());
  cluster::join(packed.data(), packed.size());
  std::size_t at = 0;
  for (Eigen::MatrixXd* m : matrices) {
    std::copy_n(packed.begin() + static_cast<std::ptrdiff_t>(at), m->size(), m->data());
    at += static_cast<std::size_t>(m->size());
  }
}

void slowestRankTimings(StageTimings& timings) {
  if (!cluster::distributed()) return;
  std::vector<double> seconds;
  for (const auto& entry : timings.entries()) seconds.push_back(entry.second);
  // Every rank runs the same stages in the same order; should the lists differ, each rank
  // keeps its own times rather than pair different stages (all ranks take the same branch).
  double count[2] = {static_cast<double>(seconds.size()), -static_cast<double>(seconds.size())};
  cluster::max(count, 2);
  if (count[0] != -count[1]) return;
  cluster::max(seconds.data(), seconds.size());
  for (std::size_t k = 0; k < seconds.size(); ++k) timings.setSeconds(k, seconds[k]);
}

}  // namespace radnet::cases
