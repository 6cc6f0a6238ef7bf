// Specular and transmissive surfaces at the geometry level, against closed forms:
// a V-groove of specular walls under a beam along its bisector (apparent absorptance
// 1 − ρ^m for an opening angle π/m: every ray reflects m times), a window passing τ of the
// Sun onto the plate behind it, and the reciprocity of traced exchange rows.
#include "geometry/irradiance/sun_grid.hpp"
#include "geometry/rays/specular.hpp"
#include "geometry/scene/facet_creases.hpp"
#include "geometry/scene/primitives.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace radnet;
using geometry::Vec3;

namespace {

// Two walls of width w and length 1 m meeting at the y axis, opening towards +z with full
// angle π/m, fronts facing into the groove.
geometry::Scene vGroove(int m, double w) {
  const double half = M_PI / (2.0 * m), s = w * std::sin(half), c = w * std::cos(half);
  geometry::Scene scene;
  scene.addSurface("left", "left", geometry::rectangle(Vec3::Zero(), Vec3(0, 1, 0), Vec3(-s, 0, c), 1, 1), "left", "");
  scene.addSurface("right", "right", geometry::rectangle(Vec3::Zero(), Vec3(s, 0, c), Vec3(0, 1, 0), 1, 1), "right",
                   "");
  return scene;
}

// A 1 m plate facing +z at z = 0 under a 3 m glass sheet (both sides nodes) at 0.2 m that
// overhangs it by 1 m all round.
geometry::Scene plateUnderGlass() {
  geometry::Scene scene;
  scene.addSurface("plate", "plate", geometry::rectangle(Vec3::Zero(), Vec3(1, 0, 0), Vec3(0, 1, 0), 1, 1), "plate",
                   "");
  scene.addSurface("glass", "glass",
                   geometry::rectangle(Vec3(-1, -1, 0.2), Vec3(3, 0, 0), Vec3(0, 3, 0), 1, 1), "glass", "glass.back");
  return scene;
}

}  // namespace

TEST_CASE("specular V-groove: the apparent absorptance of a beam along the bisector is 1 − ρ^m") {
  const double rho = 0.8, alpha = 1.0 - rho, w = 0.3;
  for (int m : {2, 3, 4}) {
    const geometry::Scene scene = vGroove(m, w);
    const geometry::RayCaster caster(scene);
    const geometry::SpecularBand band{Eigen::VectorXd::Constant(2, rho), Eigen::VectorXd::Zero(2)};
    const Vec3 toward_sun(0, 0, 1);
    geometry::SunGridOptions grid;
    grid.cell_m = 1e-3;
    const geometry::SunlitArea lit = geometry::sunlitArea(caster, toward_sun, grid);
    const geometry::RedirectedLight redirected = geometry::redirectedCollimated(caster, band, toward_sun, 65536, 11);
    // Per unit flux: what the walls absorb over what enters the opening (2 w sin(π/2m) × 1 m).
    const double opening = 2.0 * w * std::sin(M_PI / (2.0 * m));
    const double absorbed = alpha * (lit.projected_m2.sum() + redirected.arrived_m2.sum());
    const double sigma = alpha * std::hypot(redirected.stderr_m2[0], redirected.stderr_m2[1]) / opening;
    const double truth = 1.0 - std::pow(rho, m);
    INFO("m = " << m << ": " << absorbed / opening << " against " << truth << ", σ " << sigma);
    // Tolerance: 4σ of the replicas' spread plus the grid's 1e-4 on the direct part (walls
    // unshadowed: exact up to rounding); the closed form also within 0.5 %.
    CHECK(std::abs(absorbed / opening - truth) <= 4.0 * sigma + 1e-4);
    CHECK(std::abs(absorbed / opening - truth) <= 5e-3 * truth);
  }
}

