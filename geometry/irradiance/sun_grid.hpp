#pragma once
// Direct-sunlight shadowing of the whole scene at once (docs/geometry.md, "Shadows"): one
// grid of parallel rays over the scene's projection onto the plane normal to the Sun,
// one jittered ray per cell, found by a z-buffer (every triangle rasterised into the grid,
// the one nearest the Sun kept per cell: the first hit of that cell's ray, exactly).
//
// Each node's lit projected area is a ratio estimate: its exact unshadowed projection
// ∫ max(0, n·d) dA times (cells it wins) / (cells its sun-facing triangles cover). A node
// that nothing shadows is therefore exact whatever the spacing; only shadow edges that
// cross a node carry sampling error. Its standard error comes from the grid itself: with
// one jittered point per cell, a cell that an edge crosses is a Bernoulli trial of mean
// p (p(1−p) averages 1/6), and the number of such cells is the count of 4-neighbour
// cell pairs of the node whose lit state differs (a straight edge flips about once per
// row and column it crosses).
#include "geometry/rays/ray_caster.hpp"

#include <Eigen/Dense>

#include <cstdint>

namespace radnet::geometry {

struct SunGridOptions {
  double cell_m = 0.0;                   ///< grid spacing, m (> 0)
  std::int64_t max_cells = 1LL << 22;    ///< the spacing grows until the grid fits (memory: 4 bytes a cell)
  int min_crossings = 64;                ///< nodes covering fewer cells cast their own shadow rays instead ...
  /// ... unless their unshadowed projection is at most this fraction of their area (seen
  /// nearly edge-on: their load is too small to matter, and the grid's estimate stands)
  double negligible_fraction = 0.005;
  /// Nodes whose grid estimate has a standard error above this fraction of their
  /// unshadowed projection (long shadow edges across a narrow node) cast their own rays too;
  /// 0: never
  double max_relative_stderr = 0.0;
  int node_samples = 2048;               ///< points per such node (Sobol, as litArea) ...
  int node_replicas = 16;                ///< ... in this many replicas, for the error, doubled up to
  int max_node_samples = 32768;          ///< this while a node's σ is above max_relative_stderr
  std::uint64_t seed = 1;
};

struct SunlitArea {
  Eigen::VectorXd projected_m2;  ///< lit ∫ max(0, n·d) dA per node, m²
  Eigen::VectorXd stderr_m2;     ///< its standard error, m²
  Eigen::VectorXd facing_m2;     ///< ∫ max(0, n·d) dA without shadows (exact), m²
  std::int64_t cells = 0;        ///< grid cells, one ray each
  double cell_m = 0.0;           ///< the spacing used, m
  int sampled_nodes = 0;         ///< nodes too small for the grid, shadowed by their own rays
  std::int64_t node_rays = 0;    ///< the shadow rays of those nodes
  std::int64_t occluding_pairs = 0;  ///< exact clipping (sun_clip.hpp): receiver–occluder pairs clipped
};

/// Lit projected area of every node for a collimated source in direction `toward_sun`
/// (unit, body frame). Deterministic for a seed, whatever the thread count.
/// @throws std::invalid_argument when the spacing is not positive and finite
SunlitArea sunlitArea(const RayCaster& caster, const Vec3& toward_sun, const SunGridOptions& options);

/// The grid spacing (m) that holds the ratio estimate's relative standard error near
/// `relative_error` for a square node of area `area_m2` crossed by one straight shadow
/// edge: σ/A ≈ (h/s)^{3/2}/√6 with s = √A, so h = s (√6 ε)^{2/3}.
double sunGridSpacing(double area_m2, double relative_error);

}  // namespace radnet::geometry
