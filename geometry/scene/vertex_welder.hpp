#pragma once
#include "geometry/scene/scene.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>

namespace radnet::geometry {

// Vertices of the faces welded within a tolerance: a grid of cells of that size, each
// position looked up in its cell and the 26 around it.
class VertexWelder {
 public:
  explicit VertexWelder(double tolerance) : tol_(tolerance) {}
  /// The index of the first point within the tolerance of p, or p's own new index.
  int id(const Vec3& p) {
    const std::array<long, 3> c = cell(p);
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == cells_.end()) continue;
          for (int v : it->second)
            if ((points_[static_cast<size_t>(v)] - p).norm() <= tol_) return v;
        }
    points_.push_back(p);
    const int v = static_cast<int>(points_.size()) - 1;
    cells_[c].push_back(v);
    return v;
  }

  /// The welded position of index v (the first point seen there).
  const Vec3& point(int v) const { return points_[static_cast<size_t>(v)]; }

 private:
  // Cell indices clamped to ±2⁵⁰: a tolerance far below a coordinate's size (1e-18 m against
  // 5e5 m) would overflow the integer (undefined behaviour, found by UBSan); clamped cells
  // only group more points, which the distance test still tells apart.
  std::array<long, 3> cell(const Vec3& p) const {
    constexpr double kMaxCell = 1125899906842624.0;  // 2⁵⁰
    auto index = [&](double x) { return std::lround(std::clamp(std::floor(x / tol_), -kMaxCell, kMaxCell)); };
    return {index(p.x()), index(p.y()), index(p.z())};
  }
  double tol_;
  std::vector<Vec3> points_;
  std::map<std::array<long, 3>, std::vector<int>> cells_;
};

}  // namespace radnet::geometry
