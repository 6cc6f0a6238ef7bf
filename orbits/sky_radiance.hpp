#pragma once
// The planet's radiance over the sky kernel's bins (geometry/irradiance/sky_kernel: a cube
// map of 1.4° bins), a block of positions at a time: what every node's counted rays are
// weighed with (orbits/sky_loads). Each bin's mean radiance by Simpson's rule on its centre
// and corners, cells the limb or the terminator cross split to an eighth of the bin, and
// the error scale of that mean (|trapezoid − midpoint| / 3 per cell, summed).
#include "geometry/irradiance/sky_kernel.hpp"
#include "orbits/planet_sky.hpp"

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace radnet::orbits {

inline constexpr int kSkyChannels = 3;  ///< view factor, albedo, planet IR
/// Positions a block of radiance tables holds: blocks bound the tables' memory (at most
/// 6 × bins × kRadianceBlock floats, 19 MB, where the planet reaches every bin all block).
inline constexpr int kRadianceBlock = 32;
/// Per channel, a block's positions. Row-major: the sums run along a channel's positions (a
/// column-major row's stride of three kept them from vectorising: a third of the nodes'
/// sums on the 19,202-node satellite).
using ChannelRows = Eigen::Array<double, kSkyChannels, Eigen::Dynamic, Eigen::RowMajor>;
/// A bin's radiance over its span of a block's positions, single precision (a bin's
/// radiance to 6e-8 relative, far below any load's σ).
using RadianceSpan = Eigen::Map<const Eigen::Array<float, 1, Eigen::Dynamic>>;

// A block of positions' planet radiance per channel: for each bin its mean by Simpson's
// rule (the centre and the four corners, cells a step crosses split) and the error scale
// of that mean, over the positions of the block the planet's cap can reach it (its span:
// from the first such position to the last, packed bin after bin, laid out for every bin when
// the block is first asked for; 0 outside). Packed, not
// bins × positions: an inertial block's planet reaches a bin at a quarter of the
// positions, and on virtual machines fresh memory costs ~2–4 ms a MB to touch
// (docs/benchmarks.md): the dense tables were 38 MB on the 2,306-node satellite. A bin's
// span is computed the first time a round uses it and kept for the rounds after (they
// re-sweep the nodes over their target, whose bins the first round had mostly computed:
// 0.19 of the 0.54 s of sweeps on the 1,602-node satellite, inertial).
struct RadianceTables {
  struct Span {
    std::int64_t offset = 0;  ///< of the bin's first entry in the packed channels
    int first = 0, count = 0;  ///< positions of the block; count 0: the planet never reaches the bin
  };
  /// Packed spans, uninitialised until a bin is computed (each entry is written then, in
  /// the parallel loop that computes it: no serial pass touches the memory first).
  std::array<std::unique_ptr<float[]>, kSkyChannels> mean, half;
  std::vector<Span> spans;  ///< per bin
  ChannelRows peak;  // the planet's largest radiance anywhere, per channel and position
  int first = -1;  // the block's first position
  int positions = 0;  // the block's, ≤ kRadianceBlock
  int first_channel = 0;  // the channels before it are neither written nor read
  std::vector<char> computed;  ///< per bin: its span is this block's

  /// Whether the planet reaches `bin` at some position of the block (if not, its radiance
  /// is 0 all block and the bin has no entries).
  bool lit(int bin) const { return spans[static_cast<size_t>(bin)].count > 0; }
  RadianceSpan meanSpan(int channel, int bin) const { return spanOf(mean, channel, bin); }
  RadianceSpan halfSpan(int channel, int bin) const { return spanOf(half, channel, bin); }
  /// The mean and error scale at one position of the block (0 outside the bin's span).
  float meanAt(int channel, int bin, int q) const { return at(mean, channel, bin, q); }
  float halfAt(int channel, int bin, int q) const { return at(half, channel, bin, q); }

 private:
  using Packed = std::array<std::unique_ptr<float[]>, kSkyChannels>;
  RadianceSpan spanOf(const Packed& v, int channel, int bin) const {
    const Span& s = spans[static_cast<size_t>(bin)];
    return RadianceSpan(v[static_cast<size_t>(channel)].get() + s.offset, s.count);
  }
  float at(const Packed& v, int channel, int bin, int q) const {
    const Span& s = spans[static_cast<size_t>(bin)];
    return q < s.first || q >= s.first + s.count ? 0.0f : v[static_cast<size_t>(channel)][static_cast<size_t>(s.offset + q - s.first)];
  }
};

/// The tables of positions [p0, p0 + B), B ≤ kRadianceBlock, of `views`, for the bins
/// `used`: the rows not yet computed for this block (all of them when the tables held
/// another block). Channels from `first_channel` on (1: the view factor's left out, a
/// uniform emitter's IR is its flux times it; a third of the tables' pages).
void radianceBlock(const std::vector<int>& used, const std::vector<PlanetView>& views, int p0, int B,
                   RadianceTables& t, int first_channel = 0);

}  // namespace radnet::orbits
