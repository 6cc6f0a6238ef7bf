#include "geometry/queries.hpp"

#include "geometry/sampling.hpp"

#include <cmath>

namespace radnet::geometry {

bool raySphere(const Vec3& origin, const Vec3& dir, const Vec3& center, double radius, Vec3& hit) {
  // |o + t d − c|² = r²: t² + 2 b t + c = 0 with b = d·(o − c), c = |o − c|² − r².
  const Vec3 oc = origin - center;
  const double b = dir.dot(oc), c = oc.squaredNorm() - radius * radius;
  const double disc = b * b - c;
  if (disc < 0) return false;
  const double root = std::sqrt(disc);
  // The numerically stable near root (no cancellation when |b| ≫ root, i.e. far planets).
  double t = c > 0 ? c / (-b + root) : -b + root;
  if (b > 0 && c > 0) return false;  // sphere behind the origin
  if (!(t > 0)) return false;
  hit = origin + t * dir;
  return true;
}

LitArea litArea(const RayCaster& caster, const Vec3& toward_source, int samples, std::uint64_t seed) {
  const Scene& scene = caster.scene();
  const int n = static_cast<int>(scene.nodes().size());
  LitArea out;
  out.projected_m2 = Eigen::VectorXd::Zero(n);
  out.lit_fraction = Eigen::VectorXd::Zero(n);
  const Vec3 d = toward_source.normalized();
  std::int64_t rays_cast = 0;
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : rays_cast)
#endif
  for (int i = 0; i < n; ++i) {
    const Node& node = scene.nodes()[static_cast<size_t>(i)];
    double facing = 0.0;  // ∫ max(0, n·d) dA without shadows
    for (int f : node.faces)
      facing += scene.faces()[static_cast<size_t>(f)].area_m2 *
                std::max(0.0, node.side * scene.faces()[static_cast<size_t>(f)].normal.dot(d));
    if (facing <= 0) continue;  // faces away: no rays
    const NodeSampler sampler(scene, i);
    Sobol4 sobol(mixSeed(seed, static_cast<std::uint64_t>(i), 0x5a17));
    double lit = 0.0;
    for (int k = 0; k < samples; ++k) {
      const auto u = sobol.next();
      const NodeSampler::Ray p = sampler.mapPoint(u[0], u[1]);
      const double cosine = p.normal.dot(d);
      if (cosine <= 0) continue;
      ++rays_cast;
      const Hit hit = caster.firstHit(caster.offsetOrigin(p.point, p.normal), d, p.face);
      if (hit.face < 0) lit += cosine;
    }
    out.projected_m2[i] = node.area_m2 * lit / samples;
    out.lit_fraction[i] = out.projected_m2[i] / facing;
  }
  out.rays_cast = rays_cast;
  return out;
}

std::vector<PlanetRays> planetRays(const RayCaster& caster, const Vec3& center, double radius,
                                   std::int64_t rays_per_node, std::uint64_t seed) {
  const Scene& scene = caster.scene();
  const int n = static_cast<int>(scene.nodes().size());
  const int replicas = 32;
  const std::int64_t per_replica = std::max<std::int64_t>(1, rays_per_node / replicas);
  std::vector<PlanetRays> out(static_cast<size_t>(n));
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1)
#endif
  for (int i = 0; i < n; ++i) {
    const NodeSampler sampler(scene, i);
    PlanetRays& pr = out[static_cast<size_t>(i)];
    double sum = 0.0, sum2 = 0.0;
    for (int r = 0; r < replicas; ++r) {
      Sobol4 sobol(mixSeed(seed, static_cast<std::uint64_t>(i), 0x9a7e7 + static_cast<std::uint64_t>(r)));
      std::int64_t hits = 0;
      for (std::int64_t k = 0; k < per_replica; ++k) {
        const NodeSampler::Ray ray = sampler.map(sobol.next());
        Vec3 at;
        if (!raySphere(ray.point, ray.direction, center, radius, at)) continue;
        const Vec3 origin = caster.offsetOrigin(ray.point, ray.normal);
        if (caster.firstHit(origin, ray.direction, ray.face).face >= 0) continue;  // the spacecraft is in the way
        ++hits;
        pr.hit_points.push_back(at);
        pr.directions.push_back(ray.direction);
      }
      const double p = double(hits) / per_replica;
      sum += p;
      sum2 += p * p;
    }
    pr.rays = per_replica * replicas;
    pr.view_factor = sum / replicas;
    pr.standard_error =
        std::sqrt(std::max(0.0, (sum2 - replicas * pr.view_factor * pr.view_factor) / (replicas - 1)) / replicas);
  }
  return out;
}

}  // namespace radnet::geometry
