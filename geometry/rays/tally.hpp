#pragma once
// Where a row's rays land, counted replica by replica, and the row's estimate from the counts:
// shared by the Monte Carlo view factors and the rows recast after parts move.
#include "geometry/rays/ray_caster.hpp"

#include <cstdint>
#include <map>
#include <set>
#include <utility>
#include <vector>

namespace radnet::geometry::tally {

constexpr int kSpace = -1;
constexpr int kBlocked = -2;

/// Target (node index, kSpace or kBlocked) → rays, of one replica.
using Tally = std::map<int, std::int64_t>;

/// What a ray's first hit counts as: a node's side, an inactive side (blocked) or space.
int classify(const RayCaster& caster, const Hit& hit);

/// Mean and standard error of the mean over replicas of the fractions c_r / per_replica.
std::pair<double, double> replicaStats(const std::vector<Tally>& tallies, int target, double per_replica);

/// Every target any replica hit, in increasing order (space and blocked first).
std::set<int> targetsOf(const std::vector<Tally>& tallies);

/// The largest standard error of any target.
double worstError(const std::vector<Tally>& tallies, double per_replica);

/// The row (node, F) and its errors, F_space and F_blocked as (mean, error).
void rowEstimate(const std::vector<Tally>& tallies, double per_replica, std::vector<std::pair<int, double>>& row,
                 std::vector<std::pair<int, double>>& row_error, double space[2], double blocked[2]);

}  // namespace radnet::geometry::tally
