#include "orbits/sky_loads.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>

namespace radnet::orbits {

using geometry::SkyBins;

std::vector<int> usedSkyBins(const geometry::SkyKernel& kernel, const std::vector<char>& mask) {
  std::vector<char> used(SkyBins::kBins, 0);
  for (size_t i = 0; i < kernel.nodes.size(); ++i)
    if (mask.empty() || mask[i])
      for (const std::int32_t b : kernel.nodes[i].bins) used[static_cast<size_t>(b)] = 1;
  std::vector<int> bins;
  for (int b = 0; b < SkyBins::kBins; ++b)
    if (used[static_cast<size_t>(b)]) bins.push_back(b);
  return bins;
}

namespace {

constexpr int kChannels = 3;  // view factor, albedo, planet IR
// Positions a block of radiance tables holds: blocks bound the tables' memory (6 × used
// bins × kBlock doubles, ≤ 38 MB).
constexpr int kBlock = 32;
using Table = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
// Row-major: the sums run along a channel's positions (a column-major row's stride of three
// kept them from vectorising: a third of the nodes' sums on the 19,202-node satellite).
using Rows = Eigen::Array<double, kChannels, Eigen::Dynamic, Eigen::RowMajor>;

std::array<double, kChannels> values(const PlanetChannels& c) { return {c.view, c.albedo, c.ir}; }

// The unit directions of every bin corner (6 faces × 65²) and bin centre, computed once,
// and the cosine of the largest angle between a bin's centre and its corners.
struct BinDirections {
  std::vector<Eigen::Vector3d> corners, centres;
  double cos_radius = 1.0;
};

const BinDirections& binDirections() {
  static const BinDirections table = [] {
    constexpr int edge = SkyBins::kBinsPerEdge, corners = edge + 1;
    BinDirections t;
    for (int face = 0; face < 6; ++face)
      for (int i = 0; i < corners; ++i)
        for (int j = 0; j < corners; ++j) t.corners.push_back(SkyBins::corner(face, i, j));
    for (int b = 0; b < SkyBins::kBins; ++b) {
      t.centres.push_back(SkyBins::direction(b, 0.5, 0.5));
      const int face = b / (edge * edge), i = (b / edge) % edge, j = b % edge;
      for (const int di : {0, 1})
        for (const int dj : {0, 1})
          t.cos_radius = std::min(
              t.cos_radius,
              t.centres.back().dot(t.corners[static_cast<size_t>((face * corners + i + di) * corners + j + dj)]));
    }
    return t;
  }();
  return table;
}

}  // namespace

// A block of positions' planet radiance over the used bins (row: a bin's slot, column: a
// position of the block), per channel: the bin's mean by Simpson's rule (the centre and
// the four corners) and the error scale of that mean. Sized once for every bin and kBlock
// positions and kept from round to round: every entry a block reads is written again, none
// is cleared (fresh tables per round, 28 MB on the 1,602-node satellite, cost 50–80 ms of
// page faults each).
struct RadianceTables {
  std::array<Table, kChannels> mean, half;
  Rows peak;  // the planet's largest radiance anywhere, per channel and position
  int positions = 0;  // the block's, ≤ kBlock
  /// Per row: whether the planet can reach the bin at some position of the block. A row
  /// it cannot is neither written nor read (its radiance is 0 all block: a third of an
  /// inertial block's rows on the 1,602-node satellite).
  std::vector<char> lit;
};

namespace {

// Only bins that can reach into the planet's cap carry radiance: the angle from the cap's
// axis to the bin's centre at most the cap's angular radius plus the bin's. The cosine of
// that angle.
double cosReach(const PlanetView& view) {
  const double cap = std::asin(std::sqrt(view.capSin2()));
  const double bin_radius = std::acos(std::clamp(binDirections().cos_radius, -1.0, 1.0));
  return std::cos(std::min(M_PI, cap + bin_radius));
}

// Column q of the radiance tables at one position (one thread): the rows the block lights.
void binRadiance(const std::vector<int>& used, const PlanetView& view, int q, RadianceTables& t) {
  constexpr int edge = SkyBins::kBinsPerEdge, corners = edge + 1;
  const BinDirections& dirs = binDirections();
  const double cos_reach = cosReach(view);
  // Kept per thread between positions: a fresh 600 kB a position went back to the kernel
  // and faulted in again (a tenth of the sweep on the 1,602-node satellite).
  thread_local std::vector<PlanetChannels> at;
  thread_local std::vector<char> have;
  at.resize(dirs.corners.size());
  have.assign(dirs.corners.size(), 0);
  const auto corner = [&](size_t c) -> const PlanetChannels& {
    if (!have[c]) at[c] = planetRadiance(view, dirs.corners[c]), have[c] = 1;
    return at[c];
  };
  for (size_t slot = 0; slot < used.size(); ++slot) {
    if (!t.lit[slot]) continue;
    const int b = used[slot];
    if (dirs.centres[static_cast<size_t>(b)].dot(view.toward_center) < cos_reach) {
      for (int c = 0; c < kChannels; ++c)
        t.mean[static_cast<size_t>(c)](static_cast<Eigen::Index>(slot), q) =
            t.half[static_cast<size_t>(c)](static_cast<Eigen::Index>(slot), q) = 0.0;
      continue;
    }
    const int face = b / (edge * edge), i = (b / edge) % edge, j = b % edge;
    const size_t c00 = static_cast<size_t>((face * corners + i) * corners + j);
    PlanetChannels trapezoid;
    for (const size_t c : {c00, c00 + 1, c00 + corners, c00 + corners + 1}) trapezoid += corner(c) * 0.25;
    const PlanetChannels midpoint = planetRadiance(view, dirs.centres[static_cast<size_t>(b)]);
    // Simpson's (2 M + T) / 3 cancels the h² terms of both; |T − M| / 3 estimates the
    // midpoint's error (more than Simpson's), large only where the limb or the terminator
    // cross the bin.
    const std::array<double, kChannels> m = values(midpoint), tr = values(trapezoid);
    for (int c = 0; c < kChannels; ++c) {
      t.mean[static_cast<size_t>(c)](static_cast<Eigen::Index>(slot), q) = (2.0 * m[c] + tr[c]) / 3.0;
      t.half[static_cast<size_t>(c)](static_cast<Eigen::Index>(slot), q) = std::abs(tr[c] - m[c]) / 3.0;
    }
  }
}

// What the view factors tell of a node's sky: its blocked share and σ (NaN: nothing).
struct KnownShare {
  double blocked = std::numeric_limits<double>::quiet_NaN(), stderr_share = 0.0;
};

// The node's counted load over a block (the planet's radiance over the rays it counts) and
// the variance of its sampling, from the replicas' estimates per channel (m × B each) and
// their counted shares. With the known share t of what the node counts (b, or 1 − b
// counting open rays) the estimate is the ratio t Ŷ/ŝ: only the split of the counted
// share between directions is sampled, so a node whose blockers lie wholly inside the
// planet's cap, or wholly outside it, has no sampling error left. Its variance to first
// order is (t/ŝ)² Var(Ŷ − (Ŷ/ŝ) ŝ) over the replicas plus (Ŷ/ŝ)² σ_t² (Cochran, Sampling
// Techniques, §6.3), taken where it is smaller than the plain estimate's. A kernel that
// saw none of a known share cannot place it: σ covers half of it at the planet's largest
// radiance. A kernel and a share more than 5σ apart
// (other geometry, a clipped row) leave the kernel's own estimate. `binning` (in: the
// binning variance) comes back as the estimate's share of it, the part more rays leave.
void countedLoad(const std::array<Table, kChannels>& estimates, const Eigen::ArrayXd& replica_share,
                 const KnownShare& known, bool counts_open, const Rows& peak, int first_channel, Rows& counted,
                 Rows& variance, Rows& binning) {
  constexpr int m = geometry::kSkyReplicas;
  const auto spread = [m](const Table& e) {
    const Eigen::ArrayXd sum = e.colwise().sum().transpose().array();
    const Eigen::ArrayXd sum2 = e.array().square().colwise().sum().transpose();
    return Eigen::ArrayXd(((sum2 - sum.square() / m) / (m - 1)).max(0.0) / m);
  };
  const double s = replica_share.mean();
  const double var_s = (replica_share - s).square().sum() / (m - 1) / m;
  const double t = counts_open ? 1.0 - known.blocked : known.blocked, var_t = known.stderr_share * known.stderr_share;
  const bool have = std::isfinite(t) && t >= 0.0;
  const bool ratio = have && t > 0 && s > 0 && std::abs(s - t) <= 5.0 * std::sqrt(var_s + var_t) + 1e-3;
  variance = binning;
  for (int c = first_channel; c < kChannels; ++c) {
    const Table& e = estimates[static_cast<size_t>(c)];
    if (!ratio) {
      variance.row(c) += spread(e).transpose();
      if (have && t > 0 && s == 0) variance.row(c) += (0.5 * t * M_PI * peak.row(c)).square();
      continue;
    }
    const Eigen::ArrayXd r = counted.row(c).transpose() / s;  // Ŷ/ŝ per position
    Table residual = e;
    residual.array() -= (replica_share.matrix() * r.matrix().transpose()).array();
    const double f = t / s;
    const Eigen::ArrayXd plain = binning.row(c).transpose() + spread(e);
    const Eigen::ArrayXd by_ratio = f * f * (binning.row(c).transpose() + spread(residual)) + var_t * r.square();
    // The share's own σ (the view factors' rays) can outweigh what it saves: the smaller.
    for (Eigen::Index q = 0; q < r.size(); ++q) {
      const bool better = by_ratio[q] < plain[q];
      counted(c, q) *= better ? f : 1.0;
      variance(c, q) = better ? by_ratio[q] : plain[q];
      binning(c, q) *= better ? f * f : 1.0;
    }
  }
}

// One node's loads and σ at every position of a block, from its kernel, per channel. The
// σ: the spread of the 32 replicas' own estimates (each from its counted rays' bins) and
// the binning error. Each bin's radiance over the block is one row: the sums run along them.
// The binning errors are summed over the bins, not in quadrature: the bins a limb or
// terminator crosses err the same way (in quadrature a CAD model's wing cells, seeing a
// sliver of the planet past the bus, came out 3–8σ low).
void nodeLoads(const geometry::NodeSky& sky, const std::vector<int>& slot, const RadianceTables& t,
               const UnobstructedLoads& unobstructed, int p0, const KnownShare& known, double uniform_ir,
               Rows& value, Rows& sigma, Rows& binning_sigma) {
  const int c0 = uniform_ir > 0 ? 1 : 0;  // uniform IR: the view factor's sums are the IR's / flux
  const Eigen::Index B = t.positions;
  Rows free = Rows::Zero(kChannels, B), counted = Rows::Zero(kChannels, B), binning = Rows::Zero(kChannels, B);
  for (const auto& [k, share] : sky.normals)
    for (int c = 0; c < kChannels; ++c)
      free.row(c) += share * unobstructed.channel[static_cast<size_t>(c)].row(k).segment(p0, B).array();
  for (size_t j = 0; j < sky.bins.size(); ++j) {
    const Eigen::Index u = slot[static_cast<size_t>(sky.bins[j])];
    if (!t.lit[static_cast<size_t>(u)]) continue;
    const double w = M_PI * sky.weights[j];  // E = π × mean of L over cosine-weighted rays
    for (int c = c0; c < kChannels; ++c) {
      counted.row(c) += w * t.mean[static_cast<size_t>(c)].row(u).head(B).array();
      binning.row(c) += w * t.half[static_cast<size_t>(c)].row(u).head(B).array();
    }
  }
  binning = binning.square();  // summed, then a variance: limb bins err alike (docs/orbits.md)
  // Replica r's estimate over the block: π Σ its counted rays' bin radiance × the share
  // of the hemisphere each of its rays stands for.
  constexpr int m = geometry::kSkyReplicas;
  const double per_replica = static_cast<double>(sky.rays) / m / sky.ray_share;
  std::array<Table, kChannels> estimates;
  for (int c = c0; c < kChannels; ++c) estimates[static_cast<size_t>(c)] = Table::Zero(m, B);
  Eigen::ArrayXd replica_share = Eigen::ArrayXd::Zero(m);
  for (const geometry::NodeSky::ReplicaCount& e : sky.replica_counts) {
    const Eigen::Index u = slot[static_cast<size_t>(e.bin)];
    const double share = e.count / per_replica;
    replica_share[e.replica] += share;
    if (!t.lit[static_cast<size_t>(u)]) continue;
    for (int c = c0; c < kChannels; ++c)
      estimates[static_cast<size_t>(c)].row(e.replica) += M_PI * share * t.mean[static_cast<size_t>(c)].row(u).head(B);
  }
  Rows variance;
  countedLoad(estimates, replica_share, known, sky.counts_open, t.peak, c0, counted, variance, binning);
  // One ray's worth: a blocker thinner than the rays' spacing can lie inside the planet's
  // cap between them, unseen by every replica, and their spread then says nothing of it.
  // The kernel resolves the sky to one ray's share of the node's cosine-weighted hemisphere
  // (1/N), so a partly blocked node that sees the planet carries that share at the
  // planet's largest radiance in σ. (1,602-node satellite, Sun-pointing: a wing back at
  // 4,096 rays reported 2.2e-5 W for an error of 1.0e-3 W, two rays' worth of its IR.)
  // Rays drawn in a region each stand for its share of the hemisphere.
  if (sky.blocked_fraction > 0 && sky.blocked_fraction < 1) {
    const double per_ray = M_PI * sky.ray_share / static_cast<double>(sky.rays);
    for (int c = c0; c < kChannels; ++c)
      variance.row(c) += ((free.row(c) > 0).cast<double>() * per_ray * t.peak.row(c)).square();
  }
  if (c0 == 1) {
    counted.row(0) = counted.row(2) / uniform_ir;
    variance.row(0) = variance.row(2) / (uniform_ir * uniform_ir);
    binning.row(0) = binning.row(2) / (uniform_ir * uniform_ir);
  }
  value = sky.counts_open ? counted : Rows(free - counted);
  // What reaches a node is never below 0 nor above what reaches it unobstructed.
  value = value.max(0.0).min(free);
  sigma = variance.sqrt();
  binning_sigma = binning.sqrt();
}

// The tables of positions [p0, p0 + B), B ≤ kBlock.
void blockTables(const std::vector<int>& used, const std::vector<PlanetView>& views, int p0, int B, RadianceTables& t) {
  const Eigen::Index rows = static_cast<Eigen::Index>(used.size());
  // Once at the largest size any round can ask (38 MB): a round that used more bins than
  // the last would fault fresh pages in again.
  if (t.mean[0].rows() < rows)
    for (int c = 0; c < kChannels; ++c) {
      t.mean[static_cast<size_t>(c)].resize(geometry::SkyBins::kBins, kBlock);
      t.half[static_cast<size_t>(c)].resize(geometry::SkyBins::kBins, kBlock);
    }
  t.positions = B;
  t.lit.assign(used.size(), 0);
  std::vector<double> cos_reach;
  for (int q = 0; q < B; ++q) cos_reach.push_back(cosReach(views[static_cast<size_t>(p0 + q)]));
  const BinDirections& dirs = binDirections();
  for (size_t row = 0; row < used.size(); ++row)
    for (int q = 0; q < B && !t.lit[row]; ++q)
      t.lit[row] = dirs.centres[static_cast<size_t>(used[row])].dot(views[static_cast<size_t>(p0 + q)].toward_center) >=
                   cos_reach[static_cast<size_t>(q)];
#ifdef _OPENMP
// Contiguous positions per thread: a row's positions share cache lines, and threads taking
// every other position wrote into each other's lines.
#pragma omp parallel for schedule(static)
#endif
  for (int q = 0; q < B; ++q) binRadiance(used, views[static_cast<size_t>(p0 + q)], q, t);
  t.peak = Rows::Zero(kChannels, B);
  for (int q = 0; q < B; ++q) {
    const PlanetView& v = views[static_cast<size_t>(p0 + q)];
    t.peak(0, q) = 1.0 / M_PI;
    t.peak(1, q) = v.albedo * v.solar_flux_w_m2 / M_PI;
    t.peak(2, q) = v.ir.maxExitance(v.solar_flux_w_m2) / M_PI;
  }
}

}  // namespace

void UnobstructedLoads::fill(const geometry::SkyKernel& kernel, const std::vector<PlanetView>& views,
                             const std::vector<char>& mask) {
  const Eigen::Index normals = static_cast<Eigen::Index>(kernel.normals.size());
  const int P = static_cast<int>(views.size());
  if (have.size() != kernel.normals.size() || channel[0].cols() != P) {
    have.assign(kernel.normals.size(), 0);
    for (auto& c : channel) c.setZero(normals, P);
  }
  std::vector<char> wanted(kernel.normals.size(), 0);
  for (size_t i = 0; i < kernel.nodes.size(); ++i)
    if ((mask.empty() || mask[i]) && kernel.nodes[i].rays > 0)
      for (const auto& [k, share] : kernel.nodes[i].normals) wanted[static_cast<size_t>(k)] = !have[static_cast<size_t>(k)];
  std::vector<int> todo;
  for (size_t k = 0; k < wanted.size(); ++k)
    if (wanted[k]) todo.push_back(static_cast<int>(k)), have[k] = 1;
  if (todo.empty()) return;
  // A position's rings serve all its normals (their pieces and points computed once).
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1)
#endif
  for (int p = 0; p < P; ++p) {
    const PlanetRings rings(views[static_cast<size_t>(p)]);
    for (const int k : todo) {
      const PlanetChannels u = rings.loads(kernel.normals[static_cast<size_t>(k)]);
      channel[0](k, p) = u.view, channel[1](k, p) = u.albedo, channel[2](k, p) = u.ir;
    }
  }
}

