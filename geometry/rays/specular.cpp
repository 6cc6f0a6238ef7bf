#include "geometry/rays/specular.hpp"

#include "geometry/rays/sampling.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <stdexcept>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace radnet::geometry {
namespace {

constexpr int kSpace = -1;
constexpr int kBlocked = -2;

// Weights of one replica: target (node, kSpace or kBlocked) → Σ w.
using WeightTally = std::map<int, double>;

// One ray's path: every surface it meets takes κ w (exchange factors) or records the whole
// arrival w (`arrivals`: external light, whose redirected part the path carries on); the rest
// goes on reflected (probability ρs / (ρs + τ)) or transmitted, at weight (ρs + τ) w; Russian
// roulette below kRouletteWeight. Paths cut at kMaxRedirections count as blocked.
void tracePath(const RayCaster& caster, const SpecularBand& band, Vec3 origin, Vec3 dir, int face,
               std::mt19937_64& rng, WeightTally& tally, double w = 1.0, bool arrivals = false) {
  const Scene& scene = caster.scene();
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const double roulette = kRouletteWeight * w;  // relative to the weight the path started with
  for (int redirections = 0;; ++redirections) {
    const Hit hit = caster.firstHit(origin, dir, face);
    if (hit.face < 0) {
      tally[kSpace] += w;
      return;
    }
    const Face& f = scene.faces()[static_cast<size_t>(hit.face)];
    const int node = hit.front ? f.front_node : f.back_node;
    if (node < 0) {
      tally[kBlocked] += w;
      return;
    }
    const double rs = band.specular[node], tau = band.transmittance[node];
    const double kappa = std::max(0.0, 1.0 - rs - tau);
    if (arrivals)
      tally[node] += w;
    else if (kappa > 0)
      tally[node] += w * kappa;
    const double carry = rs + tau;
    if (!(carry > 0)) return;
    if (redirections >= kMaxRedirections) {
      tally[kBlocked] += w * carry;
      return;
    }
    w *= carry;
    if (w < roulette) {
      if (uniform(rng) * roulette >= w) return;  // ended: its expected weight is kept by the survivors
      w = roulette;
    }
    const Vec3 point = origin + hit.distance * dir;
    const bool reflect = uniform(rng) * carry < rs;
    const Vec3 side = hit.front ? f.normal : Vec3(-f.normal);  // the side the ray arrived on
    if (reflect) {
      dir = specularDirection(scene, hit.face, point, dir, hit.front);
      origin = caster.offsetOrigin(point, side);
    } else {
      origin = caster.offsetOrigin(point, -side);  // through the sheet, the direction unchanged
    }
    face = hit.face;
  }
}

std::pair<double, double> weightStats(const std::vector<WeightTally>& tallies, int target, double per_replica) {
  const double r = static_cast<double>(tallies.size());
  double sum = 0.0, sum2 = 0.0;
  for (const WeightTally& t : tallies) {
    const auto it = t.find(target);
    const double p = it == t.end() ? 0.0 : it->second / per_replica;
    sum += p;
    sum2 += p * p;
  }
  const double mean = sum / r;
  return {mean, std::sqrt(std::max(0.0, (sum2 - r * mean * mean) / (r - 1.0)) / r)};
}

struct TracedRow {
  std::vector<std::pair<int, double>> values, errors;
  double space[2] = {0, 0}, blocked[2] = {0, 0};
  std::int64_t rays = 0;
};

TracedRow traceRow(const RayCaster& caster, const SpecularBand& band, int node, const ViewFactorOptions& opt) {
  TracedRow row;
  if (!(1.0 - band.specular[node] - band.transmittance[node] > 0)) {  // a pure mirror: no radiosity node
    row.space[0] = 1.0;
    return row;
  }
  const NodeSampler sampler(caster.scene(), node);
  const int replicas = opt.replicas;
  std::vector<WeightTally> tallies(static_cast<size_t>(replicas));
  std::vector<Sobol4> sobol;
  std::vector<std::mt19937_64> rng;
  for (int r = 0; r < replicas; ++r) {
    sobol.emplace_back(mixSeed(opt.seed, static_cast<std::uint64_t>(node), static_cast<std::uint64_t>(r)));
    rng.emplace_back(mixSeed(opt.seed ^ 0x5bd1e995u, static_cast<std::uint64_t>(node), static_cast<std::uint64_t>(r)));
  }
  const std::int64_t cap = std::max<std::int64_t>(1, opt.rays_per_node / replicas);
  std::int64_t per_replica =
      opt.target_error > 0 ? std::min(cap, std::max<std::int64_t>(1, opt.min_rays_per_node / replicas)) : cap;
  std::int64_t done = 0;
  for (;;) {
    for (int r = 0; r < replicas; ++r) {
      sobol[static_cast<size_t>(r)].seek(static_cast<std::uint32_t>(done));
      for (std::int64_t i = done; i < per_replica; ++i) {
        const NodeSampler::Ray ray = sampler.map(sobol[static_cast<size_t>(r)].next());
        tracePath(caster, band, caster.offsetOrigin(ray.point, ray.normal), ray.direction, ray.face,
                  rng[static_cast<size_t>(r)], tallies[static_cast<size_t>(r)]);
      }
    }
    done = per_replica;
    if (opt.target_error <= 0 || per_replica >= cap) break;
    std::set<int> targets;
    for (const WeightTally& t : tallies)
      for (const auto& kv : t) targets.insert(kv.first);
    double worst = 0.0;
    for (int target : targets) worst = std::max(worst, weightStats(tallies, target, double(per_replica)).second);
    if (worst <= opt.target_error) break;
    per_replica = std::min(cap, 2 * per_replica);
  }
  row.rays = per_replica * replicas;
  std::set<int> targets;
  for (const WeightTally& t : tallies)
    for (const auto& kv : t) targets.insert(kv.first);
  for (int target : targets) {
    const auto [mean, err] = weightStats(tallies, target, double(per_replica));
    if (target == kSpace) {
      row.space[0] = mean, row.space[1] = err;
    } else if (target == kBlocked) {
      row.blocked[0] = mean, row.blocked[1] = err;
    } else {
      row.values.emplace_back(target, mean);
      row.errors.emplace_back(target, err);
    }
  }
  return row;
}

// Light travelling along `travel` that reaches node j at sample `at` (its side), carried on at
// weight w: reflected (probability ρs/(ρs + τ)) or passed through, every arrival recorded whole.
void passOn(const RayCaster& caster, const SpecularBand& band, int j, const NodeSampler::Ray& at, const Vec3& travel,
            std::mt19937_64& rng, WeightTally& tally, double w) {
  const Scene& scene = caster.scene();
  const double rs = band.specular[j], tau = band.transmittance[j];
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  if (uniform(rng) * (rs + tau) < rs)
    tracePath(caster, band, caster.offsetOrigin(at.point, at.normal),
              specularDirection(scene, at.face, at.point, travel, scene.nodes()[static_cast<size_t>(j)].side > 0),
              at.face, rng, tally, w, true);
  else
    tracePath(caster, band, caster.offsetOrigin(at.point, -at.normal), travel, at.face, rng, tally, w, true);
}

// Node j's share of the beam: `replicas` × `per_replica` points, each lit one starting the
// reflected or transmitted path at its weight A_j cos / N (m² per unit flux). Returns the points.
std::int64_t redirectFromNode(const RayCaster& caster, const SpecularBand& band, int j, const Vec3& toward_source,
                              std::int64_t per_replica, int replicas, std::uint64_t seed,
                              std::vector<WeightTally>& mine) {
  const Scene& scene = caster.scene();
  const Node& node = scene.nodes()[static_cast<size_t>(j)];
  const double rs = band.specular[j], tau = band.transmittance[j];
  const Vec3 travel = -toward_source;
  const NodeSampler sampler(scene, j);
  std::int64_t rays = 0;
  mine.resize(static_cast<size_t>(replicas));
  for (int r = 0; r < replicas; ++r) {
    Sobol4 sobol(mixSeed(seed ^ 0x9e3779b9u, static_cast<std::uint64_t>(j), static_cast<std::uint64_t>(r)));
    std::mt19937_64 rng(mixSeed(seed ^ 0x85ebca6bu, static_cast<std::uint64_t>(j), static_cast<std::uint64_t>(r)));
    for (std::int64_t k = 0; k < per_replica; ++k) {
      const auto u = sobol.next();
      const NodeSampler::Ray at = sampler.mapPoint(u[0], u[1]);
      const double cosine = at.normal.dot(toward_source);
      if (!(cosine > 0)) continue;  // the node's side faces away from the source here
      const Vec3 lit_from = caster.offsetOrigin(at.point, at.normal);
      ++rays;
      if (caster.occluded(lit_from, toward_source, at.face)) continue;
      passOn(caster, band, j, at, travel, rng, mine[static_cast<size_t>(r)],
             node.area_m2 * cosine / double(per_replica) * (rs + tau));
    }
  }
  return rays;
}

// Node j's share of the planet's light: a point and a direction in the sphere's cone per
// sample; unobstructed ones start the reflected or transmitted path, each arrival kept with its
// sphere point. Returns the points whose side faced the sphere.
std::int64_t planetFromNode(const RayCaster& caster, const SpecularBand& band, int j, const Vec3& center,
                            double radius, std::int64_t per_replica, int replicas, std::uint64_t seed,
                            RedirectedPlanetPaths& out) {
  const Scene& scene = caster.scene();
  const Node& node = scene.nodes()[static_cast<size_t>(j)];
  const double rs = band.specular[j], tau = band.transmittance[j];
  const NodeSampler sampler(scene, j);
  std::int64_t rays = 0;
  for (int r = 0; r < replicas; ++r) {
    Sobol4 sobol(mixSeed(seed ^ 0xc2b2ae35u, static_cast<std::uint64_t>(j), static_cast<std::uint64_t>(r)));
    std::mt19937_64 rng(mixSeed(seed ^ 0x27d4eb2fu, static_cast<std::uint64_t>(j), static_cast<std::uint64_t>(r)));
    for (std::int64_t k = 0; k < per_replica; ++k) {
      const auto u = sobol.next();
      const NodeSampler::Ray at = sampler.mapPoint(u[0], u[1]);
      const Vec3 to_center = center - at.point;
      const double distance = to_center.norm();
      if (!(distance > radius)) continue;
      // Uniform in the cone of half-angle asin(R/d) about the centre: Ω = 2π (1 − cos θmax).
      const double cos_max = std::sqrt(1.0 - (radius / distance) * (radius / distance));
      const double cos_t = 1.0 - u[2] * (1.0 - cos_max), sin_t = std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t));
      const Vec3 axis = to_center / distance;
      const Vec3 e0 = (std::abs(axis.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(axis).normalized();
      const Vec3 e1 = axis.cross(e0);
      const double phi = 2.0 * M_PI * u[3];
      const Vec3 w = cos_t * axis + sin_t * (std::cos(phi) * e0 + std::sin(phi) * e1);
      const double cosine = at.normal.dot(w);
      if (!(cosine > 0)) continue;
      ++rays;
      Vec3 hit;
      const Vec3 from = caster.offsetOrigin(at.point, at.normal);
      if (!raySphere(at.point, w, center, radius, hit) || caster.occluded(from, w, at.face)) continue;
      WeightTally tally;
      passOn(caster, band, j, at, -w, rng, tally,
             node.area_m2 * 2.0 * M_PI * (1.0 - cos_max) * cosine / double(per_replica) * (rs + tau));
      for (const auto& [target, value] : tally)
        if (target >= 0)
          out.arrivals.push_back({target, r, static_cast<int>(out.hit_points.size()), value});
      out.hit_points.push_back(hit);
    }
  }
  return rays;
}

}  // namespace

