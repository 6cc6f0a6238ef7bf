#pragma once
#include "geometry/scene/scene.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace radnet::geometry {

// Vertices of the faces welded within a tolerance: a hash grid of cells four tolerances wide.
// A point within the tolerance of p lies in p's cell or, along each axis, in the neighbour
// whose face p is within 1.5 tolerances of (the half tolerance spare covers rounding in
// the cell index): 1 to 8 cells looked up, not the 27 of cells one tolerance wide, and each
// in constant time (an ordered map of cells took minutes on a surface of 3.6 million
// triangles, a fuzzed case's 10,000 × 180 subdivisions).
class VertexWelder {
 public:
  explicit VertexWelder(double tolerance) : tol_(tolerance), size_(4.0 * tolerance) {}
  /// The lowest index of the points within the tolerance of p, or p's own new index.
  int id(const Vec3& p) {
    const Cell c = cell(p);
    std::array<long, 3> lo{}, hi{};
    for (int k = 0; k < 3; ++k) {
      const double offset = p[k] - static_cast<double>(c[static_cast<size_t>(k)]) * size_;  // in [0, size_) up to rounding
      lo[static_cast<size_t>(k)] = offset <= 1.5 * tol_ ? -1 : 0;
      hi[static_cast<size_t>(k)] = size_ - offset <= 1.5 * tol_ ? 1 : 0;
    }
    int found = -1;
    for (long dx = lo[0]; dx <= hi[0]; ++dx)
      for (long dy = lo[1]; dy <= hi[1]; ++dy)
        for (long dz = lo[2]; dz <= hi[2]; ++dz) {
          const auto it = cells_.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == cells_.end()) continue;
          for (int v : it->second)
            if ((found < 0 || v < found) && (points_[static_cast<size_t>(v)] - p).norm() <= tol_) found = v;
        }
    if (found >= 0) return found;
    points_.push_back(p);
    const int v = static_cast<int>(points_.size()) - 1;
    cells_[c].push_back(v);
    return v;
  }

  /// The welded position of index v (the first point seen there).
  const Vec3& point(int v) const { return points_[static_cast<size_t>(v)]; }

 private:
  using Cell = std::array<long, 3>;
  struct CellHash {
    std::size_t operator()(const Cell& c) const {
      std::uint64_t h = 0x9E3779B97F4A7C15ull;
      for (long x : c) h = (h ^ static_cast<std::uint64_t>(x)) * 0xBF58476D1CE4E5B9ull, h ^= h >> 31;
      return static_cast<std::size_t>(h);
    }
  };
  // Cell indices clamped to ±2⁵⁰: a tolerance far below a coordinate's size (1e-18 m against
  // 5e5 m) would overflow the integer (undefined behaviour, found by UBSan); clamped cells
  // only group more points, which the distance test still tells apart.
  Cell cell(const Vec3& p) const {
    constexpr double kMaxCell = 1125899906842624.0;  // 2⁵⁰
    auto index = [&](double x) { return std::lround(std::clamp(std::floor(x / size_), -kMaxCell, kMaxCell)); };
    return {index(p.x()), index(p.y()), index(p.z())};
  }
  double tol_, size_;
  std::vector<Vec3> points_;
  std::unordered_map<Cell, std::vector<int>, CellHash> cells_;
};

}  // namespace radnet::geometry
