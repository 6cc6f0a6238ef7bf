// Rows cast again after parts turn (geometry/rays/recast_rows.hpp): a plan grown row by row
// is the plan cast at once, and the share of a row's rays a turn can redirect, drawn without
// tracing, agrees with the share the cast traced.
#include "geometry/rays/recast_rows.hpp"
#include "geometry/scene/primitives.hpp"
#include "geometry/scene/swept_volume.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using namespace radnet::geometry;

namespace {

// A deck (fixed, facing +z), a wall beside it (fixed, facing −x) and a flap above the deck's
// edge that turns about the y axis through (1, 0, 0.5).
Scene deckWallFlap() {
  Scene s;
  s.addSurface("deck", "deck", rectangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 2, 2), "deck", "");
  s.addSurface("wall", "wall", rectangle(Vec3(2, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), 2, 2), "wall", "");
  s.addSurface("flap", "flap", rectangle(Vec3(1, 0, 0.5), Vec3(0.6, 0, 0), Vec3(0, 1, 0), 2, 2), "flap", "flap.back");
  return s;
}

// Rays from a fixed node meeting the flap's swept cylinder; from the flap's nodes, all.
RayMayChange mayChange(const Scene& s) {
  const SweptCylinder swept = sweptCylinder(s, {2}, Vec3(1, 0, 0.5), Vec3(0, 1, 0));
  return [swept](int node, const Vec3& origin, const Vec3& dir) { return node >= 2 || swept.meets(origin, dir); };
}

ViewFactorOptions rayOptions() {
  ViewFactorOptions opt;
  opt.rays_per_node = 1 << 15;
  opt.min_rays_per_node = 1024;
  opt.target_error = 2e-3;  // rows double their rays to it: the plan's counts differ row by row
  opt.replicas = 16;
  return opt;
}

}  // namespace

TEST_CASE("recast rows: a plan grown by addPlannedRows equals the plan cast at once, and so do the turned rows") {
  const Scene written = deckWallFlap();
  const RayCaster caster(written);
  const RayMayChange may_change = mayChange(written);
  const std::vector<char> all = {1, 1, 1, 1}, first = {1, 0, 0, 1}, rest = {0, 1, 1, 0};
  ViewFactorOptions opt = rayOptions();
  opt.cast_rows = all;
  RecastPlan whole;
  castPlannedRows(caster, opt, may_change, whole);
  opt.cast_rows = first;
  RecastPlan grown;
  castPlannedRows(caster, opt, may_change, grown);
  CHECK(grown.per_replica[1] == 0);  // not cast yet
  addPlannedRows(caster, may_change, rest, grown);
  for (size_t i = 0; i < all.size(); ++i) {
    INFO("node " << i);
    CHECK(grown.per_replica[i] == whole.per_replica[i]);
    CHECK(grown.traced[i] == whole.traced[i]);
    CHECK(grown.kept[i] == whole.kept[i]);
    REQUIRE(grown.rays[i].size() == whole.rays[i].size());
    for (size_t r = 0; r < grown.rays[i].size(); ++r) {
      REQUIRE(grown.rays[i][r].size() == whole.rays[i][r].size());
      for (size_t k = 0; k < grown.rays[i][r].size(); ++k)
        CHECK((grown.rays[i][r][k].origin == whole.rays[i][r][k].origin &&
               grown.rays[i][r][k].direction == whole.rays[i][r][k].direction));
    }
  }
  CHECK(grown.rays_kept == whole.rays_kept);
  CHECK(whole.traced[0] > 0);  // the deck has rays the flap can redirect, and kept ones
  // The flap turned by 70°: the rows cast again from either plan are the same, bit for bit.
  Scene turned = written;
  turned.rotateSurfaces({2}, Vec3(1, 0, 0.5), Vec3(0, 1, 0), 70.0 * M_PI / 180.0);
  const RayCaster moved(turned);
  const Eigen::Isometry3d turn = Eigen::Translation3d(1, 0, 0.5) * Eigen::AngleAxisd(70.0 * M_PI / 180.0, Vec3::UnitY()) *
                                 Eigen::Translation3d(-1, 0, -0.5);
  std::vector<Eigen::Isometry3d> motion(4, Eigen::Isometry3d::Identity());
  motion[2] = motion[3] = turn;
  const ViewFactorResult a = recastRows(moved, whole, may_change, motion), b = recastRows(moved, grown, may_change, motion);
  CHECK(Eigen::MatrixXd(a.view_factors - b.view_factors).cwiseAbs().maxCoeff() == 0.0);
  CHECK(Eigen::MatrixXd(a.standard_error - b.standard_error).cwiseAbs().maxCoeff() == 0.0);
  CHECK(a.view_factors.coeff(0, 2) + a.view_factors.coeff(0, 3) > 0.01);  // the deck sees the turned flap
}

TEST_CASE("recast rows: the redirectable share drawn without tracing agrees with the share the cast traced") {
  const Scene written = deckWallFlap();
  const RayCaster caster(written);
  const RayMayChange may_change = mayChange(written);
  ViewFactorOptions opt = rayOptions();
  opt.cast_rows = {1, 1, 1, 1};
  RecastPlan plan;
  const ViewFactorResult cast = castPlannedRows(caster, opt, may_change, plan);
  const std::int64_t pilot = 64;  // per replica: 1,024 rays a row
  const std::vector<double> share = redirectableShares(written, opt, may_change, opt.cast_rows, pilot);
  for (int i = 0; i < 4; ++i) {
    const double traced = double(plan.traced[size_t(i)]) / double(cast.rays[size_t(i)]);
    // The pilot's rays are the cast's first ones: a binomial share of 1,024 within 4σ of the
    // cast's (itself of ≥ 1,024 rays; 4σ of the pilot's spread bounds both).
    const double sigma = std::sqrt(std::max(traced * (1 - traced), 1e-3) / double(pilot * opt.replicas));
    INFO("node " << i << ": pilot " << share[size_t(i)] << ", traced " << traced);
    CHECK(std::abs(share[size_t(i)] - traced) <= 4 * sigma);
  }
  CHECK(share[2] == 1.0);                          // the flap's own rays: all may change
  CHECK((share[0] > 0.05 && share[0] < 0.95));     // the deck: some meet the swept cylinder, some not
}
