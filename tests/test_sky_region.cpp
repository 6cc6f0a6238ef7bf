// The sky kernel's sectors (geometry/irradiance/sky_region): outside a flat node's sector no
// ray is ever blocked (checked by rays over the whole hemisphere, a second method), the
// sector's directions are uniform in its area, and the kernel drawn in sectors gives the
// blocked share the whole hemisphere's rays give, within their σ.
#include "geometry/irradiance/sky_kernel.hpp"
#include "geometry/irradiance/sky_region.hpp"
#include "geometry/rays/ray_caster.hpp"
#include "geometry/rays/sampling.hpp"
#include "geometry/scene/primitives.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <string>

using namespace radnet;
using geometry::Vec3;

namespace {

// A bus (five faces of a 1 m box, each a node), a wing of six two-sided panels along the
// bus's lower edge 5 cm off it, a mast tilted over the top and a small plate floating
// beside the wing: sectors of every size, blockers near and far, tilted and not.
geometry::Scene busWingMast() {
  geometry::Scene s;
  const std::array<geometry::TriangleSoup, 6> box = geometry::boxFaces(Vec3(-0.5, -0.5, -0.5), Vec3(1, 1, 1), 3);
  for (int f = 0; f < 5; ++f) {
    const std::string name = "bus" + std::to_string(f);
    s.addSurface(name, name, box[static_cast<size_t>(f)], name, "");
  }
  for (int k = 0; k < 6; ++k) {
    const std::string name = "wing" + std::to_string(k);
    s.addSurface(name, name, geometry::rectangle(Vec3(0.55 + 0.5 * k, -0.5, -0.5), Vec3(0, 1, 0), Vec3(0.5, 0, 0), 2, 2),
                 name, name + ".back");
  }
  s.addSurface("mast", "mast", geometry::rectangle(Vec3(-0.2, -0.1, 0.8), Vec3(0.9, 0, 0.6), Vec3(0, 0.2, 0), 3, 1),
               "mast", "mast.back");
  s.addSurface("float", "float", geometry::rectangle(Vec3(2.0, 1.0, 0.3), Vec3(0.3, 0.1, 0), Vec3(0, 0.2, 0.2), 1, 1),
               "float", "float.back");
  return s;
}

}  // namespace

TEST_CASE("sky region: no ray outside a flat node's region meets anything") {
  // 20,000 cosine-weighted rays over each node's whole hemisphere (pseudo-random, fixed
  // seed): every blocked one must lie in the region (none tolerated: the region is what
  // makes the untraced rays open for certain). Not vacuous: regions of less than half the
  // disc exist, of both kinds, and rays inside them are blocked.
  const geometry::Scene s = busWingMast();
  const geometry::RayCaster caster(s);
  const geometry::BlockerSpheres blockers(s, caster.originOffset());
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int small_sectors = 0, rectangles = 0, sectors = 0;
  std::int64_t blocked_inside = 0;
  for (int node = 0; node < static_cast<int>(s.nodes().size()); ++node) {
    const geometry::SkyRegion region = blockers.regionOf(node);
    if (region.whole) continue;
    small_sectors += region.share() < 0.5;
    rectangles += region.box_count > 0, sectors += region.box_count == 0;
    // The one regionOf chose is one of the two candidates.
    const std::array<geometry::SkyRegion, 2> both = blockers.candidates(node);
    CHECK(region.share() == std::min(both[0].share(), both[1].share()));
    const geometry::NodeSampler sampler(s, node);
    int outside = 0;
    for (int k = 0; k < 20000; ++k) {
      const geometry::NodeSampler::Ray ray = sampler.map({u(rng), u(rng), u(rng), u(rng)});
      if (!caster.occluded(caster.offsetOrigin(ray.point, ray.normal), ray.direction, ray.face)) continue;
      if (region.contains(ray.direction))
        ++blocked_inside;
      else
        ++outside;
    }
    INFO(s.nodes()[static_cast<size_t>(node)].name << ": region share " << region.share() << ", " << region.box_count
                                                   << " rectangles");
    CHECK(outside == 0);
  }
  CHECK(small_sectors >= 4);
  CHECK(rectangles >= 1);
  CHECK(sectors >= 1);
  CHECK(blocked_inside > 1000);
}

