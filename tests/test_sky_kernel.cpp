// Planet loads from the sky kernel (each node's blocked sky cast once, any attitude):
// exact where nothing blocks, exactly zero shut in a box, and where something blocks the
// same as the planet rays (a second method: rays into the planet's cone, cast at each
// position) within their error bars.
#include "geometry/irradiance/sky_kernel.hpp"
#include "geometry/scene/primitives.hpp"
#include "loads_support.hpp"
#include "orbits/loads.hpp"
#include "orbits/planet_sky.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

using namespace radnet;
using geometry::Vec3;

namespace {

const double kR = orbits::CentralBody::earth().equatorial_radius_m;

// Positions round the sky: planet and Sun directions from a fixed seed (an attitude
// that is neither nadir nor fixed), 600 km up.
std::vector<orbits::SweepPosition> tumblingPositions(int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g;
  std::vector<orbits::SweepPosition> ps;
  for (int k = 0; k < count; ++k) {
    const Vec3 planet(g(rng), g(rng), g(rng)), sun(g(rng), g(rng), g(rng));
    ps.push_back(testing::sweepPosition(sun, kR + 600e3, 1.0, 1361.0, planet));
  }
  return ps;
}

orbits::PlanetView viewAt(const orbits::SweepPosition& pos, const orbits::EnvironmentOptions& opt) {
  orbits::PlanetView v;
  v.toward_center = pos.planet_body;
  v.distance_m = pos.planet_distance_m;
  v.radius_m = kR;
  v.toward_sun = pos.sun_body;
  v.solar_flux_w_m2 = pos.solar_flux_w_m2;
  v.albedo = opt.albedo;
  v.ir = opt.planet_ir;
  return v;
}

// A 1 m² floor of 3 × 3 nodes and a 0.6 m wall of 2 × 2 along one edge, both sides of the
// wall active: half the floor's sky is blocked toward the wall.
geometry::Scene floorAndWall() {
  geometry::Scene s;
  s.addSurface("floor", "floor", geometry::rectangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 3, 3), "floor", "");
  s.addSurface("wall", "wall", geometry::rectangle(Vec3(0, 0, 0), Vec3(0, 0, 0.6), Vec3(0, 1, 0), 2, 2), "wall.back",
               "wall");
  return s;
}

}  // namespace

TEST_CASE("sky bins: every direction falls in the bin whose corners enclose it") {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> bin(0, geometry::SkyBins::kBins - 1);
  std::uniform_real_distribution<double> u(0.01, 0.99);
  for (int k = 0; k < 20000; ++k) {
    const int b = bin(rng);
    const Vec3 d = geometry::SkyBins::direction(b, u(rng), u(rng));
    CHECK(std::abs(d.norm() - 1.0) < 1e-14);
    REQUIRE(geometry::SkyBins::bin(d) == b);
  }
}

TEST_CASE("sky kernel: an unobstructed plate gets the closed-form rings, σ 0, at every attitude") {
  geometry::Scene s;
  s.addSurface("plate", "plate", geometry::rectangle(Vec3(0, 0, 0), Vec3(0.3, 0, 0), Vec3(0, 0.2, 0), 2, 3), "top",
               "bottom");
  geometry::RayCaster caster(s);
  orbits::EnvironmentOptions opt;
  const auto ps = tumblingPositions(24, 11);
  const orbits::EnvironmentLoads l = orbits::environmentLoads(caster, testing::nodeAreas(s), ps, false, kR, opt);
  REQUIRE(l.planet_kernel);
  CHECK(l.planet_rays == 0);  // nothing cast per position
  CHECK(l.kernel_rays == 0);  // nothing in front of either side: not a ray traced
  for (size_t p = 0; p < ps.size(); ++p) {
    const orbits::PlanetView v = viewAt(ps[p], opt);
    for (int side = 0; side < 2; ++side) {
      const orbits::PlanetChannels exact = orbits::unobstructedPlanetLoads(v, Vec3(0, 0, side == 0 ? 1 : -1));
      const Eigen::Index i = side, c = static_cast<Eigen::Index>(p);
      CHECK(l.earth_view_factor(i, c) == Approx(exact.view).epsilon(1e-12).margin(1e-15));
      CHECK(l.albedo(i, c) == Approx(exact.albedo).epsilon(1e-12).margin(1e-12));
      CHECK(l.earth_ir(i, c) == Approx(exact.ir).epsilon(1e-12).margin(1e-12));
      CHECK(l.albedo_stderr(i, c) == 0.0);
      CHECK(l.earth_ir_stderr(i, c) == 0.0);
    }
  }
}

