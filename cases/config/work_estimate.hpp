#pragma once
// The memory a geometry case will need, estimated from its counts before anything is computed
// (docs/limits.md): a case that cannot fit this machine is refused at once, at the key that
// makes it large, instead of failing late (bad_alloc in a worker, hours in).
#include "cases/config/geometry_case.hpp"
#include "cases/config/yaml_document.hpp"

#include <algorithm>
#include <cstdint>

namespace radnet::cases {

/// Memory one triangle of the scene takes while the case runs: its CGAL mesh entry, the
/// scene's face record, the AABB tree and the exact method's patches (measured on a 4M-triangle
/// sphere, docs/limits.md).
inline constexpr double kSceneBytesPerTriangle = 600.0;

/// The least memory a node takes in any run: 8 vectors of the rank cap's 200 (eigenvectors,
/// the Lanczos basis of up to 320, GR's basis, the uncertainty stage's products) and its
/// per-position series, about 20 kB (the 19,202-node satellite peaked at 63 kB a node with
/// its scene and F). Beyond it checkNodeMemory refuses before anything is built.
inline constexpr double kMinBytesPerNode = 20e3;

/// Share of node pairs that face each other (each one's centroid in front of the other's
/// plane, on a random face of each), from 100,000 random pairs with a fixed seed: about the
/// density of F before occlusion, an upper bound for it. Below the sparse-storage density
/// and without temperatures the network, its GR and its result file are sparse.
double facingPairShare(const geometry::Scene& scene);

/// The rays `auto` expects a row it leaves to sampling to take (and `monte_carlo` a row): the
/// pinned count, or under the budget's target error what rows take on average (most stop
/// well below the cap).
double rowRays(const GeometryCase& c);

/// Auto's cap on F's entries from integrated pairs: what kPairEntriesMemoryShare of
/// `memory_bytes` holds at kBytesPerPairEntry (F, its raw estimate and σ, G, GR's direct part
/// and their copies while the correction builds them), after the n × k vectors' floor. Rows
/// beyond it are cast: their entries are the distinct nodes their rays hit (0.47 % of n² at
/// 4,000 rays a row on the 100,002-node satellite, against 5.5 % from every facing pair).
/// −1: memory unknown (≤ 0), no cap.
inline constexpr double kPairEntriesMemoryShare = 0.4, kBytesPerPairEntry = 120.0;
std::int64_t pairEntriesCap(const GeometryCase& c, double memory_bytes);

/// The distinct nodes a row cast with `rays` rays reaches (its non-zeros in F), averaged over
/// up to 64 nodes drawn with a fixed seed: what a sampled row holds, far below the nodes
/// that face it (rays concentrate on near nodes).
double sampledRowEntries(const geometry::Scene& scene, double rays);

/// The memory this process may use, bytes (0 when unknown): the least of the machine's
/// physical memory, the process's address-space and data limits (`ulimit -v`, `ulimit -d`:
/// RLIMIT_AS, RLIMIT_DATA) and its cgroup's `memory.max`, with the words that say which.
struct MemoryLimit {
  double bytes = 0;
  std::string source;  ///< e.g. "this machine's 25.2 GB", "the process's address-space limit (ulimit -v) of 4.1 GB"
};
MemoryLimit memoryLimit();

/// This machine's physical memory, bytes (0 when unknown).
double physicalMemory();

/// @throws InputError at `where` when `triangles` (the scene so far) alone would need more
///         than this machine's memory: checked as surfaces are added, before a YAML alias
///         repeated 300 times builds them all
void checkSceneMemory(const YamlDocument& doc, const YAML::Node& where, const std::string& what, double triangles);

/// Of the 10 copies of a sparse entry counted, those kept after the network is built: F's raw
/// estimate, σ_F, G and GR's direct part (the 100,002-node defaults: 11.8–12.6 GB from the
/// eigendecomposition on, against a 13.4 GB peak while the network was built).
inline constexpr double kSparseHeldShare = 0.4;

struct WorkEstimate {
  double scene_bytes = 0;     ///< triangles: mesh, faces, AABB tree
  double dense_bytes = 0;     ///< node × node matrices: F, its raw estimate and σ, G, GR per optical set
  double facing_share = 1.0;  ///< facingPairShare: F's density before occlusion
  /// Sparse: the non-zeros of F counted. An upper bound from the pairs that face each other
  /// (or the rays), or, when that bound is large and rows are cast, auto's cap plus the
  /// sampled rows' entries (sampledRowEntries, with a 25 % margin): then `rows_sampled`.
  double nonzeros = 0;
  bool rows_sampled = false;
  bool sparse = false;        ///< the matrices counted sparse (facing share < 0.25, GR kept factored)
  /// Sparse: the part of dense_bytes that does not depend on F's non-zeros (n × k vectors);
  /// the rest is an upper bound (pairs that face each other, or rays), not an expectation.
  double sparse_floor_bytes = 0;
  double planet_bytes = 0;    ///< planet-ray hit points kept for the reuse over positions (24 B each)
  double position_bytes = 0;  ///< per-position results: loads, heat flows, temperatures, ParaView copies
  long long positions = 0;    ///< over every design and orbit case
  /// Turning parts: the configurations the run will make (the geometry as written and each
  /// distinct binned angle tuple over every design case's positions); 0 without drives.
  double configurations = 0;
  /// The peak: on a sparse network the planet rays' hit points are cast after the view
  /// factors' peak, beside the copies kept from then on (kSparseHeldShare of the non-zeros'
  /// bytes); on a dense one everything counts at once.
  double total() const {
    if (!sparse) return scene_bytes + dense_bytes + planet_bytes + position_bytes;
    const double held = sparse_floor_bytes + kSparseHeldShare * (dense_bytes - sparse_floor_bytes);
    return scene_bytes + std::max(dense_bytes, held + planet_bytes) + position_bytes;
  }
  /// Everything but F's non-zeros (a sparse network is refused only when this does not fit).
  double floorTotal() const { return scene_bytes + sparse_floor_bytes + planet_bytes + position_bytes; }
};

WorkEstimate estimateWork(const GeometryCase& c);

/// @throws InputError, located at `geometry`, `environment.planet_rays` or `orbit.positions`
///         (whichever dominates), when the estimate exceeds `memory_bytes` (default:
///         memoryLimit(), the least of the machine's memory and the process's limits). A
///         sparse network is refused only when its floor does not fit; when only its upper
///         bound does not, the case gets a warning.
void checkWorkEstimate(const YamlDocument& doc, GeometryCase& c, double memory_bytes = 0);

}  // namespace radnet::cases
