#include "geometry/irradiance/sky_kernel.hpp"

#include "geometry/rays/sampling.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace radnet::geometry {

// The equal-angle cube map: on the face of major axis k (sign s) a direction d maps to
// (4/π) atan(d_k1 / |d_k|), (4/π) atan(d_k2 / |d_k|) ∈ [−1, 1]², bins of nearly equal
// solid angle (within 30 %, against 5× for the plain cube map).
int SkyBins::bin(const Vec3& d) {
  const Vec3 a = d.cwiseAbs();
  const int k = a.x() >= a.y() && a.x() >= a.z() ? 0 : (a.y() >= a.z() ? 1 : 2);
  const int face = 2 * k + (d[k] < 0 ? 1 : 0);
  const double major = a[k];
  const auto cell = [&](double c) {
    const double u = (4.0 / M_PI) * std::atan(c / major);
    return std::clamp(static_cast<int>((u + 1.0) * 0.5 * kBinsPerEdge), 0, kBinsPerEdge - 1);
  };
  return (face * kBinsPerEdge + cell(d[(k + 1) % 3])) * kBinsPerEdge + cell(d[(k + 2) % 3]);
}

int SkyBins::coarse(int bin) {
  const int face = bin / (kBinsPerEdge * kBinsPerEdge), i = (bin / kBinsPerEdge) % kBinsPerEdge,
            j = bin % kBinsPerEdge;
  return (face * kCoarseSplit + kCoarseSplit * i / kBinsPerEdge) * kCoarseSplit + kCoarseSplit * j / kBinsPerEdge;
}

namespace {

// The direction at cube-map coordinates (i, j) (in bins, fractional) of a face.
Vec3 faceDirection(int face, double i, double j) {
  const int k = face / 2;
  const auto along = [](double c) { return std::tan((-1.0 + 2.0 * c / SkyBins::kBinsPerEdge) * M_PI / 4.0); };
  Vec3 d = Vec3::Zero();
  d[k] = face % 2 ? -1.0 : 1.0;
  d[(k + 1) % 3] = along(i);
  d[(k + 2) % 3] = along(j);
  return d.normalized();
}

}  // namespace

Vec3 SkyBins::direction(int bin, double s, double t) {
  const int face = bin / (kBinsPerEdge * kBinsPerEdge), i = (bin / kBinsPerEdge) % kBinsPerEdge,
            j = bin % kBinsPerEdge;
  return faceDirection(face, i + s, j + t);
}

Vec3 SkyBins::corner(int face, int i, int j) { return faceDirection(face, i, j); }

std::size_t SkyKernel::bytes() const {
  std::size_t b = normals.size() * sizeof(Vec3) + nodes.size() * sizeof(NodeSky);
  for (const NodeSky& s : nodes)
    b += s.bins.size() * (sizeof(std::int32_t) + sizeof(float)) + s.normals.size() * sizeof(s.normals[0]) +
         s.cells.size() * (sizeof(std::int16_t) + sizeof(s.cell_shares[0]));
  return b;
}

namespace {

constexpr int kReplicas = kSkyReplicas;

// One cast ray: its bin and whether the spacecraft blocks it.
struct SkyRay {
  std::int32_t bin;
  bool blocked;
};

// Rays from one node, doubling per replica until the counted share's σ meets the target.
NodeSky castNodeSky(const RayCaster& caster, int node, const SkyKernelOptions& opt) {
  const NodeSampler sampler(caster.scene(), node);
  std::vector<Sobol4> streams;
  for (int r = 0; r < kReplicas; ++r)
    streams.emplace_back(mixSeed(opt.seed, static_cast<std::uint64_t>(node), 0x5c7 + static_cast<std::uint64_t>(r)));
  std::vector<std::vector<SkyRay>> rays(kReplicas);
  const bool fixed = !opt.node_rays.empty();
  const std::int64_t asked = fixed ? opt.node_rays[static_cast<size_t>(node)] : opt.max_rays_per_node;
  const std::int64_t cap = std::max<std::int64_t>(1, (asked + kReplicas - 1) / kReplicas);
  std::int64_t per_replica = opt.target_stderr > 0 && !fixed ? std::min<std::int64_t>(cap, 32) : cap, cast = 0;
  std::vector<double> share(kReplicas);
  for (;;) {
    for (int r = 0; r < kReplicas; ++r)
      for (std::int64_t k = cast; k < per_replica; ++k) {
        const NodeSampler::Ray ray = sampler.map(streams[static_cast<size_t>(r)].next());
        const bool blocked = caster.occluded(caster.offsetOrigin(ray.point, ray.normal), ray.direction, ray.face);
        rays[static_cast<size_t>(r)].push_back({SkyBins::bin(ray.direction), blocked});
      }
    cast = per_replica;
    double sum = 0.0, sum2 = 0.0;
    for (int r = 0; r < kReplicas; ++r) {
      const auto& v = rays[static_cast<size_t>(r)];
      share[static_cast<size_t>(r)] =
          double(std::count_if(v.begin(), v.end(), [](const SkyRay& s) { return s.blocked; })) / double(cast);
      sum += share[static_cast<size_t>(r)], sum2 += share[static_cast<size_t>(r)] * share[static_cast<size_t>(r)];
    }
    const double mean = sum / kReplicas;
    const double sigma = std::sqrt(std::max(0.0, (sum2 - kReplicas * mean * mean) / (kReplicas - 1)) / kReplicas);
    if (fixed || opt.target_stderr <= 0 || sigma <= opt.target_stderr || per_replica >= cap) break;
    per_replica = std::min(cap, 2 * per_replica);
  }
  NodeSky sky;
  sky.rays = cast * kReplicas;
  double blocked = 0.0;
  for (double s : share) blocked += s;
  sky.blocked_fraction = blocked / kReplicas;
  sky.counts_open = sky.blocked_fraction > 0.5;
  // The counted rays, binned, and their share per coarse cell and replica for the σ.
  std::map<std::int32_t, std::int64_t> counts;
  std::map<std::int16_t, std::array<float, kReplicas>> cells;
  for (int r = 0; r < kReplicas; ++r)
    for (const SkyRay& s : rays[static_cast<size_t>(r)]) {
      if (s.blocked == sky.counts_open) continue;
      ++counts[s.bin];
      auto [it, fresh] = cells.try_emplace(static_cast<std::int16_t>(SkyBins::coarse(s.bin)));
      if (fresh) it->second.fill(0.0f);
      it->second[static_cast<size_t>(r)] += static_cast<float>(1.0 / double(cast));
    }
  for (const auto& [bin, count] : counts) {
    sky.bins.push_back(bin);
    sky.weights.push_back(static_cast<float>(double(count) / double(sky.rays)));
  }
  for (const auto& [cell, shares] : cells) {
    sky.cells.push_back(cell);
    sky.cell_shares.push_back(shares);
  }
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
  std::int64_t rays = 0;
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : rays)
#endif
  for (int i = 0; i < n; ++i) {
    if (!opt.nodes.empty() && !opt.nodes[static_cast<size_t>(i)]) continue;
    if (!opt.node_rays.empty() && opt.node_rays[static_cast<size_t>(i)] <= 0) continue;
    kernel.nodes[static_cast<size_t>(i)] = castNodeSky(caster, i, opt);
    rays += kernel.nodes[static_cast<size_t>(i)].rays;
  }
  kernel.rays = rays;
  collectNormals(caster.scene(), kernel);
  return kernel;
}

}  // namespace radnet::geometry