Eigen::VectorXd SpecularBand::kappa() const {
  return (Eigen::VectorXd::Ones(specular.size()) - specular - transmittance).cwiseMax(0.0);
}

bool SpecularBand::anyRedirects() const {
  return !empty() && (specular.maxCoeff() > 0 || transmittance.maxCoeff() > 0);
}

Vec3 specularDirection(const Scene& scene, int face, const Vec3& point, const Vec3& dir, bool front) {
  const Face& f = scene.faces()[static_cast<size_t>(face)];
  const Vec3 facet = front ? f.normal : Vec3(-f.normal);  // towards the side the ray came from
  Vec3 n = scene.shadingNormal(face, point);
  if (!front) n = -n;
  Vec3 out = dir - 2.0 * dir.dot(n) * n;
  if (out.dot(facet) <= 0) out = dir - 2.0 * dir.dot(facet) * facet;
  return out.normalized();
}

ViewFactorResult traceSpecularRows(const RayCaster& caster, const SpecularBand& band, const ViewFactorOptions& opt) {
  const Scene& scene = caster.scene();
  const int n = static_cast<int>(scene.nodes().size());
  if (band.specular.size() != n || band.transmittance.size() != n)
    throw std::invalid_argument("specular optics need one value per node");
  if (opt.replicas < 2) throw std::invalid_argument("specular rows need at least 2 replicas for an error estimate");
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<TracedRow> rows(static_cast<size_t>(n));
  int finished = 0;
#ifdef _OPENMP
  const int threads = opt.threads > 0 ? opt.threads : omp_get_max_threads();
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
#endif
  for (int i = 0; i < n; ++i) {
    if (opt.cast_rows.empty() || opt.cast_rows[static_cast<size_t>(i)])
      rows[static_cast<size_t>(i)] = traceRow(caster, band, i, opt);
#ifdef _OPENMP
#pragma omp critical(radnet_specular_progress)
#endif
    {
      ++finished;
      if (opt.progress) opt.progress(finished, n);
    }
  }
  ViewFactorResult res;
  res.space = res.space_error = res.blocked = res.blocked_error = Eigen::VectorXd::Zero(n);
  res.rays.assign(static_cast<size_t>(n), 0);
  std::vector<Eigen::Triplet<double>> f, e;
  for (int i = 0; i < n; ++i) {
    const TracedRow& row = rows[static_cast<size_t>(i)];
    for (const auto& [j, v] : row.values) f.emplace_back(i, j, v);
    for (const auto& [j, v] : row.errors) e.emplace_back(i, j, v);
    res.space[i] = row.space[0], res.space_error[i] = row.space[1];
    res.blocked[i] = row.blocked[0], res.blocked_error[i] = row.blocked[1];
    res.rays[static_cast<size_t>(i)] = row.rays;
    res.total_rays += row.rays;
  }
  res.view_factors.resize(n, n);
  res.view_factors.setFromTriplets(f.begin(), f.end());
  res.standard_error.resize(n, n);
  res.standard_error.setFromTriplets(e.begin(), e.end());
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

RedirectedLight redirectedCollimated(const RayCaster& caster, const SpecularBand& band, const Vec3& toward_source,
                                     int samples, std::uint64_t seed, int replicas) {
  const Scene& scene = caster.scene();
  const int n = static_cast<int>(scene.nodes().size());
  RedirectedLight out;
  out.arrived_m2 = out.stderr_m2 = Eigen::VectorXd::Zero(n);
  if (!band.anyRedirects()) return out;
  const std::int64_t per_replica = std::max(1, samples / std::max(1, replicas));
  std::vector<std::vector<WeightTally>> tallies(static_cast<size_t>(n));
  std::vector<std::int64_t> rays(static_cast<size_t>(n), 0);
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1)
#endif
  for (int j = 0; j < n; ++j)
    if (band.redirects(j))
      rays[static_cast<size_t>(j)] = redirectFromNode(caster, band, j, toward_source, per_replica, replicas, seed,
                                                      tallies[static_cast<size_t>(j)]);
  // Replica sums from every redirecting node are independent: means and variances add.
  for (int j = 0; j < n; ++j) {
    const std::vector<WeightTally>& t = tallies[static_cast<size_t>(j)];
    out.rays += rays[static_cast<size_t>(j)];
    if (t.empty()) continue;
    std::set<int> targets;
    for (const WeightTally& w : t)
      for (const auto& kv : w)
        if (kv.first >= 0) targets.insert(kv.first);
    for (int target : targets) {
      // weightStats divides by per_replica; the weights already carry 1/N: scale back.
      const auto [mean, err] = weightStats(t, target, 1.0);
      out.arrived_m2[target] += mean;
      out.stderr_m2[target] = std::hypot(out.stderr_m2[target], err);
    }
  }
  return out;
}

