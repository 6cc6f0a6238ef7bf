// The reciprocity and closure correction of reciprocity.cpp with F's rows shared out over
// processes (docs/mpi.md): a process holds its rows of F and σ, learns its rows' partner
// entries A_j F_ji from their holders, and keeps every unordered pair twice, once in each
// of its two rows, combined the same way by both holders (the lower index's estimate
// first), so the two copies stay equal bit for bit through the multipliers and the pinning.
#include "geometry/reciprocity.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

namespace radnet::geometry {
namespace {

using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;

double floorVariance(const Eigen::VectorXd& area, const Eigen::VectorXd& rays, Eigen::Index i) {
  return std::pow(area[i] / std::max(1.0, rays[i]), 2);
}

// One estimate's variance, (A_i σ_ij)², floored at one ray's worth (as enforceReciprocity).
double entryVariance(const Eigen::VectorXd& area, const Eigen::VectorXd& rays, Eigen::Index row, double error) {
  return std::max(std::pow(area[row] * error, 2), floorVariance(area, rays, row));
}

// Each held row's pairs, every partner j (itself too) in increasing order: the combined
// estimate ĝ_ij of the conductance and its variance. A pair pinned at zero keeps ĝ = v = 0:
// it then adds nothing to K or to the right-hand side, and its corrected value is 0 (20 B a
// pair, not 29 with a flag and the value stored: this array is the shared correction's peak).
struct RowPairs {
  std::vector<std::int64_t> start;  // n + 1; rows not held are empty
  std::vector<int> partner;
  std::vector<double> g_hat, var;
};

// The corrected conductance of pair s of row i: ĝ + v (μ_lo + μ_hi), the multipliers added in
// the pair's own order so that both holders get the same bits.
double corrected(const RowPairs& rp, size_t s, Eigen::Index i, const Eigen::VectorXd& mu) {
  const Eigen::Index j = rp.partner[s];
  return rp.g_hat[s] + rp.var[s] * (i == j ? mu[i] : mu[std::min(i, j)] + mu[std::max(i, j)]);
}

// One directional estimate: x = A_i F_ij and its variance, from row i's holder.
struct Side {
  double x = 0.0, v = 0.0;
  bool present = false;
};

// ĝ and its variance from the two sides of the pair (lo, hi), lo ≤ hi, as combinedPairs in
// reciprocity.cpp combines them (the same operations in the same order).
void combine(const Side& lo, const Side& hi, Eigen::Index lo_node, Eigen::Index hi_node, const Eigen::VectorXd& area,
             const Eigen::VectorXd& rays, double& g_hat, double& var) {
  if (lo.present) {
    double num = lo.x / lo.v, den = 1.0 / lo.v;
    if (lo_node != hi_node) {
      if (hi.present) {
        num += hi.x / hi.v;
        den += 1.0 / hi.v;
      } else {
        den += 1.0 / floorVariance(area, rays, hi_node);
      }
    }
    g_hat = num / den;
    var = 1.0 / den;
    return;
  }
  const double den = 1.0 / hi.v + 1.0 / floorVariance(area, rays, lo_node);
  g_hat = hi.x / hi.v / den;
  var = 1.0 / den;
}

// The partner entries of the held rows, from their rows' holders: (j · n + i, A_i F_ij, its
// variance) triples, `order` sorting them by row (`first`: each row's start) and partner.
struct Partners {
  std::vector<double> received;
  std::vector<std::int64_t> first;
  std::vector<std::uint32_t> order;
  std::int64_t key(size_t q) const { return static_cast<std::int64_t>(received[3 * q]); }
};

Partners partnerEntries(const Eigen::VectorXd& area, const ViewFactorEstimate& est, const Eigen::VectorXd& rays,
                        const solver::RowShare& share) {
  const RowSparse &f = est.view_factors, &sigma = est.standard_error;
  const Eigen::Index n = area.size();
  auto variance = [&](Eigen::Index row, double error) { return entryVariance(area, rays, row, error); };
  std::vector<std::vector<double>> send(static_cast<size_t>(share.parts));
  for (Eigen::Index i = 0; i < n; ++i)
    if (share.holds(i))
      for (Eigen::Index k = f.outerIndexPtr()[i]; k < f.outerIndexPtr()[i + 1]; ++k) {
        const Eigen::Index j = f.innerIndexPtr()[k];
        if (j == i) continue;
        std::vector<double>& to = send[static_cast<size_t>(share.holder(j))];
        to.push_back(double(j) * double(n) + double(i));
        to.push_back(area[i] * f.valuePtr()[k]);
        to.push_back(variance(i, sigma.valuePtr()[k]));
      }
  Partners p;
  p.received = share.whole() ? std::move(send[0]) : share.exchange(send);
  send.clear();
  send.shrink_to_fit();
  // Received triples by row (a counting sort), each row's by partner.
  const size_t count = p.received.size() / 3;
  auto key = [&](size_t q) { return p.key(q); };
  std::vector<std::int64_t>& first = p.first;
  first.assign(static_cast<size_t>(n) + 1, 0);
  for (size_t q = 0; q < count; ++q) ++first[static_cast<size_t>(key(q) / n) + 1];
  for (size_t i = 0; i < static_cast<size_t>(n); ++i) first[i + 1] += first[i];
  if (count >= std::numeric_limits<std::uint32_t>::max())
    throw std::length_error("shared reciprocity correction: more than 2^32 partner entries on one process");
  std::vector<std::uint32_t>& order = p.order;
  order.resize(count);  // 4 B an entry: indices into `received`
  {
    std::vector<std::int64_t> fill(first.begin(), first.end() - 1);
    for (size_t q = 0; q < count; ++q)
      order[static_cast<size_t>(fill[static_cast<size_t>(key(q) / n)]++)] = static_cast<std::uint32_t>(q);
  }
  for (size_t i = 0; i < static_cast<size_t>(n); ++i)
    std::sort(order.begin() + first[i], order.begin() + first[i + 1],
              [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
  return p;
}

// The held rows' pairs: own entries, and the partners' entries received from their holders
// as (j · n + i, A_j F_ji, variance) triples, sorted into each row.
RowPairs rowPairs(const Eigen::VectorXd& area, const ViewFactorEstimate& est, const Eigen::VectorXd& rays,
                  const solver::RowShare& share) {
  const RowSparse &f = est.view_factors, &sigma = est.standard_error;
  const Eigen::Index n = area.size();
  auto variance = [&](Eigen::Index row, double error) { return entryVariance(area, rays, row, error); };
  const Partners p = partnerEntries(area, est, rays, share);
  const std::vector<double>& received = p.received;
  const std::vector<std::int64_t>& first = p.first;
  const std::vector<std::uint32_t>& order = p.order;
  auto key = [&](size_t q) { return p.key(q); };
  // Each held row's own entries and received ones merged by partner: counted, then filled.
  auto mergeRow = [&](Eigen::Index i, const auto& visit) {
    Eigen::Index k = f.outerIndexPtr()[i];
    const Eigen::Index end = f.outerIndexPtr()[i + 1];
    auto r = first[static_cast<size_t>(i)];
    const auto r_end = first[static_cast<size_t>(i) + 1];
    while (k < end || r < r_end) {
      const Eigen::Index own_j = k < end ? f.innerIndexPtr()[k] : n;
      const size_t at = r < r_end ? static_cast<size_t>(order[static_cast<size_t>(r)]) : 0;
      const Eigen::Index recv_j = r < r_end ? static_cast<Eigen::Index>(key(at) % n) : n;
      const Eigen::Index j = std::min(own_j, recv_j);
      Side mine, theirs;
      if (own_j == j) {
        mine = {area[i] * f.valuePtr()[k], variance(i, sigma.valuePtr()[k]), true};
        ++k;
      }
      if (recv_j == j) {
        theirs = {received[3 * at + 1], received[3 * at + 2], true};
        ++r;
      }
      visit(j, mine, theirs);
    }
  };
  RowPairs rp;
  rp.start.assign(static_cast<size_t>(n) + 1, 0);
  for (Eigen::Index i = 0; i < n; ++i) {
    std::int64_t count = 0;
    if (share.holds(i)) mergeRow(i, [&](Eigen::Index, const Side&, const Side&) { ++count; });
    rp.start[static_cast<size_t>(i) + 1] = rp.start[static_cast<size_t>(i)] + count;
  }
  const auto total = static_cast<size_t>(rp.start.back());
  rp.partner.resize(total);
  rp.g_hat.resize(total);
  rp.var.resize(total);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!share.holds(i)) continue;
    auto s = static_cast<size_t>(rp.start[static_cast<size_t>(i)]);
    mergeRow(i, [&](Eigen::Index j, const Side& mine, const Side& theirs) {
      if (i <= j) combine(mine, theirs, i, j, area, rays, rp.g_hat[s], rp.var[s]);
      else combine(theirs, mine, j, i, area, rays, rp.g_hat[s], rp.var[s]);
      rp.partner[s++] = static_cast<int>(j);
    });
  }
  return rp;
}

// K's held rows times x, whole on every process: diagonal then the free pairs, by row.
Eigen::VectorXd timesK(const RowPairs& rp, const Eigen::VectorXd& diag, const Eigen::VectorXd& x,
                       const solver::RowShare& share) {
  const Eigen::Index n = diag.size();
  Eigen::VectorXd y = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!share.holds(i)) continue;
    double sum = diag[i] * x[i];
    for (auto q = rp.start[size_t(i)]; q < rp.start[size_t(i) + 1]; ++q)
      if (rp.partner[size_t(q)] != i) sum += rp.var[size_t(q)] * x[rp.partner[size_t(q)]];
    y[i] = sum;
  }
  share.joinRows(y.data(), static_cast<size_t>(n));
  return y;
}

