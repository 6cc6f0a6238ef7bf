#include "geometry/irradiance/sky_kernel.hpp"

#include "geometry/irradiance/sky_region.hpp"
#include "geometry/scene/open_sides.hpp"
#include "geometry/rays/sampling.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace radnet::geometry {

// The equal-angle cube map: on the face of major axis k (sign s) a direction d maps to
// (4/π) atan(d_k1 / |d_k|), (4/π) atan(d_k2 / |d_k|) ∈ [−1, 1]², bins of nearly equal
// solid angle (within 30 %, against 5× for the plain cube map).
namespace {

// The bins' edges on a face as tangents: cell j spans [kEdgeTangent[j], kEdgeTangent[j + 1])
// of c / major (the equal-angle cube map: angle −π/4 + j π / (2 kBinsPerEdge)).
const std::array<double, SkyBins::kBinsPerEdge + 1>& edgeTangents() {
  static const auto t = [] {
    std::array<double, SkyBins::kBinsPerEdge + 1> e{};
    for (int j = 0; j <= SkyBins::kBinsPerEdge; ++j)
      e[static_cast<size_t>(j)] = std::tan((-1.0 + 2.0 * j / SkyBins::kBinsPerEdge) * M_PI / 4.0);
    e.front() = -1.0, e.back() = 1.0;
    return e;
  }();
  return t;
}

}  // namespace

// The cell of x = c / major without an arctangent (two per ray were a tenth of the kernel's
// cast): a guess from atan x ≈ x (π/4 + 0.273 (1 − |x|)) (within 0.004 rad, a sixth of a
// cell), then the edges' tangents decide.
int SkyBins::bin(const Vec3& d) {
  const Vec3 a = d.cwiseAbs();
  const int k = a.x() >= a.y() && a.x() >= a.z() ? 0 : (a.y() >= a.z() ? 1 : 2);
  const int face = 2 * k + (d[k] < 0 ? 1 : 0);
  const double major = a[k];
  const auto& edges = edgeTangents();
  const auto cell = [&](double c) {
    const double x = std::clamp(c / major, -1.0, 1.0);
    const double u = (4.0 / M_PI) * x * (M_PI / 4.0 + 0.273 * (1.0 - std::abs(x)));
    int j = std::clamp(static_cast<int>((u + 1.0) * 0.5 * kBinsPerEdge), 0, kBinsPerEdge - 1);
    while (j > 0 && x < edges[static_cast<size_t>(j)]) --j;
    while (j < kBinsPerEdge - 1 && x >= edges[static_cast<size_t>(j + 1)]) ++j;
    return j;
  };
  return (face * kBinsPerEdge + cell(d[(k + 1) % 3])) * kBinsPerEdge + cell(d[(k + 2) % 3]);
}

namespace {

// The direction of a face whose other two coordinates are the tangents u, v.
Vec3 faceDirection(int face, double u, double v) {
  const int k = face / 2;
  Vec3 d = Vec3::Zero();
  d[k] = face % 2 ? -1.0 : 1.0;
  d[(k + 1) % 3] = u;
  d[(k + 2) % 3] = v;
  return d.normalized();
}

// tan(angle of edge i + s of a bin's angle), s ∈ [0, 1], by the addition formula from the
// edge's tangent: tan x of the bin's fraction (x ≤ 0.0246 rad) to double precision by four
// terms of its series (the next, 62 x⁹/2835, is 7e-17). The sky loads' split cells ask
// for directions inside bins at every position: two library tangents each were a quarter
// of the radiance tables' cost.
double alongEdge(int i, double s) {
  constexpr double kBinAngle = M_PI / (2.0 * SkyBins::kBinsPerEdge);
  const double x = s * kBinAngle, x2 = x * x;
  const double tan_x = x * (1.0 + x2 * (1.0 / 3.0 + x2 * (2.0 / 15.0 + x2 * (17.0 / 315.0))));
  const double t = edgeTangents()[static_cast<size_t>(i)];
  return (t + tan_x) / (1.0 - t * tan_x);
}

}  // namespace

Vec3 SkyBins::direction(int bin, double s, double t) {
  const int face = bin / (kBinsPerEdge * kBinsPerEdge), i = (bin / kBinsPerEdge) % kBinsPerEdge,
            j = bin % kBinsPerEdge;
  return faceDirection(face, alongEdge(i, s), alongEdge(j, t));
}

Vec3 SkyBins::corner(int face, int i, int j) {
  return faceDirection(face, edgeTangents()[static_cast<size_t>(i)], edgeTangents()[static_cast<size_t>(j)]);
}