RedirectedPlanetPaths redirectedPlanetPaths(const RayCaster& caster, const SpecularBand& band,
                                            const Vec3& sphere_center, double sphere_radius, int samples,
                                            std::uint64_t seed, int replicas) {
  const int n = static_cast<int>(caster.scene().nodes().size());
  RedirectedPlanetPaths out;
  out.replicas = replicas;
  if (!band.anyRedirects()) return out;
  const std::int64_t per_replica = std::max(1, samples / std::max(1, replicas));
  std::vector<RedirectedPlanetPaths> parts(static_cast<size_t>(n));
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1)
#endif
  for (int j = 0; j < n; ++j)
    if (band.redirects(j))
      parts[static_cast<size_t>(j)].rays =
          planetFromNode(caster, band, j, sphere_center, sphere_radius, per_replica, replicas, seed,
                         parts[static_cast<size_t>(j)]);
  for (const RedirectedPlanetPaths& part : parts) {  // in node order: the same for any thread count
    const int offset = static_cast<int>(out.hit_points.size());
    out.hit_points.insert(out.hit_points.end(), part.hit_points.begin(), part.hit_points.end());
    for (RedirectedPlanetPaths::Arrival a : part.arrivals) {
      a.hit += offset;
      out.arrivals.push_back(a);
    }
    out.rays += part.rays;
  }
  return out;
}

}  // namespace radnet::geometry
