#include "geometry/rays/recast_rows.hpp"

#include "geometry/rays/sampling.hpp"

#include <atomic>
#include <chrono>
#include <stdexcept>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace radnet::geometry {
namespace {

// The Sobol (or random) streams of one node's replicas, as computeViewFactors draws them.
struct Streams {
  std::vector<Sobol4> sobol;
  std::vector<Random4> random;
  Streams(const ViewFactorOptions& opt, int node) {
    for (int r = 0; r < opt.replicas; ++r) {
      const std::uint64_t s = mixSeed(opt.seed, static_cast<std::uint64_t>(node), static_cast<std::uint64_t>(r));
      if (opt.sampling == Sampling::Sobol) sobol.emplace_back(s);
      else random.emplace_back(s);
    }
  }
  std::array<double, 4> draw(int r) {
    return sobol.empty() ? random[static_cast<size_t>(r)].next() : sobol[static_cast<size_t>(r)].next();
  }
};

// Samples [from, to) of every replica: redirectable rays traced into `moving` (and, with
// `rays`, kept), the others traced into `kept` when it is given (the arrangement as written),
// skipped otherwise.
std::int64_t castRange(const RayCaster& caster, const NodeSampler& sampler, Streams& streams, int node,
                       std::int64_t from, std::int64_t to, const RayMayChange& may_change,
                       std::vector<tally::Tally>& moving, std::vector<tally::Tally>* kept,
                       std::vector<std::vector<RecastPlan::Ray>>* rays = nullptr) {
  std::int64_t traced = 0;
  for (size_t r = 0; r < moving.size(); ++r) {
    if (!streams.sobol.empty()) streams.sobol[r].seek(static_cast<std::uint32_t>(from));
    for (std::int64_t i = from; i < to; ++i) {
      const NodeSampler::Ray ray = sampler.map(streams.draw(static_cast<int>(r)));
      const bool changes = may_change(node, ray.point, ray.direction);
      if (!changes && !kept) continue;
      const Vec3 origin = caster.offsetOrigin(ray.point, ray.normal);
      const Hit hit = caster.firstHit(origin, ray.direction, ray.face);
      ++(changes ? moving[r] : (*kept)[r])[tally::classify(caster, hit)];
      traced += changes;
      if (changes && rays) (*rays)[r].push_back({origin, ray.direction, ray.face});
    }
  }
  return traced;
}

// The kept redirectable rays of one row, moved with its part, traced in `moved`.
void traceKept(const RayCaster& moved, const std::vector<std::vector<RecastPlan::Ray>>& rays,
               const Eigen::Isometry3d& motion, std::vector<tally::Tally>& tallies) {
  for (size_t r = 0; r < rays.size(); ++r)
    for (const RecastPlan::Ray& ray : rays[r])
      ++tallies[r][tally::classify(moved, moved.firstHit(motion * ray.origin, motion.linear() * ray.direction, ray.face))];
}

std::vector<tally::Tally> sum(const std::vector<tally::Tally>& a, const std::vector<tally::Tally>& b) {
  std::vector<tally::Tally> out = a;
  for (size_t r = 0; r < b.size(); ++r)
    for (const auto& [target, count] : b[r]) out[r][target] += count;
  return out;
}

// Fills row i of `res` from its replicas' counts.
void storeRow(int i, const std::vector<tally::Tally>& tallies, std::int64_t per_replica,
              std::vector<std::vector<std::pair<int, double>>>& rows,
              std::vector<std::vector<std::pair<int, double>>>& errors, ViewFactorResult& res) {
  double space[2], blocked[2];
  tally::rowEstimate(tallies, double(per_replica), rows[static_cast<size_t>(i)], errors[static_cast<size_t>(i)], space,
                     blocked);
  res.space[i] = space[0];
  res.space_error[i] = space[1];
  res.blocked[i] = blocked[0];
  res.blocked_error[i] = blocked[1];
  res.rays[static_cast<size_t>(i)] = per_replica * static_cast<std::int64_t>(tallies.size());
}

ViewFactorResult assemble(int n, const std::vector<std::vector<std::pair<int, double>>>& rows,
                          const std::vector<std::vector<std::pair<int, double>>>& errors, ViewFactorResult res) {
  std::vector<Eigen::Triplet<double>> f, e;
  for (int i = 0; i < n; ++i) {
    for (const auto& [j, v] : rows[static_cast<size_t>(i)]) f.emplace_back(i, j, v);
    for (const auto& [j, v] : errors[static_cast<size_t>(i)]) e.emplace_back(i, j, v);
  }
  res.view_factors.resize(n, n);
  res.view_factors.setFromTriplets(f.begin(), f.end());
  res.standard_error.resize(n, n);
  res.standard_error.setFromTriplets(e.begin(), e.end());
  return res;
}

ViewFactorResult emptyResult(int n) {
  ViewFactorResult res;
  res.space = res.space_error = res.blocked = res.blocked_error = Eigen::VectorXd::Zero(n);
  res.rays.assign(static_cast<size_t>(n), 0);
  return res;
}

}  // namespace

