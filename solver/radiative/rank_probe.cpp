#include "solver/radiative/rank_probe.hpp"

#include "solver/radiative/policy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <utility>

namespace radnet::solver {
namespace {

// The refined reference for GR x: a tenth of the tightest solver tolerance the error budget
// sets (1e-10, for exact view factors), so the reference's own error never decides a rank.
constexpr double kReferenceTolerance = 1e-11;

double inf() { return std::numeric_limits<double>::infinity(); }

}  // namespace

RankProbe::RankProbe(const Network& net, RankTargets targets, unsigned seed) : net_(net), targets_(std::move(targets)) {
  const int n = net.size();
  if (targets_.reflectance.size() != n) throw std::invalid_argument("rank probe: one reflectance per node");
  // A uniform field (the mode of an isothermal spacecraft) and random ones, which excite
  // every eigenvector: on the 1,602-node satellite their residual is 1–2× that of the
  // orbit's real solar right-hand sides at every rank from 8 to 400.
  probes_.resize(n, kProbes);
  probes_.col(0).setOnes();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int c = 1; c < kProbes; ++c)
    for (int i = 0; i < n; ++i) probes_(i, c) = u(rng);
  if (targets_.emissivities.empty()) targets_.emissivities.push_back(Eigen::VectorXd::Ones(n) - targets_.reflectance);
  for (const Eigen::VectorXd& eps : targets_.emissivities)
    if (eps.size() != n) throw std::invalid_argument("rank probe: one emissivity per node");
}

bool RankProbe::exchangeReferences(const EigenPairs& found) {
  if (reference_failed_) return false;
  if (!reference_gr_x_.empty()) return true;
  for (const Eigen::VectorXd& eps : targets_.emissivities) {
    const LowRankBandSolver band(net_, found, Eigen::VectorXd::Ones(net_.size()) - eps);
    // GR x = E G M with M = E x + S G M: one refined band solve per probe.
    const BandSolution sol = band.solve(eps.asDiagonal() * probes_, kReferenceTolerance);
    if (band.status() != Status::Converged || sol.status != Status::Converged) {
      reference_failed_ = true;
      return false;
    }
    reference_gr_x_.push_back(eps.asDiagonal() * net_.applyConductance(sol.exitance));
  }
  return true;
}

// max over probes and nodes of |(GR_k x − GR x)_i| / (ε_i A_i max x), GR_k formed as
// exchangeFactorsLowRank forms it: E (G + V (C − Λ) Vᵀ) E.
double RankProbe::exchangeError(const LowRankBandSolver& band, const Eigen::VectorXd& eps,
                                const Eigen::MatrixXd& reference) const {
  const Eigen::MatrixXd ex = eps.asDiagonal() * probes_;
  const Eigen::MatrixXd vt_ex = band.vectors().transpose() * ex;
  const Eigen::MatrixXd reflected = band.applyCore(ex) - band.vectors() * (band.values().asDiagonal() * vt_ex);
  const Eigen::MatrixXd gr_x = eps.asDiagonal() * (net_.applyConductance(ex) + reflected);
  double worst = 0.0;
  for (int c = 0; c < kProbes; ++c) {
    const double x_max = probes_.col(c).maxCoeff();
    for (int i = 0; i < net_.size(); ++i) {
      const double scale = eps[i] * net_.area()[i] * x_max;
      if (scale > 0) worst = std::max(worst, std::abs(gr_x(i, c) - reference(i, c)) / scale);
    }
  }
  return worst;
}

RankMeasure RankProbe::measure(const EigenPairs& found, int k) {
  RankMeasure m;
  m.rank = std::clamp(k, 0, found.rank());
  const EigenPairs pairs = truncate(found, m.rank);
  const LowRankBandSolver band(net_, pairs, targets_.reflectance);
  if (band.status() != Status::Converged) {
    m.band_residual = m.exchange_error = inf();
    return m;
  }
  const BandSolution sol = band.solve(probes_);
  m.band_residual = sol.status == Status::Converged ? sol.max_residual : inf();
  if (targets_.exchange_error <= 0) return m;
  if (!exchangeReferences(found)) {
    m.exchange_error = inf();
    return m;
  }
  for (std::size_t set = 0; set < targets_.emissivities.size(); ++set) {
    const Eigen::VectorXd& eps = targets_.emissivities[set];
    const LowRankBandSolver ir(net_, pairs, Eigen::VectorXd::Ones(net_.size()) - eps);
    if (ir.status() != Status::Converged) {
      m.exchange_error = inf();
      return m;
    }
    m.exchange_error = std::max(m.exchange_error, exchangeError(ir, eps, reference_gr_x_[set]));
  }
  return m;
}

