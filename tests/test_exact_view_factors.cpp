// The deterministic view-factor method against closed forms (Howell's catalogue),
// conservation laws (closure, reciprocity of a convex body inside an enclosure) and a
// second route to the same number (a polygon with a hole against the difference of two
// polygons). Tolerances: the method's own error estimate where it is the claim under
// test, else the stated requested tolerance.
#include "geometry/exact/assemble_rows.hpp"
#include "geometry/exact/occluded_factor.hpp"
#include "geometry/exact/patches.hpp"
#include "geometry/exact/polygon_factor.hpp"
#include "geometry/exact/view_factors.hpp"
#include "geometry/scene/primitives.hpp"
#include "tests/howell.hpp"
#include "tests/room_scene.hpp"

#include <catch2/catch.hpp>

#include <algorithm>

#include <cmath>

using namespace radnet::geometry;
namespace howell = radnet::howell;

namespace {

PlanarRegion square(const Vec3& origin, const Vec3& u, const Vec3& v) {
  // Counter-clockwise about u × v.
  return {{{origin, origin + u, origin + u + v, origin + v}}, u.cross(v).normalized()};
}

Scene room(int sub) { return radnet::test::paperRoom(sub); }

Scene occludedSquares(int sub) {
  Scene s;
  s.addSurface("a", "a", rectangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), sub, sub), "a", "");
  s.addSurface("b", "b", rectangle(Vec3(0, 0, 1), Vec3(0, 1, 0), Vec3(1, 0, 0), sub, sub), "b", "");
  s.addSurface("shade", "shade", rectangle(Vec3(0.25, 0.25, 0.5), Vec3(0.5, 0, 0), Vec3(0, 0.5, 0), sub, sub), "",
               "");
  return s;
}

}  // namespace

TEST_CASE("polygon to polygon: the double contour integral meets Howell's closed forms") {
  const PlanarRegion a = square(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0));
  const PlanarRegion facing = square(Vec3(0, 0, 1), Vec3(0, 1, 0), Vec3(1, 0, 0));
  const PlanarRegion wall = square(Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, 0));  // shares a's edge on the x axis
  const PlanarRegion wide = square(Vec3(0, 0, 2), Vec3(0, 3, 0), Vec3(2, 0, 0));  // 2 × 3 at distance 2
  for (double tol : {1e-4, 1e-7, 1e-10}) {
    const FactorEstimate p = polygonExchangeArea(a, facing, tol);
    const FactorEstimate q = polygonExchangeArea(a, wall, tol);  // shared edge: r → 0 along it
    const double fp = howell::parallelRectangles(1, 1, 1), fq = howell::perpendicularRectangles(1, 1, 1);
    INFO("tolerance " << tol << ": parallel " << p.value << " ± " << p.error << ", perpendicular " << q.value << " ± "
                      << q.error);
    CHECK(std::abs(p.value - fp) <= std::max(p.error, 1e-14));  // the estimate covers the error
    CHECK(std::abs(q.value - fq) <= std::max(q.error, 1e-14));
    CHECK(p.error <= tol);
    CHECK(q.error <= tol);
  }
  // Reciprocity between unequal, offset polygons: A_a F_a→wide = A_wide F_wide→a, the
  // contour sums taken in opposite orders.
  const FactorEstimate ab = polygonExchangeArea(a, wide, 1e-12), ba = polygonExchangeArea(wide, a, 1e-12);
  CHECK(ab.value == Approx(ba.value).epsilon(1e-10));
}

TEST_CASE("point to polygon: Lambert's formula meets Howell B-3") {
  // Under the centre of a unit square at height 1: four corner cells of A = B = 0.5,
  // F = (1/2π)[A/√(1+A²) tan⁻¹(B/√(1+A²)) + B/√(1+B²) tan⁻¹(A/√(1+B²))] each.
  const double quadrant = (1.0 / (2 * M_PI)) * 2.0 * (0.5 / std::sqrt(1.25)) * std::atan(0.5 / std::sqrt(1.25));
  const Loop ceiling = {Vec3(0, 0, 1), Vec3(0, 1, 1), Vec3(1, 1, 1), Vec3(1, 0, 1)};  // faces −z
  CHECK(pointToConvexPolygon(Vec3(0.5, 0.5, 0), Vec3(0, 0, 1), ceiling) == Approx(4 * quadrant).epsilon(1e-12));
}