TEST_CASE("sky kernel: inside a closed box the planet loads are exactly zero, outside the unobstructed face's") {
  const geometry::Scene s = testing::closedBox(3);
  geometry::RayCaster caster(s);
  orbits::EnvironmentOptions opt;
  const auto ps = tumblingPositions(30, 5);
  const orbits::EnvironmentLoads l = orbits::environmentLoads(caster, testing::nodeAreas(s), ps, false, kR, opt);
  REQUIRE(l.planet_kernel);
  CHECK(l.kernel_fallbacks == 0);
  for (int i = 0; i < static_cast<int>(s.nodes().size()); ++i) {
    const geometry::Node& node = s.nodes()[static_cast<size_t>(i)];
    const Vec3 normal = node.side * s.faces()[static_cast<size_t>(node.faces.front())].normal;
    for (size_t p = 0; p < ps.size(); ++p) {
      INFO(node.name << " position " << p);
      const Eigen::Index c = static_cast<Eigen::Index>(p);
      if (node.name.rfind("in", 0) == 0) {
        CHECK(l.earth_view_factor(i, c) == 0.0);
        CHECK(l.albedo(i, c) == 0.0);
        CHECK(l.earth_ir(i, c) == 0.0);
        CHECK(l.albedo_stderr(i, c) == 0.0);
      } else {
        const orbits::PlanetChannels exact = orbits::unobstructedPlanetLoads(viewAt(ps[p], opt), normal);
        CHECK(l.albedo(i, c) == Approx(exact.albedo).epsilon(1e-12).margin(1e-12));
        CHECK(l.earth_ir(i, c) == Approx(exact.ir).epsilon(1e-12).margin(1e-12));
      }
    }
  }
}

TEST_CASE("sky kernel: a plate beside a wall and under an awning agrees with planet rays within the error bars") {
  // Partly blocked nodes at 16 tumbling attitudes; the planet rays (65,536 per node,
  // cast at each position) are the second method. |kernel − rays| ≤ 4 × the combined σ
  // (plus 1e-3 of the scale for the rays' own correlated error of the limb's round-off).
  geometry::Scene s;
  s.addSurface("floor", "floor", geometry::rectangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 2, 2), "floor", "");
  s.addSurface("wall", "wall", geometry::rectangle(Vec3(0, 0, 0), Vec3(0, 0, 0.6), Vec3(0, 1, 0), 1, 1), "wall.back",
               "wall");
  s.addSurface("awning", "awning", geometry::rectangle(Vec3(0, 0, 0.6), Vec3(0, 1, 0), Vec3(0.5, 0, 0), 1, 1),
               "awning.top", "awning.bottom");
  geometry::RayCaster caster(s);
  const auto ps = tumblingPositions(16, 3);
  orbits::EnvironmentOptions kernel_opt, ray_opt;
  ray_opt.planet_method = orbits::EnvironmentOptions::PlanetMethod::Rays;
  ray_opt.planet_rays = 65536;
  const Eigen::VectorXd area = testing::nodeAreas(s);
  const orbits::EnvironmentLoads k = orbits::environmentLoads(caster, area, ps, false, kR, kernel_opt);
  const orbits::EnvironmentLoads r = orbits::environmentLoads(caster, area, ps, false, kR, ray_opt);
  REQUIRE(k.planet_kernel);
  REQUIRE_FALSE(r.planet_kernel);
  const double scale_albedo = 0.3 * 1361.0, scale_ir = 237.0;  // × a view factor ≤ 1
  double worst = 0.0;
  for (Eigen::Index i = 0; i < k.albedo.rows(); ++i)
    for (Eigen::Index p = 0; p < k.albedo.cols(); ++p) {
      INFO(s.nodes()[static_cast<size_t>(i)].name << " position " << p << ": albedo " << k.albedo(i, p) << " ± "
                                                   << k.albedo_stderr(i, p) << " vs " << r.albedo(i, p) << " ± "
                                                   << r.albedo_stderr(i, p));
      const double sa = std::hypot(k.albedo_stderr(i, p), r.albedo_stderr(i, p));
      const double si = std::hypot(k.earth_ir_stderr(i, p), r.earth_ir_stderr(i, p));
      CHECK(std::abs(k.albedo(i, p) - r.albedo(i, p)) <= 4 * sa + 1e-3 * scale_albedo);
      CHECK(std::abs(k.earth_ir(i, p) - r.earth_ir(i, p)) <= 4 * si + 1e-3 * scale_ir);
      // The kernel's error bar is a useful one: within 1 % of the scale.
      CHECK(k.earth_ir_stderr(i, p) <= 0.01 * scale_ir);
      worst = std::max(worst, std::abs(k.earth_ir(i, p) - r.earth_ir(i, p)) / scale_ir);
    }
  INFO("largest IR difference " << worst << " of 237 W/m²");
  CHECK(worst < 5e-3);
  CHECK(k.earth_ir.cwiseAbs().sum() > 0);
}