int RankProbe::nextRank(int nev) const {
  if (history_.size() < 2) return 2 * nev;
  return nextRank(nev, history_.back(), history_.size() - 2);
}

// `now` measured at nev pairs, history_[before_at] the run before it.
int RankProbe::nextRank(int nev, const RankMeasure& now, size_t before_at) const {
  double needed = nev;
  if (before_at < history_.size() && now.rank == nev) {
    const RankMeasure& before = history_[before_at];
    // error ∝ k^slope between the last two ranks; the rank where it meets its target.
    const auto extrapolate = [&](double e_now, double e_before, double target) {
      if (!(e_now > target) || !(e_before > e_now) || !std::isfinite(e_before)) return;
      const double slope = std::log(e_now / e_before) / std::log(double(now.rank) / before.rank);
      needed = std::max(needed, nev * std::pow(target / e_now, 1.0 / slope));
    };
    extrapolate(now.band_residual, before.band_residual, targets_.band_residual);
    if (targets_.exchange_error > 0) extrapolate(now.exchange_error, before.exchange_error, targets_.exchange_error);
  }
  const double next = std::min(1.2 * needed, 1e9);
  return std::max(2 * nev, static_cast<int>(std::ceil(next)));
}

bool RankProbe::meets(const RankMeasure& m) const {
  return m.band_residual <= targets_.band_residual &&
         (targets_.exchange_error <= 0 || m.exchange_error <= targets_.exchange_error);
}

int RankProbe::operator()(const EigenPairs& found) {
  const int nev = found.rank();
  if (nev == 0) return 0;
  const RankMeasure all = measure(found, nev);
  if (!meets(all)) {
    // The band solves are refined to the budget whatever the rank, and GR may fall back to
    // the exact dense form (Cholesky or LU): when what misses its target falls more slowly than 1/k from the last run
    // (twice the pairs not halving it: a flat spectrum, as in a closed room), more pairs cost
    // more Lanczos time than they save. GR from the pairs with no fallback is never given up
    // this way. The ranks' ratio matters since the runs do not always double (nextRank).
    const RankMeasure before = history_.empty() ? RankMeasure{} : history_.back();
    const double expected_fall = before.rank > 0 ? double(before.rank) / nev : 0.5;
    const auto stalled = [&](double now, double then, double target) {
      return now <= target || (then > 0 && std::isfinite(now) && now > expected_fall * then);
    };
    const bool exchange_ok = targets_.exchange_error <= 0 || all.exchange_error <= targets_.exchange_error;
    const bool band_ok = all.band_residual <= targets_.band_residual;
    const bool band_done = band_ok || (targets_.band_refined &&
                                       stalled(all.band_residual, before.band_residual, targets_.band_residual));
    const bool flat = !history_.empty() && band_done &&
                      (exchange_ok || (targets_.exchange_fallback &&
                                       stalled(all.exchange_error, before.exchange_error, targets_.exchange_error)));
    // Only GR wants more pairs and the exact dense GR can take over: the pairs the GR error's
    // decay asks for cost more Lanczos time on a dense G than the exact GR (n³ flops) does.
    // The exact GR: n³ flops by Cholesky, about 4.7 n³ by the LU when a node is (nearly) black.
    double exact_flops = std::pow(double(net_.size()), 3);
    for (const Eigen::VectorXd& eps : targets_.emissivities)
      if (eps.size() && eps.maxCoeff() > 1.0 - kSymmetricExchangeMinReflectance) exact_flops *= 4.7;
    const bool costly = !flat && !history_.empty() && band_done && targets_.exchange_fallback && !net_.isSparse() &&
                        double(nextRank(nev, all, history_.size() - 1) - nev) * double(net_.size()) * net_.size() *
                                policy::kDenseLanczosSecondsPerPairEntry >
                            std::min(exact_flops, 4.7 * std::pow(double(net_.size()), 3)) / policy::kDenseFlopsPerSecond;
    history_.push_back(all);
    if (costly) {
      rule_ = "a posteriori: more pairs would cost more than the exact GR";
      if (!band_ok) rule_ += ", refinement finishes the band solves";
      rule_ += ", GR exact (dense)";
      return nev;
    }
    if (!flat) return 0;
    rule_ = "a posteriori: spectrum flat (what misses its target fell more slowly than 1/k)";
    if (!band_ok) rule_ += ", refinement finishes the band solves";
    if (!exchange_ok) rule_ += ", GR exact (dense)";
    return nev;
  }
  // The smallest rank that still meets the targets, halving from the pairs found.
  int k = nev;
  while (k / 2 >= kMinRank && meets(measure(found, k / 2))) k /= 2;
  rule_ = "a posteriori: probes meet the targets";
  return k;
}

}  // namespace radnet::solver
