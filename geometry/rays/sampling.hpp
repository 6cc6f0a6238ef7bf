#pragma once
// Sample points for ray casting: randomised quasi-Monte Carlo (a 4-D Sobol sequence with a
// random digital shift per replica) or plain pseudo-random points, mapped to area-uniform
// points on a node's triangles and cosine-weighted directions about the side's normal.
#include "geometry/scene/scene.hpp"

#include <array>
#include <cstdint>
#include <random>
#include <vector>

namespace radnet::geometry {

/// splitmix64: independent 64-bit seeds from (seed, node, replica) so that every node's
/// stream is fixed whatever thread computes it.
std::uint64_t mixSeed(std::uint64_t seed, std::uint64_t a, std::uint64_t b = 0);

/// The first four outputs of std::mt19937_64 seeded with `seed`, without the engine's
/// 312-word state (a Sobol stream's digital shift: equal to the engine's bit for bit).
std::array<std::uint64_t, 4> mt19937_64FirstFour(std::uint64_t seed);

/// 4-D Sobol points (Joe & Kuo 2008 direction numbers) with a random digital shift:
/// each shifted sequence is an unbiased estimator, and independent shifts give
/// independent replicas for an honest standard error (randomised QMC).
class Sobol4 {
 public:
  explicit Sobol4(std::uint64_t seed);
  /// Positions the stream at point `index` for next() (O(log index)).
  void seek(std::uint32_t index);
  /// The current point, then advances (Antonov–Saleev Gray-code update, O(1)).
  std::array<double, 4> next();

 private:
  std::array<std::uint32_t, 4> shift_;
  std::array<std::uint32_t, 4> state_{};
  std::uint32_t index_ = 0;
};

/// Plain pseudo-random 4-D points (for comparison, and as the fallback sampler).
class Random4 {
 public:
  explicit Random4(std::uint64_t seed) : rng_(seed) {}
  std::array<double, 4> next();

 private:
  std::mt19937_64 rng_;
};

/// Maps unit-cube points to ray origins and directions on one node's side.
class NodeSampler {
 public:
  NodeSampler(const Scene& scene, int node);
  struct Ray {
    Vec3 point;      ///< on the triangle, m
    Vec3 direction;  ///< unit, cosine-distributed about `normal`
    Vec3 normal;     ///< unit normal of the emitting side
    int face;
  };
  /// u[0] picks the triangle (area-weighted) and, rescaled, with u[1] the point;
  /// u[2], u[3] the direction (Malley's method: uniform on the disc, lifted) in a tangent
  /// frame taken from the triangle's first edge: the rays turn with the triangle (a part turned
  /// rigidly casts the same rays turned: geometry/rays/recast_rows.hpp).
  Ray map(const std::array<double, 4>& u) const;
  /// A point only (for shadow rays): u[0], u[1] as above.
  Ray mapPoint(double u0, double u1) const;
  /// The node's triangles.
  size_t triangleCount() const { return faces_.size(); }

 private:
  const Scene& scene_;
  std::vector<int> faces_;
  std::vector<double> cdf_;  ///< cumulative area fractions
  /// guide_[j]: the first triangle whose cdf_ exceeds j / m, m = faces_.size() (Chen & Asau's
  /// guide table: the triangle for u is searched among a few, not all; the same triangle).
  std::vector<std::int32_t> guide_;
  /// Per triangle: its first edge's unit direction in its plane, the tangent frame's first
  /// axis (a property of the triangle, kept rather than normalised again for every ray).
  std::vector<Vec3> tangent_;
  double side_ = 1.0;
  /// The point of mapPoint and the triangle's index among the node's (for tangent_).
  Ray mapPointOn(double u0, double u1, size_t& local) const;
};

/// Where a ray from `origin` along unit `dir` first meets a sphere (t > 0), if it does.
bool raySphere(const Vec3& origin, const Vec3& dir, const Vec3& center, double radius, Vec3& hit);

}  // namespace radnet::geometry
