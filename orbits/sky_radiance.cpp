#include "orbits/sky_radiance.hpp"

#include <algorithm>
#include <cmath>

namespace radnet::orbits {

using geometry::SkyBins;

namespace {

constexpr int kChannels = kSkyChannels;

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


// Only bins that can reach into the planet's cap carry radiance: the angle from the cap's
// axis to the bin's centre at most the cap's angular radius plus the bin's. The cosine of
// that angle.
double cosReach(const PlanetView& view) {
  const double cap = std::asin(std::sqrt(view.capSin2()));
  const double bin_radius = std::acos(std::clamp(binDirections().cos_radius, -1.0, 1.0));
  return std::cos(std::min(M_PI, cap + bin_radius));
}

// The planet's largest radiance anywhere at a view, per channel (W/m²/sr; 1/π for the view
// factor).
std::array<double, kChannels> peakRadiance(const PlanetView& v) {
  return {1.0 / M_PI, v.albedo * v.solar_flux_w_m2 / M_PI, v.ir.maxExitance(v.solar_flux_w_m2) / M_PI};
}

// Cells a limb or terminator crosses are split into four, to kMaxSplits levels (a bin's
// 1/8 at most): where the radiance steps, Simpson's rule on the whole 1.4° bin errs by up
// to a third of the step, and that error, summed over a node's bins (nodeLoads), left less
// of the budget for the rays than the rays' own spread (4.8 M kernel rays against 2.0 M
// on the 1,602-node satellite, inertial). A cell splits where its |T − M| passes
// kSplitShare of the planet's peak radiance: smooth radiance differs there by ~1e-4.
constexpr int kMaxSplits = 3;
constexpr double kSplitShare = 1e-2;

// One cell of bin b, [s, s + h] × [t, t + h] in the bin's fractional coordinates, given its
// corners' and centre's radiance: adds its Simpson mean and error scale, times `area` (its
// share of the bin), to mean and half. Splits where a step crosses it.
struct BinCell {
  const PlanetView& view;
  int bin;
  std::array<double, kChannels> split_at;  // |T − M| that splits, per channel
  std::array<double, kChannels> mean{}, half{};

  PlanetChannels at(double s, double t) const { return planetRadiance(view, SkyBins::direction(bin, s, t)); }

