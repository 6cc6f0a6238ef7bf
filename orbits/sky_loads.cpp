#include "orbits/sky_loads.hpp"

#include "orbits/sky_radiance.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <tuple>

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

constexpr int kChannels = kSkyChannels;
constexpr int kBlock = kRadianceBlock;
// Blocks whose tables a sweep's memory keeps for its later rounds (19 MB each).
constexpr int kKeptBlocks = 4;
using Table = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using Rows = ChannelRows;

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
// the binning error. Each bin's radiance over its span of the block's positions (the planet
// reaches it nowhere else) is one row: the sums run along them.
// The binning errors are summed over the bins, not in quadrature: the bins a limb or
// terminator crosses err the same way (in quadrature a CAD model's wing cells, seeing a
// sliver of the planet past the bus, came out 3–8σ low).
void nodeLoads(const geometry::NodeSky& sky, const RadianceTables& t, const Rows& free, const KnownShare& known,
               double uniform_ir, Rows& value, Rows& sigma, Rows& binning_sigma) {
  const int c0 = uniform_ir > 0 ? 1 : 0;  // uniform IR: the view factor's sums are the IR's / flux
  const Eigen::Index B = t.positions;
  Rows counted = Rows::Zero(kChannels, B), binning = Rows::Zero(kChannels, B);
  for (size_t j = 0; j < sky.bins.size(); ++j) {
    const int u = sky.bins[j];
    const RadianceTables::Span& span = t.spans[static_cast<size_t>(u)];
    if (span.count == 0) continue;
    const double w = M_PI * sky.weights[j];  // E = π × mean of L over cosine-weighted rays
    for (int c = c0; c < kChannels; ++c)
      binning.row(c).segment(span.first, span.count) += w * t.halfSpan(c, u).cast<double>();
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
    const Eigen::Index u = e.bin;
    const double share = e.count / per_replica;
    replica_share[e.replica] += share;
    const RadianceTables::Span& span = t.spans[static_cast<size_t>(u)];
    if (span.count == 0) continue;
    for (int c = c0; c < kChannels; ++c)
      estimates[static_cast<size_t>(c)].row(e.replica).segment(span.first, span.count).array() +=
          M_PI * share * t.meanSpan(c, static_cast<int>(u)).cast<double>();
  }
  // The counted load is the replicas' mean (a bin's weight is its rays' share over all
  // replicas): no sum of its own.
  for (int c = c0; c < kChannels; ++c)
    counted.row(c) = estimates[static_cast<size_t>(c)].colwise().sum().array() / m;
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

// Grouped nodes whose facets are an earlier grouped node's with their normals negated and
// the same shares (the two sides of a curved part): for each such row the earlier row and
// its Σ shares × normals (UnobstructedLoads::mirror_of). Candidates by their facet count
// and Σ shares × normals (negated), then checked facet by facet, exactly.
void findMirrors(const geometry::SkyKernel& kernel, const std::vector<int>& node_row, std::vector<int>& mirror_of,
                 std::vector<Eigen::Vector3d>& mirror_sum) {
  using Key = std::tuple<size_t, long long, long long, long long>;
  const auto key = [](size_t count, const Eigen::Vector3d& sum) {
    return Key{count, std::llround(sum.x() * 1e9), std::llround(sum.y() * 1e9), std::llround(sum.z() * 1e9)};
  };
  std::map<Key, size_t> seen;  // → node
  for (size_t i = 0; i < kernel.nodes.size(); ++i) {
    const int row = node_row[i];
    if (row < 0) continue;
    const auto& facets = kernel.nodes[i].normals;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const auto& [k, share] : facets) sum += share * kernel.normals[static_cast<size_t>(k)];
    mirror_sum[static_cast<size_t>(row)] = sum;
    const auto it = seen.find(key(facets.size(), -sum));
    if (it != seen.end()) {
      std::map<std::array<double, 3>, double> other;
      for (const auto& [k, share] : kernel.nodes[it->second].normals) {
        const Eigen::Vector3d& n = kernel.normals[static_cast<size_t>(k)];
        other[{-n.x(), -n.y(), -n.z()}] += share;
      }
      bool same = other.size() == facets.size();
      for (const auto& [k, share] : facets) {
        const Eigen::Vector3d& n = kernel.normals[static_cast<size_t>(k)];
        const auto o = other.find({n.x(), n.y(), n.z()});
        same = same && o != other.end() && std::abs(o->second - share) <= 1e-12;
      }
      if (same) {
        mirror_of[static_cast<size_t>(row)] = node_row[it->second];
        continue;
      }
    }
    seen.emplace(key(facets.size(), sum), i);
  }
}

