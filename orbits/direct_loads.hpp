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
};

/// Direct irradiance and its σ of every node at lit position p (column p of `out`), W/m².
void directLoads(const geometry::RayCaster& caster, const Eigen::VectorXd& area, const SweepPosition& pos,
                 const EnvironmentOptions& opt, EnvironmentLoads& out, int p, LitCache& cache);

/// Every position's direct irradiance (n × P, W/m²): `out`'s where this process computed
/// it, the rest (other processes' positions) computed here too, so that whatever reads it
/// (the sky kernel's targets) is the same on any number of processes.
Eigen::MatrixXd directAtEveryPosition(const geometry::RayCaster& caster, const Eigen::VectorXd& area,
                                      const std::vector<SweepPosition>& positions, const EnvironmentOptions& opt,
                                      const EnvironmentLoads& out);

}  // namespace radnet::orbits