void skyKernelSweep(const geometry::SkyKernel& kernel, const std::vector<PlanetView>& views,
                    SkySweepMemory& memory, const std::vector<char>& mask,
                    const Eigen::VectorXd& blocked_share, const Eigen::VectorXd& blocked_share_stderr,
                    EnvironmentLoads& out, BinningErrors* binning) {
  UnobstructedLoads& unobstructed = memory.unobstructed;
  unobstructed.fill(kernel, views, mask);
  const std::vector<int> used = usedSkyBins(kernel, mask);
  std::vector<int> slot(SkyBins::kBins, -1);
  for (size_t k = 0; k < used.size(); ++k) slot[static_cast<size_t>(used[k])] = static_cast<int>(k);
  const int n = static_cast<int>(kernel.nodes.size()), P = static_cast<int>(views.size());
  double uniform_ir = P > 0 && views[0].ir.uniform() ? views[0].ir.uniform_w_m2 : 0.0;
  for (const PlanetView& v : views)
    if (!v.ir.uniform() || v.ir.uniform_w_m2 != uniform_ir) uniform_ir = 0.0;
  if (!memory.tables) memory.tables = std::make_shared<RadianceTables>();
  RadianceTables& t = *memory.tables;
  for (int p0 = 0; p0 < P; p0 += kBlock) {
    const int B = std::min(kBlock, P - p0);
    blockTables(used, views, p0, B, t);
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 16)
#endif
    for (int i = 0; i < n; ++i) {
      const geometry::NodeSky& sky = kernel.nodes[static_cast<size_t>(i)];
      if ((!mask.empty() && !mask[static_cast<size_t>(i)]) || sky.rays == 0) continue;
      Rows value, sigma, binning_sigma;
      KnownShare known;
      if (blocked_share.size() == n) known = {blocked_share[i], blocked_share_stderr[i]};
      nodeLoads(sky, slot, t, unobstructed, p0, known, uniform_ir, value, sigma, binning_sigma);
      if (binning)
        for (int q = 0; q < B; ++q)
          binning->albedo(i, p0 + q) = binning_sigma(1, q), binning->ir(i, p0 + q) = binning_sigma(2, q);
      for (int q = 0; q < B; ++q) {
        out.earth_view_factor(i, p0 + q) = value(0, q);
        out.albedo(i, p0 + q) = value(1, q), out.albedo_stderr(i, p0 + q) = sigma(1, q);
        out.earth_ir(i, p0 + q) = value(2, q), out.earth_ir_stderr(i, p0 + q) = sigma(2, q);
      }
    }
  }
}

}  // namespace radnet::orbits