TEST_CASE("sky region: a region's directions are uniform in its area of the disc") {
  // Cosine-weighted directions are uniform on the disc: of 200,000 points drawn in a sector
  // (or in two rectangles, one reaching past the disc's edge), each quarter of the region
  // (by r² and by φ; by x in each rectangle, and the rectangles by their areas) holds its
  // share to 4σ of a binomial count (σ = √(p(1 − p)/N) ≤ 0.0011); every direction is a
  // unit vector above the plane and in the region; a rectangle's points past the disc are
  // refused, as many as their area's share.
  geometry::SkyRegion region;
  region.whole = false;
  region.n = Vec3(0.3, -0.2, 0.9).normalized();
  region.t0 = region.n.unitOrthogonal(), region.t1 = region.n.cross(region.t0);
  region.r0_squared = 0.2, region.r1_squared = 0.7, region.phi0 = 5.5, region.phi_span = 1.9;
  CHECK(region.share() == Approx(1.9 / (2 * M_PI) * 0.5).epsilon(1e-15));
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int N = 200000;
  const double sigma = std::sqrt(0.25 * 0.75 / N);
  std::array<int, 4> by_radius{}, by_angle{};
  for (int k = 0; k < N; ++k) {
    Vec3 d;
    REQUIRE(region.direction(u(rng), u(rng), d));
    REQUIRE(std::abs(d.norm() - 1.0) < 1e-14);
    REQUIRE(d.dot(region.n) > 0.0);
    REQUIRE(region.contains(d));
    const double r2 = 1.0 - d.dot(region.n) * d.dot(region.n);
    ++by_radius[static_cast<size_t>(std::min(3.0, 4.0 * (r2 - 0.2) / 0.5))];
    const double phi = std::atan2(d.dot(region.t1), d.dot(region.t0));
    const double from = std::fmod(std::fmod(phi - 5.5, 2.0 * M_PI) + 2.0 * M_PI, 2.0 * M_PI);
    ++by_angle[static_cast<size_t>(std::min(3.0, 4.0 * from / 1.9))];
  }
  for (int q = 0; q < 4; ++q) {
    CHECK(std::abs(by_radius[static_cast<size_t>(q)] / double(N) - 0.25) < 4 * sigma);
    CHECK(std::abs(by_angle[static_cast<size_t>(q)] / double(N) - 0.25) < 4 * sigma);
  }
  // Two rectangles: [−0.2, 0.2] × [0.1, 0.5] (area 0.16) and [0.6, 1.0] × [−0.3, 0.1] (0.16,
  // of which the part past the disc, x² + y² ≥ 1, is refused).
  region.box_count = 2;
  region.boxes[0] = {-0.2, 0.2, 0.1, 0.5};
  region.boxes[1] = {0.6, 1.0, -0.3, 0.1};
  CHECK(region.share() == Approx(0.32 / M_PI).epsilon(1e-15));
  std::array<std::array<int, 4>, 2> by_x{};
  int refused = 0, outside_disc = 0;
  for (int k = 0; k < N; ++k) {
    const double u2 = u(rng), u3 = u(rng);
    Vec3 d;
    // The point the rectangle map gives, to know past-the-disc points in advance.
    const int box = u2 < 0.5 ? 0 : 1;
    const double s = box == 0 ? 2 * u2 : 2 * u2 - 1;
    const auto& b = region.boxes[static_cast<size_t>(box)];
    const double x = b[0] + s * (b[1] - b[0]), y = b[2] + u3 * (b[3] - b[2]);
    outside_disc += x * x + y * y >= 1.0;
    if (!region.direction(u2, u3, d)) {
      ++refused;
      continue;
    }
    REQUIRE(std::abs(d.norm() - 1.0) < 1e-14);
    REQUIRE(region.contains(d));
    const double dx = d.dot(region.t0);
    const int in = dx <= 0.2 ? 0 : 1;
    ++by_x[static_cast<size_t>(in)][static_cast<size_t>(std::min(3.0, 4.0 * (dx - region.boxes[static_cast<size_t>(in)][0]) / 0.4))];
  }
  CHECK(refused == outside_disc);
  CHECK(refused > 0);
  for (int q = 0; q < 4; ++q) CHECK(std::abs(by_x[0][static_cast<size_t>(q)] / double(N) - 0.125) < 4 * sigma);
}

TEST_CASE("sky region: the kernel's blocked shares from sectors equal the whole hemisphere's") {
  // Each node's blocked share from the kernel (65,536 rays, in its sector where it has one)
  // against 400,000 pseudo-random rays over the whole hemisphere: within 4σ of both σ
  // combined (the kernel's from its 32 replicas, the reference's binomial).
  const geometry::Scene s = busWingMast();
  const geometry::RayCaster caster(s);
  geometry::SkyKernelOptions opt;
  opt.max_rays_per_node = 65536;
  const geometry::SkyKernel kernel = geometry::skyKernel(caster, opt);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int sectors = 0;
  for (int node = 0; node < static_cast<int>(s.nodes().size()); ++node) {
    const geometry::NodeSky& sky = kernel.nodes[static_cast<size_t>(node)];
    if (sky.blocked_fraction <= 0.0) continue;
    sectors += sky.ray_share < 1.0;
    const geometry::NodeSampler sampler(s, node);
    const int N = 400000;
    int blocked = 0;
    for (int k = 0; k < N; ++k) {
      const geometry::NodeSampler::Ray ray = sampler.map({u(rng), u(rng), u(rng), u(rng)});
      blocked += caster.occluded(caster.offsetOrigin(ray.point, ray.normal), ray.direction, ray.face);
    }
    const double p = blocked / double(N), sigma_ref = std::sqrt(p * (1 - p) / N);
    // The kernel's own σ: the replicas' spread of their blocked shares.
    std::array<double, geometry::kSkyReplicas> share{};
    for (const geometry::NodeSky::ReplicaCount& e : sky.replica_counts)
      share[static_cast<size_t>(e.replica)] += e.count;
    const double per_replica = double(sky.rays) / geometry::kSkyReplicas;
    double mean = 0.0, sum2 = 0.0;
    for (double& x : share) x = (sky.counts_open ? per_replica - x : x) / per_replica * sky.ray_share, mean += x;
    mean /= geometry::kSkyReplicas;
    for (const double x : share) sum2 += (x - mean) * (x - mean);
    const double sigma_kernel = std::sqrt(sum2 / (geometry::kSkyReplicas - 1) / geometry::kSkyReplicas);
    INFO(s.nodes()[static_cast<size_t>(node)].name << ": kernel " << sky.blocked_fraction << " ± " << sigma_kernel
                                                   << " (share " << sky.ray_share << "), whole hemisphere " << p
                                                   << " ± " << sigma_ref);
    CHECK(mean == Approx(sky.blocked_fraction).epsilon(1e-12));
    CHECK(std::abs(sky.blocked_fraction - p) < 4.0 * std::hypot(sigma_kernel, sigma_ref) + 1e-12);
  }
  CHECK(sectors >= 4);
}