TEST_CASE("exact method: a meshed face is one patch, and the room's node factors are the closed forms") {
  for (int sub : {1, 8, 32}) {
    const Scene s = room(sub);
    const ExactResult r = exactViewFactors(s, ExactOptions::withTolerance(1e-9));
    INFO(sub << " × " << sub << " per face");
    CHECK(r.patches == 12);  // six nodes and six inactive back sides, whatever the mesh
    CHECK(r.pairs_occluded == 0);
    // Ceiling → floor (5 × 3 at 2.5) and floor → end1 (common edge 3, widths 5 and 2.5).
    CHECK(std::abs(r.view_factors.coeff(0, 5) - howell::parallelRectangles(5, 3, 2.5)) <= 1e-9);
    CHECK(std::abs(r.view_factors.coeff(5, 1) - howell::perpendicularRectangles(3, 5, 2.5)) <= 1e-9);
    for (int i = 0; i < 6; ++i) {
      CHECK(std::abs(r.view_factors.row(i).sum() - 1.0) <= 6e-9);  // six entries at 1e-9 each
      CHECK(r.space[i] <= 6e-9);
    }
  }
}

TEST_CASE("exact method: a square blocker halfway between two squares (View3D: F = 0.0995063)") {
  for (int sub : {1, 4}) {
    const ExactResult r = exactViewFactors(occludedSquares(sub), ExactOptions::withTolerance(1e-6));
    INFO(sub << " × " << sub << ": F = " << r.view_factors.coeff(0, 1) << " ± " << r.standard_error.coeff(0, 1));
    CHECK(r.pairs_occluded == 1);
    // View3D's figure carries 7 digits (±5e-8); ours is good to its tolerance 1e-6.
    CHECK(std::abs(r.view_factors.coeff(0, 1) - 0.0995063) <= 1e-6 + 5e-8);
    CHECK(r.standard_error.coeff(0, 1) <= 1e-6);
    // What the shade stops is blocked, not space: F_blocked = F_unoccluded − F (both
    // from a's side, the shade's lower face seen by a).
    CHECK(r.blocked[0] > 0.1);
    CHECK(r.view_factors.coeff(0, 1) + r.blocked[0] + r.space[0] == Approx(1.0).margin(3e-6));
  }
}

TEST_CASE("exact method: a square crossing the other's plane is clipped to the part in front") {
  // a: unit square in z = 0 facing +z. b: 1 × 2 in the plane y = 0 facing +y, z ∈ [−1, 1]:
  // a sees only b's upper half (C-14), and b's lower half sees nothing of a.
  Scene s;
  s.addSurface("a", "a", rectangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 1, 1), "a", "");
  s.addSurface("b", "b", rectangle(Vec3(0, 0, -1), Vec3(0, 0, 2), Vec3(1, 0, 0), 1, 1), "b", "");
  const ExactResult r = exactViewFactors(s, ExactOptions::withTolerance(1e-9));
  const double f = howell::perpendicularRectangles(1, 1, 1);
  CHECK(std::abs(r.view_factors.coeff(0, 1) - f) <= 1e-9);
  CHECK(std::abs(r.view_factors.coeff(1, 0) - f / 2) <= 1e-9);  // reciprocity, A_b = 2
}

TEST_CASE("exact method: a disc with a hole equals the difference of two discs") {
  // The annulus is one patch bounded by two loops (outer counter-clockwise, hole
  // clockwise); the discs are convex polygons on the same 48 sides.
  const Vec3 up(0, 0, 1), down(0, 0, -1);
  Scene annulus;
  annulus.addSurface("top", "top", disc(Vec3(0, 0, 1), down, 1.0, 0.0, {}, 2, 48), "top", "");
  annulus.addSurface("ring", "ring", disc(Vec3(0, 0, 0), up, 1.0, 0.5, {}, 2, 48), "ring", "");
  const ExactResult ring = exactViewFactors(annulus, ExactOptions::withTolerance(1e-10));
  Scene inner;
  inner.addSurface("top", "top", disc(Vec3(0, 0, 1), down, 1.0, 0.0, {}, 2, 48), "top", "");
  inner.addSurface("inner", "inner", disc(Vec3(0, 0, 0), up, 0.5, 0.0, {}, 2, 48), "inner", "");
  Scene outer;
  outer.addSurface("top", "top", disc(Vec3(0, 0, 1), down, 1.0, 0.0, {}, 2, 48), "top", "");
  outer.addSurface("outer", "outer", disc(Vec3(0, 0, 0), up, 1.0, 0.0, {}, 2, 48), "outer", "");
  const double difference = exactViewFactors(outer, ExactOptions::withTolerance(1e-10)).view_factors.coeff(0, 1) -
                            exactViewFactors(inner, ExactOptions::withTolerance(1e-10)).view_factors.coeff(0, 1);
  CHECK(ring.view_factors.coeff(0, 1) == Approx(difference).margin(1e-9));
  // And the 48-gons are close to the circles (C-40): within the polygon's bias of 1e-3.
  CHECK(std::abs(difference - (howell::coaxialDiscs(1, 1, 1) - howell::coaxialDiscs(1, 0.5, 1))) < 1e-3);
}