std::size_t SkyKernel::bytes() const {
  std::size_t b = normals.size() * sizeof(Vec3) + nodes.size() * sizeof(NodeSky);
  for (const NodeSky& s : nodes)
    b += s.bins.size() * (sizeof(std::int32_t) + sizeof(float)) + s.normals.size() * sizeof(s.normals[0]) +
         s.replica_counts.size() * sizeof(NodeSky::ReplicaCount);
  return b;
}

namespace {

constexpr int kReplicas = kSkyReplicas;

// One cast ray in 32 bits: its bin × kReplicas + replica, and kBlockedBit where the
// spacecraft blocks it (bins × replicas < 2^20).
constexpr std::uint32_t kBlockedBit = 1u << 31;
static_assert(std::int64_t{SkyBins::kBins} * kReplicas < kBlockedBit);

// A node's kernel as counts: rays per replica, each replica's blocked rays, and the
// counted rays (the minority) per bin and per (bin, replica).
struct SkyCounts {
  std::int64_t per_replica = 0;
  double ray_share = 1.0;  // of the hemisphere, the rays' region (NodeSky::ray_share)
  std::array<std::int64_t, kReplicas> blocked{};
  bool counts_open = false;
  /// (bin × kReplicas + replica, count), ascending, a key repeated at most in adjacent entries.
  std::vector<std::pair<std::int64_t, std::int64_t>> replica_bins;
};

// The counts a kept kernel stands for (its shares times its ray counts, integers again).
SkyCounts countsOf(const NodeSky& sky) {
  SkyCounts c;
  c.per_replica = sky.rays / kReplicas;
  c.counts_open = sky.counts_open;
  c.ray_share = sky.ray_share;
  std::array<std::int64_t, kReplicas> counted{};
  for (const NodeSky::ReplicaCount& e : sky.replica_counts) {
    c.replica_bins.emplace_back(std::int64_t{e.bin} * kReplicas + e.replica, e.count);
    counted[static_cast<size_t>(e.replica)] += e.count;
  }
  for (int r = 0; r < kReplicas; ++r)
    c.blocked[static_cast<size_t>(r)] = sky.counts_open ? c.per_replica - counted[static_cast<size_t>(r)] : counted[static_cast<size_t>(r)];
  return c;
}

// The kernel of counts (the counted minority chosen by the blocked fraction beforehand).
NodeSky nodeSkyOf(SkyCounts& c) {
  NodeSky sky;
  sky.rays = c.per_replica * kReplicas;
  sky.counts_open = c.counts_open;
  sky.ray_share = c.ray_share;
  double blocked = 0.0;
  for (const std::int64_t b : c.blocked) blocked += double(b);
  sky.blocked_fraction = sky.rays > 0 ? c.ray_share * blocked / double(sky.rays) : 0.0;
  for (size_t k = 0; k < c.replica_bins.size();) {
    const std::int64_t key = c.replica_bins[k].first;
    std::int64_t count = 0;
    for (; k < c.replica_bins.size() && c.replica_bins[k].first == key; ++k) count += c.replica_bins[k].second;
    const std::int32_t bin = static_cast<std::int32_t>(key / kReplicas);
    sky.replica_counts.push_back({bin, static_cast<std::int16_t>(key % kReplicas), static_cast<std::uint16_t>(count)});
    if (sky.bins.empty() || sky.bins.back() != bin) sky.bins.push_back(bin), sky.weights.push_back(0.0f);
    sky.weights.back() += static_cast<float>(c.ray_share * double(count) / double(sky.rays));
  }
  return sky;
}

// σ of the blocked share over the replicas.
double blockedSigma(const SkyCounts& c) {
  double sum = 0.0, sum2 = 0.0;
  for (const std::int64_t b : c.blocked) {
    const double share = double(b) / double(c.per_replica);
    sum += share, sum2 += share * share;
  }
  const double mean = sum / kReplicas;
  return c.ray_share * std::sqrt(std::max(0.0, (sum2 - kReplicas * mean * mean) / (kReplicas - 1)) / kReplicas);
}

// The kernel of a node's counts with its new rays' minority (c.counts_open) added.
// The new rays' keys sorted (32-bit keys: a sort of (key, count) pairs was 5 % of the
// cast), counted, and merged with the earlier counts (ascending already).
NodeSky countedSky(SkyCounts& c, const std::vector<std::uint32_t>& rays) {
  thread_local std::vector<std::uint32_t> keys;
  keys.clear();
  const bool count_blocked = !c.counts_open;
  for (const std::uint32_t ray : rays)
    if (((ray & kBlockedBit) != 0) == count_blocked) keys.push_back(ray & ~kBlockedBit);
  std::sort(keys.begin(), keys.end());
  const auto earlier = static_cast<std::ptrdiff_t>(c.replica_bins.size());
  for (size_t k = 0; k < keys.size();) {
    size_t end = k;
    while (end < keys.size() && keys[end] == keys[k]) ++end;
    c.replica_bins.emplace_back(keys[k], static_cast<std::int64_t>(end - k));
    k = end;
  }
  std::inplace_merge(c.replica_bins.begin(), c.replica_bins.begin() + earlier, c.replica_bins.end());
  return nodeSkyOf(c);
}

// Rays a replica for a node drawn in `region` (SkyKernelOptions::rays_per_share).
std::int64_t regionRaysPerReplica(const SkyKernelOptions& opt, const SkyRegion& region) {
  const double wanted = opt.rays_per_share * region.share() / kReplicas;
  return std::max<std::int64_t>({1, opt.min_rays_per_node / kReplicas, static_cast<std::int64_t>(std::ceil(wanted))});
}

// Rays from one node, doubling per replica until the counted share's σ meets the target
// (or to a count per node). With `before` (the same seed's first points, cast earlier) the
// stream resumes after them and only the new rays are traced; `cast` counts those. With
// `blockers`, a flat node's rays are drawn in its region alone (sky_region.hpp) and count
// the blocked ones. A node with nothing in front of any of its triangles (`open_sides`,
// open_sides.hpp) meets nothing: its kernel is exactly empty and costs no ray.
NodeSky castNodeSky(const RayCaster& caster, int node, const SkyKernelOptions& opt, const NodeSky* before,
                    const std::vector<std::uint8_t>* open_sides, const BlockerSpheres* blockers, std::int64_t& cast) {
  const bool fixed = !opt.node_rays.empty();
  const std::int64_t asked = fixed ? opt.node_rays[static_cast<size_t>(node)] : opt.max_rays_per_node;
  std::int64_t cap = std::max<std::int64_t>(1, (asked + kReplicas - 1) / kReplicas);
  if (open_sides && nodeOpen(caster.scene().nodes()[static_cast<size_t>(node)], *open_sides)) {
    NodeSky open;  // what the asked rays would all find, none traced
    open.rays = cap * kReplicas;
    return open;
  }
  const NodeSampler sampler(caster.scene(), node);
  // The region once per node: a re-cast draws in the same one (its first rays' share).
  const SkyRegion region =
      before && before->region_known ? before->region : (blockers ? blockers->regionOf(node) : SkyRegion{});
  if (!fixed && opt.rays_per_share > 0 && !region.whole) cap = regionRaysPerReplica(opt, region);
  const bool resumes = before && before->rays % kReplicas == 0 && before->rays / kReplicas <= cap &&
                       before->ray_share == region.share();
  SkyCounts c = resumes ? countsOf(*before) : SkyCounts{};
  c.ray_share = region.share();
  std::vector<Sobol4> streams;
  for (int r = 0; r < kReplicas; ++r) {
    streams.emplace_back(mixSeed(opt.seed, static_cast<std::uint64_t>(node), 0x5c7 + static_cast<std::uint64_t>(r)));
    streams.back().seek(static_cast<std::uint32_t>(c.per_replica));
  }
  const std::int64_t start = c.per_replica;
  // Kept per thread: fresh vectors a node faulted their pages in again (7 % of the cast).
  thread_local std::vector<std::uint32_t> rays;
  rays.clear();
  std::int64_t per_replica = opt.target_stderr > 0 && !fixed ? std::min<std::int64_t>(cap, 32) : cap;
  for (;;) {
    for (int r = 0; r < kReplicas; ++r)
      for (std::int64_t k = c.per_replica; k < per_replica; ++k) {
        const std::array<double, 4> u = streams[static_cast<size_t>(r)].next();
        NodeSampler::Ray ray = region.whole ? sampler.map(u) : sampler.mapPoint(u[0], u[1]);
        // A region's point outside the disc is a ray that meets nothing: counted (by
        // per_replica), not traced. A region's node counts its blocked rays only (below):
        // its open rays are neither binned nor kept (the bin was 9 % of the cast).
        if (!region.whole && !region.direction(u[2], u[3], ray.direction)) continue;
        const bool blocked = caster.occluded(caster.offsetOrigin(ray.point, ray.normal), ray.direction, ray.face);
        if (blocked || region.whole)
          rays.push_back(static_cast<std::uint32_t>(SkyBins::bin(ray.direction) * kReplicas + r) | (blocked ? kBlockedBit : 0u));
        c.blocked[static_cast<size_t>(r)] += blocked;
      }
    cast += (per_replica - c.per_replica) * kReplicas;
    c.per_replica = std::max(c.per_replica, per_replica);
    if (fixed || opt.target_stderr <= 0 || blockedSigma(c) <= opt.target_stderr || per_replica >= cap) break;
    per_replica = std::min(cap, 2 * per_replica);
  }
  double blocked = 0.0;
  for (const std::int64_t b : c.blocked) blocked += double(b);
  // A region's open rays outside it are not traced: it counts the blocked ones.
  const bool counts_open = region.whole && blocked > 0.5 * double(c.per_replica * kReplicas);
  // The earlier rays kept only their minority: if the majority turned, cast them all again.
  if (start > 0 && counts_open != c.counts_open) return castNodeSky(caster, node, opt, nullptr, open_sides, blockers, cast);
  c.counts_open = counts_open;
  NodeSky sky = countedSky(c, rays);
  sky.region = region;
  sky.region_known = blockers != nullptr;
  return sky;
}

// Each node's facet normals (on its side) as indices into one list of distinct normals,
// with the share of the node's area each carries.
void collectNormals(const Scene& scene, SkyKernel& kernel) {
  std::map<std::array<double, 3>, std::int32_t> index;
  for (size_t i = 0; i < scene.nodes().size(); ++i) {
    const Node& node = scene.nodes()[i];
    double area = 0.0;
    std::map<std::int32_t, double> shares;
    for (int f : node.faces) {
      const Face& face = scene.faces()[static_cast<size_t>(f)];
      const Vec3 n = node.side * face.normal;
      const auto [it, fresh] = index.try_emplace({n.x(), n.y(), n.z()}, static_cast<std::int32_t>(kernel.normals.size()));
      if (fresh) kernel.normals.push_back(n);
      shares[it->second] += face.area_m2;
      area += face.area_m2;
    }
    for (const auto& [k, a] : shares) kernel.nodes[i].normals.emplace_back(k, area > 0 ? a / area : 0.0);
  }
}

}  // namespace

