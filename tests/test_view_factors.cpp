// View factors by ray casting against Howell's catalogue and conservation laws.
// Tolerance: "3σ" plus the stated bias of the facetted geometry where a curved surface is
// involved. σ is estimated from 32 randomised-QMC replicas, so (F̂ − F)/σ follows Student's
// t with 31 degrees of freedom; its 99.73 % quantile (the normal 3σ coverage) is 3.29.
#include "geometry/exact/view_factors.hpp"
#include "geometry/scene/primitives.hpp"
#include "geometry/reciprocity.hpp"
#include "geometry/rays/view_factors.hpp"
#include "tests/howell.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <optional>
#include <random>
#include <tuple>

using namespace radnet::geometry;
using namespace radnet;

namespace {

constexpr double kThreeSigma = 3.29;  // t(31) quantile of the normal 3σ coverage

using howell::parallelRectangles;
using howell::perpendicularRectangles;

ViewFactorResult cast(const Scene& scene, std::int64_t rays, std::uint64_t seed = 1,
                      Sampling sampling = Sampling::Sobol) {
  RayCaster caster(scene);
  ViewFactorOptions opt;
  opt.rays_per_node = rays;
  opt.seed = seed;
  opt.sampling = sampling;
  return computeViewFactors(caster, opt);
}

void checkWithin3Sigma(const ViewFactorResult& r, int i, int j, double exact, double bias = 0.0) {
  const double f = r.view_factors.coeff(i, j), s = r.standard_error.coeff(i, j);
  INFO("F[" << i << "][" << j << "] = " << f << " ± " << s << ", exact " << exact << ", allowed bias " << bias);
  CHECK(s > 0);
  CHECK(std::abs(f - exact) <= kThreeSigma * s + bias);
}

Scene parallelSquares(double gap = 1.0) {
  Scene s;
  s.addSurface("a", "a", rectangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 2, 2), "a", "");
  s.addSurface("b", "b", rectangle(Vec3(0, 0, gap), Vec3(0, 1, 0), Vec3(1, 0, 0), 2, 2), "b", "");
  return s;
}

}  // namespace

TEST_CASE("analytic references reproduce Howell's tabulated values") {
  CHECK(parallelRectangles(1, 1, 1) == Approx(0.19982).margin(5e-6));
  CHECK(perpendicularRectangles(1, 1, 1) == Approx(0.20004).margin(5e-6));
}

TEST_CASE("parallel directly opposed unit squares at distance 1: F = 0.19982") {
  const ViewFactorResult r = cast(parallelSquares(), 200000);
  checkWithin3Sigma(r, 0, 1, parallelRectangles(1, 1, 1));
  checkWithin3Sigma(r, 1, 0, parallelRectangles(1, 1, 1));
  // Each ray lands somewhere: F + F_space = 1 per row, exactly (counts).
  CHECK(r.view_factors.coeff(0, 1) + r.space[0] == Approx(1.0).margin(1e-14));
}

TEST_CASE("perpendicular unit squares sharing an edge: F = 0.20004") {
  Scene s;
  s.addSurface("a", "a", rectangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 3, 3), "a", "");
  s.addSurface("b", "b", rectangle(Vec3(0, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, 0), 3, 3), "b", "");
  const ViewFactorResult r = cast(s, 200000);
  checkWithin3Sigma(r, 0, 1, perpendicularRectangles(1, 1, 1));
  checkWithin3Sigma(r, 1, 0, perpendicularRectangles(1, 1, 1));
}

TEST_CASE("coaxial parallel discs, radius 1, distance 1: F = (3 − √5)/2 = 0.38197") {
  Scene s;
  s.addSurface("a", "a", disc(Vec3(0, 0, 0), Vec3(0, 0, 1), 1.0, 0.0, {}, 4, 64), "a", "");
  s.addSurface("b", "b", disc(Vec3(0, 0, 1), Vec3(0, 0, -1), 1.0, 0.0, {}, 4, 64), "b", "");
  const double exact = (3.0 - std::sqrt(5.0)) / 2.0;
  // Bias of the 64-gon against the circle, measured by the deterministic method on the
  // same facets: |F_facetted − F_circle| < 2e-4 (the polygon's area equals the circle's).
  const ExactResult det = exactViewFactors(s, ExactOptions::withTolerance(1e-8));
  INFO("deterministic on the facetted discs: " << det.view_factors.coeff(0, 1));
  CHECK(std::abs(det.view_factors.coeff(0, 1) - exact) < 2e-4);
  const ViewFactorResult r = cast(s, 200000);
  checkWithin3Sigma(r, 0, 1, exact, 2e-4);
}