TEST_CASE("exact method: inside a facetted sphere around a facetted ball, F_out→in = A_in/A_out") {
  // The convex ball sees only the shell, so reciprocity gives F_out→in = A_in/A_out
  // exactly for these facets; the shell's view of itself passes the ball (occluded pairs).
  Scene s;
  s.addSurface("inner", "inner", sphere(Vec3(0, 0, 0), 1.0, Vec3(0, 0, 1), 0, 180, {}, 2, 4), "inner", "");
  s.addSurface("outer", "outer", sphere(Vec3(0, 0, 0), 2.0, Vec3(0, 0, 1), 0, 180, {}, 2, 4), "", "outer");
  const ExactResult r = exactViewFactors(s, ExactOptions::withTolerance(1e-5));
  const double ratio = s.nodes()[0].area_m2 / s.nodes()[1].area_m2;
  CHECK(r.pairs_occluded > 0);
  CHECK(r.view_factors.coeff(0, 1) == Approx(1.0).margin(1e-5));
  CHECK(std::abs(r.view_factors.coeff(1, 0) - ratio) <= 1e-5);
  CHECK(std::abs(r.view_factors.coeff(1, 1) - (1 - ratio)) <= std::max(r.standard_error.coeff(1, 1), 1e-12));
}

TEST_CASE("exact method: bit-identical for any thread count, auto leaves crowded pairs to rays") {
  const Scene s = occludedSquares(2);
  ExactOptions one = ExactOptions::withTolerance(1e-6), two = one;
  one.threads = 1;
  two.threads = 2;
  const ExactResult a = exactViewFactors(s, one), b = exactViewFactors(s, two);
  CHECK(Eigen::MatrixXd(a.view_factors) == Eigen::MatrixXd(b.view_factors));
  CHECK(Eigen::MatrixXd(a.standard_error) == Eigen::MatrixXd(b.standard_error));
  ExactOptions crowded = ExactOptions::withTolerance(1e-6);
  crowded.max_blockers = 0;  // every occluded pair goes to sampling
  const ExactResult c = exactViewFactors(s, crowded);
  CHECK(c.pairs_occluded == 0);
  CHECK(c.sampled_rows == std::vector<char>{1, 1});
  CHECK(c.view_factors.nonZeros() == 0);
  ViewFactorEstimate sampled = a;
  sampled.view_factors *= 2.0;
  const ViewFactorEstimate merged = withSampledRows(a, sampled, {0, 1});
  CHECK(merged.view_factors.coeff(0, 1) == a.view_factors.coeff(0, 1));
  CHECK(merged.view_factors.coeff(1, 0) == 2.0 * a.view_factors.coeff(1, 0));
}

namespace {

// Two walls of 12 × 12 separate 1 m cells, 3 m apart, facing each other: each cell a node
// (a0, b0, a1, b1, …), each its own patch.
Scene facingWalls() {
  Scene s;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j) {
      const std::string a = "a" + std::to_string(i * 12 + j), b = "b" + std::to_string(i * 12 + j);
      s.addSurface(a, a, rectangle(Vec3(i, j, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 1, 1), a, "");
      s.addSurface(b, b, rectangle(Vec3(i, j, 3), Vec3(0, 1, 0), Vec3(1, 0, 0), 1, 1), b, "");
    }
  return s;
}

// The entry whose error estimate is largest against max(tolerance, relative × F_ij), the
// first of equals in row order: a plain scan of the result's F and σ.
ErrorAgainstTarget worstAgainstTarget(const ExactResult& r, const ExactOptions& opt) {
  ErrorAgainstTarget worst{0.0, opt.tolerance};
  for (Eigen::Index i = 0; i < r.view_factors.outerSize(); ++i) {
    Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator f(r.view_factors, i), e(r.standard_error, i);
    for (; e; ++e, ++f) {
      REQUIRE(f.col() == e.col());
      const double target = std::max(opt.tolerance, opt.relative_tolerance * f.value());
      if (e.value() / target > worst.error / worst.target) worst = {e.value(), target};
    }
  }
  return worst;
}

// A facetted ball inside a facetted shell (nodes of many patches: a node pair gets values
// from many patch pairs, summed in credit order) and a plate between them whose back side is
// inactive (its pairs credit F_blocked).
Scene ballInShellWithPlate() {
  Scene s;
  s.addSurface("ball", "ball", sphere(Vec3(0, 0, 0), 0.6, Vec3(0, 0, 1), 0, 180, {}, 3, 6), "ball", "");
  s.addSurface("shell", "shell", sphere(Vec3(0, 0, 0), 2.0, Vec3(0, 0, 1), 0, 180, {}, 6, 10), "", "shell");
  s.addSurface("plate", "plate", rectangle(Vec3(1.0, -0.3, -0.3), Vec3(0, 0.6, 0), Vec3(0, 0, 0.6), 2, 2), "plate", "");
  return s;
}

// The paper's room with every face cut into k × k nodes of one cell each (paperRoom's faces).
Scene cellRoom(int k) {
  const double lx = 5.0, ly = 3.0, lz = 2.5;
  const Vec3 faces[6][3] = {
      {Vec3(0, 0, lz), Vec3(0, ly, 0), Vec3(lx, 0, 0)}, {Vec3(0, 0, 0), Vec3(0, ly, 0), Vec3(0, 0, lz)},
      {Vec3(lx, 0, 0), Vec3(0, 0, lz), Vec3(0, ly, 0)}, {Vec3(0, 0, 0), Vec3(0, 0, lz), Vec3(lx, 0, 0)},
      {Vec3(0, ly, 0), Vec3(lx, 0, 0), Vec3(0, 0, lz)}, {Vec3(0, 0, 0), Vec3(lx, 0, 0), Vec3(0, ly, 0)}};
  Scene s;
  for (int f = 0; f < 6; ++f)
    for (int a = 0; a < k; ++a)
      for (int b = 0; b < k; ++b) {
        const Vec3 u = faces[f][1] / k, v = faces[f][2] / k;
        const std::string name = "f" + std::to_string(f) + "." + std::to_string(a) + "." + std::to_string(b);
        s.addSurface(name, name, rectangle(faces[f][0] + a * u + b * v, u, v, 1, 1), name, "");
      }
  return s;
}

}  // namespace

