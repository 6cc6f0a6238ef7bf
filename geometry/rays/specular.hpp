#pragma once
// Specular exchange factors by ray tracing (Siegel & Howell, "Thermal Radiation Heat
// Transfer", the E^s factors of specular–diffuse enclosures): diffuse energy leaving node i
// that reaches node j directly or through any number of specular reflections and
// transmissions. What a ray meeting node j does there is split by j's optics in the band:
// κ_j = 1 − ρs_j − τ_j of it is absorbed or diffusely re-emitted (the network's share), ρs_j
// reflects about the surface normal, τ_j passes the thin sheet unchanged in direction.
//
// The rows come out as the network's F̃_ij = E^s_ij κ_j (docs/solver.md, "Specular and
// transmissive surfaces"): with Ã = A κ they close (Σ_j F̃_ij + F̃_space + F̃_blocked = 1) and
// Ã F̃ is symmetric, so the diffuse machinery (reciprocity correction, one eigendecomposition,
// GR) applies unchanged.
#include "geometry/rays/view_factors.hpp"

#include <Eigen/Dense>

namespace radnet::geometry {

/// One band's specular optics per scene node.
struct SpecularBand {
  Eigen::VectorXd specular;       ///< ρs, –
  Eigen::VectorXd transmittance;  ///< τ, –
  bool empty() const { return specular.size() == 0; }
  /// κ = 1 − ρs − τ per node: what of an arriving ray the node absorbs or re-emits diffusely.
  Eigen::VectorXd kappa() const;
  /// Whether node `node` (≥ 0) reflects specularly or transmits.
  bool redirects(int node) const {
    return specular[node] > 0 || transmittance[node] > 0;
  }
  bool anyRedirects() const;
  /// The same ρs and τ at every node (both empty counts as the same).
  bool sameAs(const SpecularBand& other) const {
    return specular.size() == other.specular.size() && transmittance.size() == other.transmittance.size() &&
           specular == other.specular && transmittance == other.transmittance;
  }
};

/// A ray's weight, relative to the one it started with, below which Russian roulette decides
/// whether it goes on: it survives with probability w / (kRouletteWeight w₀) at kRouletteWeight w₀
/// (unbiased: no cutoff bias).
inline constexpr double kRouletteWeight = 0.05;
/// Paths longer than this many redirections end (a ray trapped between two parallel ideal
/// mirrors); their weight is counted as lost and reported.
inline constexpr int kMaxRedirections = 10000;

/// Traces the rows of `options.cast_rows` (empty: all) with specular reflection and
/// transmission; rows of nodes with κ = 0 (pure mirrors, no radiosity of their own) come out
/// empty with F̃_space = 1. Reproducible per (seed, node, replica) whatever the thread count.
ViewFactorResult traceSpecularRows(const RayCaster& caster, const SpecularBand& band,
                                   const ViewFactorOptions& options);

/// External collimated light (the Sun) after specular surfaces redirect it.
struct RedirectedLight {
  /// Per node: what arrives at it by one or more reflections or transmissions, per unit flux
  /// of the beam (W per W/m², i.e. m²); direct arrival is not included (the shadow grid's).
  Eigen::VectorXd arrived_m2;
  Eigen::VectorXd stderr_m2;  ///< its standard error over the replicas, m²
  std::int64_t rays = 0;
};

/// The beam towards `toward_source` (unit) as the redirecting nodes pass it on: `samples`
/// points per such node (Sobol, `replicas` shifted sequences for the error), each lit one
/// (a shadow ray towards the source) sending ρs of its share along the mirror direction or
/// τ straight through the sheet, then traced like the exchange rays. A redirector behind
/// another's glass counts as shadowed (second-order light).
RedirectedLight redirectedCollimated(const RayCaster& caster, const SpecularBand& band, const Vec3& toward_source,
                                     int samples, std::uint64_t seed = 1, int replicas = 16);

/// Planet light (albedo, planet IR) that specular and transmissive surfaces pass on, as paths
/// whose radiance is the caller's: each arrival's power is L(hit) × weight, L the sphere's
/// radiance at the point the light left (W m⁻² sr⁻¹), weight in m² sr.
struct RedirectedPlanetPaths {
  struct Arrival {
    int node = -1;     ///< where the redirected light arrives (the whole arrival)
    int replica = 0;   ///< which replica's sample it came from
    int hit = 0;       ///< index into hit_points: where on the sphere it left
    double weight = 0.0;  ///< m² sr
  };
  std::vector<Vec3> hit_points;  ///< body frame, m
  std::vector<Arrival> arrivals;
  int replicas = 0;
  std::int64_t rays = 0;
};

/// From `samples` points per redirecting node (Sobol, `replicas` shifted sequences), a
/// direction each uniform in the cone the sphere subtends from that point; unobstructed ones
/// bring the sphere's light, which the node reflects (ρs) or passes (τ) on, traced as the
/// exchange rays. Radiance-free, so one set serves every position while the sphere holds still
/// in the body frame.
RedirectedPlanetPaths redirectedPlanetPaths(const RayCaster& caster, const SpecularBand& band,
                                            const Vec3& sphere_center, double sphere_radius, int samples,
                                            std::uint64_t seed = 1, int replicas = 16);

/// Where a ray travelling along `dir` that meets face `face` at `point` from its `front`
/// side goes on: reflected about the surface normal (the exact one of a curved primitive).
/// A shading normal may send the reflection into the surface near a facet's edge: the facet
/// normal is used there.
Vec3 specularDirection(const Scene& scene, int face, const Vec3& point, const Vec3& dir, bool front);

}  // namespace radnet::geometry