TEST_CASE("interior of a closed cube: opposite 0.19982, adjacent 0.20004, closed rows after correction") {
  Scene s;
  const auto faces = boxFaces(Vec3(0, 0, 0), Vec3(1, 1, 1), 2);
  for (int k = 0; k < 6; ++k) s.addSurface(kBoxFaceNames[k], kBoxFaceNames[k], faces[k], "", kBoxFaceNames[k]);
  const ViewFactorResult r = cast(s, 100000);
  CHECK(r.space.cwiseAbs().maxCoeff() == 0.0);                   // nothing escapes a closed box
  checkWithin3Sigma(r, 0, 1, parallelRectangles(1, 1, 1));       // +x → −x
  checkWithin3Sigma(r, 0, 2, perpendicularRectangles(1, 1, 1));  // +x → +y
  checkWithin3Sigma(r, 4, 5, parallelRectangles(1, 1, 1));       // +z → −z
  Eigen::VectorXd area = Eigen::VectorXd::Ones(6), rays(6);
  for (int i = 0; i < 6; ++i) rays[i] = double(r.rays[static_cast<size_t>(i)]);
  const ReciprocityCorrection c = enforceReciprocity(area, r, rays);
  const Eigen::MatrixXd f = Eigen::MatrixXd(c.view_factors);
  CHECK((f.rowwise().sum().array() - 1.0).abs().maxCoeff() < 1e-12);
  CHECK((f - f.transpose()).cwiseAbs().maxCoeff() < 1e-15);  // equal areas: F symmetric
  CHECK(c.max_change_sigma < 4.0);                           // the correction stays within the noise
  // The correction does not make the answers worse.
  CHECK(std::abs(f(0, 1) - parallelRectangles(1, 1, 1)) <= kThreeSigma * r.standard_error.coeff(0, 1));
}

TEST_CASE("concentric spheres r = 1 and 2: F_outer→inner = 0.25, F_outer→outer = 0.75") {
  Scene s;
  const Sweep full;
  s.addSurface("inner", "inner", sphere(Vec3(0, 0, 0), 1.0, Vec3(0, 0, 1), 0, 180, full, 24, 48), "inner", "");
  s.addSurface("outer", "outer", sphere(Vec3(0, 0, 0), 2.0, Vec3(0, 0, 1), 0, 180, full, 24, 48), "", "outer");
  CHECK(s.nodes()[0].area_m2 == Approx(4 * M_PI).epsilon(1e-12));  // area-preserving facets
  CHECK(s.nodes()[1].area_m2 == Approx(16 * M_PI).epsilon(1e-12));
  const ViewFactorResult r = cast(s, 200000);
  // The facetted inner sphere's silhouette differs from the sphere's by < 0.2 % (measured
  // against 96 × 192 facets): allow 5e-4 of bias.
  checkWithin3Sigma(r, 1, 0, 0.25, 5e-4);
  checkWithin3Sigma(r, 1, 1, 0.75, 5e-4);
  CHECK(r.view_factors.coeff(0, 1) == Approx(1.0).margin(1e-12));  // the inner sphere sees only the outer
}

TEST_CASE("occlusion: a plate halfway between two squares changes F as the deterministic method predicts") {
  Scene s = parallelSquares();
  s.addSurface("blocker", "blocker", rectangle(Vec3(0.25, 0.0, 0.5), Vec3(0, 0.5, 0), Vec3(0.5, 0, 0), 4, 4), "blocker",
               "blocker.back");
  RayCaster caster(s);
  ViewFactorOptions opt;
  opt.rays_per_node = 400000;
  const ViewFactorResult mc = computeViewFactors(caster, opt);
  const ExactResult det = exactViewFactors(s, ExactOptions::withTolerance(1e-7));
  const double unblocked = parallelRectangles(1, 1, 1);
  INFO("MC " << mc.view_factors.coeff(0, 1) << " ± " << mc.standard_error.coeff(0, 1) << ", deterministic "
             << det.view_factors.coeff(0, 1) << " (error estimate " << det.standard_error.coeff(0, 1) << ")");
  CHECK(mc.view_factors.coeff(0, 1) < unblocked - 0.02);  // the blocker takes a visible share
  // The exact method's error (≤ 1e-7) is far below the rays' σ: compare within 3σ.
  checkWithin3Sigma(mc, 0, 1, det.view_factors.coeff(0, 1));
  checkWithin3Sigma(mc, 0, 2, det.view_factors.coeff(0, 2));
  // Rays stopped by the blocker's sides count as the blocker's, not as space.
  CHECK(mc.view_factors.coeff(0, 2) > 0.05);
}

