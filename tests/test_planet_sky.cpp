// The planet's unobstructed loads on a plane (orbits/planet_sky): the ring quadrature
// against the closed-form plate-to-sphere view factor, and the albedo and day-night IR
// against a brute-force integral over the planet's surface (a second method: area
// elements of the sphere, not directions of the sky).
#include "orbits/planet_sky.hpp"
#include "orbits/sky_loads.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using radnet::orbits::PlanetChannels;
using radnet::orbits::PlanetView;
using Eigen::Vector3d;

namespace {

// A differential plate at distance d = H R from a sphere's centre, its normal at β from
// the line to the centre (Howell, A Catalog of Radiation Heat Transfer Configuration
// Factors, B-? "plane element to sphere, tilted"; the partial case for a plate whose
// plane cuts the sphere).
double plateToSphere(double H, double beta) {
  if (beta <= std::acos(1.0 / H)) return std::cos(beta) / (H * H);
  if (beta >= M_PI - std::acos(1.0 / H)) return 0.0;
  const double x = std::sqrt(H * H - 1.0), y = -x / std::tan(beta);
  return 0.5 - std::asin(x / (H * std::sin(beta))) / M_PI +
         (std::cos(beta) * std::acos(y) - x * std::sqrt(1.0 - H * H * std::cos(beta) * std::cos(beta))) /
             (M_PI * H * H);
}

// ∫ L cos θ_plate cos θ_surface / s² dA over the visible sphere, midpoints in (γ, φ) about
// the sub-spacecraft point, the plate at the origin: what the radiance field of a
// Lambertian albedo and the view's IR model give.
PlanetChannels bySurfaceElements(const PlanetView& v, const Vector3d& n, int steps) {
  const Vector3d c = v.toward_center, e1 = c.unitOrthogonal(), e2 = c.cross(e1);
  const double R = v.radius_m, d = v.distance_m, gmax = std::acos(R / d);
  PlanetChannels sum;
  for (int i = 0; i < steps; ++i) {
    const double g = (i + 0.5) * gmax / steps;
    for (int j = 0; j < 2 * steps; ++j) {
      const double phi = (j + 0.5) * M_PI / steps;
      const Vector3d normal = -std::cos(g) * c + std::sin(g) * (std::cos(phi) * e1 + std::sin(phi) * e2);
      const Vector3d s = d * c + R * normal;  // plate → surface point
      const double dist = s.norm(), cos_plate = n.dot(s) / dist, cos_surface = -normal.dot(s) / dist;
      if (cos_plate <= 0 || cos_surface <= 0) continue;
      const double dA = R * R * std::sin(g) * (gmax / steps) * (M_PI / steps);
      const double geometric = cos_plate * cos_surface / (dist * dist) * dA;
      const double cos_z = normal.dot(v.toward_sun);
      sum += PlanetChannels{1.0 / M_PI, v.albedo * v.solar_flux_w_m2 * std::max(0.0, cos_z) / M_PI,
                            v.ir.exitance(cos_z, v.solar_flux_w_m2) / M_PI} *
             geometric;
    }
  }
  return sum;
}

PlanetView earthAt(double altitude_m) {
  PlanetView v;
  v.radius_m = 6371e3;
  v.distance_m = v.radius_m + altitude_m;
  v.toward_center = Vector3d(0, 0, -1);
  v.solar_flux_w_m2 = 1361.0;
  v.albedo = 0.3;
  return v;
}

Vector3d tilted(double beta) { return Vector3d(std::sin(beta), 0, -std::cos(beta)); }

}  // namespace