TEST_CASE("window: τ of the beam reaches the plate behind it, the rest stops at the glass") {
  const geometry::Scene scene = plateUnderGlass();
  const geometry::RayCaster caster(scene);
  const int plate = scene.nodeIndex("plate"), glass = scene.nodeIndex("glass");
  geometry::SpecularBand band{Eigen::VectorXd::Zero(3), Eigen::VectorXd::Zero(3)};
  band.transmittance[glass] = band.transmittance[scene.nodeIndex("glass.back")] = 0.9;
  const Vec3 toward_sun = Vec3(0.2, -0.1, 1.0).normalized();
  geometry::SunGridOptions grid;
  grid.cell_m = 2e-3;
  const geometry::SunlitArea lit = geometry::sunlitArea(caster, toward_sun, grid);
  CHECK(lit.projected_m2[plate] == Approx(0.0).margin(1e-12));  // the glass shadows it in the grid
  const geometry::RedirectedLight through = geometry::redirectedCollimated(caster, band, toward_sun, 16384, 3);
  // A 3 m sheet over a 1 m plate: all the plate's projection is behind glass, τ A cos θ passes.
  // Every sample is lit and passes (no roulette at 0.9): the estimate is exact up to the
  // Sobol points' coverage of the glass, i.e. σ; tolerance 4σ + 1e-9.
  const double truth = 0.9 * toward_sun.z();
  INFO("through " << through.arrived_m2[plate] << " ± " << through.stderr_m2[plate]);
  CHECK(std::abs(through.arrived_m2[plate] - truth) <= 4.0 * through.stderr_m2[plate] + 2e-3 * truth);
  CHECK(through.arrived_m2[glass] == Approx(0.0).margin(1e-12));  // nothing comes back to the glass
}