TEST_CASE("two-sided panel: the back face sees nothing the front face sees") {
  Scene s;
  s.addSurface("panel", "panel", rectangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 2, 2), "panel", "panel.back");
  s.addSurface("above", "above", rectangle(Vec3(0, 0, 1), Vec3(0, 1, 0), Vec3(1, 0, 0), 2, 2), "above", "");
  s.addSurface("below", "below", rectangle(Vec3(0, 0, -1), Vec3(1, 0, 0), Vec3(0, 1, 0), 2, 2), "below", "");
  const ViewFactorResult r = cast(s, 100000);
  const int front = s.nodeIndex("panel"), back = s.nodeIndex("panel.back");
  const int above = s.nodeIndex("above"), below = s.nodeIndex("below");
  CHECK(r.view_factors.coeff(front, below) == 0.0);
  CHECK(r.view_factors.coeff(back, above) == 0.0);
  checkWithin3Sigma(r, front, above, parallelRectangles(1, 1, 1));
  checkWithin3Sigma(r, back, below, parallelRectangles(1, 1, 1));
  // One-sided surfaces stop rays from behind: "above" faces down, so rays from below that
  // reach its back (inactive) side are blocked, not passed to space.
  CHECK(r.view_factors.coeff(above, front) > 0.19);
}

TEST_CASE("the paper's 5 × 3 × 2.5 m room reproduces its form factors within 3σ") {
  Scene s;
  // Inward-facing walls: ceiling (z = 2.5), end walls (x = 0, 5), side walls (y = 0, 3), floor.
  const double lx = 5.0, ly = 3.0, lz = 2.5;
  s.addSurface("ceiling", "ceiling", rectangle(Vec3(0, 0, lz), Vec3(0, ly, 0), Vec3(lx, 0, 0), 4, 4), "ceiling", "");
  s.addSurface("end1", "end1", rectangle(Vec3(0, 0, 0), Vec3(0, ly, 0), Vec3(0, 0, lz), 4, 4), "end1", "");
  s.addSurface("end2", "end2", rectangle(Vec3(lx, 0, 0), Vec3(0, 0, lz), Vec3(0, ly, 0), 4, 4), "end2", "");
  s.addSurface("side1", "side1", rectangle(Vec3(0, 0, 0), Vec3(0, 0, lz), Vec3(lx, 0, 0), 4, 4), "side1", "");
  s.addSurface("side2", "side2", rectangle(Vec3(0, ly, 0), Vec3(lx, 0, 0), Vec3(0, 0, lz), 4, 4), "side2", "");
  s.addSurface("floor", "floor", rectangle(Vec3(0, 0, 0), Vec3(lx, 0, 0), Vec3(0, ly, 0), 4, 4), "floor", "");
  const ViewFactorResult r = cast(s, 400000);
  // The paper prints 4 decimals: allow its rounding (5e-5) on top of 3σ.
  checkWithin3Sigma(r, 0, 5, 0.3213, 5e-5);
  checkWithin3Sigma(r, 0, 1, 0.1249, 5e-5);
  checkWithin3Sigma(r, 0, 3, 0.2145, 5e-5);
  CHECK(r.space.cwiseAbs().maxCoeff() == 0.0);
}

