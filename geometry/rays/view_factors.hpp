#pragma once
// Monte Carlo view factors by ray casting: from every node, area-uniform origins on its
// triangles and cosine-weighted directions about its side normal; the first hit through
// the AABB tree decides where the ray's share of power lands (a node's side, an inactive
// side = blocked, or nothing = space). F_ij is the fraction landing on node j.
#include "geometry/rays/ray_caster.hpp"
#include "geometry/reciprocity.hpp"
#include "geometry/scene/scene.hpp"

#include <Eigen/SparseCore>

#include <cstdint>
#include <functional>
#include <vector>

namespace radnet::geometry {

enum class Sampling {
  Sobol,  ///< randomised QMC: R digitally shifted Sobol sequences per node
  Random  ///< plain pseudo-random points, R independent streams per node
};

struct ViewFactorOptions {
  /// Rays per node: fixed count, or the cap when target_error > 0.
  std::int64_t rays_per_node = 100000;
  /// Target standard error (absolute, view-factor units) of every entry of a node's row,
  /// space included; 0: cast exactly rays_per_node. Small or far nodes stop early.
  double target_error = 0.0;
  /// First batch when a target error is set (doubled until met or capped).
  std::int64_t min_rays_per_node = 2048;
  std::uint64_t seed = 1;
  /// Independent replicas per node; the spread of their estimates is the standard error
  /// (a Student t variable with replicas − 1 degrees of freedom: 32 replicas make ±3σ a
  /// 99.5 % interval and ±3.29σ the normal 99.73 % one).
  int replicas = 32;
  Sampling sampling = Sampling::Sobol;
  int threads = 0;  ///< 0: OpenMP's default
  /// Nodes that cast (empty: all). The others' rows come out empty with 0 rays; the
  /// deterministic method's `auto` mode casts only the rows it leaves to sampling.
  std::vector<char> cast_rows;
  /// Called as nodes finish (from one thread at a time): (nodes done, nodes total).
  std::function<void(int, int)> progress;
};

/// The estimate (F, F_space, F_blocked and their standard errors) and how it was made.
struct ViewFactorResult : ViewFactorEstimate {
  std::vector<std::int64_t> rays;  ///< rays cast per node
  std::int64_t total_rays = 0;
  double seconds = 0.0;
  /// Dense copies (for small networks and output).
  Eigen::MatrixXd denseViewFactors() const { return Eigen::MatrixXd(view_factors); }
  Eigen::MatrixXd denseStandardError() const { return Eigen::MatrixXd(standard_error); }
};

/// Casts the rays of every node. Reproducible: each node's streams depend only on
/// (seed, node, replica), so results are bit-identical for any thread count.
ViewFactorResult computeViewFactors(const RayCaster& caster, const ViewFactorOptions& options);

}  // namespace radnet::geometry
