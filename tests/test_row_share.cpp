// The network's rows shared out over processes (solver::RowShare, docs/mpi.md), played by
// threads: every part holds only its rows, and the results must equal each other for 1, 2
// and 3 parts bit for bit, and the one-process methods to their solvers' tolerances.
#include "geometry/reciprocity.hpp"
#include "threaded_parts.hpp"

#include <catch2/catch.hpp>

#include <mutex>
#include <random>

using namespace radnet;
using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;

namespace {

// A noisy, non-reciprocal estimate of n nodes of unequal areas: each row sees a random
// third of the others, some pairs from one side only, tiny entries with large σ (pinned
// to zero by the correction where a row is over-full), space and blocked shares with
// their errors.
struct NoisyEstimate {
  Eigen::VectorXd area, rays;
  geometry::ViewFactorEstimate estimate;
};

NoisyEstimate noisyEstimate(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  NoisyEstimate e;
  e.area.resize(n);
  e.rays.resize(n);
  for (int i = 0; i < n; ++i) e.area[i] = 0.2 + 2.0 * u(rng), e.rays[i] = 500 + std::floor(4000 * u(rng));
  std::vector<Eigen::Triplet<double>> f, s;
  e.estimate.space.resize(n);
  e.estimate.space_error.resize(n);
  e.estimate.blocked = Eigen::VectorXd::Zero(n);
  e.estimate.blocked_error = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < n; ++i) {
    std::vector<double> row(static_cast<size_t>(n), 0.0);
    double sum = 0.0;
    for (int j = 0; j < n; ++j)
      if (u(rng) < 0.33) sum += row[size_t(j)] = u(rng) < 0.1 ? 1e-5 * u(rng) : u(rng);
    const double keep = 0.3 + 0.6 * u(rng);  // what the row's entries add up to
    for (int j = 0; j < n; ++j)
      if (row[size_t(j)] > 0) {
        const double v = row[size_t(j)] * keep / sum;
        f.emplace_back(i, j, v);
        s.emplace_back(i, j, v < 1e-4 ? 5e-3 : std::sqrt(v * (1 - v) / e.rays[i]));
      }
    e.estimate.space[i] = (1.0 - keep) * 0.8 + (i % 3 == 0 ? 0.08 : 0.0);  // a third of the rows over-full
    e.estimate.space_error[i] = 0.01;
    if (i % 4 == 0) e.estimate.blocked[i] = (1.0 - keep) * 0.2, e.estimate.blocked_error[i] = 0.005;
  }
  e.estimate.view_factors.resize(n, n);
  e.estimate.view_factors.setFromTriplets(f.begin(), f.end());
  e.estimate.standard_error.resize(n, n);
  e.estimate.standard_error.setFromTriplets(s.begin(), s.end());
  return e;
}

// The rows of m that `share` holds (the others empty).
RowSparse heldRows(const RowSparse& m, const solver::RowShare& share) {
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index i = 0; i < m.outerSize(); ++i)
    if (share.holds(i))
      for (RowSparse::InnerIterator it(m, i); it; ++it) t.emplace_back(int(i), int(it.col()), it.value());
  RowSparse out(m.rows(), m.cols());
  out.setFromTriplets(t.begin(), t.end());
  return out;
}

struct SharedCorrection {
  Eigen::MatrixXd f, ft;  // every part's rows, put together
  geometry::ReciprocityCorrection part0;
};

SharedCorrection correctOnParts(const NoisyEstimate& e, int parts) {
  const Eigen::Index n = e.area.size();
  SharedCorrection out{Eigen::MatrixXd::Zero(n, n), Eigen::MatrixXd::Zero(n, n), {}};
  std::mutex gather;
  testing::ThreadedParts(parts).run([&](const solver::RowShare& share) {
    geometry::ViewFactorEstimate mine = e.estimate;
    mine.view_factors = heldRows(e.estimate.view_factors, share);
    mine.standard_error = heldRows(e.estimate.standard_error, share);
    geometry::ReciprocityCorrection c = geometry::enforceReciprocityOnRows(e.area, mine, e.rays, share);
    std::lock_guard<std::mutex> lock(gather);
    for (Eigen::Index i = 0; i < n; ++i) {
      for (RowSparse::InnerIterator it(c.view_factors, i); it; ++it) {
        REQUIRE(share.holds(i));
        out.f(i, it.col()) = it.value();
      }
      for (RowSparse::InnerIterator it(c.transposed, i); it; ++it) out.ft(i, it.col()) = it.value();
    }
    if (share.part == 0) out.part0 = c;
  });
  return out;
}

}  // namespace

TEST_CASE("correction on shared rows: 1, 2 and 3 parts bit for bit, the one-process correction to 1e-12") {
  const NoisyEstimate e = noisyEstimate(90, 7);
  const geometry::ReciprocityCorrection whole = geometry::enforceReciprocity(e.area, e.estimate, e.rays);
  const Eigen::MatrixXd f_whole = Eigen::MatrixXd(whole.view_factors);
  REQUIRE(whole.max_change > 0.0);
  const SharedCorrection one = correctOnParts(e, 1), two = correctOnParts(e, 2), three = correctOnParts(e, 3);
  for (const SharedCorrection* c : {&two, &three}) {
    CHECK((c->f.array() == one.f.array()).all());
    CHECK((c->ft.array() == one.ft.array()).all());
    CHECK((c->part0.space.array() == one.part0.space.array()).all());
    CHECK((c->part0.blocked.array() == one.part0.blocked.array()).all());
    CHECK(c->part0.max_change == one.part0.max_change);
    CHECK(c->part0.max_change_sigma == one.part0.max_change_sigma);
    CHECK(c->part0.worst_from == one.part0.worst_from);
    CHECK(c->part0.worst_to == one.part0.worst_to);
    CHECK(c->part0.max_closure_error == one.part0.max_closure_error);
  }
  // Fᵀ's rows are F's columns; the areas make A F symmetric.
  CHECK((one.ft.array() == one.f.transpose().array()).all());
  const Eigen::MatrixXd g = e.area.asDiagonal() * one.f;
  CHECK((g - g.transpose()).cwiseAbs().maxCoeff() < 1e-15 * g.cwiseAbs().maxCoeff() * 4);
  // Against the one-process correction (a direct or a preconditioned CG solve of the
  // multipliers, tolerance 1e-13 of the residual): entries, pinned zeros and report agree.
  CHECK((one.f - f_whole).cwiseAbs().maxCoeff() < 1e-12);
  CHECK(((one.f.array() > 0) == (f_whole.array() > 0)).all());
  CHECK((one.part0.space - whole.space).cwiseAbs().maxCoeff() < 1e-12);
  CHECK((one.part0.blocked - whole.blocked).cwiseAbs().maxCoeff() < 1e-12);
  CHECK(one.part0.max_change == Approx(whole.max_change).epsilon(1e-9));
  CHECK(one.part0.max_change_sigma == Approx(whole.max_change_sigma).epsilon(1e-9));
  CHECK(one.part0.worst_from == whole.worst_from);
  CHECK(one.part0.worst_to == whole.worst_to);
  CHECK(one.part0.max_closure_error < 1e-12);
  // Some entries were pinned: the case exercises the correction's second passes.
  const Eigen::MatrixXd raw = Eigen::MatrixXd(e.estimate.view_factors);
  CHECK(((raw.array() > 0) && (one.f.array() == 0)).count() > 0);
}
