#pragma once
// Planet loads of every node at one position from the sky kernel (geometry/irradiance/
// sky_kernel): the unobstructed load of each facet normal (orbits/planet_sky, exact
// rings) less, or for a node that sees mostly spacecraft instead of, the kernel's
// counted rays times the planet's radiance in their bins. No ray is cast per position,
// whatever the attitude.
//
// The σ reported per node: the kernel's sampling error (each coarse cell's replica σ of
// the counted share times π × the largest radiance in that cell, in quadrature) and the
// binning error (each counted bin's share times π × the error scale of its mean radiance,
// summed: bins along the limb or the terminator err the same way; the bin's radiance
// itself is Simpson's, on cells split to an eighth of the bin where a step crosses it:
// orbits/sky_radiance.hpp).
#include "geometry/irradiance/sky_kernel.hpp"
#include "orbits/loads.hpp"
#include "orbits/planet_sky.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace radnet::orbits {

/// The bins the kernels of the nodes `mask` leaves in (empty: all) use, ascending.
std::vector<int> usedSkyBins(const geometry::SkyKernel& kernel, const std::vector<char>& mask = {});

/// The unobstructed loads (view factor, albedo, planet IR) of the kernel's normals at every
/// position (normals × positions, per channel), each computed once however many sweeps read
/// it: the rings cost some 2 µs a normal and position (7 µs before their arcs' ends were
/// taken by angle addition; a position's pieces are shared by its normals, PlanetRings),
/// and a curved part has a normal per facet (2,204 on the 1,602-node satellite, whose dish
/// alone is 1,100). A node of more than kGroupedFacets normals is summed per node and
/// position instead (PlanetRings::facetLoads: its normals that see the whole cap cost one
/// ring integral together).
struct UnobstructedLoads {
  using Rows = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  static constexpr size_t kGroupedFacets = 8;
  /// Row-major: a node's sums read a normal's positions.
  std::array<Rows, 3> channel;
  std::vector<char> have;  ///< per normal: computed
  std::array<Rows, 3> node_channel;  ///< the grouped nodes' own rows (nodes × positions)
  std::vector<int> node_row;         ///< per node: its row there, −1: summed from `channel`
  std::vector<char> node_have;       ///< per grouped row: computed
  /// Per grouped row: the row whose facets it has seen from their other side (the back of a
  /// two-sided dish), −1: none; and that row's Σ shares × normals, S. Such a row is the
  /// other's loads less S · V, V = ∫_cap L d dΩ per channel (max(0, n·d) − max(0, −n·d) =
  /// n·d makes loads(−n) = loads(n) − n · V for every facet): no rings of its own; equal to
  /// its own rings within their accuracy (3e-6 of the load's scale seen, their 2e-5 bound).
  std::vector<int> mirror_of;
  std::vector<Eigen::Vector3d> mirror_sum;
  std::vector<int> row_node;  ///< per grouped row: its node
  /// Computes the normals and grouped nodes the nodes `mask` leaves in use that are not
  /// there yet.
  void fill(const geometry::SkyKernel& kernel, const std::vector<PlanetView>& views, const std::vector<char>& mask);
  /// Sizes the tables for `kernel` and `positions`, nothing computed; finds the mirror rows.
  void layOut(const geometry::SkyKernel& kernel, int positions);
  /// Node i's unobstructed loads at positions [p0, p0 + B), per channel.
  Eigen::Array<double, 3, Eigen::Dynamic, Eigen::RowMajor> node(const geometry::SkyKernel& kernel, size_t i, int p0,
                                                                int B) const;
};

struct RadianceTables;  // orbits/sky_radiance.hpp

/// What the rounds of one sweep (one vector of views) share: the unobstructed loads (each
/// normal and position computed once) and the radiance tables (allocated once, each bin's
/// radiance computed once while the sweep's blocks of positions fit in memory).
struct SkySweepMemory {
  UnobstructedLoads unobstructed;
  std::vector<std::shared_ptr<RadianceTables>> tables;
};

/// The binning part of each node-position's albedo and IR σ (n × P, W/m²): what more rays
/// leave (the planet's radiance varying across a bin the limb or terminator crosses).
struct BinningErrors {
  Eigen::MatrixXd albedo, ir;
};

/// Writes every position's earth_view_factor, albedo, earth_ir and their σ (a column per
/// view) for the nodes `mask` leaves in (empty: all). Whether a node's σ is within its
/// target is the caller's to judge (orbits/loads.cpp: against the node's largest load
/// over the sweep).
/// `blocked_share`, `blocked_share_stderr` (empty: not known): each node's blocked share of
/// its sky from the view factors and its σ, for the ratio estimate (EnvironmentOptions);
/// `binning` (optional, sized n × P): the nodes' binning σ written there.
void skyKernelSweep(const geometry::SkyKernel& kernel, const std::vector<PlanetView>& views,
                    SkySweepMemory& memory, const std::vector<char>& mask,
                    const Eigen::VectorXd& blocked_share, const Eigen::VectorXd& blocked_share_stderr,
                    EnvironmentLoads& out, BinningErrors* binning = nullptr);