// The multipliers: K μ = c − Σ ĝ (free pairs) by Jacobi-preconditioned conjugate gradients,
// K = Σ v over each row's terms on the diagonal and v_ij off it (K is diagonally dominant).
Eigen::VectorXd multipliers(const RowPairs& rp, const Eigen::VectorXd& free_rhs, const Eigen::VectorXd& free_variance,
                            const solver::RowShare& share) {
  const Eigen::Index n = free_rhs.size();
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n), diag = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!share.holds(i)) continue;
    double b = free_rhs[i], d = free_variance[i];
    for (auto q = rp.start[size_t(i)]; q < rp.start[size_t(i) + 1]; ++q)
      b -= rp.g_hat[size_t(q)], d += rp.var[size_t(q)];  // a pinned pair adds 0
    rhs[i] = b;
    diag[i] = d > 0 ? d : 1.0;  // isolated rows: μ = 0
  }
  share.joinRows(rhs.data(), static_cast<size_t>(n));
  share.joinRows(diag.data(), static_cast<size_t>(n));
  const Eigen::VectorXd inverse_diag = diag.cwiseInverse();
  Eigen::VectorXd mu = Eigen::VectorXd::Zero(n), r = rhs, z = inverse_diag.cwiseProduct(r), p = z;
  const double rhs_norm2 = rhs.squaredNorm(), tol2 = 1e-26 * rhs_norm2;
  double rz = r.dot(z);
  for (int it = 0; it < 2000 && rhs_norm2 > 0 && r.squaredNorm() > tol2; ++it) {
    const Eigen::VectorXd q = timesK(rp, diag, p, share);
    const double alpha = rz / p.dot(q);
    mu += alpha * p;
    r -= alpha * q;
    z = inverse_diag.cwiseProduct(r);
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  return mu;
}

