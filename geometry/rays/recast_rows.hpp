#pragma once
// Rows of F cast again after parts of the scene turned (docs/geometry.md, "Moving parts").
// Each row casts the same rays in every arrangement: the same Sobol points, mapped in each
// triangle's own frame (NodeSampler::map), so a turned part casts its rays turned.
// A ray that no motion can redirect (it misses every volume a moving part sweeps, or, from a
// moving part, the volume the rest of the scene sweeps about its axis) lands where it landed
// in the scene as written: its count is kept from there, and only the others are traced again.
#include "geometry/rays/ray_caster.hpp"
#include "geometry/rays/tally.hpp"
#include "geometry/rays/view_factors.hpp"

#include <Eigen/Geometry>

#include <cstdint>
#include <functional>
#include <vector>

namespace radnet::geometry {

/// Whether a ray (origin, unit direction) from `node` may land elsewhere once parts turn.
using RayMayChange = std::function<bool(int node, const Vec3& origin, const Vec3& direction)>;

/// What the rows cast in the scene as written: each row's rays per replica, and the counts of
/// the rays no motion can redirect.
struct RecastPlan {
  ViewFactorOptions options;  ///< the rows' (cast_rows marks them)
  std::vector<std::int64_t> per_replica;         ///< per node, rays of each replica (0: not cast)
  std::vector<std::vector<tally::Tally>> kept;   ///< per node and replica: the unredirectable rays' counts
  std::vector<std::int64_t> traced;              ///< per node, rays a moved arrangement traces again
  /// The redirectable rays themselves (offset origin, direction, emitting face), per node and
  /// replica, as cast in the scene as written: a moved arrangement turns a moving node's with
  /// its part and traces them, instead of drawing, mapping and testing every ray of the row
  /// again. Kept while they fit kMaxKeptRayBytes; else empty (rays_kept false) and redrawn.
  struct Ray {
    Vec3 origin, direction;
    int face;
  };
  std::vector<std::vector<std::vector<Ray>>> rays;
  bool rays_kept = false;
};

/// The most memory the redirectable rays may take (RecastPlan::rays), bytes.
inline constexpr double kMaxKeptRayBytes = 2e9;

/// Casts the rows marked in opt.cast_rows in `caster`'s scene (the arrangement as written),
/// until opt.target_error or opt.rays_per_node as computeViewFactors does, and keeps the plan.
ViewFactorResult castPlannedRows(const RayCaster& caster, const ViewFactorOptions& opt, const RayMayChange& may_change,
                                 RecastPlan& plan);

/// Casts rows `rows` (in `caster`'s scene, the arrangement as written) into a plan made by
/// castPlannedRows, with its options: the same rays and counts as if they had been cast with
/// it. Rows it already holds are cast again. (A plan first cast for the rows known to need
/// it, and grown when a moved arrangement asks for another.)
void addPlannedRows(const RayCaster& caster, const RayMayChange& may_change, const std::vector<char>& rows,
                    RecastPlan& plan);

/// Per row marked in `rows` (others 0): the share of its first `per_replica` rays of each
/// replica (the plan's own first rays, with `opt`'s seed and replicas) that `may_change`
/// says a motion can redirect. Draws and maps the rays, traces none.
std::vector<double> redirectableShares(const Scene& scene, const ViewFactorOptions& opt, const RayMayChange& may_change,
                                       const std::vector<char>& rows, std::int64_t per_replica);

/// The plan's rows in a moved arrangement of the same scene: the same rays, the kept counts
/// where no motion can redirect them, the rest traced in `moved`.
/// @param node_motion  per node, the rigid motion of its part (empty, or identity: fixed)
/// @param rows  per node (empty: all the plan's): the plan's rows to recast, the others left empty
ViewFactorResult recastRows(const RayCaster& moved, const RecastPlan& plan, const RayMayChange& may_change,
                            const std::vector<Eigen::Isometry3d>& node_motion = {}, const std::vector<char>& rows = {});

}  // namespace radnet::geometry