TEST_CASE("planet sky: a tilted plate's view factor and uniform IR equal the closed form and the surface integral") {
  // Tilts from facing the planet to past the horizon, at 400 km (the limb at 70.2°: 45°
  // onwards see the limb), 700 km, 2,000 km and GEO. The code's closed form against the one
  // written here (1e-12: the same formula, its branches and clamps), and against the sum
  // over the planet's surface elements (a second method: 2e-5 of sin² θ_max, 20× the
  // sum's error at 600 × 1,200 elements).
  for (const double altitude : {400e3, 700e3, 2000e3, 35786e3}) {
    PlanetView v = earthAt(altitude);
    const double H = v.distance_m / v.radius_m;
    for (const double beta_deg : {0.0, 10.0, 30.0, 45.0, 60.0, 75.0, 90.0, 100.0, 110.0, 125.0, 140.0, 150.0, 153.0, 154.0, 160.0}) {
      const double beta = beta_deg * M_PI / 180.0;
      const PlanetChannels got = radnet::orbits::unobstructedPlanetLoads(v, tilted(beta));
      const double exact = plateToSphere(H, beta);
      INFO("altitude " << altitude / 1e3 << " km, tilt " << beta_deg << "°: F " << got.view << ", closed form " << exact);
      CHECK(got.view == Approx(exact).epsilon(1e-12).margin(1e-15));
      CHECK(got.ir == Approx(237.0 * exact).epsilon(1e-12).margin(1e-12));
      if (static_cast<int>(beta_deg) % 30 == 0 || beta_deg == 125.0 || beta_deg == 153.0) {
        const PlanetChannels fine = bySurfaceElements(v, tilted(beta), 600);
        CHECK(std::abs(got.view - fine.view) <= 2e-5 * v.capSin2());
      }
    }
  }
}

TEST_CASE("planet sky: albedo and day-night IR equal the integral over the planet's surface") {
  // Suns overhead, oblique, at the terminator and behind the planet; tilts that see the
  // whole cap, the limb and nothing. The surface midpoint sum (1,000 × 2,000 elements) is
  // second order in the step (the integrand is continuous, with kinks at the terminator
  // and the plate's horizon); the tolerance, 2e-5 of the load's scale a·S·F_max, is met
  // by the rings' 12-point Gauss rule per piece (an 8-point rule misses by 30×).
  PlanetView v = earthAt(500e3);
  v.ir.kind = radnet::orbits::PlanetIr::Kind::DayNight;  // the Moon's kind of emission
  v.ir.subsolar_temperature_k = 390.0;
  v.ir.night_temperature_k = 95.0;
  v.ir.reference_flux_w_m2 = 1361.0;
  const double scale_albedo = v.albedo * v.solar_flux_w_m2 * v.capSin2();
  const double scale_ir = v.ir.maxExitance(v.solar_flux_w_m2) * v.capSin2();
  for (const double sun_deg : {0.0, 40.0, 85.0, 120.0, 180.0}) {
    const double s = sun_deg * M_PI / 180.0;
    // +z points away from the planet: the Sun's zenith angle at the sub-spacecraft point.
    v.toward_sun = Vector3d(std::sin(s) * std::cos(0.3), std::sin(s) * std::sin(0.3), std::cos(s));
    for (const double beta_deg : {0.0, 50.0, 95.0, 150.0}) {
      const Vector3d n = tilted(beta_deg * M_PI / 180.0);
      const PlanetChannels got = radnet::orbits::unobstructedPlanetLoads(v, n);
      const PlanetChannels fine = bySurfaceElements(v, n, 1000);
      INFO("Sun " << sun_deg << "° from the zenith, tilt " << beta_deg << "°: albedo " << got.albedo << " vs "
                  << fine.albedo << ", IR " << got.ir << " vs " << fine.ir);
      CHECK(std::abs(got.albedo - fine.albedo) <= 2e-5 * scale_albedo);
      CHECK(std::abs(got.ir - fine.ir) <= 2e-5 * scale_ir);
      CHECK(std::abs(got.view - fine.view) <= 2e-5 * v.capSin2());
    }
  }
}

