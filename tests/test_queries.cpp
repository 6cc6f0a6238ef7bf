// Ray-casting queries for the orbit stage: lit areas and planet rays.
#include "geometry/scene/primitives.hpp"
#include "geometry/irradiance/queries.hpp"
#include "geometry/rays/sampling.hpp"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

using namespace radnet::geometry;

TEST_CASE("lit area: a plate facing the source, tilted, behind another plate, half shadowed") {
  Scene s;
  s.addSurface("plate", "plate", rectangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 2, 0), 2, 2), "plate", "plate.back");
  RayCaster caster(s);
  const LitArea up = litArea(caster, Vec3(0, 0, 1), 256);
  CHECK(up.projected_m2[0] == Approx(2.0).epsilon(1e-12));  // fully lit, normal incidence
  CHECK(up.projected_m2[1] == 0.0);                         // the back faces away: no rays
  const LitArea tilted = litArea(caster, Vec3(0, std::sin(0.5), std::cos(0.5)), 256);
  CHECK(tilted.projected_m2[0] == Approx(2.0 * std::cos(0.5)).epsilon(1e-12));
  CHECK(tilted.lit_fraction[0] == Approx(1.0));

  Scene shaded;
  shaded.addSurface("plate", "plate", rectangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 1, 1), "plate", "");
  shaded.addSurface("roof", "roof", rectangle(Vec3(-1, -1, 1), Vec3(3, 0, 0), Vec3(0, 3, 0), 1, 1), "roof", "");
  RayCaster c2(shaded);
  CHECK(litArea(c2, Vec3(0, 0, 1), 256).projected_m2[0] == 0.0);  // behind another plate: no direct Sun

  Scene half;
  half.addSurface("plate", "plate", rectangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 1, 1), "plate", "");
  half.addSurface("shade", "shade", rectangle(Vec3(0, 0, 1), Vec3(0.5, 0, 0), Vec3(0, 1, 0), 1, 1), "shade", "");
  RayCaster c3(half);
  // Sobol points stratify x exactly in halves: the error is a few ulps at 1024 points.
  CHECK(litArea(c3, Vec3(0, 0, 1), 1024).lit_fraction[0] == Approx(0.5).margin(2e-3));
}

TEST_CASE("planet rays: Earth view factor of a nadir-facing plate is (R/(R+h))²") {
  const double R = 6378137.0, h = 500e3;
  Scene s;
  // Plate at the origin facing −z (towards the planet centre at −(R+h) z).
  s.addSurface("plate", "plate", rectangle(Vec3(0, 0, 0), Vec3(0, 0.1, 0), Vec3(0.1, 0, 0), 1, 1), "plate", "");
  RayCaster caster(s);
  const auto rays = planetRays(caster, Vec3(0, 0, -(R + h)), R, 64000);
  const double exact = std::pow(R / (R + h), 2);
  INFO("F = " << rays[0].view_factor << " ± " << rays[0].standard_error << ", exact " << exact);
  CHECK(std::abs(rays[0].view_factor - exact) <= 3.29 * rays[0].standard_error + 1e-12);
  REQUIRE(!rays[0].hit_points.empty());
  for (size_t k = 0; k < rays[0].hit_points.size(); k += 97)
    CHECK((rays[0].hit_points[k] - Vec3(0, 0, -(R + h))).norm() == Approx(R).epsilon(1e-9));
  // A plate whose normal is horizontal (Howell: F = (1/π)(atan(1/√(H²−1)) − √(H²−1)/H²), H = (R+h)/R).
  Scene v;
  v.addSurface("wall", "wall", rectangle(Vec3(0, 0, 0), Vec3(0, 0, 0.1), Vec3(0, 0.1, 0), 1, 1), "wall", "");
  RayCaster cv(v);
  const auto side = planetRays(cv, Vec3(0, 0, -(R + h)), R, 64000);
  const double H = (R + h) / R, x = std::sqrt(H * H - 1);
  const double vertical = (std::atan(1 / x) - x / (H * H)) / M_PI;
  INFO("vertical plate F = " << side[0].view_factor << " ± " << side[0].standard_error << ", exact " << vertical);
  CHECK(std::abs(side[0].view_factor - vertical) <= 3.29 * side[0].standard_error + 1e-12);
}

TEST_CASE("planet rays: self-shadowing by the spacecraft, ray-sphere geometry") {
  const double R = 6378137.0, h = 500e3;
  Scene s;
  s.addSurface("plate", "plate", rectangle(Vec3(0, 0, 0), Vec3(0, 0.1, 0), Vec3(0.1, 0, 0), 1, 1), "plate", "");
  s.addSurface("shield", "shield", rectangle(Vec3(-5, -5, -0.5), Vec3(10, 0, 0), Vec3(0, 10, 0), 1, 1), "shield", "");
  RayCaster caster(s);
  const auto rays = planetRays(caster, Vec3(0, 0, -(R + h)), R, 32000);
  CHECK(rays[0].view_factor == 0.0);  // the shield hides the planet from the plate
  Vec3 hit;
  CHECK(raySphere(Vec3(0, 0, 10), Vec3(0, 0, -1), Vec3(0, 0, 0), 1.0, hit));
  CHECK(hit.z() == Approx(1.0));
  CHECK_FALSE(raySphere(Vec3(0, 0, 10), Vec3(0, 0, 1), Vec3(0, 0, 0), 1.0, hit));
  CHECK_FALSE(raySphere(Vec3(0, 2, 10), Vec3(0, 0, -1), Vec3(0, 0, 0), 1.0, hit));
}