ViewFactorResult castPlannedRows(const RayCaster& caster, const ViewFactorOptions& opt, const RayMayChange& may_change,
                                 RecastPlan& plan) {
  if (opt.replicas < 2) throw std::invalid_argument("view factors need at least 2 replicas for an error estimate");
  const auto t0 = std::chrono::steady_clock::now();
  const int n = static_cast<int>(caster.scene().nodes().size());
  plan.options = opt;
  plan.per_replica.assign(static_cast<size_t>(n), 0);
  plan.kept.assign(static_cast<size_t>(n), {});
  plan.traced.assign(static_cast<size_t>(n), 0);
  plan.rays.assign(static_cast<size_t>(n), {});
  std::atomic<std::int64_t> kept_rays{0};  // across rows: the memory they take
  const auto fits = [&] { return double(kept_rays.load()) * sizeof(RecastPlan::Ray) <= kMaxKeptRayBytes; };
  std::vector<std::vector<std::pair<int, double>>> rows(static_cast<size_t>(n)), errors(static_cast<size_t>(n));
  ViewFactorResult res = emptyResult(n);
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1)
#endif
  for (int i = 0; i < n; ++i) {
    if (opt.cast_rows.empty() || !opt.cast_rows[static_cast<size_t>(i)]) continue;
    std::vector<std::vector<RecastPlan::Ray>>& row_rays = plan.rays[static_cast<size_t>(i)];
    row_rays.assign(static_cast<size_t>(opt.replicas), {});
    const NodeSampler sampler(caster.scene(), i);
    Streams streams(opt, i);
    std::vector<tally::Tally> moving(static_cast<size_t>(opt.replicas)), kept(moving.size());
    const std::int64_t cap = std::max<std::int64_t>(1, opt.rays_per_node / opt.replicas);
    std::int64_t per_replica =
        opt.target_error > 0 ? std::min(cap, std::max<std::int64_t>(1, opt.min_rays_per_node / opt.replicas)) : cap;
    std::int64_t done = 0, traced = 0;
    for (;;) {  // doubling until the target error, as computeViewFactors
      traced += castRange(caster, sampler, streams, i, done, per_replica, may_change, moving, &kept,
                          fits() ? &row_rays : nullptr);
      done = per_replica;
      if (opt.target_error <= 0 || per_replica >= cap ||
          tally::worstError(sum(kept, moving), double(per_replica)) <= opt.target_error)
        break;
      per_replica = std::min(cap, 2 * per_replica);
    }
    plan.per_replica[static_cast<size_t>(i)] = per_replica;
    plan.traced[static_cast<size_t>(i)] = traced;
    kept_rays += traced;
    storeRow(i, sum(kept, moving), per_replica, rows, errors, res);
    plan.kept[static_cast<size_t>(i)] = std::move(kept);
  }
  // Every row's redirectable rays, or none (a row cut short by the memory is no use).
  std::int64_t held = 0;
  for (int i = 0; i < n; ++i)
    for (const auto& replica : plan.rays[static_cast<size_t>(i)]) held += static_cast<std::int64_t>(replica.size());
  std::int64_t redirectable = 0;
  for (std::int64_t t : plan.traced) redirectable += t;
  plan.rays_kept = held == redirectable;
  if (!plan.rays_kept) plan.rays.assign(static_cast<size_t>(n), {});
  for (std::int64_t r : res.rays) res.total_rays += r;
  res = assemble(n, rows, errors, std::move(res));
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

