#include "orbits/loads.hpp"

#include "solver/units.hpp"

#include <chrono>
#include <cmath>

namespace radnet::orbits {

double albedoAt(const EnvironmentOptions& opt, double lat) {
  const auto& t = opt.albedo_by_latitude;
  if (t.empty()) return opt.albedo;
  lat = std::abs(lat);
  if (lat <= t.front().first) return t.front().second;
  for (size_t k = 1; k < t.size(); ++k)
    if (lat <= t[k].first) {
      const double w = (lat - t[k - 1].first) / (t[k].first - t[k - 1].first);
      return (1 - w) * t[k - 1].second + w * t[k].second;
    }
  return t.back().second;
}

EnvironmentLoads environmentLoads(const geometry::RayCaster& caster, const Eigen::VectorXd& area,
                                  const std::vector<SweepPosition>& positions, bool earth_fixed, double re,
                                  const EnvironmentOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const int n = static_cast<int>(area.size());
  const int P = static_cast<int>(positions.size());
  EnvironmentLoads out;
  out.direct = out.albedo = out.earth_ir = out.earth_view_factor = Eigen::MatrixXd::Zero(n, P);
  std::vector<geometry::PlanetRays> rays;
  Eigen::Vector3d cached_center(0, 0, 0);
  for (int p = 0; p < P; ++p) {
    const SweepPosition& pos = positions[static_cast<size_t>(p)];
    // Direct Sun: no rays in the umbra.
    if (pos.sunlit_fraction > 0) {
      const geometry::LitArea lit = geometry::litArea(caster, pos.sun_body, opt.shadow_samples, opt.seed);
      out.direct.col(p) = (pos.solar_flux_w_m2 * pos.sunlit_fraction) * lit.projected_m2.cwiseQuotient(area);
      out.shadow_rays += lit.rays_cast;
    }
    // Planet rays: cast again unless the Earth sits where it did (reuse).
    const Eigen::Vector3d center = pos.earth_body * pos.earth_distance_m;
    const bool reuse = earth_fixed && !rays.empty() && (center - cached_center).norm() <= 1e-9 * center.norm();
    if (!reuse) {
      rays = geometry::planetRays(caster, center, re, opt.planet_rays, opt.seed);
      cached_center = center;
      ++out.planet_casts;
    }
    const Eigen::Matrix3d eciFromBody = pos.body_from_eci.transpose();
    for (int i = 0; i < n; ++i) {
      const geometry::PlanetRays& r = rays[static_cast<size_t>(i)];
      out.earth_view_factor(i, p) = r.view_factor;
      out.earth_ir(i, p) = opt.earth_ir_w_m2 * r.view_factor;
      double sum = 0.0;
      for (const auto& hit : r.hit_points) {
        const Eigen::Vector3d normal = (hit - center) / re;  // outward, body frame
        const double cos_sun = normal.dot(pos.sun_body);
        if (cos_sun <= 0) continue;  // night side
        const double a =
            opt.albedo_by_latitude.empty()
                ? opt.albedo
                : albedoAt(opt, units::radToDeg(std::asin(std::clamp((eciFromBody * normal).z(), -1.0, 1.0))));
        sum += a * cos_sun;
      }
      // E = π ∫ L cos θ dω / π … with L = a S cos θ_s / π and rays drawn with pdf cos θ / π.
      out.albedo(i, p) = r.rays > 0 ? pos.solar_flux_w_m2 * sum / double(r.rays) : 0.0;
    }
    if (opt.progress) opt.progress(p + 1, P);
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace radnet::orbits
