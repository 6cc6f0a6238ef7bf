#pragma once
// The paper's 5 × 3 × 2.5 m room, its six inner faces each split sub × sub, one node per
// face (front sides inward): shared by the view-factor tests and benchmarks.
#include "geometry/scene/primitives.hpp"
#include "geometry/scene/scene.hpp"

namespace radnet::test {

inline geometry::Scene paperRoom(int sub) {
  using geometry::rectangle;
  using geometry::Vec3;
  geometry::Scene s;
  const double lx = 5.0, ly = 3.0, lz = 2.5;
  s.addSurface("ceiling", "c", rectangle(Vec3(0, 0, lz), Vec3(0, ly, 0), Vec3(lx, 0, 0), sub, sub), "ceiling", "");
  s.addSurface("end1", "e1", rectangle(Vec3(0, 0, 0), Vec3(0, ly, 0), Vec3(0, 0, lz), sub, sub), "end1", "");
  s.addSurface("end2", "e2", rectangle(Vec3(lx, 0, 0), Vec3(0, 0, lz), Vec3(0, ly, 0), sub, sub), "end2", "");
  s.addSurface("side1", "s1", rectangle(Vec3(0, 0, 0), Vec3(0, 0, lz), Vec3(lx, 0, 0), sub, sub), "side1", "");
  s.addSurface("side2", "s2", rectangle(Vec3(0, ly, 0), Vec3(lx, 0, 0), Vec3(0, 0, lz), sub, sub), "side2", "");
  s.addSurface("floor", "f", rectangle(Vec3(0, 0, 0), Vec3(lx, 0, 0), Vec3(0, ly, 0), sub, sub), "floor", "");
  return s;
}

}  // namespace radnet::test