TEST_CASE("sky kernel: a partly blocked node's σ carries one ray's share of the sky at the planet's peak") {
  // Where a node sees the planet and something blocks part of its sky, the kernel resolves
  // that sky to one ray's share (1/N of the cosine-weighted hemisphere): σ is at least that
  // share at the planet's largest radiance, per channel (orbits/sky_loads.cpp, nodeLoads);
  // a node nothing blocks keeps σ = 0 (exact), and so does a node that cannot see the planet.
  const geometry::Scene s = testing::plateUnderRoof();
  geometry::RayCaster caster(s);
  const auto ps = tumblingPositions(12, 21);
  geometry::SkyKernel kernel;
  orbits::EnvironmentOptions opt;
  opt.sky_kernel_cache = &kernel;
  const orbits::EnvironmentLoads k = orbits::environmentLoads(caster, testing::nodeAreas(s), ps, false, kR, opt);
  REQUIRE(k.planet_kernel);
  int partly = 0;
  for (Eigen::Index i = 0; i < k.albedo.rows(); ++i) {
    const geometry::NodeSky& sky = kernel.nodes[static_cast<size_t>(i)];
    const bool blocked = sky.blocked_fraction > 0 && sky.blocked_fraction < 1;
    partly += blocked;
    for (Eigen::Index p = 0; p < k.albedo.cols(); ++p) {
      INFO(s.nodes()[static_cast<size_t>(i)].name << " position " << p << ", " << sky.rays << " rays");
      const double albedo_peak = opt.albedo * ps[static_cast<size_t>(p)].solar_flux_w_m2, ir_peak = 237.0;
      const double per_ray = sky.ray_share / double(sky.rays);  // the hemisphere one ray stands for
      if (blocked && k.albedo(i, p) > 0) CHECK(k.albedo_stderr(i, p) >= albedo_peak * per_ray * (1 - 1e-12));
      if (blocked && k.earth_ir(i, p) > 0) CHECK(k.earth_ir_stderr(i, p) >= ir_peak * per_ray * (1 - 1e-12));
      if (k.earth_view_factor(i, p) == 0) CHECK(k.earth_ir_stderr(i, p) == 0.0);
    }
  }
  CHECK(partly >= 2);
}

