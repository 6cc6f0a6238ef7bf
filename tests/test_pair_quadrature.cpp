// The ladder of point rules for far patch pairs (geometry/exact/pair_quadrature.hpp): its
// error estimates against the contour integral driven to 1e-14 (a second, exact method),
// and the exact method with relative targets against Howell's closed forms for whole faces
// of a room whose every cell is a node. Tolerances: the method's own estimates, which are
// the claim under test (issue 30: below the estimate for at least 99 % of pairs).
#include "geometry/exact/pair_quadrature.hpp"
#include "geometry/exact/polygon_factor.hpp"
#include "geometry/exact/view_factors.hpp"
#include "geometry/scene/primitives.hpp"
#include "tests/howell.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <string>

using namespace radnet::geometry;
namespace howell = radnet::howell;

namespace {

struct Face {
  Vec3 origin, u, v;  // u × v points into the room
};

// The 5 × 3 × 2.5 m room: ceiling, floor and two perpendicular walls.
const Face kFaces[] = {{Vec3(0, 0, 2.5), Vec3(0, 3, 0), Vec3(5, 0, 0)},
                       {Vec3(0, 0, 0), Vec3(5, 0, 0), Vec3(0, 3, 0)},
                       {Vec3(0, 0, 0), Vec3(0, 3, 0), Vec3(0, 0, 2.5)},
                       {Vec3(0, 0, 0), Vec3(0, 0, 2.5), Vec3(5, 0, 0)}};

// Every cell of every face as a patch of its own.
std::vector<Patch> cellPatches(int k) {
  std::vector<Patch> out;
  for (const Face& f : kFaces)
    for (int i = 0; i < k; ++i)
      for (int j = 0; j < k; ++j) {
        const Vec3 o = f.origin + (double(i) / k) * f.u + (double(j) / k) * f.v, du = f.u / k, dv = f.v / k;
        Patch p;
        p.node = static_cast<int>(out.size());
        p.region = {{{o, o + du, o + du + dv, o + dv}}, du.cross(dv).normalized()};
        p.pieces = p.region.loops;
        p.offset = p.region.normal.dot(o);
        p.area_m2 = du.cross(dv).norm();
        out.push_back(p);
      }
  return out;
}

Scene cellRoom(int k) {
  Scene s;
  const char* names[] = {"ceiling", "floor", "end", "side"};
  for (size_t f = 0; f < 4; ++f)
    for (int i = 0; i < k; ++i)
      for (int j = 0; j < k; ++j) {
        const Face& face = kFaces[f];
        const Vec3 o = face.origin + (double(i) / k) * face.u + (double(j) / k) * face.v;
        const std::string name = std::string(names[f]) + "." + std::to_string(i) + "." + std::to_string(j);
        s.addSurface(name, name, rectangle(o, face.u / k, face.v / k, 1, 1), name, "");
      }
  return s;
}

}  // namespace

TEST_CASE("point rules: the true error is below the estimate for at least 99 % of accepted pairs") {
  const int k = 8;
  const std::vector<Patch> patches = cellPatches(k);
  const PatchRules rules(patches);
  for (double relative : {1e-2, 1e-3, 1e-4}) {
    long accepted = 0, covered = 0, near = 0;
    double worst_ratio = 0.0;
    for (size_t p = 0; p < patches.size(); ++p)
      for (size_t q = p + 1; q < patches.size(); ++q) {
        if (p / (k * k) == q / (k * k)) continue;  // same face: coplanar
        bool found = false;
        const FactorEstimate est = rules.exchangeArea(p, q, 0.0, relative, found);
        if (!found) {
          ++near;
          continue;
        }
        const double exact = polygonExchangeArea(patches[p].region, patches[q].region, 1e-14).value;
        ++accepted;
        const double error = std::abs(est.value - exact);
        covered += error <= est.error;
        worst_ratio = std::max(worst_ratio, error / std::max(est.error, 1e-300));
        // The target itself is met (the estimate is within it by construction).
        CHECK(est.error <= relative * est.value * (1 + 1e-12));
      }
    INFO("relative " << relative << ": " << accepted << " accepted, " << near << " to the contour integral, "
                     << covered << " covered, worst true/estimate " << worst_ratio);
    CHECK(accepted > near);  // the ladder takes most pairs of a finely meshed room
    CHECK(double(covered) >= 0.99 * double(accepted));
  }
}