TEST_CASE("standard errors are honest: coverage of ±2σ over 200 seeds") {
  // Student t with 31 degrees of freedom: P(|t| ≤ 2) = 0.946. With 200 trials the count's
  // standard deviation is 1.6 % (3.2 trials), so accept [0.88, 0.99].
  const Scene s = parallelSquares();
  RayCaster caster(s);
  const double exact = parallelRectangles(1, 1, 1);
  for (Sampling sampling : {Sampling::Sobol, Sampling::Random}) {
    int covered = 0;
    double mean_sigma = 0.0;
    for (int seed = 1; seed <= 200; ++seed) {
      ViewFactorOptions opt;
      opt.rays_per_node = 4096;
      opt.seed = static_cast<std::uint64_t>(seed);
      opt.sampling = sampling;
      const ViewFactorResult r = computeViewFactors(caster, opt);
      const double err = std::abs(r.view_factors.coeff(0, 1) - exact), sigma = r.standard_error.coeff(0, 1);
      covered += err <= 2 * sigma;
      mean_sigma += sigma / 200;
    }
    INFO((sampling == Sampling::Sobol ? "Sobol" : "random")
         << ": coverage " << covered / 200.0 << ", mean σ " << mean_sigma);
    CHECK(covered >= 176);
    CHECK(covered <= 198);
    if (sampling == Sampling::Random) {
      // Plain Monte Carlo: σ ≈ √(F(1 − F)/N).
      CHECK(mean_sigma == Approx(std::sqrt(exact * (1 - exact) / 4096)).epsilon(0.1));
    }
  }
}

TEST_CASE("reproducible: same seed and any thread count give the same bits, and a target error stops early") {
  const Scene s = parallelSquares();
  RayCaster caster(s);
  ViewFactorOptions opt;
  opt.rays_per_node = 20000;
  opt.threads = 1;
  const ViewFactorResult one = computeViewFactors(caster, opt);
  opt.threads = 2;
  const ViewFactorResult two = computeViewFactors(caster, opt);
  CHECK((one.denseViewFactors() - two.denseViewFactors()).cwiseAbs().maxCoeff() == 0.0);
  opt.seed = 2;
  CHECK((computeViewFactors(caster, opt).denseViewFactors() - one.denseViewFactors()).cwiseAbs().maxCoeff() > 0.0);
  // Target error: stop once every entry of a row has σ ≤ 1e-3.
  opt.rays_per_node = 1 << 22;
  opt.target_error = 1e-3;
  const ViewFactorResult adaptive = computeViewFactors(caster, opt);
  CHECK(adaptive.rays[0] < (1 << 22));
  CHECK(adaptive.standard_error.coeff(0, 1) <= 1e-3);
  CHECK(std::abs(adaptive.view_factors.coeff(0, 1) - parallelRectangles(1, 1, 1)) <= 3e-3);
}

