#include "geometry/irradiance/queries.hpp"

#include "geometry/rays/sampling.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace radnet::geometry {

namespace {

// One replica of a node's shadow rays: Σ c, Σ c L and Σ c² (L − ratio)² over `samples`
// Sobol points (c = n·d, L = 1 when lit), for the ratio estimate Σ c L / Σ c.
struct LitSums {
  double weight = 0.0, lit = 0.0, spread = 0.0;
  std::int64_t rays = 0;
};

LitSums litSums(const RayCaster& caster, const NodeSampler& sampler, const Vec3& d, int samples, std::uint64_t seed) {
  Sobol4 sobol(seed);
  std::vector<std::pair<double, bool>> points;
  points.reserve(static_cast<size_t>(samples));
  LitSums s;
  for (int k = 0; k < samples; ++k) {
    const auto u = sobol.next();
    const NodeSampler::Ray p = sampler.mapPoint(u[0], u[1]);
    const double cosine = p.normal.dot(d);
    if (cosine <= 0) continue;
    ++s.rays;
    const bool sunlit = !caster.occluded(caster.offsetOrigin(p.point, p.normal), d, p.face);
    points.emplace_back(cosine, sunlit);
    s.weight += cosine;
    s.lit += sunlit ? cosine : 0.0;
  }
  const double ratio = s.weight > 0 ? s.lit / s.weight : 0.0;
  for (const auto& [c, l] : points) s.spread += c * c * ((l ? 1.0 : 0.0) - ratio) * ((l ? 1.0 : 0.0) - ratio);
  return s;
}

}  // namespace

LitArea litArea(const RayCaster& caster, const Vec3& toward_source, int samples, std::uint64_t seed,
                const std::vector<char>& only, int replicas) {
  const Scene& scene = caster.scene();
  const int n = static_cast<int>(scene.nodes().size());
  LitArea out;
  out.projected_m2 = Eigen::VectorXd::Zero(n);
  out.lit_fraction = out.stderr_m2 = Eigen::VectorXd::Zero(n);
  const Vec3 d = toward_source.normalized();
  replicas = std::max(1, std::min(replicas, samples));
  std::int64_t rays_cast = 0;
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : rays_cast)
#endif
  for (int i = 0; i < n; ++i) {
    if (!only.empty() && !only[static_cast<size_t>(i)]) continue;
    const Node& node = scene.nodes()[static_cast<size_t>(i)];
    double facing = 0.0;  // ∫ max(0, n·d) dA without shadows
    for (int f : node.faces)
      facing += scene.faces()[static_cast<size_t>(f)].area_m2 *
                std::max(0.0, node.side * scene.faces()[static_cast<size_t>(f)].normal.dot(d));
    if (facing <= 0) continue;  // faces away: no rays
    const NodeSampler sampler(scene, i);
    // The ratio estimate facing · Σ c L / Σ c: exact for a node nothing shadows. Its σ:
    // the delta method for one replica (as if the points were independent), else the
    // spread of the replicas' ratios (randomised QMC, honest for Sobol points).
    double sum = 0.0, sum2 = 0.0, only_spread = 0.0, only_weight = 0.0;
    int used = 0;
    for (int r = 0; r < replicas; ++r) {
      const LitSums s = litSums(caster, sampler, d, samples / replicas,
                                mixSeed(seed, static_cast<std::uint64_t>(i), 0x5a17 + static_cast<std::uint64_t>(r)));
      rays_cast += s.rays;
      if (!(s.weight > 0)) continue;
      const double ratio = s.lit / s.weight;
      sum += ratio;
      sum2 += ratio * ratio;
      only_spread = s.spread;
      only_weight = s.weight;
      ++used;
    }
    if (used == 0) continue;
    const double ratio = sum / used;
    out.projected_m2[i] = facing * ratio;
    out.stderr_m2[i] = used == 1 ? facing * std::sqrt(only_spread) / only_weight
                                 : facing * std::sqrt(std::max(0.0, (sum2 - used * ratio * ratio) / (used - 1)) / used);
    out.lit_fraction[i] = ratio;
  }
  out.rays_cast = rays_cast;
  return out;
}

namespace {

constexpr int kPlanetReplicas = 32;

// One node's cone rays in rounds: `per_replica` Sobol points per replica, each an
// area-uniform point on the node and a direction uniform in the cone towards the sphere
// (pdf 1/Ω). A round casts only the points past the last round's in every replica's stream
// and adds them to its running sums in the same order, so the estimate after any round is
// the one a single cast of that many points gives, bit for bit; doubling from 1,024 rays to
// 16,384 used to cast every earlier round's points again (1.9× the rays).
class ConeRayRounds {
 public:
  ConeRayRounds(const RayCaster& caster, const NodeSampler& sampler, int node, const Vec3& center, double radius,
                std::uint64_t seed)
      : caster_(caster), sampler_(sampler), center_(center), radius_(radius) {
    for (int r = 0; r < kPlanetReplicas; ++r)
      replicas_.emplace_back(mixSeed(seed, static_cast<std::uint64_t>(node), 0x9a7e7 + static_cast<std::uint64_t>(r)));
  }

  void castTo(std::int64_t per_replica) {
    for (Replica& rep : replicas_)
      for (std::int64_t k = cast_; k < per_replica; ++k) castOne(rep, rep.sobol.next());
    cast_ = std::max(cast_, per_replica);
  }