TEST_CASE("exact method: rows credited in parallel chunks are the same bits for any thread count, and close") {
  // Nodes of many patches (a facetted ball and the shell around it: a node pair gets values
  // from many patch pairs, summed in credit order) and a plate between them whose back side
  // is inactive (its pairs credit F_blocked): enough emitting patches to fill every credit
  // chunk. One and two threads must give F, σ, F_blocked and F_space to the last bit, and the
  // shell's row must close: Σ F + F_blocked = 1 within its summed error estimates (the shell
  // is closed, nothing leaves to space).
  const Scene s = ballInShellWithPlate();
  ExactOptions one = ExactOptions::withTolerance(1e-4), two = one;
  one.threads = 1;
  two.threads = 2;
  const ExactResult a = exactViewFactors(s, one), b = exactViewFactors(s, two);
  REQUIRE(a.patches > 64);  // more emitting patches than credit chunks
  CHECK(Eigen::MatrixXd(a.view_factors) == Eigen::MatrixXd(b.view_factors));
  CHECK(Eigen::MatrixXd(a.standard_error) == Eigen::MatrixXd(b.standard_error));
  CHECK(a.blocked == b.blocked);
  CHECK(a.blocked_error == b.blocked_error);
  CHECK(a.space == b.space);
  const int shell = 1;
  CHECK(a.blocked[shell] > 0);  // the plate's inactive back is in the shell's view
  const double row = a.view_factors.row(shell).sum() + a.blocked[shell];
  const double bound = a.standard_error.row(shell).sum() + a.blocked_error[shell];
  INFO("shell row " << row << ", its error estimates " << bound);
  CHECK(std::abs(row - 1.0) <= std::max(bound, 1e-9));
  // The worst entry against its target, found as the rows are finished, is a scan's of the
  // merged F and σ (node entries, summed over their patch pairs).
  const ErrorAgainstTarget scanned = worstAgainstTarget(a, one);
  CHECK(a.worst_error == scanned.error);
  CHECK(a.worst_error_target == scanned.target);
  CHECK(b.worst_error == a.worst_error);
  CHECK(a.worst_error > 0);
  CHECK(a.worst_error <= a.worst_error_target);  // every pair met its share of the target
}

TEST_CASE("exact method: σ left on F's pattern is the σ of the whole matrix, bit for bit") {
  // Nodes of many patches (repeated columns summed) and an inactive side (F_blocked): σ
  // written beside F's columns or on F's pattern alone must hold the same numbers, and
  // expandErrors() must give back the matrix.
  const Scene s = ballInShellWithPlate();
  ExactOptions matrix = ExactOptions::withTolerance(1e-4), pattern = matrix;
  pattern.errors_on_pattern = true;
  const ExactResult a = exactViewFactors(s, matrix);
  ExactResult b = exactViewFactors(s, pattern);
  CHECK_FALSE(a.errors_on_pattern);
  REQUIRE(b.errors_on_pattern);
  CHECK(b.standard_error.nonZeros() == 0);
  CHECK(b.error_on_pattern.size() == b.view_factors.nonZeros());
  CHECK(Eigen::MatrixXd(a.view_factors) == Eigen::MatrixXd(b.view_factors));
  // σ is kept to float's digits on either storage: the same numbers.
  CHECK(Eigen::MatrixXd(errorsOnPattern(b).cast<double>()) == Eigen::MatrixXd(a.standard_error));
  CHECK(rowLargestErrors(b) == rowLargestErrors(a));
  CHECK(a.space == b.space);
  CHECK(a.space_error == b.space_error);
  CHECK(a.blocked_error == b.blocked_error);
  CHECK(a.worst_error == b.worst_error);
  expandErrors(b);
  CHECK_FALSE(b.errors_on_pattern);
  CHECK(b.error_on_pattern.size() == 0);
  CHECK(Eigen::MatrixXd(b.standard_error) == Eigen::MatrixXd(a.standard_error));
}

