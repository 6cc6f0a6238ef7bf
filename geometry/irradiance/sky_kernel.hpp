#pragma once
// Each node's view of the sky, once per geometry, for loads from a far source of any
// direction (a planet in any attitude): which directions of the node's hemisphere the
// spacecraft blocks. A far radiance field L(ω) (body frame) then gives the node's mean
// irradiance
//     E = (1/A) ∫_A ∫ L(ω) V(x, ω) max(0, n·ω) dω dA
//       = E_free − (1/A) ∫_A ∫ L(ω) (1 − V) max(0, n·ω) dω dA,
// E_free the unobstructed part (per facet normal, from the source's own closed form or
// quadrature), the second term from the kernel. The kernel casts cosine-weighted rays from
// area-uniform points (Sobol, 32 replicas) and keeps the minority: the blocked rays of a
// node that sees mostly sky, the open rays of one that sees mostly spacecraft, so a node
// nothing blocks costs nothing per position and a node shut in a box is exactly zero.
// Rays are binned on a cube map of directions (kBinsPerEdge² per face): a position's cost
// is one radiance per bin it uses, not one per ray.
#include "geometry/irradiance/sky_region.hpp"
#include "geometry/rays/ray_caster.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace radnet::geometry {

/// The cube map of directions the kernel bins rays on.
struct SkyBins {
  static constexpr int kBinsPerEdge = 64;  ///< 1.4° bins: a far planet's radiance varies little across one
  static constexpr int kBins = 6 * kBinsPerEdge * kBinsPerEdge;
  static int bin(const Vec3& direction);
  /// The direction at fractional position (s, t) ∈ [0, 1]² inside a bin (unit).
  static Vec3 direction(int bin, double s, double t);
  /// The bins' corner (i, j) ∈ [0, kBinsPerEdge]² of a cube face (unit): bin (face, i, j)
  /// has corners (i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1).
  static Vec3 corner(int face, int i, int j);
};

/// Independently shifted Sobol sequences per node: their spread is the kernel's σ.
inline constexpr int kSkyReplicas = 32;

/// One node's kernel.
struct NodeSky {
  /// true: the bins count the rays that reach the sky (the node sees mostly spacecraft);
  /// false: the rays the spacecraft blocks.
  bool counts_open = false;
  std::vector<std::int32_t> bins;   ///< bins holding counted rays, ascending
  std::vector<float> weights;       ///< their share of all the node's rays, –
  /// The counted rays of each replica in each bin, by (bin, replica): every replica's own
  /// estimate of a position's load, with the radiance of the bins its rays met, hence the
  /// σ from the spread of the 32. (Per coarse region of 22.5° instead, a replica's estimate
  /// took the region's pooled radiance: where the limb crossed a region the spread missed
  /// where in it the rays fell, and a 1,024-ray node reported 0.39 W/m² for a 2.3 W/m² error.)
  struct ReplicaCount {
    std::int32_t bin;
    std::int16_t replica;
    std::uint16_t count;
  };
  std::vector<ReplicaCount> replica_counts;
  /// The node's facet normals (indices into SkyKernel::normals) and their area shares.
  std::vector<std::pair<std::int32_t, double>> normals;
  std::int64_t rays = 0;
  double blocked_fraction = 0.0;    ///< cos-weighted share of the hemisphere the spacecraft covers, –
  /// The cosine-weighted share of the hemisphere the rays were drawn from (1: all of it;
  /// less: a flat node's region outside which nothing can block, geometry/irradiance/
  /// sky_region): each ray stands for ray_share / rays of the hemisphere.
  double ray_share = 1.0;
  SkyRegion region;            ///< where the rays were drawn (whole: the hemisphere)
  bool region_known = false;   ///< region computed (a re-cast takes it, not a new one)
};

struct SkyKernel {
  std::vector<Vec3> normals;   ///< the distinct facet normals (node side), unit
  std::vector<NodeSky> nodes;  ///< scene order; empty entries for nodes left out
  std::int64_t rays = 0;       ///< rays the nodes' kernels stand for
  std::int64_t cast_rays = 0;  ///< rays traced to build it (fewer when it resumed an earlier kernel)
  std::size_t bytes() const;
};

struct SkyKernelOptions {
  std::int64_t max_rays_per_node = 65536;
  /// > 0: a node drawn in a region casts rays_per_share × its region's share (rounded up
  /// to whole replicas, at least min_rays_per_node) in place of
  /// max_rays_per_node, which the nodes drawn over their whole hemisphere keep: the same
  /// density over the sky whatever a node's region (not with node_rays).
  double rays_per_share = 0.0;
  std::int64_t min_rays_per_node = 256;
  /// Rays double from 1,024 until the σ of the counted share is at most this (0: cast
  /// max_rays_per_node), –
  double target_stderr = 0.0;
  std::uint64_t seed = 1;
  std::vector<char> nodes;  ///< nodes to build (empty: all)
  /// Per node (empty: none): cast exactly this many rays (rounded up to whole replicas; 0:
  /// leave the node out), in place of the target and the cap. A node's rays are the same
  /// Sobol points whatever the count: a node cast again with more keeps its first ones.
  std::vector<std::int64_t> node_rays;
  /// An earlier kernel of the same scene and seed (null: none): a node's first rays are
  /// taken from it and only the rest are traced (a node whose majority, blocked or open,
  /// changes with the new rays is cast whole again: the earlier kept only its minority).
  const SkyKernel* prefix = nullptr;
};

SkyKernel skyKernel(const RayCaster& caster, const SkyKernelOptions& options);

}  // namespace radnet::geometry
