// The shadow grid against closed forms: a meshed plate under a square occluder whose
// shadow is the occluder translated along the Sun's direction; the grid's standard error
// against the error it actually makes; and the per-node shadow rays as a second method.
#include "geometry/scene/primitives.hpp"
#include "geometry/irradiance/queries.hpp"
#include "geometry/irradiance/sun_grid.hpp"
#include "shaded_plate.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace radnet;
using geometry::Vec3;

using Shaded = testing::ShadedPlate;

TEST_CASE("shadow grid: unshadowed nodes are exact, shadowed ones within their standard error") {
  const Shaded s(10, 0.37, 0.5, Vec3(0.213, 0.288, 0));
  const geometry::RayCaster caster(s.scene);
  const Vec3 d = Vec3(0.3, 0.17, 1.0).normalized();
  int crossed = 0, within2 = 0, within1 = 0;
  double worst_lit = 0.0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    geometry::SunGridOptions opt;
    opt.cell_m = geometry::sunGridSpacing(0.01, 0.01);  // nodes of 0.1 m, 1 %: 2.6 mm
    opt.seed = seed;
    const geometry::SunlitArea lit = geometry::sunlitArea(caster, d, opt);
    CHECK(lit.sampled_nodes == 0);
    for (int a = 0; a < s.k; ++a)
      for (int b = 0; b < s.k; ++b) {
        const int i = a * s.k + b;
        const double truth = s.exact(a, b, d);
        CHECK(lit.facing_m2[i] == Approx(0.01 * d.z()).epsilon(1e-12));
        const bool full = std::abs(truth - 0.01 * d.z()) < 1e-15, dark = truth < 1e-15;
        if (full || dark) {  // no shadow edge crosses the node: exact, and σ = 0 ... up to outline cells
          worst_lit = std::max(worst_lit, std::abs(lit.projected_m2[i] - truth));
          continue;
        }
        ++crossed;
        const double err = std::abs(lit.projected_m2[i] - truth);
        within1 += err <= lit.stderr_m2[i];
        within2 += err <= 2 * lit.stderr_m2[i];
      }
  }
  // Fully lit nodes: every covered cell is won, the ratio is 1 and the answer the exact
  // projection; fully dark ones win none.
  CHECK(worst_lit < 1e-15);
  REQUIRE(crossed > 200);
  // Coverage of an honest normal error: 95 % at 2σ, 68 % at 1σ; the estimate of σ is
  // itself approximate (edge cells' p(1−p) averaged), so ask 90 % at 2σ and at most 97 %
  // at 1σ (not so wide as to be useless).
  INFO("crossed " << crossed << ", within 1σ " << within1 << ", within 2σ " << within2);
  CHECK(within2 >= 0.90 * crossed);
  CHECK(within1 <= 0.97 * crossed);
}

TEST_CASE("shadow grid: the same answer as per-node shadow rays, and small nodes fall back to them") {
  const Shaded s(10, 0.37, 0.5, Vec3(0.213, 0.288, 0));
  const geometry::RayCaster caster(s.scene);
  const Vec3 d = Vec3(-0.2, 0.4, 1.0).normalized();
  geometry::SunGridOptions opt;
  opt.cell_m = 2e-3;
  const geometry::SunlitArea grid = geometry::sunlitArea(caster, d, opt);
  const geometry::LitArea rays = geometry::litArea(caster, d, 1 << 16, 3);
  for (int i = 0; i < 100; ++i) {
    const double sigma = std::hypot(grid.stderr_m2[i], rays.stderr_m2[i]);
    INFO("node " << i << " grid " << grid.projected_m2[i] << " rays " << rays.projected_m2[i] << " sigma " << sigma);
    CHECK(std::abs(grid.projected_m2[i] - rays.projected_m2[i]) <= 4 * sigma + 1e-10 * rays.projected_m2[i]);  // 4σ: 100 nodes compared; round-off of 65536 summed cosines
  }
  // A grid too coarse for the nodes: each covers fewer than min_crossings cells and is
  // shadowed by its own rays.
  opt.cell_m = 0.05;
  const geometry::SunlitArea coarse = geometry::sunlitArea(caster, d, opt);
  CHECK(coarse.sampled_nodes == 100);
  CHECK(coarse.node_rays > 0);
  for (int a = 0; a < s.k; ++a)
    for (int b = 0; b < s.k; ++b) {
      const int i = a * s.k + b;
      CHECK(std::abs(coarse.projected_m2[i] - s.exact(a, b, d)) <= 5 * coarse.stderr_m2[i] + 1e-15);
    }
}

TEST_CASE("shadow grid: a spacing the memory cap cannot hold grows, a bad one is refused") {
  const Shaded s(4, 0.3, 0.5, Vec3(0.2, 0.2, 0));
  const geometry::RayCaster caster(s.scene);
  geometry::SunGridOptions opt;
  opt.cell_m = 1e-5;
  opt.max_cells = 1 << 16;
  const geometry::SunlitArea lit = geometry::sunlitArea(caster, Vec3(0, 0, 1), opt);
  CHECK(lit.cells <= opt.max_cells);
  CHECK(lit.cell_m > 1e-5);
  opt.cell_m = 0.0;
  CHECK_THROWS_AS(geometry::sunlitArea(caster, Vec3(0, 0, 1), opt), std::invalid_argument);
}