// Each pair held once (ExactOptions::upper_exchange) against the whole matrix with σ on its
// pattern, on one scene. F: a node pair's patch pairs summed before the division by the area
// instead of after, a few ulps of the entry (bound 1e-14 of it). σ: the same float sums in
// another order, within two float ulps (2.4e-7 of the entry). The correction's weights are
// the pairs' variances rounded to float (6e-8 of each): the corrected entries agree to 1e-6
// of the correction's largest move (and 1e-15 of a unit row, where nothing moves).
void checkUpperAgainstWhole(const Scene& s, double tolerance) {
  ExactOptions whole = ExactOptions::withTolerance(tolerance), once = whole;
  whole.errors_on_pattern = true;
  once.upper_exchange = true;
  once.threads = 2;
  ExactResult a = exactViewFactors(s, whole);
  ExactResult u = exactViewFactors(s, once);
  REQUIRE(u.upper_exchange);
  CHECK(u.view_factors.nonZeros() == 0);
  const Eigen::VectorXd area = u.upper_area;
  const Eigen::Index n = area.size();
  for (int i = 0; i < n; ++i)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(u.exchange_upper, i); it; ++it)
      CHECK(it.col() >= i);
  CHECK(fullNonZeros(u.exchange_upper) == a.view_factors.nonZeros());
  const Eigen::MatrixXd f_whole = a.view_factors, f_once = viewFactorsFromUpper(u.exchange_upper, area);
  CHECK(((f_once - f_whole).array().abs() <= 1e-14 * f_whole.array().abs()).all());
  CHECK(denseViewFactorsFromUpper(u.exchange_upper, area) == f_once);
  CHECK((upperRowSums(u.exchange_upper, area) - f_once.rowwise().sum()).cwiseAbs().maxCoeff() <= 1e-15);
  CHECK((u.space - a.space).cwiseAbs().maxCoeff() <= 1e-14);
  CHECK(u.blocked == a.blocked);
  CHECK((u.space_error - a.space_error).cwiseAbs().maxCoeff() <= 1e-6 * a.space_error.maxCoeff());
  const Eigen::MatrixXd sigma_whole = errorsOnPattern(a).cast<double>();
  CHECK((rowLargestErrors(u) - rowLargestErrors(a)).cwiseAbs().maxCoeff() <= 2.4e-7 * sigma_whole.maxCoeff());
  CHECK(std::abs(u.worst_error - a.worst_error) <= 2.4e-7 * a.worst_error);
  ViewFactorEstimate expanded = u;
  expandUpper(expanded);
  REQUIRE(expanded.errors_on_pattern);
  const Eigen::MatrixXd sigma_once = errorsOnPattern(expanded).cast<double>();
  CHECK(((sigma_once - sigma_whole).array().abs() <= 2.4e-7 * sigma_whole.array().abs()).all());
  CHECK(Eigen::MatrixXd(expanded.view_factors) == f_once);
  // The same bits on one thread as on two.
  once.threads = 1;
  const ExactResult one = exactViewFactors(s, once);
  CHECK(Eigen::MatrixXd(one.exchange_upper) == Eigen::MatrixXd(u.exchange_upper));
  CHECK(one.exchange_error_upper == u.exchange_error_upper);
  CHECK(one.space == u.space);
  // The corrections, each in place.
  const Eigen::VectorXd rays = Eigen::VectorXd::Constant(n, 1.0 / tolerance);
  const auto ca = enforceReciprocityInPlace(area, a, rays), cu = enforceReciprocityInPlace(area, u, rays);
  REQUIRE(ca);
  REQUIRE(cu);
  CHECK(cu->view_factors.nonZeros() == 0);
  const Eigen::MatrixXd corrected = viewFactorsFromUpper(cu->exchange_upper, area);
  INFO("largest move " << ca->max_change);
  CHECK(ca->max_change > 0);
  CHECK((corrected - Eigen::MatrixXd(ca->view_factors)).cwiseAbs().maxCoeff() <= 1e-6 * ca->max_change + 1e-15);
  CHECK(std::abs(cu->max_change - ca->max_change) <= 1e-6 * ca->max_change + 1e-15);
  CHECK(cu->max_closure_error <= 1e-12);
  CHECK(((corrected.rowwise().sum() + cu->space + cu->blocked).array() - 1.0).abs().maxCoeff() <= 1e-12);
  CHECK((area.asDiagonal() * corrected - (area.asDiagonal() * corrected).transpose()).cwiseAbs().maxCoeff() <=
        1e-15 * area.maxCoeff());
}

