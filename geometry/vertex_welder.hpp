#pragma once
#include "geometry/scene.hpp"

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
  std::array<long, 3> cell(const Vec3& p) const {
    return {std::lround(std::floor(p.x() / tol_)), std::lround(std::floor(p.y() / tol_)),
            std::lround(std::floor(p.z() / tol_))};
  }
  double tol_;
  std::vector<Vec3> points_;
  std::map<std::array<long, 3>, std::vector<int>> cells_;
};

}  // namespace radnet::geometry