// V = ∫_cap L d dΩ per channel (view factor, albedo, IR) at one position: loads(n) −
// loads(−n) = n · V for any unit n, and loads(c) = c · V for the planet's direction c.
std::array<Eigen::Vector3d, 3> capMoments(const PlanetRings& rings, const PlanetView& view) {
  const Eigen::Vector3d& c = view.toward_center;
  const Eigen::Vector3d e1 = c.unitOrthogonal(), e2 = c.cross(e1);
  const PlanetChannels along = rings.loads(c);
  std::array<Eigen::Vector3d, 3> v;
  v[0] = along.view * c, v[1] = along.albedo * c, v[2] = along.ir * c;
  for (const Eigen::Vector3d& e : {e1, e2}) {
    const PlanetChannels plus = rings.loads(e), minus = rings.loads(-e);
    v[0] += (plus.view - minus.view) * e, v[1] += (plus.albedo - minus.albedo) * e, v[2] += (plus.ir - minus.ir) * e;
  }
  return v;
}

}  // namespace

void UnobstructedLoads::layOut(const geometry::SkyKernel& kernel, int positions) {
  have.assign(kernel.normals.size(), 0);
  for (auto& c : channel) c.setZero(static_cast<Eigen::Index>(kernel.normals.size()), positions);
  node_row.assign(kernel.nodes.size(), -1);
  int rows = 0;
  for (size_t i = 0; i < kernel.nodes.size(); ++i)
    if (kernel.nodes[i].normals.size() > kGroupedFacets) node_row[i] = rows++;
  node_have.assign(static_cast<size_t>(rows), 0);
  for (auto& c : node_channel) c.setZero(rows, positions);
  row_node.assign(static_cast<size_t>(rows), -1);
  for (size_t i = 0; i < kernel.nodes.size(); ++i)
    if (node_row[i] >= 0) row_node[static_cast<size_t>(node_row[i])] = static_cast<int>(i);
  mirror_of.assign(static_cast<size_t>(rows), -1);
  mirror_sum.assign(static_cast<size_t>(rows), Eigen::Vector3d::Zero());
  findMirrors(kernel, node_row, mirror_of, mirror_sum);
}

void UnobstructedLoads::fill(const geometry::SkyKernel& kernel, const std::vector<PlanetView>& views,
                             const std::vector<char>& mask) {
  const int P = static_cast<int>(views.size());
  if (have.size() != kernel.normals.size() || channel[0].cols() != P || node_row.size() != kernel.nodes.size())
    layOut(kernel, P);
  std::vector<char> wanted(kernel.normals.size(), 0);
  std::vector<int> rows_now;  // grouped rows computed by this call
  for (size_t i = 0; i < kernel.nodes.size(); ++i) {
    if ((!mask.empty() && !mask[i]) || kernel.nodes[i].rays <= 0) continue;
    if (node_row[i] < 0)
      for (const auto& [k, share] : kernel.nodes[i].normals) wanted[static_cast<size_t>(k)] = !have[static_cast<size_t>(k)];
    else if (!node_have[static_cast<size_t>(node_row[i])])
      rows_now.push_back(static_cast<int>(i)), node_have[static_cast<size_t>(node_row[i])] = 1;
  }
  // A mirror row always takes its other side's loads, computing them if no one asked for
  // them (an MPI rank that owns the back of a dish and not its front): the same numbers
  // whichever nodes a process holds.
  std::vector<int> nodes, mirrors;
  for (const int i : rows_now) {
    const int other = mirror_of[static_cast<size_t>(node_row[static_cast<size_t>(i)])];
    if (other >= 0 && !node_have[static_cast<size_t>(other)])
      nodes.push_back(row_node[static_cast<size_t>(other)]), node_have[static_cast<size_t>(other)] = 1;
    (other >= 0 ? mirrors : nodes).push_back(i);
  }
  std::vector<int> todo;
  for (size_t k = 0; k < wanted.size(); ++k)
    if (wanted[k]) todo.push_back(static_cast<int>(k)), have[k] = 1;
  if (todo.empty() && rows_now.empty()) return;
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
    std::vector<Eigen::Vector3d> facet_normals;
    std::vector<double> shares;
    for (const int i : nodes) {
      facet_normals.clear(), shares.clear();
      for (const auto& [k, share] : kernel.nodes[static_cast<size_t>(i)].normals)
        facet_normals.push_back(kernel.normals[static_cast<size_t>(k)]), shares.push_back(share);
      const PlanetChannels u = rings.facetLoads(facet_normals, shares);
      const int row = node_row[static_cast<size_t>(i)];
      node_channel[0](row, p) = u.view, node_channel[1](row, p) = u.albedo, node_channel[2](row, p) = u.ir;
    }
    if (mirrors.empty()) continue;
    const std::array<Eigen::Vector3d, 3> moments = capMoments(rings, views[static_cast<size_t>(p)]);
    for (const int i : mirrors) {
      const int row = node_row[static_cast<size_t>(i)], other = mirror_of[static_cast<size_t>(row)];
      const Eigen::Vector3d& sum = mirror_sum[static_cast<size_t>(other)];
      for (size_t c = 0; c < 3; ++c)  // rounding can leave −1e-17 where the other side takes it all
        node_channel[c](row, p) = std::max(0.0, node_channel[c](other, p) - sum.dot(moments[c]));
    }
  }
}

