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