TEST_CASE("sky kernel: every node meets its target, the loads' share of its absorbed power's lower bound") {
  // The refined kernel's promise (orbits/sky_loads.hpp, KernelTargets): at every position
  // α σ_A and ε σ_I, each over its half of relative_error × max over the sweep of α (D + A) +
  // ε I (what the node absorbs of its own irradiance, a lower bound of its orbit-maximum
  // absorbed power; or the floor of a tenth of the cap), add to at most 2, after 1,024 rays
  // and the rounds of re-casting; none of this scene's node-positions needs the planet rays'
  // fallback. (Where that bound exceeds both floors, α σ_A + ε σ_I is within relative_error
  // of it.)
  const geometry::Scene s = floorAndWall();
  geometry::RayCaster caster(s);
  const auto ps = tumblingPositions(24, 5);
  // A black floor under a low-ε coating, a white wall: the ratios far from 1 both ways.
  const Eigen::Index n = static_cast<Eigen::Index>(s.nodes().size());
  Eigen::VectorXd alpha(n), epsilon(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const bool floor = s.nodes()[static_cast<size_t>(i)].name.rfind("floor", 0) == 0;
    alpha[i] = floor ? 0.9 : 0.2, epsilon[i] = floor ? 0.1 : 0.9;
  }
  orbits::EnvironmentOptions opt;
  opt.absorptance.min_alpha_over_epsilon = alpha.cwiseQuotient(epsilon);
  opt.absorptance.min_epsilon_over_alpha = epsilon.cwiseQuotient(alpha);
  const orbits::EnvironmentLoads k = orbits::environmentLoads(caster, testing::nodeAreas(s), ps, false, kR, opt);
  REQUIRE(k.planet_kernel);
  CHECK(k.kernel_fallbacks == 0);
  // Some nodes were re-cast past the first cast's 1,024 rays, and fewer rays went than to
  // the targets without the ratios (the IR's then its largest IR alone).
  CHECK(k.kernel_rays > 1024 * n);
  const orbits::EnvironmentLoads plain =
      orbits::environmentLoads(caster, testing::nodeAreas(s), ps, false, kR, orbits::EnvironmentOptions{});
  CHECK(k.kernel_rays < plain.kernel_rays);
  double cap_sin2 = 1.0;
  for (const auto& pos : ps) cap_sin2 = std::min(cap_sin2, std::pow(kR / pos.planet_distance_m, 2));
  const double share = 0.5 * opt.relative_error, floor_view = 0.1 * cap_sin2;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double absorbed = (alpha[i] * (k.direct.row(i) + k.albedo.row(i)) + epsilon[i] * k.earth_ir.row(i)).maxCoeff();
    const double albedo_target = share * std::max(absorbed, alpha[i] * floor_view * 0.3 * 1361.0);
    const double ir_target = share * std::max(absorbed, epsilon[i] * floor_view * 237.0);
    for (Eigen::Index p = 0; p < k.albedo.cols(); ++p) {
      INFO(s.nodes()[static_cast<size_t>(i)].name << " position " << p);
      CHECK(alpha[i] * k.albedo_stderr(i, p) / albedo_target + epsilon[i] * k.earth_ir_stderr(i, p) / ir_target <=
            2 * (1 + 1e-12));
    }
  }
}

TEST_CASE("sky kernel: with a cross weight the targets hold for loads a reusing case scales") {
  // A later design case reuses the irradiances with the direct load scaled by 0.6 against
  // the albedo and IR (a lower solar constant, a higher albedo and IR): the cross weight
  // min(d/a, i/a, d/i, a/i) = 0.6 keeps α σ_A and ε σ_I, each over half the share of that
  // case's own absorbed-power bound, added within 2, every loaded quantity (and its σ) scaled
  // as the case does.
  const geometry::Scene s = floorAndWall();
  geometry::RayCaster caster(s);
  const auto ps = tumblingPositions(24, 5);
  const Eigen::Index n = static_cast<Eigen::Index>(s.nodes().size());
  const Eigen::VectorXd alpha = Eigen::VectorXd::Constant(n, 0.9), epsilon = Eigen::VectorXd::Constant(n, 0.3);
  const double d = 0.6, a = 1.0, ir = 1.0;  // the reusing case's factors on direct, albedo, IR
  orbits::EnvironmentOptions opt;
  opt.absorptance.min_alpha_over_epsilon = alpha.cwiseQuotient(epsilon);
  opt.absorptance.min_epsilon_over_alpha = epsilon.cwiseQuotient(alpha);
  opt.absorptance.cross_weight = std::min({d / a, ir / a, d / ir, a / ir});
  const orbits::EnvironmentLoads k = orbits::environmentLoads(caster, testing::nodeAreas(s), ps, false, kR, opt);
  REQUIRE(k.planet_kernel);
  double cap_sin2 = 1.0;
  for (const auto& pos : ps) cap_sin2 = std::min(cap_sin2, std::pow(kR / pos.planet_distance_m, 2));
  const double share = 0.5 * opt.relative_error, floor_view = 0.1 * cap_sin2;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double absorbed =
        (alpha[i] * (d * k.direct.row(i) + a * k.albedo.row(i)) + epsilon[i] * ir * k.earth_ir.row(i)).maxCoeff();
    for (Eigen::Index p = 0; p < k.albedo.cols(); ++p) {
      INFO(s.nodes()[static_cast<size_t>(i)].name << " position " << p);
      const double albedo_part = alpha[i] * a * k.albedo_stderr(i, p) / (share * std::max(absorbed, alpha[i] * a * floor_view * 0.3 * 1361.0));
      const double ir_part = epsilon[i] * ir * k.earth_ir_stderr(i, p) / (share * std::max(absorbed, epsilon[i] * ir * floor_view * 237.0));
      CHECK(albedo_part + ir_part <= 2 * (1 + 1e-12));
    }
  }
}