TEST_CASE("exact method: each pair held once is the whole matrix's F and σ, and corrects as it does") {
  // Nodes of many patches and an inactive side (F_blocked), then a room of 3 × 3 nodes a wall.
  checkUpperAgainstWhole(ballInShellWithPlate(), 1e-4);
  checkUpperAgainstWhole(cellRoom(3), 1e-5);
}

TEST_CASE("exact method: an occluded pair held at depth 0 reports its error above its target") {
  // The square blocker halfway: one occluded pair, its emitter quadrature unrefined, cannot
  // reach 1e-9; the run says which entry and by how much (radnet warns from it).
  ExactOptions shallow = ExactOptions::withTolerance(1e-9);
  shallow.max_depth = 0;
  const ExactResult r = exactViewFactors(occludedSquares(1), shallow);
  REQUIRE(r.pairs_occluded == 1);
  const ErrorAgainstTarget scanned = worstAgainstTarget(r, shallow);
  CHECK(r.worst_error == scanned.error);
  CHECK(r.worst_error_target == 1e-9);
  CHECK(r.worst_error > 10 * r.worst_error_target);
}

TEST_CASE("auto: a patch whose pairs cost more than casting its row stops planning there (bounded on clutter)") {
  // Two walls of 12 × 12 separate cells facing each other: each cell a node, each its own patch.
  const Scene s = facingWalls();
  ExactOptions plenty = ExactOptions::withTolerance(1e-6);
  plenty.max_blockers = 8;
  plenty.row_sampling_seconds = 10.0;  // casting a row dear: every pair is planned, every row exact
  const ExactResult all = exactViewFactors(s, plenty);
  CHECK(all.pairs_planned >= 144 * 144);  // every facing pair once (pairs on one wall are culled by cluster, unplanned)
  CHECK(std::count(all.sampled_rows.begin(), all.sampled_rows.end(), 1) == 0);
  ExactOptions cheap = plenty;
  cheap.row_sampling_seconds = 1e-9;  // a row cheaper than any pair: each patch stops at its first pair
  const ExactResult bounded = exactViewFactors(s, cheap);
  CHECK(bounded.pairs_planned <= 288 * 3);  // culled pairs (its own wall) cost nothing: it stops at the first that costs
  CHECK(std::count(bounded.sampled_rows.begin(), bounded.sampled_rows.end(), 1) == 288);
}

TEST_CASE("auto: past max_entries the rows with the most entries are cast, and the exact rows hold at most the cap") {
  // Every cell sees all 144 of the other wall: each row would hold 144 entries from pairs.
  const Scene s = facingWalls();
  ExactOptions opt = ExactOptions::withTolerance(1e-6);
  opt.max_blockers = 8;
  opt.row_sampling_seconds = 10.0;  // cost never sends a row to rays here: only the cap does
  const ExactResult all = exactViewFactors(s, opt);
  CHECK(all.rows_for_memory == 0);
  CHECK(all.view_factors.nonZeros() == 288 * 144);
  opt.max_entries = 100 * 144;  // room for 100 rows' entries
  const ExactResult capped = exactViewFactors(s, opt);
  // 288 rows of 144 entries each: 188 go to rays, the 100 kept hold exactly the cap; ties go
  // by node index, so the last 188 nodes (the b wall's and the a wall's tail) are cast.
  CHECK(capped.rows_for_memory == 188);
  CHECK(capped.entries_for_memory == 188 * 144);
  CHECK(std::count(capped.sampled_rows.begin(), capped.sampled_rows.end(), 1) == 188);
  CHECK(capped.view_factors.nonZeros() <= opt.max_entries);
  // The rows kept are the full computation's to round-off (a pair to a row now cast is
  // integrated from the kept side alone: the same integral summed in another order; measured
  // 6e-17).
  double largest = 0.0;
  for (Eigen::Index i = 0; i < 288; ++i)
    if (!capped.sampled_rows[size_t(i)])
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(all.view_factors, i); it; ++it)
        largest = std::max(largest, std::abs(capped.view_factors.coeff(i, it.col()) - it.value()));
  INFO("largest difference " << largest);
  CHECK(largest <= 1e-14);
}