TEST_CASE("traced exchange rows are reciprocal within their errors and close with space") {
  // A specular half-cylinder trough over a diffuse plate, open to space.
  geometry::Scene scene;
  scene.addSurface("plate", "plate", geometry::rectangle(Vec3(-0.5, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 2, 2),
                   "plate", "");
  geometry::Sweep half;
  half.start_deg = 180.0, half.end_deg = 360.0;
  scene.addSurface("trough", "trough",
                   geometry::cylinder(Vec3(0, 0, 0.1), Vec3(0, 1, 0), 0.5, half, 2, 24), "", "trough.in");
  const geometry::RayCaster caster(scene);
  const int n = static_cast<int>(scene.nodes().size());
  geometry::SpecularBand band{Eigen::VectorXd::Zero(n), Eigen::VectorXd::Zero(n)};
  band.specular[scene.nodeIndex("trough.in")] = 0.6;
  geometry::ViewFactorOptions opt;
  opt.rays_per_node = 64000;
  opt.seed = 9;
  const geometry::ViewFactorResult r = geometry::traceSpecularRows(caster, band, opt);
  const Eigen::VectorXd kappa = band.kappa();
  const Eigen::MatrixXd f = r.denseViewFactors(), e = r.denseStandardError();
  for (int i = 0; i < n; ++i) {
    // Closure: every ray's weight ends somewhere (κ shares, space, blocked or the roulette's
    // survivors, whose expectation is the same): 4σ of the row's terms.
    const double row = f.row(i).sum() + r.space[i] + r.blocked[i];
    const double sigma = std::sqrt(e.row(i).squaredNorm() + r.space_error[i] * r.space_error[i]);
    CHECK(std::abs(row - 1.0) <= 4.0 * sigma + 1e-12);
    for (int j = 0; j < n; ++j) {
      const double ai = scene.nodes()[i].area_m2 * kappa[i], aj = scene.nodes()[j].area_m2 * kappa[j];
      const double s = std::hypot(ai * e(i, j), aj * e(j, i));
      INFO(i << " → " << j << ": " << ai * f(i, j) << " against " << aj * f(j, i));
      CHECK(std::abs(ai * f(i, j) - aj * f(j, i)) <= 4.0 * s + 1e-12);
    }
  }
}

TEST_CASE("planet light through a window: τ of the sphere's irradiance reaches the plate behind it") {
  // A 1 m plate facing +z under a 3 m glass sheet at 0.2 m, a sphere of radius 1 m whose
  // centre is 10 m above the plate's centre: every line from the plate to the sphere passes
  // the glass. A sphere of uniform radiance L gives a surface element that sees all of it
  // E = π L (R/d)² cos β (β between the normal and the centre), so the plate receives
  // τ π L R² ∫ h / d³ dA; the paths' weights (power per unit radiance) must sum to that.
  const geometry::Scene scene = plateUnderGlass();
  const geometry::RayCaster caster(scene);
  const int plate = scene.nodeIndex("plate"), glass = scene.nodeIndex("glass");
  const double tau = 0.85, radius = 1.0, height = 10.0;
  const Vec3 center(0.5, 0.5, height);
  geometry::SpecularBand band{Eigen::VectorXd::Zero(3), Eigen::VectorXd::Zero(3)};
  band.transmittance[glass] = band.transmittance[scene.nodeIndex("glass.back")] = tau;
  const int replicas = 16;
  const geometry::RedirectedPlanetPaths paths =
      geometry::redirectedPlanetPaths(caster, band, center, radius, 1 << 20, 5, replicas);
  std::vector<double> per_replica(replicas, 0.0);
  int elsewhere = 0;  // nothing but the plate lies below the glass
  for (const auto& a : paths.arrivals) {
    elsewhere += a.node != plate;
    per_replica[static_cast<size_t>(a.replica)] += a.weight;
  }
  CHECK(elsewhere == 0);
  CHECK(!paths.arrivals.empty());
  double mean = 0.0, mean2 = 0.0;
  for (double v : per_replica) mean += v / replicas, mean2 += v * v / replicas;
  const double sigma = std::sqrt((mean2 - mean * mean) / (replicas - 1));
  // The truth by a 400 × 400 midpoint rule over the plate (smooth integrand: error ~1e-7).
  double truth = 0.0;
  const int cells = 400;
  for (int a = 0; a < cells; ++a)
    for (int b = 0; b < cells; ++b) {
      const Vec3 p((a + 0.5) / cells, (b + 0.5) / cells, 0.0);
      truth += height / std::pow((center - p).norm(), 3) / (cells * cells);
    }
  truth *= tau * M_PI * radius * radius;
  INFO("through " << mean << " ± " << sigma << " m² sr against " << truth);
  // Tolerance: 4σ of the replicas' spread; the estimate is unbiased (no roulette at τ = 0.85,
  // glass fully lit), so it must also land within 2 % (σ is ~0.5 % at 2²⁰ samples).
  CHECK(std::abs(mean - truth) <= 4.0 * sigma);
  CHECK(std::abs(mean - truth) <= 0.02 * truth);
  CHECK(sigma < 0.01 * truth);
}

TEST_CASE("facet creases: a mesh sphere's neighbouring facets meet at about 360°/azimuthal segments, a box's none") {
  // A 12 × 24 sphere as a mesh (its exact shape forgotten): neighbours along a parallel meet
  // at up to 15° (360/24), along a meridian at 180/12 = 15° too; the largest crease lies
  // between them and 2 × 15° (at a pole's fan the chords bend by both), and every edge is smooth.
  geometry::TriangleSoup ball = geometry::sphere(Vec3::Zero(), 1.0, Vec3::UnitZ(), 0, 180, {}, 12, 24);
  ball.shape = {};
  geometry::Scene scene;
  scene.addSurface("ball", "ball", ball, "ball", "");
  scene.addSurface("exact", "exact", geometry::sphere(Vec3(5, 0, 0), 1.0, Vec3::UnitZ(), 0, 180, {}, 12, 24), "exact",
                   "");
  const auto box = geometry::boxFaces(Vec3(-5, 0, 0), Vec3(1, 1, 1), 3);
  for (int k = 0; k < 6; ++k) scene.addSurface(std::string("box") + geometry::kBoxFaceNames[k], "box", box[k], "box", "");
  const geometry::FacetCreases mesh = geometry::facetCreases(scene, scene.nodeIndex("ball"));
  INFO("mesh sphere: largest crease " << mesh.largest_deg << "°, " << mesh.smooth_edges << " smooth edges");
  CHECK(mesh.largest_deg >= 14.0);
  CHECK(mesh.largest_deg <= 30.0);
  CHECK(mesh.smooth_edges > 12 * 24);
  CHECK(mesh.mean_deg > 5.0);  // every edge of a 12 × 24 sphere bends by several degrees
  CHECK(mesh.mean_deg <= mesh.largest_deg);
  // The primitive knows its exact normal: its facets are left out.
  CHECK(geometry::facetCreases(scene, scene.nodeIndex("exact")).smooth_edges == 0);
  // A box's 90° edges are corners the model means; its split faces are flat.
  const geometry::FacetCreases cube = geometry::facetCreases(scene, scene.nodeIndex("box"));
  CHECK(cube.smooth_edges == 0);
  CHECK(cube.largest_deg == 0.0);
}
