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
#include <vector>

namespace radnet::orbits {

inline constexpr int kSkyChannels = 3;  ///< view factor, albedo, planet IR
/// Positions a block of radiance tables holds: blocks bound the tables' memory (6 × bins ×
/// kRadianceBlock floats, 19 MB).
inline constexpr int kRadianceBlock = 32;
/// The radiance tables in single precision: a bin's radiance to 6e-8 relative, far below
/// any load's σ, in half the memory (the pages a block's tables touch the first time cost
/// as much as computing them).
using RadianceTable = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
/// Per channel, a block's positions. Row-major: the sums run along a channel's positions (a
/// column-major row's stride of three kept them from vectorising: a third of the nodes'
/// sums on the 19,202-node satellite).
using ChannelRows = Eigen::Array<double, kSkyChannels, Eigen::Dynamic, Eigen::RowMajor>;

// A block of positions' planet radiance (row: a bin, column: a position of the block), per
// channel: the bin's mean by Simpson's rule (the centre and the four corners, cells a step
// crosses split) and the error scale of that mean. Sized once for every bin and kRadianceBlock
// positions; a bin's row is computed the first time a round uses it and kept for the
// rounds after (they re-sweep the nodes over their target, whose bins the first round had
// mostly computed: 0.19 of the 0.54 s of sweeps on the 1,602-node satellite, inertial).
struct RadianceTables {
  std::array<RadianceTable, kSkyChannels> mean, half;
  ChannelRows peak;  // the planet's largest radiance anywhere, per channel and position
  int first = -1;  // the block's first position
  int positions = 0;  // the block's, ≤ kRadianceBlock
  int first_channel = 0;  // the channels before it are neither written nor read
  /// Per bin: whether the planet can reach it at some position of the block. A row it
  /// cannot is neither written nor read (its radiance is 0 all block: a third of an
  /// inertial block's rows on the 1,602-node satellite).
  std::vector<char> lit;
  std::vector<char> computed;  ///< per bin: lit and (if lit) the row are this block's
};

/// The tables of positions [p0, p0 + B), B ≤ kRadianceBlock, of `views`, for the bins
/// `used`: the rows not yet computed for this block (all of them when the tables held
/// another block). Channels from `first_channel` on (1: the view factor's left out, a
/// uniform emitter's IR is its flux times it; a third of the tables' pages).
void radianceBlock(const std::vector<int>& used, const std::vector<PlanetView>& views, int p0, int B,
                   RadianceTables& t, int first_channel = 0);

}  // namespace radnet::orbits