TEST_CASE("exact method: shared out in two parts (as over MPI ranks) gives one process's result bit for bit") {
  // Two parts in one process: part 0's gather runs part 1, whose gather joins both packs
  // in part order, as cluster::gatherAll does across ranks.
  Scene s;
  s.addSurface("inner", "inner", sphere(Vec3(0, 0, 0), 1.0, Vec3(0, 0, 1), 0, 180, {}, 2, 4), "inner", "");
  s.addSurface("outer", "outer", sphere(Vec3(0, 0, 0), 2.0, Vec3(0, 0, 1), 0, 180, {}, 2, 4), "", "outer");
  const ExactOptions base = ExactOptions::withTolerance(1e-5);
  ExactOptions alone = base;
  int emitters = 0;
  alone.progress = [&](int, int total) { emitters = total; };
  const ExactResult whole = exactViewFactors(s, alone);
  ExactOptions first = base;
  first.parts = 2;
  int patches_seen[2] = {0, 0};
  first.progress = [&](int, int total) { patches_seen[0] = total; };
  first.gather = [&](const std::vector<double>& pack0) {
    std::vector<double> all;
    ExactOptions second = base;
    second.part = 1;
    second.parts = 2;
    second.progress = [&](int, int total) { patches_seen[1] = total; };
    second.gather = [&](const std::vector<double>& pack1) {
      all = pack0;
      all.insert(all.end(), pack1.begin(), pack1.end());
      return all;
    };
    exactViewFactors(s, second);
    return all;
  };
  const ExactResult split = exactViewFactors(s, first);
  CHECK(patches_seen[0] > 0);
  CHECK(patches_seen[1] > 0);  // each part integrated some emitters, not all
  CHECK(patches_seen[0] + patches_seen[1] == emitters);
  CHECK(Eigen::MatrixXd(split.view_factors) == Eigen::MatrixXd(whole.view_factors));
  CHECK(Eigen::MatrixXd(split.standard_error) == Eigen::MatrixXd(whole.standard_error));
  CHECK(split.space == whole.space);
  CHECK(split.pairs_occluded == whole.pairs_occluded);
  CHECK(split.pairs_unoccluded == whole.pairs_unoccluded);
  CHECK(split.evaluations == whole.evaluations);
}

TEST_CASE("patches: coplanar triangles of a node merge, a curved surface stays facets") {
  Scene s;
  s.addSurface("plate", "plate", rectangle(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 1, 0), 16, 8), "plate", "back");
  s.addSurface("can", "can", cylinder(Vec3(0, 0, 1), Vec3(0, 0, 1), 0.5, {}, 1, 12), "can", "");
  const std::vector<Patch> patches = buildPatches(s);
  int plate = 0, can = 0;
  for (const Patch& p : patches) {
    if (p.node == 0 || p.node == 1) {
      ++plate;
      CHECK(p.faces == 256);
      CHECK(p.region.loops.size() == 1);
      CHECK(p.region.loops[0].size() == 4);  // collinear boundary points merged
      CHECK(p.area_m2 == Approx(2.0).epsilon(1e-12));
    }
    if (p.node == 2) ++can;
  }
  CHECK(plate == 2);
  CHECK(can == 12);  // one patch per flat facet strip of the cylinder
}

TEST_CASE("exact method: cells added one by one weld into one patch, a plate that hides all is no integral") {
  // One node of 5 × 5 cells, each its own surface whose corners are computed afresh (they
  // differ in the last bits from their neighbours'): one patch of four corners.
  Scene s;
  const int m = 5;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      s.addSurface("cell" + std::to_string(i) + std::to_string(j), "cell",
                   rectangle(Vec3(0.3 * i / m, 0.7 * j / m, 0), Vec3(0.3 / m, 0, 0), Vec3(0, 0.7 / m, 0), 1, 1), "a", "");
  // A 2 × 2 plate at z = 0.5 hides the whole of b (z = 1) from the whole of a.
  s.addSurface("plate", "plate", rectangle(Vec3(-0.85, -0.65, 0.5), Vec3(2, 0, 0), Vec3(0, 2, 0), 1, 1), "", "");
  s.addSurface("b", "b", rectangle(Vec3(0, 0, 1), Vec3(0, 0.7, 0), Vec3(0.3, 0, 0), 1, 1), "b", "");
  int merged = 0;
  for (const Patch& p : buildPatches(s))
    if (p.node == 0) {
      ++merged;
      CHECK(p.region.loops.size() == 1);
      CHECK(p.region.loops[0].size() == 4);
    }
  CHECK(merged == 1);
  const ExactResult r = exactViewFactors(s, ExactOptions::withTolerance(1e-8));
  CHECK(r.pairs_hidden >= 1);
  CHECK(r.view_factors.coeff(0, 1) == 0.0);
  // All of a's view upwards ends on the plate's lower side: blocked, nothing to space but
  // what passes its edges (the plate subtends less than the hemisphere).
  CHECK(r.blocked[0] > 0.5);
  CHECK(r.blocked[0] + r.space[0] == Approx(1.0).margin(1e-7));
}