// Held rows of F (g / A_i) and of Fᵀ (g / A_j), in column order, straight into their arrays
// (counted first: the 50,102-node run's peak was this step's growing copies).
void heldCorrectedRows(const RowPairs& rp, const Eigen::VectorXd& mu, const Eigen::VectorXd& area,
                       ReciprocityCorrection& out) {
  const Eigen::Index n = area.size();
  std::vector<int> outer(static_cast<size_t>(n) + 1, 0);
  for (Eigen::Index i = 0; i < n; ++i) {
    int count = 0;
    for (auto q = rp.start[size_t(i)]; q < rp.start[size_t(i) + 1]; ++q) count += corrected(rp, size_t(q), i, mu) > 0;
    outer[size_t(i) + 1] = outer[size_t(i)] + count;
  }
  for (RowSparse* m : {&out.view_factors, &out.transposed}) {
    const bool transposed = m == &out.transposed;
    m->resize(n, n);
    m->resizeNonZeros(outer[size_t(n)]);
    std::copy(outer.begin(), outer.end(), m->outerIndexPtr());
    for (Eigen::Index i = 0; i < n; ++i) {
      int at = outer[size_t(i)];
      for (auto q = rp.start[size_t(i)]; q < rp.start[size_t(i) + 1]; ++q)
        if (const double g = corrected(rp, size_t(q), i, mu); g > 0) {
          const int j = rp.partner[size_t(q)];
          m->innerIndexPtr()[at] = j;
          m->valuePtr()[at++] = g / area[transposed ? j : i];
        }
    }
  }
}

}  // namespace