TEST_CASE("planet sky: one position's rings serve many normals as each normal's own rings do") {
  // PlanetRings keeps a position's pieces and Gauss points and lets each normal split the
  // piece its horizon falls in: 400 normals (every tilt and azimuth, many cutting the cap)
  // through one object against a fresh one each, to 1e-13 of the load's scale (the same
  // formulas: rounding only), with a day-night emission so that both ring integrals run.
  PlanetView v = earthAt(700e3);
  v.toward_sun = Vector3d(0.4, -0.3, 0.5).normalized();
  v.ir.kind = radnet::orbits::PlanetIr::Kind::DayNight;
  v.ir.subsolar_temperature_k = 390.0;
  v.ir.night_temperature_k = 95.0;
  v.ir.reference_flux_w_m2 = 1361.0;
  const radnet::orbits::PlanetRings rings(v);
  const double scale = v.albedo * v.solar_flux_w_m2 * v.capSin2(), scale_ir = v.ir.maxExitance(1361.0) * v.capSin2();
  int cutting = 0;
  for (int k = 0; k < 400; ++k) {
    const double beta = M_PI * (k % 20 + 0.5) / 20, azimuth = 2 * M_PI * (k / 20) / 20.0;
    const Vector3d n(std::sin(beta) * std::cos(azimuth), std::sin(beta) * std::sin(azimuth), -std::cos(beta));
    const PlanetChannels shared = rings.loads(n), own = radnet::orbits::unobstructedPlanetLoads(v, n);
    const double edge = std::acos(v.radius_m / v.distance_m);  // past it the plane cuts the sphere
    cutting += beta > edge && beta < M_PI - edge;
    CHECK(std::abs(shared.view - own.view) <= 1e-13 * v.capSin2());
    CHECK(std::abs(shared.albedo - own.albedo) <= 1e-13 * scale);
    CHECK(std::abs(shared.ir - own.ir) <= 1e-13 * scale_ir);
  }
  CHECK(cutting > 50);
}

TEST_CASE("planet sky: a facetted part's loads, the normals that see the whole cap summed first, equal each facet's") {
  // A dish-like part (300 facets in a 40° cone about an axis, uneven areas) at 400 km, 700 km
  // and GEO, the axis from nadir to past the horizon, a day-night emission: facetLoads
  // against Σ share × loads(n) facet by facet. Where a plane sees the whole cap its load is
  // n · ∫ L d dΩ, linear in n, so the sum at the facets' weighted normal is the same
  // integral: equal to the ring quadrature's rounding, 1e-12 of the scale.
  std::uint64_t state = 7;
  const auto uniform = [&state] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return double(state >> 11) / 9007199254740992.0;
  };
  int grouped = 0;
  for (const double altitude : {400e3, 700e3, 35786e3})
    for (const double axis_tilt : {0.0, 0.3, 0.9, 1.6, 2.4}) {
      PlanetView v = earthAt(altitude);
      v.toward_sun = Vector3d(0.4, -0.3, 0.5).normalized();
      v.ir.kind = radnet::orbits::PlanetIr::Kind::DayNight;
      v.ir.subsolar_temperature_k = 390.0;
      v.ir.night_temperature_k = 95.0;
      const Vector3d axis = tilted(axis_tilt), across = axis.unitOrthogonal(), third = axis.cross(across);
      std::vector<Vector3d> normals;
      std::vector<double> shares;
      for (int k = 0; k < 300; ++k) {
        const double off = 0.7 * std::sqrt(uniform()), around = 2 * M_PI * uniform();
        normals.push_back((std::cos(off) * axis + std::sin(off) * (std::cos(around) * across + std::sin(around) * third)).normalized());
        shares.push_back((0.5 + uniform()) / 300);
      }
      const radnet::orbits::PlanetRings rings(v);
      PlanetChannels each;
      for (size_t k = 0; k < normals.size(); ++k) {
        each += rings.loads(normals[k]) * shares[k];
        grouped += normals[k].dot(v.toward_center) >= std::sqrt(v.capSin2());
      }
      const PlanetChannels together = rings.facetLoads(normals, shares);
      const double scale = v.albedo * v.solar_flux_w_m2 * v.capSin2(), scale_ir = v.ir.maxExitance(1361.0) * v.capSin2();
      INFO("altitude " << altitude << " m, axis " << axis_tilt << " rad from nadir");
      CHECK(std::abs(together.view - each.view) <= 1e-12 * v.capSin2());
      CHECK(std::abs(together.albedo - each.albedo) <= 1e-12 * scale);
      CHECK(std::abs(together.ir - each.ir) <= 1e-12 * scale_ir);
    }
  CHECK(grouped > 1000);  // the grouped path taken, not only the facet-by-facet one
}

