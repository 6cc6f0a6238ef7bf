// Environment irradiances against closed forms: direct Sun with shadows and eclipses,
// Earth IR and albedo of a nadir plate.
#include "cap_quadrature.hpp"
#include "geometry/scene/primitives.hpp"
#include "loads_support.hpp"
#include "orbits/loads.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace radnet;
using geometry::Vec3;

namespace {

const double kR = orbits::CentralBody::earth().equatorial_radius_m;

orbits::SweepPosition position(const Vec3& sun_body, double r, double sunlit = 1.0, double flux = 1361.0) {
  return testing::sweepPosition(sun_body, r, sunlit, flux);
}

Eigen::VectorXd areas(const geometry::Scene& s) { return testing::nodeAreas(s); }

// Albedo irradiance on a nadir-facing plate above the subsolar point, by quadrature over
// the visible cap (ψ: angle at the Earth's centre from the sub-satellite point):
// E = ∫ (a S cos ψ / π) cos θ cos α / d² · 2π R² sin ψ dψ.
double albedoSubsolar(double a, double S, double r) {
  return testing::nadirPlateIrradiance(kR, r, [&](double psi) { return a * S * std::cos(psi); });
}

}  // namespace

TEST_CASE("direct solar: a plate facing the Sun gets the full flux, none in eclipse or behind another plate") {
  geometry::Scene s;
  s.addSurface("plate", "plate", geometry::rectangle(Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(1, 0, 0), 2, 2), "plate", "");
  s.addSurface("shaded", "shaded", geometry::rectangle(Vec3(3, 0, 0), Vec3(0, 1, 0), Vec3(1, 0, 0), 1, 1), "shaded",
               "");
  s.addSurface("roof", "roof", geometry::rectangle(Vec3(2.5, -0.5, -1), Vec3(0, 2, 0), Vec3(2, 0, 0), 1, 1), "",
               "roof.back");
  geometry::RayCaster caster(s);
  orbits::EnvironmentOptions opt;
  opt.planet_rays = 1024;
  // The plates face −z; the Sun is at −z (zenith), the Earth at +z.
  const std::vector<orbits::SweepPosition> ps = {position(Vec3(0, 0, -1), kR + 500e3),
                                                 position(Vec3(0, 0, -1), kR + 500e3, 0.0),
                                                 position(Vec3(0, 0, -1), kR + 500e3, 0.4)};
  const orbits::EnvironmentLoads l = orbits::environmentLoads(caster, areas(s), ps, true, kR, opt);
  CHECK(l.direct(0, 0) == Approx(1361.0).epsilon(1e-12));        // α S A once multiplied by α A
  CHECK(l.direct(0, 1) == 0.0);                                  // eclipse
  CHECK(l.direct(0, 2) == Approx(0.4 * 1361.0).epsilon(1e-12));  // penumbra
  CHECK(l.direct(1, 0) == 0.0);                                  // under the roof
  CHECK(l.planet_casts == 1);                                    // Earth fixed: rays cast once, reused
}

TEST_CASE("direct solar: a closed box's inside gets exactly nothing at any Sun direction, its outside the cosine") {
  // The loads' default method (exact clipping): a box with inside nodes, Sun directions
  // swept round two great circles, one 0.12° off a face axis (where grid rays slipped
  // through seams before).
  const geometry::Scene s = testing::closedBox(4);
  geometry::RayCaster caster(s);
  orbits::EnvironmentOptions opt;
  opt.planet_rays = 1024;
  std::vector<orbits::SweepPosition> ps;
  const double off = 0.12 * M_PI / 180;
  for (int k = 0; k < 36; ++k) {
    const double t = 2 * M_PI * k / 36;
    ps.push_back(position(Vec3(std::cos(t), std::sin(t) * std::cos(off), std::sin(t) * std::sin(off)), kR + 500e3));
    ps.push_back(position(Vec3(std::sin(off), std::cos(t), std::sin(t)), kR + 500e3));
  }
  const orbits::EnvironmentLoads l = orbits::environmentLoads(caster, areas(s), ps, false, kR, opt);
  for (int i = 0; i < static_cast<int>(s.nodes().size()); ++i) {
    const geometry::Node& node = s.nodes()[static_cast<size_t>(i)];
    const Vec3 outward = s.faces()[static_cast<size_t>(node.faces.front())].normal;
    for (size_t p = 0; p < ps.size(); ++p) {
      INFO(node.name << " position " << p);
      if (node.name.rfind("in", 0) == 0) CHECK(l.direct(i, static_cast<Eigen::Index>(p)) == 0.0);
      else CHECK(l.direct(i, static_cast<Eigen::Index>(p)) ==
                 Approx(1361.0 * std::max(0.0, outward.dot(ps[p].sun_body))).margin(1e-9));
      CHECK(l.direct_stderr(i, static_cast<Eigen::Index>(p)) <= 1e-9 * 1361.0);  // round-off slivers' bound only
    }
  }
  CHECK(l.shadow_rays == 0);
}

