#pragma once
// Planet loads of every node at one position from the sky kernel (geometry/irradiance/
// sky_kernel): the unobstructed load of each facet normal (orbits/planet_sky, exact
// rings) less, or for a node that sees mostly spacecraft instead of, the kernel's
// counted rays times the planet's radiance in their bins. No ray is cast per position,
// whatever the attitude.
//
// The σ reported per node: the kernel's sampling error (each coarse cell's replica σ of
// the counted share times π × the largest radiance in that cell, in quadrature) and the
// binning error (each counted bin's share times π × |trapezoid − midpoint| / 3 of the
// radiance over the bin, in quadrature; the bin's radiance itself is Simpson's).
#include "geometry/irradiance/sky_kernel.hpp"
#include "orbits/loads.hpp"
#include "orbits/planet_sky.hpp"

#include <vector>

namespace radnet::orbits {

/// The bins any node's kernel uses (ascending), computed once per kernel.
std::vector<int> usedSkyBins(const geometry::SkyKernel& kernel);

/// Writes column p of earth_view_factor, albedo, earth_ir and their σ for the nodes `mask`
/// leaves in (empty: all). Returns, per node, whether its view-factor σ exceeds
/// relative_error · max(F, 0.1 sin² θ_max) (the planet rays' own target): those nodes
/// need rays at this position.
std::vector<char> skyKernelLoads(const geometry::SkyKernel& kernel, const std::vector<int>& used_bins,
                                 const PlanetView& view, const std::vector<char>& mask, double relative_error, int p,
                                 EnvironmentLoads& out);

}  // namespace radnet::orbits