TEST_CASE("planet sky: a curved part's other side takes its loads less n · ∫ L d dΩ, equal to its own facets' rings") {
  // Two grouped nodes of a sky kernel, the second the first's facets seen from behind (the
  // back of a two-sided dish: normals negated, the same shares), and a third node with
  // one facet changed (not a mirror). UnobstructedLoads computes the second from the
  // first (loads(−n) = loads(n) − n · V, exact for the integrals); facet by facet rings are
  // the reference: the view factor (closed form both ways) and the nodes computed by their
  // own rings to rounding (1e-12 of the scale), the back side's albedo and IR to the rings'
  // own accuracy, 2e-5 of the scale (the Gauss rule's error differs between n and −n: 3e-6
  // seen; the rings meet 2e-5 against the surface integral above). Positions from nadir past
  // the horizon, a day-night emission, 400 km to GEO.
  std::uint64_t state = 11;
  const auto uniform = [&state] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return double(state >> 11) / 9007199254740992.0;
  };
  radnet::geometry::SkyKernel kernel;
  kernel.nodes.resize(3);
  const Vector3d axis = tilted(0.4), across = axis.unitOrthogonal(), third = axis.cross(across);
  for (int k = 0; k < 60; ++k) {
    const double off = 0.6 * std::sqrt(uniform()), around = 2 * M_PI * uniform();
    const Vector3d n = (std::cos(off) * axis + std::sin(off) * (std::cos(around) * across + std::sin(around) * third)).normalized();
    const double share = (0.5 + uniform()) / 60;
    const auto index = static_cast<std::int32_t>(kernel.normals.size());
    kernel.normals.push_back(n), kernel.normals.push_back(-n);
    kernel.nodes[0].normals.emplace_back(index, share);
    kernel.nodes[1].normals.emplace_back(index + 1, share);
    kernel.nodes[2].normals.emplace_back(k == 7 ? index : index + 1, share);  // one facet not turned
  }
  for (auto& node : kernel.nodes) node.rays = 1024;
  std::vector<PlanetView> views;
  for (const double altitude : {400e3, 700e3, 35786e3})
    for (const double nadir_tilt : {0.0, 0.8, 1.7, 2.6}) {
      PlanetView v = earthAt(altitude);
      v.toward_center = tilted(nadir_tilt);
      v.toward_sun = Vector3d(0.4, -0.3, 0.5).normalized();
      v.ir.kind = radnet::orbits::PlanetIr::Kind::DayNight;
      v.ir.subsolar_temperature_k = 390.0;
      v.ir.night_temperature_k = 95.0;
      views.push_back(v);
    }
  radnet::orbits::UnobstructedLoads unobstructed;
  unobstructed.fill(kernel, views, {});
  CHECK(unobstructed.mirror_of[1] == 0);   // the back side found
  CHECK(unobstructed.mirror_of[2] == -1);  // one facet differs: its own rings
  // A process holding the back alone (an MPI rank's nodes) computes the front for it: the
  // same numbers bit for bit.
  radnet::orbits::UnobstructedLoads back_only;
  back_only.fill(kernel, views, {0, 1, 0});
  const int positions = static_cast<int>(views.size());
  CHECK((back_only.node(kernel, 1, 0, positions) - unobstructed.node(kernel, 1, 0, positions)).abs().maxCoeff() == 0.0);
  for (size_t node = 0; node < 3; ++node) {
    const auto free = unobstructed.node(kernel, node, 0, static_cast<int>(views.size()));
    for (size_t p = 0; p < views.size(); ++p) {
      const PlanetView& v = views[p];
      const radnet::orbits::PlanetRings rings(v);
      PlanetChannels each;
      for (const auto& [k, share] : kernel.nodes[node].normals) each += rings.loads(kernel.normals[static_cast<size_t>(k)]) * share;
      const double scale = v.albedo * v.solar_flux_w_m2 * v.capSin2(), scale_ir = v.ir.maxExitance(1361.0) * v.capSin2();
      const double tolerance = node == 1 ? 2e-5 : 1e-12;
      INFO("node " << node << ", position " << p);
      CHECK(std::abs(free(0, static_cast<Eigen::Index>(p)) - each.view) <= 1e-12 * v.capSin2());
      CHECK(std::abs(free(1, static_cast<Eigen::Index>(p)) - each.albedo) <= tolerance * scale);
      CHECK(std::abs(free(2, static_cast<Eigen::Index>(p)) - each.ir) <= tolerance * scale_ir);
    }
  }
}