ReciprocityCorrection enforceReciprocityOnRows(const Eigen::VectorXd& area, const ViewFactorEstimate& est,
                                               const Eigen::VectorXd& rays, const solver::RowShare& share) {
  const Eigen::Index n = area.size();
  ViewFactorEstimate storage;
  const ViewFactorEstimate& relaid = onOnePattern(est, storage);  // σ on F's compressed pattern, as rowPairs reads it
  RowPairs rp = rowPairs(area, relaid, rays, share);
  Eigen::VectorXd g_space = area.cwiseProduct(est.space), g_blocked = area.cwiseProduct(est.blocked);
  Eigen::VectorXd v_space(n), v_blocked(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double floor_var = floorVariance(area, rays, i);
    v_space[i] = est.space[i] > 0 ? std::max(std::pow(area[i] * est.space_error[i], 2), floor_var) : 0.0;
    v_blocked[i] = est.blocked[i] > 0 ? std::max(std::pow(area[i] * est.blocked_error[i], 2), floor_var) : 0.0;
  }
  Eigen::VectorXd mu = Eigen::VectorXd::Zero(n);
  for (int pass = 0; pass < 20; ++pass) {  // entries driven negative pinned at zero, as in enforceReciprocity
    mu = multipliers(rp, area - g_space - g_blocked, v_space + v_blocked, share);
    bool changed = false;
    for (Eigen::Index i = 0; i < n; ++i)
      for (auto q = rp.start[size_t(i)]; q < rp.start[size_t(i) + 1]; ++q)
        if (corrected(rp, size_t(q), i, mu) < 0) {  // pinned at zero from now on
          rp.g_hat[size_t(q)] = rp.var[size_t(q)] = 0.0;
          changed = true;
        }
    for (Eigen::Index i = 0; i < n; ++i)  // whole vectors: every process alike
      for (auto [g_term, v_term] : {std::pair{&g_space, &v_space}, std::pair{&g_blocked, &v_blocked}})
        if ((*v_term)[i] > 0 && (*g_term)[i] + (*v_term)[i] * mu[i] < 0) {
          (*g_term)[i] = (*v_term)[i] = 0.0;
          changed = true;
        }
    if (!share.any(changed)) break;
  }
  ReciprocityCorrection out;
  out.space = (g_space + v_space.cwiseProduct(mu)).cwiseMax(0.0).cwiseQuotient(area);
  out.blocked = (g_blocked + v_blocked.cwiseProduct(mu)).cwiseMax(0.0).cwiseQuotient(area);
  heldCorrectedRows(rp, mu, area, out);
  rp = RowPairs();
  reportCorrection(relaid, rays, out, share);
  return out;
}

}  // namespace radnet::geometry
