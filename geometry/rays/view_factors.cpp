#include "geometry/rays/view_factors.hpp"

#include "geometry/rays/sampling.hpp"
#include "geometry/rays/tally.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace radnet::geometry {
namespace {

using tally::classify;
using tally::Tally;

struct Sample {
  std::array<double, 4> u;  ///< point on the node (u0, u1) and direction (u2, u3)
  int replica;
};

// The batch's samples by their first coordinate (which picks the point along the node's
// triangles), to 1/kBuckets: consecutive rays then start close together and walk the same
// part of the hierarchy, which stays in cache: 5–10 % more rays a second on the CubeSatSim
// frame's 3k–10k-triangle parts, within noise on the satellite. A counting sort,
// a few ns a ray; 16,384 samples (0.6 MB) a batch, as larger ones (65,536) pushed the
// hierarchy out of the cache and halved the satellite's rate.
constexpr std::int64_t kBatch = 16384;
constexpr int kBuckets = 16384;
constexpr size_t kFewTriangles = 64;
const std::vector<Sample>& inOriginOrder(const std::vector<Sample>& batch, std::vector<std::int32_t>& start,
                                         std::vector<Sample>& sorted) {
  auto bucket = [](double u0) { return std::min(kBuckets - 1, static_cast<int>(u0 * kBuckets)); };
  start.assign(kBuckets + 1, 0);
  for (const Sample& s : batch) ++start[static_cast<size_t>(bucket(s.u[0])) + 1];
  for (size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
  sorted.resize(batch.size());
  for (const Sample& s : batch) sorted[static_cast<size_t>(start[static_cast<size_t>(bucket(s.u[0]))]++)] = s;
  return sorted;
}

// Casts samples done … per_replica − 1 of every replica into its tally. On a node of many
// triangles all replicas' rays go in batches sorted by origin; a node of a few (a cell of a
// subdivided face) gains nothing from the order and casts as it draws. Each replica draws
// its own sequence in its own order and a tally counts hits: no result depends on the way.
void castSamples(const RayCaster& caster, const NodeSampler& sampler, std::vector<Sobol4>& sobol,
                 std::vector<Random4>& random, std::int64_t done, std::int64_t per_replica, std::vector<Tally>& tallies) {
  const auto replicas = static_cast<int>(tallies.size());
  for (Sobol4& s : sobol) s.seek(static_cast<std::uint32_t>(done));
  auto draw = [&](int r) { return sobol.empty() ? random[static_cast<size_t>(r)].next() : sobol[static_cast<size_t>(r)].next(); };
  auto cast = [&](const std::array<double, 4>& u, int r) {
    const NodeSampler::Ray ray = sampler.map(u);
    const Hit hit = caster.firstHit(caster.offsetOrigin(ray.point, ray.normal), ray.direction, ray.face);
    ++tallies[static_cast<size_t>(r)][classify(caster, hit)];
  };
  if (sampler.triangleCount() <= kFewTriangles) {
    for (int r = 0; r < replicas; ++r)
      for (std::int64_t i = done; i < per_replica; ++i) cast(draw(r), r);
    return;
  }
  const std::int64_t step = std::max<std::int64_t>(1, kBatch / replicas);
  std::vector<Sample> batch, sorted;
  std::vector<std::int32_t> start;
  for (std::int64_t i = done; i < per_replica; i += step) {
    const std::int64_t count = std::min(step, per_replica - i);
    batch.clear();
    for (int r = 0; r < replicas; ++r)
      for (std::int64_t k = 0; k < count; ++k) batch.push_back({draw(r), r});
    for (const Sample& s : inOriginOrder(batch, start, sorted)) cast(s.u, s.replica);
  }
}

// One node's row: rays from `node` until the fixed count or the target error.
void computeViewFactorRow(const RayCaster& caster, int node, const ViewFactorOptions& opt,
                          std::vector<std::pair<int, double>>& row, std::vector<std::pair<int, double>>& row_error,
                          double space[2], double blocked[2], std::int64_t& rays) {
  const Scene& scene = caster.scene();
  const NodeSampler sampler(scene, node);
  const int replicas = opt.replicas;
  std::vector<Tally> tallies(static_cast<size_t>(replicas));
  std::vector<Sobol4> sobol;
  std::vector<Random4> random;
  for (int r = 0; r < replicas; ++r) {
    const std::uint64_t s = mixSeed(opt.seed, static_cast<std::uint64_t>(node), static_cast<std::uint64_t>(r));
    if (opt.sampling == Sampling::Sobol)
      sobol.emplace_back(s);
    else
      random.emplace_back(s);
  }
  const std::int64_t cap = std::max<std::int64_t>(1, opt.rays_per_node / replicas);
  std::int64_t per_replica =
      opt.target_error > 0 ? std::min(cap, std::max<std::int64_t>(1, opt.min_rays_per_node / replicas)) : cap;
  std::int64_t done = 0;
  for (;;) {
    castSamples(caster, sampler, sobol, random, done, per_replica, tallies);
    done = per_replica;
    if (opt.target_error <= 0 || per_replica >= cap) break;
    if (tally::worstError(tallies, double(per_replica)) <= opt.target_error) break;
    per_replica = std::min(cap, 2 * per_replica);
  }
  rays = per_replica * replicas;
  tally::rowEstimate(tallies, double(per_replica), row, row_error, space, blocked);
}

}  // namespace

ViewFactorResult computeViewFactors(const RayCaster& caster, const ViewFactorOptions& opt) {
  if (opt.replicas < 2) throw std::invalid_argument("view factors need at least 2 replicas for an error estimate");
  if (opt.rays_per_node < opt.replicas) throw std::invalid_argument("rays per node must be at least the replica count");
  if (!(opt.target_error >= 0)) throw std::invalid_argument("target error must be >= 0");
  const Scene& scene = caster.scene();
  const int n = static_cast<int>(scene.nodes().size());
  if (!opt.cast_rows.empty() && opt.cast_rows.size() != static_cast<size_t>(n))
    throw std::invalid_argument("cast_rows must have one entry per node");
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::vector<std::pair<int, double>>> rows(static_cast<size_t>(n)), errors(static_cast<size_t>(n));
  ViewFactorResult res;
  res.space = res.space_error = res.blocked = res.blocked_error = Eigen::VectorXd::Zero(n);
  res.rays.assign(static_cast<size_t>(n), 0);
  int finished = 0;
#ifdef _OPENMP
  const int threads = opt.threads > 0 ? opt.threads : omp_get_max_threads();
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
#endif
  for (int i = 0; i < n; ++i) {
    double space[2] = {0, 0}, blocked[2] = {0, 0};
    if (opt.cast_rows.empty() || opt.cast_rows[static_cast<size_t>(i)])
      computeViewFactorRow(caster, i, opt, rows[static_cast<size_t>(i)], errors[static_cast<size_t>(i)], space, blocked,
                         res.rays[static_cast<size_t>(i)]);
    res.space[i] = space[0];
    res.space_error[i] = space[1];
    res.blocked[i] = blocked[0];
    res.blocked_error[i] = blocked[1];
#ifdef _OPENMP
#pragma omp critical(radnet_vf_progress)
#endif
    {
      ++finished;
      if (opt.progress) opt.progress(finished, n);
    }
  }
  std::vector<Eigen::Triplet<double>> f, e;
  for (int i = 0; i < n; ++i) {
    for (const auto& [j, v] : rows[static_cast<size_t>(i)]) f.emplace_back(i, j, v);
    for (const auto& [j, v] : errors[static_cast<size_t>(i)]) e.emplace_back(i, j, v);
    res.total_rays += res.rays[static_cast<size_t>(i)];
  }
  res.view_factors.resize(n, n);
  res.view_factors.setFromTriplets(f.begin(), f.end());
  res.standard_error.resize(n, n);
  res.standard_error.setFromTriplets(e.begin(), e.end());
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace radnet::geometry