Eigen::Array<double, 3, Eigen::Dynamic, Eigen::RowMajor> UnobstructedLoads::node(const geometry::SkyKernel& kernel,
                                                                                 size_t i, int p0, int B) const {
  Eigen::Array<double, 3, Eigen::Dynamic, Eigen::RowMajor> free = Eigen::Array<double, 3, Eigen::Dynamic, Eigen::RowMajor>::Zero(3, B);
  const int row = node_row[i];
  for (int c = 0; c < 3; ++c) {
    if (row >= 0) {
      free.row(c) = node_channel[static_cast<size_t>(c)].row(row).segment(p0, B).array();
      continue;
    }
    for (const auto& [k, share] : kernel.nodes[i].normals)
      free.row(c) += share * channel[static_cast<size_t>(c)].row(k).segment(p0, B).array();
  }
  return free;
}

void skyKernelSweep(const geometry::SkyKernel& kernel, const std::vector<PlanetView>& views,
                    SkySweepMemory& memory, const std::vector<char>& mask,
                    const Eigen::VectorXd& blocked_share, const Eigen::VectorXd& blocked_share_stderr,
                    EnvironmentLoads& out, BinningErrors* binning) {
  UnobstructedLoads& unobstructed = memory.unobstructed;
  unobstructed.fill(kernel, views, mask);
  const std::vector<int> used = usedSkyBins(kernel, mask);
  const int n = static_cast<int>(kernel.nodes.size()), P = static_cast<int>(views.size());
  double uniform_ir = P > 0 && views[0].ir.uniform() ? views[0].ir.uniform_w_m2 : 0.0;
  for (const PlanetView& v : views)
    if (!v.ir.uniform() || v.ir.uniform_w_m2 != uniform_ir) uniform_ir = 0.0;
  // A table per block while they fit kKeptBlocks (their rows then serve every round),
  // else one, computed again per block.
  const int blocks = (P + kBlock - 1) / kBlock;
  memory.tables.resize(static_cast<size_t>(blocks <= kKeptBlocks ? blocks : 1));
  for (auto& t : memory.tables)
    if (!t) t = std::make_shared<RadianceTables>();
  for (int p0 = 0; p0 < P; p0 += kBlock) {
    const int B = std::min(kBlock, P - p0);
    RadianceTables& t = *memory.tables[static_cast<size_t>(std::min(p0 / kBlock, static_cast<int>(memory.tables.size()) - 1))];
    radianceBlock(used, views, p0, B, t, uniform_ir > 0 ? 1 : 0);
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 16)
#endif
    for (int i = 0; i < n; ++i) {
      const geometry::NodeSky& sky = kernel.nodes[static_cast<size_t>(i)];
      if ((!mask.empty() && !mask[static_cast<size_t>(i)]) || sky.rays == 0) continue;
      Rows value, sigma, binning_sigma;
      KnownShare known;
      if (blocked_share.size() == n) known = {blocked_share[i], blocked_share_stderr[i]};
      nodeLoads(sky, t, unobstructed.node(kernel, static_cast<size_t>(i), p0, B), known, uniform_ir, value, sigma,
                binning_sigma);
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
