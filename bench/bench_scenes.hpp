#pragma once
// Scenes the benchmarks share, built from primitives (no files).
#include "geometry/scene/primitives.hpp"

#include <string>

namespace radnet::bench {

/// A 1 m bus (m × m cells a face, one node a face), two two-sided 3 × 1 m wings, a mast and
/// a dish (a 40° spherical cap, its concave side a node): 13 nodes.
inline geometry::Scene busWingsMastDish(int m) {
  using geometry::Vec3;
  geometry::Scene s;
  const auto bus = geometry::boxFaces(Vec3(-0.5, -0.5, -0.5), Vec3(1, 1, 1), m);
  for (size_t k = 0; k < 6; ++k)
    s.addSurface(std::string("bus") + geometry::kBoxFaceNames[k], "bus", bus[k],
                 std::string("bus") + geometry::kBoxFaceNames[k], "");
  s.addSurface("wing+", "w", geometry::rectangle(Vec3(0.6, -0.5, -0.2), Vec3(3, 0, 0), Vec3(0, 1, 0), 3 * m, m),
               "wing+", "wing+.back");
  s.addSurface("wing-", "w", geometry::rectangle(Vec3(-0.6, -0.5, -0.2), Vec3(0, 1, 0), Vec3(-3, 0, 0), m, 3 * m),
               "wing-", "wing-.back");
  s.addSurface("mast", "m", geometry::cylinder(Vec3(0, 0, 0.5), Vec3(0, 0, 0.6), 0.05, {}, m, 4 * m), "mast", "");
  s.addSurface("dish", "d", geometry::sphere(Vec3(0, 0, 1.8), 0.7, Vec3(0, 0, -1), 0, 40, {}, m, 4 * m), "dish.back",
               "dish");
  return s;
}

}  // namespace radnet::bench