TEST_CASE("reciprocity correction: the same answer whatever the node order, pairs seen from one side included") {
  // A random sampled estimate (fixed seed) of 40 nodes: rays per row, binomial σ, about a
  // third of the pairs seen from one side only, σ stored on a pattern of its own with
  // explicit zeros, space terms. The pairs are walked upper entry first with a cursor for
  // each row's lower part; reversing the node order swaps every pair's upper and lower
  // entries, so the corrected F must be the reversed one to rounding.
  const int n = 40;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::VectorXd area(n), rays(n);
  for (int i = 0; i < n; ++i) {
    area[i] = 0.5 + 2.0 * u(rng);
    rays[i] = 1000.0 + std::floor(4000.0 * u(rng));
  }
  std::vector<Eigen::Triplet<double>> f_entries, s_entries;
  Eigen::VectorXd space(n), space_error(n);
  for (int i = 0; i < n; ++i) {
    double row = 0.0;
    for (int j = 0; j < n; ++j) {
      if (j == i || u(rng) < 0.3) continue;  // a pair this row drew no hit of
      const double p = 0.02 * u(rng);
      f_entries.emplace_back(i, j, p);
      s_entries.emplace_back(i, j, std::sqrt(p * (1 - p) / rays[i]));
      row += p;
    }
    if (u(rng) < 0.3) s_entries.emplace_back(i, (i + 1) % n, 0.0);  // an explicit zero off F's pattern
    space[i] = 1.0 - row;
    space_error[i] = std::sqrt(space[i] * (1 - space[i]) / rays[i]);
  }
  auto estimateIn = [&](const std::vector<int>& order) {  // node k of the copy is node order[k]
    std::vector<int> where(n);
    for (int k = 0; k < n; ++k) where[static_cast<size_t>(order[static_cast<size_t>(k)])] = k;
    auto moved = [&](const std::vector<Eigen::Triplet<double>>& in) {
      std::vector<Eigen::Triplet<double>> out;
      for (const auto& t : in)
        out.emplace_back(where[static_cast<size_t>(t.row())], where[static_cast<size_t>(t.col())], t.value());
      Eigen::SparseMatrix<double, Eigen::RowMajor> m(n, n);
      m.setFromTriplets(out.begin(), out.end());
      return m;
    };
    ViewFactorEstimate e;
    e.view_factors = moved(f_entries);
    e.standard_error = moved(s_entries);
    e.space.resize(n);
    e.space_error.resize(n);
    e.blocked = e.blocked_error = Eigen::VectorXd::Zero(n);
    Eigen::VectorXd a(n), r(n);
    for (int k = 0; k < n; ++k) {
      const int i = order[static_cast<size_t>(k)];
      e.space[k] = space[i];
      e.space_error[k] = space_error[i];
      a[k] = area[i];
      r[k] = rays[i];
    }
    return std::make_tuple(e, a, r);
  };
  std::vector<int> forward(n), backward(n);
  for (int k = 0; k < n; ++k) forward[static_cast<size_t>(k)] = k, backward[static_cast<size_t>(k)] = n - 1 - k;
  const auto [ef, af, rf] = estimateIn(forward);
  const auto [eb, ab, rb] = estimateIn(backward);
  const ReciprocityCorrection cf = enforceReciprocity(af, ef, rf), cb = enforceReciprocity(ab, eb, rb);
  const Eigen::MatrixXd f = Eigen::MatrixXd(cf.view_factors), b = Eigen::MatrixXd(cb.view_factors);
  double worst = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) worst = std::max(worst, std::abs(f(i, j) - b(n - 1 - i, n - 1 - j)));
  CHECK(worst < 1e-12);  // two orders of summation in the solve: rounding only
  // And it is a correction: reciprocal, closed, every one-sided pair given a value.
  const Eigen::MatrixXd g = af.asDiagonal() * f;
  CHECK((g - g.transpose()).cwiseAbs().maxCoeff() < 1e-12);
  CHECK((f.rowwise().sum() + cf.space - Eigen::VectorXd::Ones(n)).cwiseAbs().maxCoeff() < 1e-9);
  // An estimate whose σ was left empty: every entry weighs one ray's worth, still a correction.
  ViewFactorEstimate bare = ef;
  bare.standard_error = Eigen::SparseMatrix<double, Eigen::RowMajor>();
  const ReciprocityCorrection cbare = enforceReciprocity(af, bare, rf);
  const Eigen::MatrixXd fb = Eigen::MatrixXd(cbare.view_factors);
  CHECK((fb.rowwise().sum() + cbare.space - Eigen::VectorXd::Ones(n)).cwiseAbs().maxCoeff() < 1e-9);
}