TEST_CASE("planet rays: in GEO the cone sampling keeps the error small, and the error target sets the count") {
  // Geostationary: the Earth subtends 8.7°; cosine-weighted rays over the hemisphere hit it
  // 2 % of the time, rays into its cone always. A nadir plate: F = (R/r)²; a plate tilted
  // by θ (normal still meeting the Earth, θ < 90° − 8.7°): F = (R/r)² cos θ (the sphere is
  // wholly in front of the plate).
  const double R = 6378137.0, r = 42164e3;
  for (const double theta_deg : {0.0, 45.0, 70.0}) {
    const double t = theta_deg * M_PI / 180.0;
    Scene s;
    // Normal (sin θ, 0, −cos θ): towards the planet at −z, tilted about y.
    const Vec3 n(std::sin(t), 0, -std::cos(t)), u = Vec3(0, 0.1, 0), v = n.cross(u).normalized() * 0.1;
    s.addSurface("plate", "plate", rectangle(Vec3(0, 0, 0), u, v, 1, 1), "plate", "");
    RayCaster caster(s);
    PlanetRayOptions opt;
    opt.rays_per_node = 65536;
    opt.relative_error = 0.002;
    const auto rays = planetRays(caster, Vec3(0, 0, -r), R, opt);
    const double exact = std::pow(R / r, 2) * std::cos(t);
    INFO("θ = " << theta_deg << "°: F = " << rays[0].view_factor << " ± " << rays[0].standard_error << " with "
                << rays[0].rays << " rays, exact " << exact);
    CHECK(std::abs(rays[0].view_factor - exact) <= 3.29 * rays[0].standard_error + 1e-12);  // 99.9 % (t, 31 dof)
    CHECK(std::abs(rays[0].view_factor - exact) <= 0.005 * exact);  // was 2–7 % at 16,384 hemisphere rays
    CHECK(rays[0].standard_error <= 0.002 * std::max(exact, 0.1 * std::pow(R / r, 2)) + 1e-15);  // target met
    CHECK(rays[0].rays <= opt.rays_per_node);
  }
}

TEST_CASE("sampling: a Sobol stream's shifts are std::mt19937_64's first four outputs, bit for bit") {
  // The shortcut runs the seeding recurrence to word 160 and twists four words; the engine
  // itself is the reference. Seeds as the kernel forms them (mixSeed) and edge values.
  std::vector<std::uint64_t> seeds = {0, 1, 5489, ~0ull, 0x8000000000000000ull};
  for (std::uint64_t k = 0; k < 2000; ++k) seeds.push_back(mixSeed(7, k, 0x5c7 + k % 32));
  for (const std::uint64_t seed : seeds) {
    std::mt19937_64 engine(seed);
    const std::array<std::uint64_t, 4> first = mt19937_64FirstFour(seed);
    for (const std::uint64_t value : first) REQUIRE(value == engine());
  }
}

TEST_CASE("planet rays: the inside of a tube seeing a sliver of the planet through its end is not 0 ± 0") {
  // A tube (r = 0.15 m, 1.5 m long, closed at one end) whose open end looks past the limb
  // (the planet's centre 143° from its axis at 700 km: F = 2.3e-4, a sliver at the limb;
  // the inside of a satellite's boom, Sun-pointing). From 1,024 rays every replica missed
  // it and the stopping rule took F = 0 ± 0 (this test failed so); with one ray's worth in
  // σ where the spacecraft blocks rays, the error target asks for more. Reference: the same
  // rays at 262,144 a node with no stopping rule; tolerance 4σ of both combined.
  const double R = 6378137.0, distance = R + 700e3;
  const Vec3 toward = Vec3(-0.8002489652424741, -0.3418797367178198, -0.4926660524636372).normalized();
  Scene s;
  s.addSurface("tube", "tube", cylinder(Vec3(0, 0, 0), Vec3(1.5, 0, 0), 0.15, Sweep{}, 6, 32), "tube", "tube.back");
  s.addSurface("end", "end", disc(Vec3(0, 0, 0), Vec3(1, 0, 0), 0.15, 0.0, Sweep{}, 1, 32), "end", "");
  RayCaster caster(s);
  const int inside = 1;  // the tube's back side
  REQUIRE(s.nodes()[inside].name == "tube.back");
  PlanetRayOptions budget;
  budget.rays_per_node = 65536;
  budget.relative_error = 0.005;
  const PlanetRays got = planetRays(caster, distance * toward, R, budget)[inside];
  const PlanetRays reference = planetRays(caster, distance * toward, R, 262144)[inside];
  INFO("F = " << got.view_factor << " ± " << got.standard_error << " from " << got.rays << " rays; reference "
              << reference.view_factor << " ± " << reference.standard_error);
  CHECK(reference.view_factor > 1e-4);  // the sliver is there (2.3e-4 by an analytic tube MC)
  CHECK(got.standard_error > 0.0);
  CHECK(std::abs(got.view_factor - reference.view_factor) <=
        4.0 * std::hypot(got.standard_error, reference.standard_error));
}