// One patch from a loop (counter-clockwise about `normal`).
Patch loopPatch(const Loop& loop, const Vec3& normal) {
  Patch p;
  p.node = 0;
  p.region = {{loop}, normal};
  p.pieces = {loop};
  p.offset = normal.dot(loop[0]);
  for (size_t k = 1; k + 1 < loop.size(); ++k) p.area_m2 += 0.5 * (loop[k] - loop[0]).cross(loop[k + 1] - loop[0]).norm();
  return p;
}

TEST_CASE("order 0+: the Taylor term is the centroid value's error to leading order") {
  // A tilted triangle and a skewed parallelogram facing it about 1 m away, shrunk by h: the
  // centroid value errs as h², the Taylor value as h⁴ (a second method: the contour integral
  // at 1e-14). Halving h must cut the Taylor value's error by about 16 (asserted > 10: the
  // h⁶ terms still count at h = 0.1) and leave it well under the centroid value's.
  const Vec3 np = Vec3(0.2, -0.1, 1).normalized(), nq = Vec3(-0.3, 0.2, -1).normalized();
  const Vec3 up = np.cross(Vec3(1, 0, 0)).normalized(), vp = np.cross(up);
  const Vec3 uq = nq.cross(Vec3(0, 1, 0)).normalized(), vq = nq.cross(uq);
  const Vec3 cq(0.3, -0.2, 1.0);
  double previous = 0.0;
  for (double h : {0.2, 0.1, 0.05}) {
    // About fixed centroids (the triangle's vertex mean at 0, the parallelogram's at cq).
    const Loop tri = {h * (up - 0.7 / 3 * up - 0.2 * vp), h * (0.3 * up + vp - 0.7 / 3 * up - 0.2 * vp),
                      h * (-0.6 * up - 0.4 * vp - 0.7 / 3 * up - 0.2 * vp)};
    const Vec3 mid = cq - h * (0.7 * uq + 0.4 * vq);
    const Loop quad = {mid, mid + h * uq, mid + h * (1.4 * uq + 0.8 * vq), mid + h * (0.4 * uq + 0.8 * vq)};
    const std::vector<Patch> patches = {loopPatch(tri, np), loopPatch(quad, nq)};
    const PatchRules rules(patches);
    bool found = false;
    const FactorEstimate taylor = rules.exchangeArea(0, 1, 0.0, 0.5, found);  // a loose target: order 0+ is taken
    REQUIRE(found);
    REQUIRE(taylor.evaluations == 1);
    const double exact = polygonExchangeArea(patches[0].region, patches[1].region, 1e-14).value;
    const double centroid_error = std::abs(rules.centroidValue(0, 1) - exact);
    const double taylor_error = std::abs(taylor.value - exact);
    INFO("h " << h << ": centroid error " << centroid_error / exact << ", Taylor error " << taylor_error / exact
              << " (relative), estimate " << taylor.error / exact);
    CHECK(taylor_error <= 0.05 * centroid_error);
    CHECK(taylor_error <= taylor.error);  // the reported error covers it
    if (previous > 0) CHECK(previous / taylor_error > 10.0);
    previous = taylor_error;
  }
}