SkyKernel skyKernel(const RayCaster& caster, const SkyKernelOptions& opt) {
  const int n = static_cast<int>(caster.scene().nodes().size());
  if (!opt.nodes.empty() && opt.nodes.size() != static_cast<size_t>(n))
    throw std::invalid_argument("sky kernel: the node mask must have one entry per node");
  if (!opt.node_rays.empty() && opt.node_rays.size() != static_cast<size_t>(n))
    throw std::invalid_argument("sky kernel: the rays per node must have one entry per node");
  SkyKernel kernel;
  kernel.nodes.resize(static_cast<size_t>(n));
  // A replica's count in one bin is kept in 16 bits.
  std::int64_t most = std::max(opt.max_rays_per_node, static_cast<std::int64_t>(2.0 * opt.rays_per_share));
  for (const std::int64_t r : opt.node_rays) most = std::max(most, r);
  if (most > 65535 * static_cast<std::int64_t>(kReplicas))
    throw std::invalid_argument("sky kernel: at most 2,097,120 rays a node");
  if (opt.prefix && opt.prefix->nodes.size() != static_cast<size_t>(n))
    throw std::invalid_argument("sky kernel: the earlier kernel must have one entry per node");
  std::int64_t rays = 0, cast = 0;
  // A resumed cast re-casts nodes whose first rays met something: none is free, so only a
  // first cast asks for the open sides.
  const std::vector<std::uint8_t>* open_sides = opt.prefix ? nullptr : &caster.openSides();
  const BlockerSpheres blockers(caster.scene(), caster.originOffset());
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : rays, cast)
#endif
  for (int i = 0; i < n; ++i) {
    if (!opt.nodes.empty() && !opt.nodes[static_cast<size_t>(i)]) continue;
    if (!opt.node_rays.empty() && opt.node_rays[static_cast<size_t>(i)] <= 0) continue;
    const NodeSky* before = opt.prefix ? &opt.prefix->nodes[static_cast<size_t>(i)] : nullptr;
    kernel.nodes[static_cast<size_t>(i)] =
        castNodeSky(caster, i, opt, before, open_sides, &blockers, cast);
    rays += kernel.nodes[static_cast<size_t>(i)].rays;
  }
  kernel.rays = rays;
  kernel.cast_rays = cast;
  collectNormals(caster.scene(), kernel);
  return kernel;
}

}  // namespace radnet::geometry