TEST_CASE("The correction laid over F in place equals the one beside it, and refuses a one-sided pattern",
          "[reciprocity]") {
  // An enclosure estimate on a symmetric pattern (as the exact method makes): rows summing
  // over 1 by a few per cent, and entries of 1e-4 with σ = 0.05 that the correction drives
  // below zero (pinned). n = 60 solves the multipliers by LDLᵀ, n = 520 (269,880 couplings)
  // by conjugate gradients. Both functions combine each pair with the same arithmetic in the
  // same order: their F agree to rounding (1e-14 of the largest entry allows for the
  // compiler contracting differently inlined products). Without the faint entries nothing is
  // pinned and the in-place correction skips its pass over the pairs (every pair's ĝ / v
  // bounds its corrected value above zero): the same F, every entry kept.
  for (const int n : {60, 520})
  for (const bool with_faint : {true, false}) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Eigen::VectorXd area(n), rays = Eigen::VectorXd::Constant(n, 1e6);
    for (int i = 0; i < n; ++i) area[i] = 0.5 + u(rng);
    std::vector<Eigen::Triplet<double>> f_entries, s_entries;
    for (int i = 0; i < n; ++i)
      for (int j = i; j < n; ++j) {
        if (n == 60 && u(rng) < 0.3) continue;  // a sparser pattern, still symmetric
        const bool faint = u(rng) < 0.02 && with_faint;
        const double g = faint ? 1e-4 : (1.03 + 0.04 * u(rng)) * area[i] * area[j] / area.sum();
        const double s = faint ? 0.05 : 1e-3 * g;
        f_entries.emplace_back(i, j, g / area[i] * (1 + 1e-3 * (u(rng) - 0.5)));
        s_entries.emplace_back(i, j, s / area[i]);
        if (j != i) {
          f_entries.emplace_back(j, i, g / area[j] * (1 + 1e-3 * (u(rng) - 0.5)));
          s_entries.emplace_back(j, i, s / area[j]);
        }
      }
    ViewFactorEstimate e;
    e.view_factors.resize(n, n);
    e.view_factors.setFromTriplets(f_entries.begin(), f_entries.end());
    e.standard_error.resize(n, n);
    e.standard_error.setFromTriplets(s_entries.begin(), s_entries.end());
    e.space = e.space_error = e.blocked = e.blocked_error = Eigen::VectorXd::Zero(n);
    const ViewFactorEstimate kept = e;
    const ReciprocityCorrection beside = enforceReciprocity(area, e, rays);
    int calls = 0;
    long long said = -1;
    std::optional<ReciprocityCorrection> over = enforceReciprocityInPlace(area, e, rays, [&](long long nnz) {
      ++calls;
      said = nnz;
      CHECK(e.view_factors.isApprox(kept.view_factors, 0.0));  // still the estimate when written out
    });
    INFO("n = " << n << (with_faint ? ", faint entries pinned" : ", nothing to pin"));
    REQUIRE(over);
    CHECK(calls == 1);
    CHECK(said == over->view_factors.nonZeros());
    CHECK(e.view_factors.nonZeros() == 0);
    CHECK((e.standard_error - kept.standard_error).norm() == 0.0);
    CHECK(over->view_factors.nonZeros() == beside.view_factors.nonZeros());
    if (with_faint)
      CHECK(over->view_factors.nonZeros() < kept.view_factors.nonZeros());  // some pairs pinned at zero
    else
      CHECK(over->view_factors.nonZeros() == kept.view_factors.nonZeros());
    const Eigen::MatrixXd fo = Eigen::MatrixXd(over->view_factors), fb = Eigen::MatrixXd(beside.view_factors);
    CHECK((fo - fb).cwiseAbs().maxCoeff() < 1e-14 * fb.maxCoeff());
    CHECK(over->worst_from == beside.worst_from);
    CHECK(over->worst_to == beside.worst_to);
    CHECK(over->max_change == Approx(beside.max_change).epsilon(1e-12));
    CHECK(over->max_change_sigma == Approx(beside.max_change_sigma).epsilon(1e-12));
    CHECK(over->max_closure_error == Approx(beside.max_closure_error).margin(1e-15));
    CAPTURE(over->max_closure_error);
    // Independent of either: reciprocal and closed (the multipliers solve the constraints;
    // K's variances span 4e-12 to 2.5e-3 m⁴, a condition near 1e9: 1e-9 of closure allowed,
    // as for the other corrections here).
    const Eigen::MatrixXd g = area.asDiagonal() * fo;
    CHECK((g - g.transpose()).cwiseAbs().maxCoeff() < 1e-14 * g.maxCoeff());
    const double closure = (fo.rowwise().sum() - Eigen::VectorXd::Ones(n)).cwiseAbs().maxCoeff();
    INFO("closure " << std::scientific << closure << " max_closure_error " << over->max_closure_error << " beside " << beside.max_closure_error);
    CHECK(closure < 1e-9);
    // σ on F's pattern (the exact method's, ExactOptions::errors_on_pattern): the same F to
    // the last bit, σ readable as a matrix until the overwrite, then released with the raw
    // pattern.
    // σ on F's pattern is held in float: the same correction as σ in double holding the
    // same (float) numbers, bit for bit.
    ViewFactorEstimate rounded = kept;
    for (Eigen::Index k = 0; k < rounded.standard_error.nonZeros(); ++k)
      rounded.standard_error.valuePtr()[k] = static_cast<float>(rounded.standard_error.valuePtr()[k]);
    ViewFactorEstimate on = rounded;
    on.error_on_pattern =
        Eigen::Map<const Eigen::VectorXd>(rounded.standard_error.valuePtr(), rounded.standard_error.nonZeros())
            .cast<float>();
    on.errors_on_pattern = true;
    on.standard_error = Eigen::SparseMatrix<double, Eigen::RowMajor>();
    REQUIRE(Eigen::MatrixXd(errorsOnPattern(on).cast<double>()) == Eigen::MatrixXd(rounded.standard_error));
    const std::optional<ReciprocityCorrection> in_double = enforceReciprocityInPlace(area, rounded, rays);
    REQUIRE(in_double);
    bool seen = false;
    std::optional<ReciprocityCorrection> on_pattern = enforceReciprocityInPlace(area, on, rays, [&](long long) {
      seen = Eigen::MatrixXd(errorsOnPattern(on).cast<double>()) ==
             Eigen::MatrixXd(kept.standard_error.cast<float>().cast<double>());
    });
    REQUIRE(on_pattern);
    CHECK(seen);
    CHECK(Eigen::MatrixXd(on_pattern->view_factors) == Eigen::MatrixXd(in_double->view_factors));
    CHECK(on_pattern->max_change_sigma == in_double->max_change_sigma);
    // Against the correction with σ in double: σ's rounding (6e-8 of each weight) moves an
    // entry by that share of its move, far below 1e-6 of the largest move.
    CHECK((Eigen::MatrixXd(on_pattern->view_factors) - fo).cwiseAbs().maxCoeff() < 1e-6 * over->max_change);
    CHECK_FALSE(on.errors_on_pattern);
    CHECK(on.error_on_pattern.size() == 0);
  }
  // One F_ij without its F_ji: refused, the estimate untouched, nothing written out.
  const int n = 4;
  ViewFactorEstimate e;
  e.view_factors.resize(n, n);
  e.view_factors.insert(0, 1) = 0.5;
  e.view_factors.insert(1, 0) = 0.5;
  e.view_factors.insert(2, 3) = 0.4;
  e.view_factors.makeCompressed();
  e.standard_error = e.view_factors * 0.01;
  e.space = e.space_error = e.blocked = e.blocked_error = Eigen::VectorXd::Zero(n);
  bool called = false;
  CHECK_FALSE(enforceReciprocityInPlace(Eigen::VectorXd::Ones(n), e, Eigen::VectorXd::Constant(n, 1e6),
                                        [&](long long) { called = true; }));
  CHECK_FALSE(called);
  CHECK(e.view_factors.nonZeros() == 3);
  // A lower entry without its upper partner (F_30 given, F_03 not): refused too, whichever
  // block of rows each falls in.
  e.view_factors.setZero();
  e.view_factors.insert(0, 1) = 0.5;
  e.view_factors.insert(1, 0) = 0.5;
  e.view_factors.insert(3, 0) = 0.4;
  e.view_factors.makeCompressed();
  e.standard_error = e.view_factors * 0.01;
  CHECK_FALSE(enforceReciprocityInPlace(Eigen::VectorXd::Ones(n), e, Eigen::VectorXd::Constant(n, 1e6),
                                        [&](long long) { called = true; }));
  CHECK_FALSE(called);
}