TEST_CASE("exact method: walls standing on a plate (the view jumps across their foot) meet C-11") {
  // An open square tube 0.6 × 0.6 × 0.6 m (outside "tube", inside "inside") on a 2 × 2 m
  // plate. Only the plate's footprint sees the inside, and it sees the inside walls or the
  // top opening: F_plate→inside = (A_foot/A_plate)(1 − F_C-11(0.6, 0.6, 0.6)).
  Scene s;
  s.addSurface("plate", "plate", rectangle(Vec3(-1, -1, 0), Vec3(2, 0, 0), Vec3(0, 2, 0), 2, 2), "plate", "");
  const auto faces = boxFaces(Vec3(-0.3, -0.3, 0), Vec3(0.6, 0.6, 0.6), 2);
  for (int k = 0; k < 4; ++k) s.addSurface(kBoxFaceNames[k], "tube", faces[static_cast<size_t>(k)], "tube", "inside");
  const ExactResult r = exactViewFactors(s, ExactOptions::withTolerance(1e-6));
  const double expected = (0.36 / 4.0) * (1.0 - howell::parallelRectangles(0.6, 0.6, 0.6));
  INFO("F_plate→inside = " << r.view_factors.coeff(0, 2) << " ± " << r.standard_error.coeff(0, 2) << ", expected "
                           << expected);
  CHECK(std::abs(r.view_factors.coeff(0, 2) - expected) <= 1e-6);
  // The inside sees the footprint: F_inside→plate by reciprocity, A_inside = 4 × 0.36.
  CHECK(std::abs(r.view_factors.coeff(2, 0) - expected * 4.0 / 1.44) <= 1e-6);
}

TEST_CASE("exact method: a row mask integrates those rows alone, as the whole run does (a turning part's rows)") {
  // The rows asked take every pair they hold (with the rows left out too) and nothing is
  // credited to the rows left out. A pair is integrated from whichever side visits it, so an
  // entry may differ from the whole run's by the quadrature's own error: each is held to
  // the larger of the two error estimates (plus rounding); F_space and F_blocked, sums over a
  // row of a few pairs at 1e-7 each, to 1e-6.
  for (const Scene& scene : {room(3), occludedSquares(4)}) {
    const ExactOptions whole_opt = ExactOptions::withTolerance(1e-7);
    const ExactResult whole = exactViewFactors(scene, whole_opt);
    const size_t n = scene.nodes().size();
    ExactOptions opt = whole_opt;
    opt.rows.assign(n, 0);
    for (size_t i = 0; i < n; i += 2) opt.rows[i] = 1;
    const ExactResult some = exactViewFactors(scene, opt);
    INFO(n << " nodes");
    for (size_t i = 0; i < n; ++i) {
      const auto row = static_cast<Eigen::Index>(i);
      CHECK(static_cast<bool>(some.sampled_rows[i]) == !opt.rows[i]);
      if (!opt.rows[i]) {
        CHECK(some.view_factors.row(row).nonZeros() == 0);
        continue;
      }
      for (size_t j = 0; j < n; ++j) {
        const auto col = static_cast<Eigen::Index>(j);
        const double allowed =
            std::max(whole.standard_error.coeff(row, col), some.standard_error.coeff(row, col)) + 1e-14;
        CHECK(std::abs(some.view_factors.coeff(row, col) - whole.view_factors.coeff(row, col)) <= allowed);
      }
      CHECK(some.space[row] == Approx(whole.space[row]).margin(1e-6));
      CHECK(some.blocked[row] == Approx(whole.blocked[row]).margin(1e-6));
    }
  }
  // A node-pair filter (a turning part's configuration: only the pairs a turn can change):
  // the pairs it keeps as the whole run has them, the others absent from the rows asked.
  {
    const Scene scene = room(3);
    const size_t n = scene.nodes().size();
    const ExactResult whole = exactViewFactors(scene, ExactOptions::withTolerance(1e-7));
    ExactOptions opt = ExactOptions::withTolerance(1e-7);
    opt.rows.assign(n, 1);
    opt.node_pairs = [](int i, int j) { return i == 0 || j == 0; };
    const ExactResult some = exactViewFactors(scene, opt);
    for (size_t i = 0; i < n; ++i)
      for (size_t j = 0; j < n; ++j) {
        const auto row = static_cast<Eigen::Index>(i), col = static_cast<Eigen::Index>(j);
        INFO("F(" << i << ", " << j << ")");
        if (i != 0 && j != 0) {
          CHECK(some.view_factors.coeff(row, col) == 0.0);
          continue;
        }
        const double allowed =
            std::max(whole.standard_error.coeff(row, col), some.standard_error.coeff(row, col)) + 1e-14;
        CHECK(std::abs(some.view_factors.coeff(row, col) - whole.view_factors.coeff(row, col)) <= allowed);
        if (i != j) CHECK(some.view_factors.coeff(row, col) > 0.0);  // a closed room: every other node is seen
      }
  }
  ExactOptions wrong = ExactOptions::withTolerance(1e-6);
  wrong.rows.assign(1, 1);
  CHECK_THROWS_AS(exactViewFactors(room(2), wrong), std::invalid_argument);
}