/// The sky kernel's first cast, rays a node (32 a replica) drawn over its whole hemisphere;
/// a flat node drawn in its region of possible blockers casts kMinPartlyBlockedRays × the
/// region's share at once (the density the floor below asks of a partly blocked node: the
/// re-cast round of 4,056 nodes that raised them to it cost a sweep on the 19,202-node
/// satellite, and small regions took 1,024 rays where 256 give that density: 21.7 → 17.6 M
/// kernel rays). A node whose error over the sweep is then above its target is cast again
/// with what its error asks.
inline constexpr std::int64_t kSkyKernelFirstRays = 1024;
/// Planet rays replace the kernel at a node-position only where its σ exceeds the target
/// this many times (the mean of its two channels' ratios, KernelTargets::over). The targets
/// are a sufficient bound (the albedo and the IR each against their own largest, added as
/// if both peaked together and erred the same way). A node at 65,536 rays just over its
/// half (bus faces of the 1,602-node satellite, Sun-pointing: albedo σ 0.14 W/m² against
/// 0.13) cost 8.3 M planet rays for 417 node-positions; the run's final check of every
/// node's absorbed-power σ against the accuracy asked (`nodes_over_budget`) stays the judge.
inline constexpr double kKernelFallbackRatio = 2.0;
/// The fewest rays a node partly blocked keeps (its σ from the replicas is trusted from here).
inline constexpr std::int64_t kMinPartlyBlockedRays = 4096;

/// What each node's albedo and planet IR may be off by (1σ, W/m²) at any position of the
/// sweep. The budget is a share of each node's absorbed power against its orbit maximum
/// Q_max, and Q_max ≥ max_p [α (D_p + A_p) + ε I_p] (direct, albedo and planet IR at
/// position p: what the node absorbs of its own irradiance; reflections only add). An
/// albedo σ with α σ_A ≤ ½ share Q_max and an IR σ with ε σ_I ≤ ½ share Q_max keep the
/// absorbed power's within the share (the two added as if both peaked together and erred
/// the same way: they share the blocked sky). Hence the targets
///     T_A = ½ share max_p (D_p + A_p + r_ε I_p),   T_I = ½ share max_p (r_α (D_p + A_p) + I_p),
/// r_α and r_ε the node's smallest α/ε and ε/α over every optical set the loads serve (0
/// when not known: then the albedo's target holds for any optics and the IR's is a share of
/// the node's largest IR, as before the direct load entered). Each at least the load of a
/// tenth of the planet's cap. Against the sweep's largest, not each position's own value:
/// a node's small loads where it barely sees the planet need no more rays than its large
/// ones (the old per-position target cast 3× the rays on the 1,602-node satellite). A node
/// in sunlight, whose orbit maximum the direct load sets, takes fewer rays than against its
/// largest albedo and IR alone (1,602-node satellite, inertial: 8.6 M rays → 6.7 M).
/// Each target alone gives α T_A ≤ ½ share Q_max and ε T_I ≤ ½ share Q_max, so a
/// node-position is within when the two are met together, σ_A / T_A + σ_I / T_I ≤ 2:
/// α σ_A + ε σ_I ≤ ½ share Q_max (σ_A / T_A + σ_I / T_I) ≤ share Q_max. A channel well inside
/// its half leaves the rest to the other (2,306-node satellite, inertial: 1.97 → 1.48 M
/// kernel rays against each channel held to its own half).
struct KernelTargets {
  std::vector<double> albedo, ir;  ///< per node, W/m²
  /// How far node i's σ at position p is over its target: (σ_A / T_A + σ_I / T_I) / 2, ≤ 1
  /// within.
  double over(const EnvironmentLoads& out, Eigen::Index i, int p) const;
};

/// Every position's planet loads from the kernel for the nodes opt.planet_nodes leaves in.
/// An empty kernel is cast first: kSkyKernelFirstRays a node, then, in rounds, the nodes
/// over their target again with more (up to kMaxPlanetRays). Returns the targets, for the
/// caller to give the node-positions still over planet rays.
/// `direct` (n × P, W/m²): every position's direct irradiance, for the targets.
KernelTargets kernelLoads(const geometry::RayCaster& caster, const std::vector<PlanetView>& views,
                          double smallest_cap_sin2, const EnvironmentOptions& opt, const Eigen::MatrixXd& direct,
                          geometry::SkyKernel& kernel, EnvironmentLoads& out);

}  // namespace radnet::orbits