  void add(double s, double t, double h, const std::array<PlanetChannels, 4>& corner, const PlanetChannels& centre,
           int splits, double area) {
    PlanetChannels trapezoid;
    for (const PlanetChannels& c : corner) trapezoid += c * 0.25;
    const std::array<double, kChannels> m = values(centre), tr = values(trapezoid);
    bool split = false;
    for (int c = 0; c < kChannels; ++c) split = split || std::abs(tr[c] - m[c]) > split_at[static_cast<size_t>(c)];
    if (split && splits < kMaxSplits) {
      // Corners 0 (s, t), 1 (s + h, t), 2 (s, t + h), 3 (s + h, t + h); the children share
      // the parent's centre and the four edge midpoints.
      const double g = 0.5 * h;
      const PlanetChannels below = at(s + g, t), above = at(s + g, t + h), left = at(s, t + g), right = at(s + h, t + g);
      add(s, t, g, {corner[0], below, left, centre}, at(s + 0.5 * g, t + 0.5 * g), splits + 1, 0.25 * area);
      add(s + g, t, g, {below, corner[1], centre, right}, at(s + 1.5 * g, t + 0.5 * g), splits + 1, 0.25 * area);
      add(s, t + g, g, {left, centre, corner[2], above}, at(s + 0.5 * g, t + 1.5 * g), splits + 1, 0.25 * area);
      add(s + g, t + g, g, {centre, right, above, corner[3]}, at(s + 1.5 * g, t + 1.5 * g), splits + 1, 0.25 * area);
      return;
    }
    // Simpson's (2 M + T) / 3 cancels the h² terms of both; |T − M| / 3 estimates the
    // midpoint's error (more than Simpson's), large only where a step crosses the cell.
    for (int c = 0; c < kChannels; ++c) {
      mean[static_cast<size_t>(c)] += area * (2.0 * m[c] + tr[c]) / 3.0;
      half[static_cast<size_t>(c)] += area * std::abs(tr[c] - m[c]) / 3.0;
    }
  }
};

// What one position needs of its view for the tables: the reach of its cap and the steps
// that split a cell.
struct PositionView {
  const PlanetView* view;
  double cos_reach;
  std::array<double, kChannels> split_at;
};

// Bins `chunk` of the radiance tables at every position of their spans (one thread). A
// chunk of consecutive bins at all positions, not a position at all bins: a position's pass
// over every bin touched a cache line of each of the four tables per bin, and that traffic
// was a third of the tables' time; a chunk's entries stay in cache. Corners are shared by a
// chunk's bins at one position (computed once, the touched ones reset after). Every entry
// of a bin's span is written: 0 where the planet does not reach it.
void chunkRadiance(const int* chunk, int count, const std::vector<PositionView>& at_position, RadianceTables& t) {
  constexpr int edge = SkyBins::kBinsPerEdge, corners = edge + 1;
  const BinDirections& dirs = binDirections();
  thread_local std::vector<PlanetChannels> at;
  thread_local std::vector<char> have;
  thread_local std::vector<size_t> touched;
  at.resize(dirs.corners.size());
  have.resize(dirs.corners.size(), 0);
  for (int q = 0; q < static_cast<int>(at_position.size()); ++q) {
    const PositionView& pv = at_position[static_cast<size_t>(q)];
    const PlanetView& view = *pv.view;
    const auto corner = [&](size_t c) -> const PlanetChannels& {
      if (!have[c]) at[c] = planetRadiance(view, dirs.corners[c]), have[c] = 1, touched.push_back(c);
      return at[c];
    };
    for (int k = 0; k < count; ++k) {
      const int b = chunk[k];
      const RadianceTables::Span& span = t.spans[static_cast<size_t>(b)];
      if (q < span.first || q >= span.first + span.count) continue;
      const auto entry = static_cast<size_t>(span.offset + q - span.first);
      if (dirs.centres[static_cast<size_t>(b)].dot(view.toward_center) < pv.cos_reach) {
        for (int c = t.first_channel; c < kChannels; ++c)
          t.mean[static_cast<size_t>(c)][entry] = t.half[static_cast<size_t>(c)][entry] = 0.0f;
        continue;
      }
      const int face = b / (edge * edge), i = (b / edge) % edge, j = b % edge;
      const size_t c00 = static_cast<size_t>((face * corners + i) * corners + j);
      BinCell cell{view, b, pv.split_at};
      cell.add(0.0, 0.0, 1.0, {corner(c00), corner(c00 + corners), corner(c00 + 1), corner(c00 + corners + 1)},
               planetRadiance(view, dirs.centres[static_cast<size_t>(b)]), 0, 1.0);
      for (int c = t.first_channel; c < kChannels; ++c) {
        t.mean[static_cast<size_t>(c)][entry] = static_cast<float>(cell.mean[static_cast<size_t>(c)]);
        t.half[static_cast<size_t>(c)][entry] = static_cast<float>(cell.half[static_cast<size_t>(c)]);
      }
    }
    for (const size_t c : touched) have[c] = 0;
    touched.clear();
  }
}

}  // namespace

void radianceBlock(const std::vector<int>& used, const std::vector<PlanetView>& views, int p0, int B,
                   RadianceTables& t, int first_channel) {
  constexpr int bins = geometry::SkyBins::kBins;
  std::vector<PositionView> at_position;
  for (int q = 0; q < B; ++q) {
    const PlanetView& view = views[static_cast<size_t>(p0 + q)];
    std::array<double, kChannels> split_at = peakRadiance(view);
    for (double& share : split_at) share *= kSplitShare;
    at_position.push_back({&view, cosReach(view), split_at});
  }
  if (t.first != p0 || t.positions != B || t.first_channel != first_channel) {
    t.first = p0, t.positions = B, t.first_channel = first_channel;
    t.computed.assign(bins, 0);
    t.peak = ChannelRows::Zero(kChannels, B);
    for (int q = 0; q < B; ++q) {
      const std::array<double, kChannels> peak = peakRadiance(views[static_cast<size_t>(p0 + q)]);
      for (int c = 0; c < kChannels; ++c) t.peak(c, q) = peak[static_cast<size_t>(c)];
    }
    // Every bin's span: the first and last positions the planet's cap can reach it.
    const BinDirections& dirs = binDirections();
    t.spans.assign(bins, {});
    std::int64_t entries = 0;
    for (int b = 0; b < bins; ++b) {
      int lo = B, hi = -1;
      for (int q = 0; q < B; ++q)
        if (dirs.centres[static_cast<size_t>(b)].dot(at_position[static_cast<size_t>(q)].view->toward_center) >=
            at_position[static_cast<size_t>(q)].cos_reach)
          lo = std::min(lo, q), hi = q;
      if (hi >= 0) t.spans[static_cast<size_t>(b)] = {entries, lo, hi - lo + 1}, entries += hi - lo + 1;
    }
    for (int c = 0; c < kChannels; ++c) {
      const bool kept = c >= first_channel;
      t.mean[static_cast<size_t>(c)].reset(kept ? new float[static_cast<size_t>(entries)] : nullptr);
      t.half[static_cast<size_t>(c)].reset(kept ? new float[static_cast<size_t>(entries)] : nullptr);
    }
  }
  std::vector<int> lit;  // the bins not computed yet the block lights
  for (const int b : used)
    if (!t.computed[static_cast<size_t>(b)]) {
      t.computed[static_cast<size_t>(b)] = 1;
      if (t.lit(b)) lit.push_back(b);
    }
  constexpr int kChunk = 256;
  const int chunks = (static_cast<int>(lit.size()) + kChunk - 1) / kChunk;
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1)
#endif
  for (int k = 0; k < chunks; ++k)
    chunkRadiance(lit.data() + static_cast<size_t>(k) * kChunk,
                  std::min(kChunk, static_cast<int>(lit.size()) - k * kChunk), at_position, t);
}

}  // namespace radnet::orbits