  // The estimate of the points cast so far (hits only when `with_hits`: the last round's).
  PlanetRays result(bool with_hits) const {
    PlanetRays pr;
    double sum = 0.0, sum2 = 0.0;
    for (const Replica& rep : replicas_) {
      if (with_hits) {
        pr.hit_points.insert(pr.hit_points.end(), rep.hits.begin(), rep.hits.end());
        pr.weights.insert(pr.weights.end(), rep.weights.begin(), rep.weights.end());
        pr.replica_end.push_back(static_cast<int>(pr.hit_points.size()));
      }
      const double f = rep.total / double(cast_);
      sum += f;
      sum2 += f * f;
    }
    pr.rays = cast_ * kPlanetReplicas;
    pr.view_factor = sum / kPlanetReplicas;
    const double var = (sum2 - kPlanetReplicas * pr.view_factor * pr.view_factor) / (kPlanetReplicas - 1);
    pr.one_ray_share = blocked_ ? largest_weight_ / static_cast<double>(pr.rays) : 0.0;
    pr.standard_error = std::sqrt(std::max(0.0, var) / kPlanetReplicas + pr.one_ray_share * pr.one_ray_share);
    return pr;
  }

 private:
  struct Replica {
    explicit Replica(std::uint64_t seed) : sobol(seed) {}
    Sobol4 sobol;
    double total = 0.0;
    std::vector<Vec3> hits;
    std::vector<double> weights;
  };

  void castOne(Replica& rep, const std::array<double, 4>& u) {
    const NodeSampler::Ray p = sampler_.mapPoint(u[0], u[1]);
    const Vec3 to_center = center_ - p.point;
    const double dist = to_center.norm();
    const Vec3 axis = to_center / dist;
    const double cos_max = dist > radius_ ? std::sqrt(1.0 - (radius_ / dist) * (radius_ / dist)) : 0.0;
    const double solid_angle = 2.0 * M_PI * (1.0 - cos_max);
    largest_weight_ = std::max(largest_weight_, solid_angle / M_PI);
    // Uniform in the cone: cos θ uniform on [cos θ_max, 1], φ uniform.
    const double cos_t = 1.0 - u[2] * (1.0 - cos_max), sin_t = std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t));
    const double phi = 2.0 * M_PI * u[3];
    const Vec3 e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
    const Vec3 dir = (cos_t * axis + sin_t * (std::cos(phi) * e1 + std::sin(phi) * e2)).normalized();
    const double cosine = dir.dot(p.normal);
    if (cosine <= 0) return;  // behind the node's side
    Vec3 at;
    if (!raySphere(p.point, dir, center_, radius_, at)) return;  // grazing: round-off at the limb
    if (caster_.occluded(caster_.offsetOrigin(p.point, p.normal), dir, p.face)) {
      blocked_ = true;
      return;
    }
    const double w = solid_angle * cosine / M_PI;
    rep.hits.push_back(at);
    rep.weights.push_back(w);
    rep.total += w;
  }

  const RayCaster& caster_;
  const NodeSampler& sampler_;
  Vec3 center_;
  double radius_;
  std::vector<Replica> replicas_;
  std::int64_t cast_ = 0;
  bool blocked_ = false;
  double largest_weight_ = 0.0;
};

}  // namespace

std::vector<PlanetRays> planetRays(const RayCaster& caster, const Vec3& center, double radius,
                                   const PlanetRayOptions& opt) {
  const Scene& scene = caster.scene();
  const int n = static_cast<int>(scene.nodes().size());
  const std::int64_t cap = std::max<std::int64_t>(1, opt.rays_per_node / kPlanetReplicas);
  std::vector<PlanetRays> out(static_cast<size_t>(n));
  if (!opt.nodes.empty() && opt.nodes.size() != static_cast<size_t>(n))
    throw std::invalid_argument("planet rays: the node mask must have one entry per node");
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1)
#endif
  for (int i = 0; i < n; ++i) {
    if (!opt.nodes.empty() && !opt.nodes[static_cast<size_t>(i)]) continue;
    const NodeSampler sampler(scene, i);
    std::int64_t per_replica = opt.relative_error > 0 ? std::min<std::int64_t>(cap, 32) : cap;
    ConeRayRounds rounds(caster, sampler, i, center, radius, opt.seed);
    const double dist = (center - sampler.mapPoint(0.5, 0.5).point).norm();
    const double sin_max = std::min(1.0, radius / dist);
    for (;;) {
      rounds.castTo(per_replica);
      const PlanetRays pr = rounds.result(false);
      const double target = opt.relative_error * std::max(pr.view_factor, 0.1 * sin_max * sin_max);
      if (opt.relative_error <= 0 || pr.standard_error <= target || per_replica >= cap) break;
      per_replica = std::min(cap, 2 * per_replica);
    }
    out[static_cast<size_t>(i)] = rounds.result(true);
  }
  return out;
}

std::vector<PlanetRays> planetRays(const RayCaster& caster, const Vec3& center, double radius,
                                   std::int64_t rays_per_node, std::uint64_t seed) {
  PlanetRayOptions opt;
  opt.rays_per_node = rays_per_node;
  opt.seed = seed;
  return planetRays(caster, center, radius, opt);
}

}  // namespace radnet::geometry