TEST_CASE("sky region: no ray outside the region of a floor under scattered plates meets anything") {
  // 40 random scenes (fixed seed): a floor and 2–7 small plates floating above it at any
  // azimuth, height and tilt, so that the blockers' azimuth arcs wrap past the frame's
  // zero and overlap in every way; 4,000 hemisphere rays from the floor each. No blocked
  // ray may fall outside either region the floor's is chosen from (the sector's azimuth arc
  // once missed what an arc wrapping past 2π covered: this test found it).
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int regions = 0;
  for (int scene_index = 0; scene_index < 40; ++scene_index) {
    geometry::Scene s;
    s.addSurface("floor", "floor", geometry::rectangle(Vec3(-0.1, -0.1, 0), Vec3(0.2, 0, 0), Vec3(0, 0.2, 0), 1, 1),
                 "floor", "");
    const int plates = 2 + static_cast<int>(6 * u(rng));
    for (int k = 0; k < plates; ++k) {
      const double azimuth = 2 * M_PI * u(rng), distance = 0.4 + 1.5 * u(rng), height = 0.05 + 1.2 * u(rng);
      const Vec3 at(distance * std::cos(azimuth), distance * std::sin(azimuth), height);
      const Vec3 a = Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized() * (0.1 + 0.4 * u(rng));
      const Vec3 b = a.cross(Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5)).normalized() * (0.1 + 0.3 * u(rng));
      const std::string name = "plate" + std::to_string(k);
      s.addSurface(name, name, geometry::rectangle(at, a, b, 1, 1), name, name + ".back");
    }
    const geometry::RayCaster caster(s);
    const geometry::BlockerSpheres blockers(s, caster.originOffset());
    const geometry::NodeSampler sampler(s, 0);
    for (const geometry::SkyRegion& region : blockers.candidates(0)) {  // the sector and the rectangles
      if (region.whole) continue;
      ++regions;
      int outside = 0;
      for (int k = 0; k < 4000; ++k) {
        const geometry::NodeSampler::Ray ray = sampler.map({u(rng), u(rng), u(rng), u(rng)});
        if (caster.occluded(caster.offsetOrigin(ray.point, ray.normal), ray.direction, ray.face) &&
            !region.contains(ray.direction))
          ++outside;
      }
      INFO("scene " << scene_index << " with " << plates << " plates: share " << region.share() << ", "
                    << region.box_count << " rectangles");
      CHECK(outside == 0);
    }
  }
  CHECK(regions >= 40);
}

TEST_CASE("sky region: the covering arc of azimuths wrapping past 2π") {
  // An arc from −1.4 to 1.0 rad wraps past 2π and covers [0, 1.0]: two small arcs inside it
  // and one from 0.98 to 4.9 leave no gap, so the whole circle (a sweep that did not split
  // the wrapping arc saw a false gap of 0.4 rad between the small ones, and left it out).
  const auto whole = geometry::coveringArc({{-0.2, 1.2}, {0.3, 0.05}, {0.8, 0.05}, {2.94, 1.96}});
  CHECK(whole.second == Approx(2 * M_PI));
  // A genuine gap, from 1.05 to 2.0: the arc starts at 2.0 and spans 2π − 0.95.
  const auto arc = geometry::coveringArc({{-0.2, 1.2}, {0.3, 0.05}, {0.8, 0.25}, {3.4, 1.4}});
  CHECK(arc.first == Approx(2.0));
  CHECK(arc.second == Approx(2 * M_PI - 0.95));
  // One arc straddling 0: itself.
  const auto one = geometry::coveringArc({{0.1, 0.3}});
  CHECK(std::fmod(one.first + 2 * M_PI, 2 * M_PI) == Approx(2 * M_PI - 0.2));
  CHECK(one.second == Approx(0.6));
  CHECK(geometry::coveringArc({{1.0, M_PI}}).second == Approx(2 * M_PI));
}