TEST_CASE("sky kernel loads shared out by node (as over MPI ranks) add up to the whole, bit for bit") {
  const geometry::Scene s = testing::plateUnderRoof();
  geometry::RayCaster caster(s);
  const auto ps = tumblingPositions(6, 9);
  const orbits::EnvironmentOptions opt;
  const Eigen::VectorXd area = testing::nodeAreas(s);
  const orbits::EnvironmentLoads whole = orbits::environmentLoads(caster, area, ps, false, kR, opt);
  orbits::EnvironmentLoads parts[2];
  for (int part = 0; part < 2; ++part) {
    orbits::EnvironmentOptions o = opt;
    for (size_t i = 0; i < s.nodes().size(); ++i) o.planet_nodes.push_back(static_cast<char>(i % 2 == size_t(part)));
    // The direct loads shared out by position: the kernel's targets read every position's.
    for (size_t p = 0; p < ps.size(); ++p) o.sun_positions.push_back(static_cast<char>(p % 2 == size_t(part)));
    parts[part] = orbits::environmentLoads(caster, area, ps, false, kR, o);
  }
  CHECK(Eigen::MatrixXd(parts[0].direct + parts[1].direct) == whole.direct);
  CHECK(Eigen::MatrixXd(parts[0].albedo + parts[1].albedo) == whole.albedo);
  CHECK(Eigen::MatrixXd(parts[0].albedo_stderr + parts[1].albedo_stderr) == whole.albedo_stderr);
  CHECK(Eigen::MatrixXd(parts[0].earth_ir + parts[1].earth_ir) == whole.earth_ir);
  CHECK(Eigen::MatrixXd(parts[0].earth_view_factor + parts[1].earth_view_factor) == whole.earth_view_factor);
  CHECK(parts[0].kernel_rays + parts[1].kernel_rays == whole.kernel_rays);
  CHECK(whole.albedo.cwiseAbs().sum() > 0);
}

TEST_CASE("planet method auto: planet rays cast once when the planet stays put, the kernel when it moves") {
  geometry::Scene s;
  s.addSurface("plate", "plate", geometry::rectangle(Vec3(0, 0, 0), Vec3(0.3, 0, 0), Vec3(0, 0.2, 0), 1, 1), "top",
               "bottom");
  geometry::RayCaster caster(s);
  const orbits::EnvironmentOptions opt;  // auto
  const Eigen::VectorXd area = testing::nodeAreas(s);
  std::vector<orbits::SweepPosition> still, elliptic;
  for (int k = 0; k < 4; ++k) {
    still.push_back(testing::sweepPosition(Vec3(1, k, 0.5), kR + 600e3));
    elliptic.push_back(testing::sweepPosition(Vec3(1, k, 0.5), kR + 600e3 + 1e5 * k));
  }
  const orbits::EnvironmentLoads a = orbits::environmentLoads(caster, area, still, true, kR, opt);
  CHECK_FALSE(a.planet_kernel);
  CHECK(a.planet_casts == 1);
  const orbits::EnvironmentLoads b = orbits::environmentLoads(caster, area, elliptic, true, kR, opt);
  CHECK(b.planet_kernel);
  CHECK(b.planet_rays == 0);
  const orbits::EnvironmentLoads c = orbits::environmentLoads(caster, area, tumblingPositions(4, 1), false, kR, opt);
  CHECK(c.planet_kernel);
  // An albedo by latitude, or a planet beyond 7,900 km: planet rays.
  orbits::EnvironmentOptions table = opt;
  table.albedo_by_latitude = {{0.0, 0.3}, {90.0, 0.2}};
  CHECK_FALSE(orbits::environmentLoads(caster, area, tumblingPositions(2, 1), false, kR, table).planet_kernel);
  std::vector<orbits::SweepPosition> geo;
  for (auto p : tumblingPositions(2, 1)) p.planet_distance_m = 42164e3, geo.push_back(p);
  CHECK_FALSE(orbits::environmentLoads(caster, area, geo, false, kR, opt).planet_kernel);
}
