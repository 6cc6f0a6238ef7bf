#pragma once
// Direct sunlight of every node at a sweep's positions (orbits/loads.cpp's first stage): the
// lit projection by the case's method (exact clipping, the shadow grid or per-node rays)
// and what mirrors and windows pass on.
#include "geometry/rays/ray_caster.hpp"
#include "orbits/loads.hpp"

#include <Eigen/Core>
#include <vector>

namespace radnet::orbits {

/// A Sun-pointing sweep casts the same shadows at every position (the exact clipping cost
/// 5 ms a position on the 19,202-node satellite): positions whose Sun lies within 1e-12 rad
/// of the sweep's first sunlit position's take that position's lit projection (continuous
/// in the direction; the first position's whatever process owns it: MPI ranks agree bit for
/// bit). Exact clipping only (the sampled methods' rays would be counted on every rank).
struct LitCache {
  SweepPosition first;
  bool have_first = false;  ///< a sunlit position in the sweep
  Eigen::VectorXd projected_m2, stderr_m2;  ///< the first's, once computed
  explicit LitCache(const std::vector<SweepPosition>& positions) {
    for (const SweepPosition& pos : positions)
      if (pos.sunlit_fraction > 0 && !have_first) first = pos, have_first = true;
  }
  /// Whether the first's lit projection serves `pos` (exact clipping only).
  bool serves(const SweepPosition& pos) const { return have_first && (pos.sun_body - first.sun_body).norm() <= 1e-12; }
};

/// Direct irradiance and its σ at every position `wanted` asks for and the Sun lights
/// (columns of `out`). Exact clipping without mirrors or windows, positions in parallel, each
/// on one thread (the clipping of one position on two threads ran only 1.3–1.5× faster: its
/// projection and bins, a third of it, are serial); otherwise one after the other. The same
/// numbers either way.
void directLoadsAt(const geometry::RayCaster& caster, const Eigen::VectorXd& area,
                   const std::vector<SweepPosition>& positions, const EnvironmentOptions& opt,
                   const std::vector<char>& wanted, EnvironmentLoads& out, LitCache& cache);

/// Every position's direct irradiance (n × P, W/m²): `out`'s where this process computed
/// it, the rest (other processes' positions) computed here too, so that whatever reads it
/// (the sky kernel's targets) is the same on any number of processes.
Eigen::MatrixXd directAtEveryPosition(const geometry::RayCaster& caster, const Eigen::VectorXd& area,
                                      const std::vector<SweepPosition>& positions, const EnvironmentOptions& opt,
                                      const EnvironmentLoads& out);

}  // namespace radnet::orbits