TEST_CASE("σ as stored: its own matrix, compressed or not, or floats on F's pattern", "[reciprocity]") {
  ViewFactorEstimate e;
  e.view_factors.resize(3, 3);
  e.standard_error.resize(3, 3);
  e.standard_error.reserve(Eigen::VectorXi::Constant(3, 2));  // uncompressed: room left in each row
  e.standard_error.insert(0, 2) = 0.25;
  e.standard_error.insert(2, 0) = 0.5;
  e.standard_error.insert(1, 1) = 0.125;
  REQUIRE_FALSE(e.standard_error.isCompressed());
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(3, 3);
  expected(0, 2) = 0.25, expected(2, 0) = 0.5, expected(1, 1) = 0.125;
  const Eigen::Vector3d largest(0.25, 0.125, 0.5);
  CHECK(rowLargestErrors(e) == largest);
  // The same numbers (exact in float) on F's pattern, F's values elsewhere.
  e.view_factors = expected.sparseView() * 2.0;
  e.view_factors.makeCompressed();
  e.error_on_pattern =
      (Eigen::Map<const Eigen::VectorXd>(e.view_factors.valuePtr(), e.view_factors.nonZeros()) / 2.0).cast<float>();
  e.errors_on_pattern = true;
  e.standard_error = Eigen::SparseMatrix<double, Eigen::RowMajor>();
  CHECK(Eigen::MatrixXd(errorsOnPattern(e).cast<double>()) == expected);
  CHECK(rowLargestErrors(e) == largest);
  expandErrors(e);
  CHECK_FALSE(e.errors_on_pattern);
  CHECK(e.error_on_pattern.size() == 0);
  CHECK(Eigen::MatrixXd(e.standard_error) == expected);
}