TEST_CASE("Earth IR and albedo of a nadir plate against closed forms") {
  const double h = 500e3, r = kR + h;
  geometry::Scene s;
  s.addSurface("plate", "plate", geometry::rectangle(Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0, 0.1, 0), 1, 1), "plate",
               "");
  geometry::RayCaster caster(s);
  orbits::EnvironmentOptions opt;
  opt.planet_rays = 65536;
  const orbits::EnvironmentLoads l =
      orbits::environmentLoads(caster, areas(s), {position(Vec3(0, 0, -1), r)}, true, kR, opt);
  // Earth IR: OLR (R/r)²; the ray estimate's σ of the view factor is ~2e-3 at 65k rays:
  // allow 1 % (about 4σ).
  CHECK(l.earth_ir(0, 0) == Approx(237.0 * std::pow(kR / r, 2)).epsilon(0.01));
  const double exact = albedoSubsolar(0.30, 1361.0, r);
  INFO("albedo " << l.albedo(0, 0) << " W/m², quadrature " << exact);
  CHECK(l.albedo(0, 0) == Approx(exact).epsilon(0.01));
  // The Sun below the horizon of the whole visible cap: no albedo, same Earth IR.
  const orbits::EnvironmentLoads night =
      orbits::environmentLoads(caster, areas(s), {position(Vec3(0, 0, 1), r, 0.0)}, true, kR, opt);
  CHECK(night.albedo(0, 0) == 0.0);
  CHECK(night.earth_ir(0, 0) == Approx(l.earth_ir(0, 0)));
  // Latitude-dependent albedo: a table constant at 0.5 doubles nothing but the coefficient.
  opt.albedo_by_latitude = {{0.0, 0.5}, {90.0, 0.5}};
  const orbits::EnvironmentLoads half =
      orbits::environmentLoads(caster, areas(s), {position(Vec3(0, 0, -1), r)}, true, kR, opt);
  CHECK(half.albedo(0, 0) == Approx(l.albedo(0, 0) * 0.5 / 0.3).epsilon(1e-12));
  CHECK(orbits::albedoAt(opt, 45.0) == 0.5);
}

TEST_CASE("loads shared out by sun position and planet node (as over MPI ranks) add up to the whole, bit for bit") {
  const geometry::Scene s = testing::plateUnderRoof();
  geometry::RayCaster caster(s);
  const double r = kR + 500e3;
  const std::vector<orbits::SweepPosition> ps = {position(Vec3(0.3, 0, -1), r), position(Vec3(1, 0.2, -1), r, 0.5),
                                                 position(Vec3(-0.2, 1, -0.3), r), position(Vec3(0, 0, 1), r)};
  orbits::EnvironmentOptions opt;
  opt.planet_rays = 2048;
  const orbits::EnvironmentLoads whole = orbits::environmentLoads(caster, areas(s), ps, true, kR, opt);
  orbits::EnvironmentLoads parts[2];
  for (int part = 0; part < 2; ++part) {
    orbits::EnvironmentOptions o = opt;
    for (size_t p = 0; p < ps.size(); ++p) o.sun_positions.push_back(static_cast<char>(p % 2 == size_t(part)));
    for (size_t i = 0; i < s.nodes().size(); ++i) o.planet_nodes.push_back(static_cast<char>(i % 2 == size_t(part)));
    parts[part] = orbits::environmentLoads(caster, areas(s), ps, true, kR, o);
  }
  // What a part does not own is exactly 0, so the sum is each owner's value.
  CHECK(Eigen::MatrixXd(parts[0].direct + parts[1].direct) == whole.direct);
  CHECK(Eigen::MatrixXd(parts[0].direct_stderr + parts[1].direct_stderr) == whole.direct_stderr);
  CHECK(Eigen::MatrixXd(parts[0].albedo + parts[1].albedo) == whole.albedo);
  CHECK(Eigen::MatrixXd(parts[0].earth_ir + parts[1].earth_ir) == whole.earth_ir);
  CHECK(Eigen::MatrixXd(parts[0].earth_view_factor + parts[1].earth_view_factor) == whole.earth_view_factor);
  CHECK(parts[0].planet_rays + parts[1].planet_rays == whole.planet_rays);
  CHECK(parts[0].shadow_rays + parts[1].shadow_rays == whole.shadow_rays);
  CHECK(whole.direct.cwiseAbs().sum() > 0);  // the comparison is not of zeros
  CHECK(whole.albedo.cwiseAbs().sum() > 0);
  CHECK(parts[0].direct.col(1).isZero(0));   // position 1 is part 1's
  CHECK(parts[1].albedo.row(0).isZero(0));   // node 0 is part 0's
}
