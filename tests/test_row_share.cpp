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

// ---- The network, its eigenpairs, GR and the band solves on shared rows ----------------

#include "solver/radiative/exchange.hpp"
#include "solver/radiative/policy.hpp"
#include "solver/radiative/uncertainty.hpp"

namespace {

// A reciprocal sparse network of n nodes on a ring: each sees its 8 neighbours on either
// side, A_i F_ij = g_ij symmetric and random, rows summing to 0.5–0.9.
struct RingNetwork {
  Eigen::VectorXd area;
  RowSparse f, sigma;  // F and a σ_F on its pattern
  std::vector<std::string> names;
};

RingNetwork ringNetwork(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  RingNetwork r;
  r.area.resize(n);
  for (int i = 0; i < n; ++i) r.area[i] = 0.5 + u(rng), r.names.push_back("n" + std::to_string(i));
  std::vector<Eigen::Triplet<double>> g;
  for (int i = 0; i < n; ++i)
    for (int d = 1; d <= 8; ++d) {
      const double gij = 0.01 + u(rng);
      g.emplace_back(i, (i + d) % n, gij);
      g.emplace_back((i + d) % n, i, gij);
    }
  RowSparse gm(n, n);
  gm.setFromTriplets(g.begin(), g.end());
  Eigen::VectorXd row = gm * Eigen::VectorXd::Ones(n);
  const double scale = 0.9 * (r.area.cwiseQuotient(row)).minCoeff();  // every row sum ≤ 0.9
  r.f = r.area.cwiseInverse().asDiagonal() * (scale * gm);
  r.sigma = r.f;
  for (Eigen::Index k = 0; k < r.sigma.nonZeros(); ++k) r.sigma.valuePtr()[k] = 1e-3 * (1.0 + u(rng));
  return r;
}

// What a part computes, put together from the parts (rows from their holders).
struct SharedRun {
  Eigen::VectorXd f_space, gr_space, values, probe;
  Eigen::MatrixXd vectors, exitance, gr_times, var_f;
  RowSparse g_rows, direct;  // every part's held rows, put together
  double bound = 0.0, change = 0.0, g_entry = 0.0, gr_entry = 0.0;
  int worst_from = -1, worst_to = -1;
};

void addRows(RowSparse& into, const RowSparse& held) { into += held; }

SharedRun runShared(const RingNetwork& r, int parts) {
  const Eigen::Index n = r.area.size();
  const Eigen::VectorXd eps = Eigen::VectorXd::LinSpaced(n, 0.3, 0.9), rho = Eigen::VectorXd::Ones(n) - eps;
  solver::SolverSettings settings;
  settings.tolerance = 1e-6;
  settings.rank = 24;  // one Lanczos run: the test's time is six decompositions (1 + 2 + 3 parts)
  SharedRun out;
  out.g_rows.resize(n, n);
  out.direct.resize(n, n);
  std::mutex gather;
  testing::ThreadedParts(parts).run([&](const solver::RowShare& share) {
    const RowSparse f = heldRows(r.f, share), ft = heldRows(RowSparse(r.f.transpose()), share);
    const solver::Network net(r.names, r.area, f, ft, Eigen::VectorXd(), solver::policy::kCorrectedNetworkTolerances,
                              share);
    const solver::EigenPairs pairs = solver::policy::decomposeForBands(net, rho, settings, {eps});
    const solver::ExchangeFactors ex = solver::policy::exchangeFactors(net, pairs, eps, settings);
    const solver::LowRankBandSolver band(net, pairs, rho);
    const Eigen::MatrixXd m0 = Eigen::MatrixXd::Constant(n, 2, 100.0);
    const solver::BandSolution sol = band.solve(m0, 1e-9);
    const Eigen::MatrixXd gr_times = ex.apply(Eigen::MatrixXd::Ones(n, 1));
    const solver::AbsorbedVariance var = solver::absorbedVariance(net, band, heldRows(r.sigma, share), sol.exitance,
                                                                  Eigen::MatrixXd::Constant(n, 2, 1.0));
    const double bound = net.spectralBound(), g_entry = net.conductance(5, 7), gr_entry = ex.entry(5, 7);
    const Eigen::Map<const RowSparse> g_held(n, n, net.sparseConductance().nonZeros(),
                                             net.sparseConductance().outerIndexPtr(),
                                             net.sparseConductance().innerIndexPtr(),
                                             net.sparseConductance().valuePtr());
    std::lock_guard<std::mutex> lock(gather);
    addRows(out.g_rows, RowSparse(g_held));
    addRows(out.direct, ex.direct);
    if (share.part != 0) return;
    out.f_space = net.spaceViewFactor();
    out.gr_space = ex.gr_space;
    out.values = pairs.values;
    out.vectors = pairs.vectors;
    out.exitance = sol.exitance;
    out.gr_times = gr_times;
    out.var_f = var.view_factors;
    out.bound = bound, out.g_entry = g_entry, out.gr_entry = gr_entry;
    out.change = net.reciprocity().max_view_factor_change;
    out.worst_from = net.reciprocity().worst_from, out.worst_to = net.reciprocity().worst_to;
  });
  return out;
}

bool same(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() && (a.array() == b.array()).all();
}
bool same(const RowSparse& a, const RowSparse& b) { return same(Eigen::MatrixXd(a), Eigen::MatrixXd(b)); }

}  // namespace

TEST_CASE("network, eigenpairs, GR and band solves on shared rows: the one-process numbers bit for bit") {
  // 9,000 nodes: above every dense threshold of the policy (8,000), as shared rows are.
  const RingNetwork r = ringNetwork(9000, 3);
  const SharedRun one = runShared(r, 1), two = runShared(r, 2), three = runShared(r, 3);
  REQUIRE(one.values.size() > 10);
  for (const SharedRun* s : {&two, &three}) {
    CHECK(same(s->g_rows, one.g_rows));
    CHECK(same(s->direct, one.direct));
    CHECK(same(s->f_space, one.f_space));
    CHECK(same(s->values, one.values));
    CHECK(same(s->vectors, one.vectors));
    CHECK(same(s->gr_space, one.gr_space));
    CHECK(same(s->exitance, one.exitance));
    CHECK(same(s->gr_times, one.gr_times));
    CHECK(same(s->var_f, one.var_f));
    CHECK(s->bound == one.bound);
    CHECK(s->g_entry == one.g_entry);
    CHECK(s->gr_entry == one.gr_entry);
    CHECK(s->change == one.change);
    CHECK(s->worst_from == one.worst_from);
    CHECK(s->worst_to == one.worst_to);
  }
  // One part against the one-process network of the whole F (column-major, as the pipeline
  // builds it): the same G, F_space and eigenpairs.
  const solver::Network whole(r.names, r.area, Eigen::SparseMatrix<double>(r.f), Eigen::VectorXd(),
                              solver::policy::kCorrectedNetworkTolerances);
  const Eigen::SparseMatrix<double>& g = whole.sparseConductance();
  CHECK(same(RowSparse(Eigen::Map<const RowSparse>(g.rows(), g.cols(), g.nonZeros(), g.outerIndexPtr(),
                                                   g.innerIndexPtr(), g.valuePtr())),
             one.g_rows));
  CHECK(same(whole.spaceViewFactor(), one.f_space));
  CHECK(whole.spectralBound() == one.bound);
  CHECK(whole.conductance(5, 7) == one.g_entry);
  CHECK(one.g_entry > 0.0);
}
