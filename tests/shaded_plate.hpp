#pragma once
// A closed form for shadow tests: a 1 m plate at z = 0 facing +z, meshed into k × k nodes,
// under a square occluder of side `side` at height `height` (both sides inactive: it
// shadows, belongs to no node). Its shadow is the square translated by −height (dx, dy)/dz,
// so node (a, b) is lit on (its square − the overlap) · cos θ.
#include "geometry/scene/primitives.hpp"

#include <algorithm>
#include <string>

namespace radnet::testing {

struct ShadedPlate {
  geometry::Scene scene;
  int k;
  double side, height;
  geometry::Vec3 corner;
  /// @param roof_cells the occluder split roof_cells × roof_cells (its triangles' seams must not leak)
  ShadedPlate(int k_, double side_, double height_, geometry::Vec3 corner_, int roof_cells = 1)
      : k(k_), side(side_), height(height_), corner(corner_) {
    using geometry::Vec3;
    for (int a = 0; a < k; ++a)
      for (int b = 0; b < k; ++b) {
        const std::string name = "p" + std::to_string(a) + "_" + std::to_string(b);
        scene.addSurface(name, name,
                         geometry::rectangle(Vec3(double(a) / k, double(b) / k, 0), Vec3(1.0 / k, 0, 0),
                                             Vec3(0, 1.0 / k, 0), 1, 1),
                         name, "");
      }
    scene.addSurface("roof", "roof",
                     geometry::rectangle(corner + Vec3(0, 0, height), Vec3(side, 0, 0), Vec3(0, side, 0), roof_cells,
                                         roof_cells),
                     "", "");
  }
  /// Lit projected area of node (a, b) for the Sun along d (d.z() > 0), m².
  double exact(int a, int b, const geometry::Vec3& d) const {
    const double sx = corner.x() - height * d.x() / d.z(), sy = corner.y() - height * d.y() / d.z();
    const auto overlap = [](double a0, double a1, double b0, double b1) {
      return std::max(0.0, std::min(a1, b1) - std::max(a0, b0));
    };
    const double x0 = double(a) / k, y0 = double(b) / k, s = 1.0 / k;
    return (s * s - overlap(x0, x0 + s, sx, sx + side) * overlap(y0, y0 + s, sy, sy + side)) * d.z();
  }
};

}  // namespace radnet::testing
