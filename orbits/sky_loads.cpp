#include "orbits/sky_loads.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace radnet::orbits {

using geometry::SkyBins;

std::vector<int> usedSkyBins(const geometry::SkyKernel& kernel) {
  std::vector<char> used(SkyBins::kBins, 0);
  for (const geometry::NodeSky& s : kernel.nodes)
    for (const std::int32_t b : s.bins) used[static_cast<size_t>(b)] = 1;
  std::vector<int> bins;
  for (int b = 0; b < SkyBins::kBins; ++b)
    if (used[static_cast<size_t>(b)]) bins.push_back(b);
  return bins;
}

namespace {

PlanetChannels square(const PlanetChannels& c) { return {c.view * c.view, c.albedo * c.albedo, c.ir * c.ir}; }

// The planet's radiance over each used bin at one position: its mean by Simpson's rule
// (the centre and the four corners) and the error scale of that mean.
struct BinRadiance {
  std::vector<PlanetChannels> mean, half;
};

BinRadiance binRadiance(const std::vector<int>& used, const PlanetView& view) {
  constexpr int edge = SkyBins::kBinsPerEdge, corners = edge + 1;
  BinRadiance r;
  r.mean.assign(SkyBins::kBins, PlanetChannels{});
  r.half.assign(SkyBins::kBins, PlanetChannels{});
  // The radiance at every bin corner (a corner serves four bins); those beyond the limb
  // return at once.
  std::vector<PlanetChannels> at(6 * corners * corners);
#ifdef _OPENMP
#pragma omp parallel for schedule(static)
#endif
  for (int k = 0; k < 6 * corners; ++k)
    for (int j = 0; j < corners; ++j)
      at[static_cast<size_t>(k * corners + j)] =
          planetRadiance(view, SkyBins::corner(k / corners, k % corners, j));
  const int count = static_cast<int>(used.size());
#ifdef _OPENMP
#pragma omp parallel for schedule(static)
#endif
  for (int k = 0; k < count; ++k) {
    const int b = used[static_cast<size_t>(k)];
    const int face = b / (edge * edge), i = (b / edge) % edge, j = b % edge;
    const size_t c00 = static_cast<size_t>((face * corners + i) * corners + j);
    PlanetChannels trapezoid;
    for (const size_t c : {c00, c00 + 1, c00 + corners, c00 + corners + 1}) trapezoid += at[c] * 0.25;
    const PlanetChannels midpoint = planetRadiance(view, SkyBins::direction(b, 0.5, 0.5));
    // Simpson's (2 M + T) / 3 cancels the h² terms of both; |T − M| / 3 estimates the
    // midpoint's error (more than Simpson's), large only where the limb or the terminator
    // cross the bin.
    PlanetChannels simpson = midpoint * 2.0;
    simpson += trapezoid;
    r.mean[static_cast<size_t>(b)] = simpson * (1.0 / 3.0);
    r.half[static_cast<size_t>(b)] = {std::abs(trapezoid.view - midpoint.view) / 3.0,
                                      std::abs(trapezoid.albedo - midpoint.albedo) / 3.0,
                                      std::abs(trapezoid.ir - midpoint.ir) / 3.0};
  }
  return r;
}

// One node's loads and σ (per channel) from its kernel. The σ: each replica's estimate
// from its counted share per coarse cell times the radiance of the cell's counted bins
// (the cells' correlations kept), the spread of the 32; and the binning error.
void nodeLoads(const geometry::NodeSky& sky, const std::vector<PlanetChannels>& unobstructed, const BinRadiance& radiance,
               PlanetChannels& value, PlanetChannels& sigma) {
  PlanetChannels free, counted, variance;
  for (const auto& [k, share] : sky.normals) free += unobstructed[static_cast<size_t>(k)] * share;
  std::array<PlanetChannels, SkyBins::kCoarse> cell_radiance{};
  std::array<double, SkyBins::kCoarse> cell_weight{};
  for (size_t j = 0; j < sky.bins.size(); ++j) {
    const size_t b = static_cast<size_t>(sky.bins[j]), c = static_cast<size_t>(SkyBins::coarse(sky.bins[j]));
    const double w = M_PI * sky.weights[j];  // E = π × mean of L over cosine-weighted rays
    counted += radiance.mean[b] * w;
    cell_radiance[c] += radiance.mean[b] * w;
    cell_weight[c] += w;
    variance += square(radiance.half[b] * w);
  }
  PlanetChannels sum, sum2;
  for (int r = 0; r < geometry::kSkyReplicas; ++r) {
    PlanetChannels estimate;
    for (size_t k = 0; k < sky.cells.size(); ++k) {
      const size_t c = static_cast<size_t>(sky.cells[k]);
      if (cell_weight[c] > 0) estimate += cell_radiance[c] * (M_PI * sky.cell_shares[k][static_cast<size_t>(r)] / cell_weight[c]);
    }
    sum += estimate;
    sum2 += square(estimate);
  }
  const double m = geometry::kSkyReplicas;
  const auto spread = [m](double s, double s2) { return std::max(0.0, (s2 - s * s / m) / (m - 1)) / m; };
  variance += PlanetChannels{spread(sum.view, sum2.view), spread(sum.albedo, sum2.albedo), spread(sum.ir, sum2.ir)};
  value = sky.counts_open ? counted : PlanetChannels{free.view - counted.view, free.albedo - counted.albedo,
                                                      free.ir - counted.ir};
  // What reaches a node is never below 0 nor above what reaches it unobstructed.
  value = {std::clamp(value.view, 0.0, free.view), std::clamp(value.albedo, 0.0, free.albedo),
           std::clamp(value.ir, 0.0, free.ir)};
  sigma = {std::sqrt(variance.view), std::sqrt(variance.albedo), std::sqrt(variance.ir)};
}

}  // namespace

std::vector<char> skyKernelLoads(const geometry::SkyKernel& kernel, const std::vector<int>& used_bins,
                                 const PlanetView& view, const std::vector<char>& mask, double relative_error, int p,
                                 EnvironmentLoads& out) {
  const int normals = static_cast<int>(kernel.normals.size()), n = static_cast<int>(kernel.nodes.size());
  std::vector<PlanetChannels> unobstructed(static_cast<size_t>(normals));
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 16)
#endif
  for (int k = 0; k < normals; ++k)
    unobstructed[static_cast<size_t>(k)] = unobstructedPlanetLoads(view, kernel.normals[static_cast<size_t>(k)]);
  const BinRadiance radiance = binRadiance(used_bins, view);
  std::vector<char> over(static_cast<size_t>(n), 0);
  const double floor = 0.1 * view.capSin2();
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 64)
#endif
  for (int i = 0; i < n; ++i) {
    const geometry::NodeSky& sky = kernel.nodes[static_cast<size_t>(i)];
    if ((!mask.empty() && !mask[static_cast<size_t>(i)]) || sky.rays == 0) continue;
    PlanetChannels value, sigma;
    nodeLoads(sky, unobstructed, radiance, value, sigma);
    out.earth_view_factor(i, p) = value.view;
    out.albedo(i, p) = value.albedo, out.albedo_stderr(i, p) = sigma.albedo;
    out.earth_ir(i, p) = value.ir, out.earth_ir_stderr(i, p) = sigma.ir;
    over[static_cast<size_t>(i)] = sigma.view > relative_error * std::max(value.view, floor);
  }
  return over;
}

}  // namespace radnet::orbits