TEST_CASE("order 0+ on random tilted triangles and parallelograms: the estimate covers the true error") {
  // Shapes and orientations the room does not have (its constant was measured there): 2,000
  // pairs, a triangle or a parallelogram each side, random sizes, tilts and offsets (fixed
  // seed), facing each other. Of the pairs the ladder accepts at a relative target of 1e-3,
  // the true error (contour integral at 1e-14) must be within the estimate for ≥ 99 % (the
  // claim of the room test, here off its geometry).
  std::mt19937_64 rng(20261207);
  std::uniform_real_distribution<double> u(-1.0, 1.0), size(0.05, 0.4);
  auto unit = [&] { return Vec3(u(rng), u(rng), u(rng)).normalized(); };
  long accepted = 0, covered = 0, by_taylor = 0, taylor_covered = 0;
  for (int k = 0; k < 2000; ++k) {
    const Vec3 cq = Vec3(u(rng), u(rng), 0) + Vec3(0, 0, 1.0 + 1.5 * (u(rng) + 1));
    Vec3 np = (Vec3(0, 0, 1) + 0.6 * unit()).normalized(), nq = (-Vec3(0, 0, 1) + 0.6 * unit()).normalized();
    auto loop = [&](const Vec3& centre, const Vec3& n, bool triangle) {
      const Vec3 e1 = n.unitOrthogonal(), e2 = n.cross(e1);
      const double h = size(rng), skew = 0.5 * u(rng), aspect = 0.5 + 0.5 * (u(rng) + 1);
      const Vec3 a = h * e1, b = h * aspect * (e2 + skew * e1);
      if (triangle) return Loop{centre - (a + b) / 3, centre + a - (a + b) / 3, centre + b - (a + b) / 3};
      return Loop{centre - (a + b) / 2, centre + a - (a + b) / 2, centre + a + b - (a + b) / 2, centre + b - (a + b) / 2};
    };
    const std::vector<Patch> patches = {loopPatch(loop(Vec3::Zero(), np, k % 2 == 0), np),
                                        loopPatch(loop(cq, nq, k % 3 == 0), nq)};
    const PatchRules rules(patches);
    bool found = false;
    const FactorEstimate est = rules.exchangeArea(0, 1, 0.0, 1e-3, found);
    if (!found) continue;
    const double exact = polygonExchangeArea(patches[0].region, patches[1].region, 1e-14).value;
    ++accepted;
    const bool within = std::abs(est.value - exact) <= est.error;
    covered += within;
    if (est.evaluations == 1) ++by_taylor, taylor_covered += within;
  }
  INFO(accepted << " accepted, " << covered << " covered; by order 0+ " << by_taylor << ", " << taylor_covered
                << " covered");
  CHECK(by_taylor > accepted / 5);  // the rung is exercised
  CHECK(double(covered) >= 0.99 * double(accepted));
  CHECK(double(taylor_covered) >= 0.99 * double(by_taylor));
}

TEST_CASE("exact method with relative targets: cell rows sum to the room's closed forms") {
  const int k = 8;
  const Scene s = cellRoom(k);
  ExactOptions opt;
  opt.relative_tolerance = 1e-3;  // the error budget's at solver.accuracy 0.01
  opt.tolerance = 1e-6;
  const ExactResult r = exactViewFactors(s, opt);
  CHECK(r.pairs_by_quadrature > r.pairs_unoccluded / 2);
  const int cells = k * k;
  // Face to face: Σ_i∈a Σ_j∈b A_i F_ij / A_a, against C-11 (ceiling → floor) and C-14
  // (floor → end wall: common edge 3, widths 5 and 2.5), within the summed estimates.
  auto faceFactor = [&](int a, int b, double& bound) {
    double sum = 0.0, area = 0.0;
    bound = 0.0;
    for (int i = a * cells; i < (a + 1) * cells; ++i) {
      const double ai = s.nodes()[size_t(i)].area_m2;
      area += ai;
      for (int j = b * cells; j < (b + 1) * cells; ++j) {
        sum += ai * r.view_factors.coeff(i, j);
        bound += ai * r.standard_error.coeff(i, j);
      }
    }
    bound /= area;
    return sum / area;
  };
  double bound = 0.0;
  const double ceiling_floor = faceFactor(0, 1, bound);
  CHECK(std::abs(ceiling_floor - howell::parallelRectangles(5, 3, 2.5)) <= bound);
  CHECK(bound <= 1e-3 * ceiling_floor);
  const double floor_end = faceFactor(1, 2, bound);
  CHECK(std::abs(floor_end - howell::perpendicularRectangles(3, 5, 2.5)) <= bound);
  // Symmetric exchange areas by construction: A_i F_ij = A_j F_ji to round-off.
  for (int i = 0; i < 4 * cells; i += 37)
    for (int j = 0; j < 4 * cells; j += 11)
      CHECK(std::abs(s.nodes()[size_t(i)].area_m2 * r.view_factors.coeff(i, j) -
                     s.nodes()[size_t(j)].area_m2 * r.view_factors.coeff(j, i)) <= 1e-15);
}
