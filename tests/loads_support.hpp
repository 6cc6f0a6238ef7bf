#pragma once
// Sweep positions made by hand and node areas for the environment-load tests.
#include "geometry/scene/primitives.hpp"
#include "geometry/scene/scene.hpp"
#include "orbits/sweep.hpp"

#include <Eigen/Dense>

#include <string>

namespace radnet::testing {

/// One position: the planet's centre at distance r along `planet_body` (default +z), the
/// Sun along `sun_body` (both body frame, normalised here).
inline orbits::SweepPosition sweepPosition(const geometry::Vec3& sun_body, double r, double sunlit = 1.0,
                                           double flux = 1361.0,
                                           const geometry::Vec3& planet_body = geometry::Vec3::UnitZ()) {
  orbits::SweepPosition p;
  p.sun_body = sun_body.normalized();
  p.planet_body = planet_body.normalized();
  p.planet_distance_m = r;
  p.sunlit_fraction = sunlit;
  p.solar_flux_w_m2 = flux;
  p.body_from_eci = Eigen::Matrix3d::Identity();
  return p;
}

/// A per node, scene order, m².
inline Eigen::VectorXd nodeAreas(const geometry::Scene& s) {
  Eigen::VectorXd a(static_cast<Eigen::Index>(s.nodes().size()));
  for (size_t i = 0; i < s.nodes().size(); ++i) a[static_cast<Eigen::Index>(i)] = s.nodes()[i].area_m2;
  return a;
}

/// A two-sided 1 m plate (2 × 2 nodes) and a two-sided roof 1 m above it, offset: the
/// shared scene of the tests that split loads as MPI ranks do.
inline geometry::Scene plateUnderRoof() {
  using geometry::Vec3;
  geometry::Scene s;
  s.addSurface("plate", "plate", geometry::rectangle(Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(1, 0, 0), 2, 2), "plate",
               "plate.back");
  s.addSurface("roof", "roof", geometry::rectangle(Vec3(0.5, -0.5, -1), Vec3(0, 2, 0), Vec3(2, 0, 0), 1, 1), "roof",
               "roof.back");
  return s;
}

/// A closed box about the origin (0.2 × 0.2 × 0.3 m, each face split n × n), its six faces
/// two-sided: outside nodes "out+x" …, inside nodes "in+x" ….
inline geometry::Scene closedBox(int n) {
  using geometry::Vec3;
  geometry::Scene s;
  const auto faces = geometry::boxFaces(Vec3(-0.1, -0.1, -0.15), Vec3(0.2, 0.2, 0.3), n);
  for (int f = 0; f < 6; ++f) {
    const std::string name = geometry::kBoxFaceNames[static_cast<size_t>(f)];
    s.addSurface(name, name, faces[static_cast<size_t>(f)], "out" + name, "in" + name);
  }
  return s;
}

}  // namespace radnet::testing