void addPlannedRows(const RayCaster& caster, const RayMayChange& may_change, const std::vector<char>& rows,
                    RecastPlan& plan) {
  const size_t n = caster.scene().nodes().size();
  if (rows.size() != n || plan.per_replica.size() != n) throw std::invalid_argument("planned rows: one entry per node");
  ViewFactorOptions opt = plan.options;
  opt.cast_rows = rows;
  RecastPlan more;
  castPlannedRows(caster, opt, may_change, more);
  std::int64_t held = 0;
  for (size_t i = 0; i < n; ++i) {
    if (rows[i]) {
      plan.per_replica[i] = more.per_replica[i];
      plan.kept[i] = std::move(more.kept[i]);
      plan.traced[i] = more.traced[i];
      plan.rays[i] = std::move(more.rays[i]);
      if (!plan.options.cast_rows.empty()) plan.options.cast_rows[i] = 1;
    }
    for (const auto& replica : plan.rays[i]) held += static_cast<std::int64_t>(replica.size());
  }
  // Every row's redirectable rays within the memory they may take, or none.
  plan.rays_kept = plan.rays_kept && more.rays_kept && double(held) * sizeof(RecastPlan::Ray) <= kMaxKeptRayBytes;
  if (!plan.rays_kept) plan.rays.assign(n, {});
}

std::vector<double> redirectableShares(const Scene& scene, const ViewFactorOptions& opt, const RayMayChange& may_change,
                                       const std::vector<char>& rows, std::int64_t per_replica) {
  const int n = static_cast<int>(scene.nodes().size());
  std::vector<double> share(static_cast<size_t>(n), 0.0);
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 16)
#endif
  for (int i = 0; i < n; ++i) {
    if (!rows[static_cast<size_t>(i)]) continue;
    const NodeSampler sampler(scene, i);
    Streams streams(opt, i);
    std::int64_t redirectable = 0;
    for (int r = 0; r < opt.replicas; ++r)
      for (std::int64_t k = 0; k < per_replica; ++k) {
        const NodeSampler::Ray ray = sampler.map(streams.draw(r));
        redirectable += may_change(i, ray.point, ray.direction);
      }
    share[static_cast<size_t>(i)] = double(redirectable) / double(std::max<std::int64_t>(1, per_replica * opt.replicas));
  }
  return share;
}

ViewFactorResult recastRows(const RayCaster& moved, const RecastPlan& plan, const RayMayChange& may_change,
                            const std::vector<Eigen::Isometry3d>& node_motion, const std::vector<char>& only) {
  const auto t0 = std::chrono::steady_clock::now();
  const int n = static_cast<int>(moved.scene().nodes().size());
  std::vector<std::vector<std::pair<int, double>>> rows(static_cast<size_t>(n)), errors(static_cast<size_t>(n));
  ViewFactorResult res = emptyResult(n);
  std::vector<std::int64_t> traced(static_cast<size_t>(n), 0);
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1)
#endif
  for (int i = 0; i < n; ++i) {
    const std::int64_t per_replica = plan.per_replica[static_cast<size_t>(i)];
    if (per_replica == 0 || (!only.empty() && !only[static_cast<size_t>(i)])) continue;
    const NodeSampler sampler(moved.scene(), i);
    Streams streams(plan.options, i);
    std::vector<tally::Tally> moving(static_cast<size_t>(plan.options.replicas));
    if (plan.rays_kept) {
      traceKept(moved, plan.rays[static_cast<size_t>(i)],
                node_motion.empty() ? Eigen::Isometry3d::Identity() : node_motion[static_cast<size_t>(i)], moving);
      traced[static_cast<size_t>(i)] = plan.traced[static_cast<size_t>(i)];
    } else {
      traced[static_cast<size_t>(i)] = castRange(moved, sampler, streams, i, 0, per_replica, may_change, moving, nullptr);
    }
    storeRow(i, sum(plan.kept[static_cast<size_t>(i)], moving), per_replica, rows, errors, res);
  }
  for (std::int64_t t : traced) res.total_rays += t;  // the rays traced, not the rows' counts
  res = assemble(n, rows, errors, std::move(res));
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace radnet::geometry
