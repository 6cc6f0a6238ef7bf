#pragma once
// The design cases of a run are swept and solved one after another; their results are then
// joined into one sweep and one thermal solution, positions after positions, so that the
// output writers and `radnet check` see one run with several orbit cases.
#include "cases/pipeline/results.hpp"

#include <Eigen/Dense>

#include <vector>

namespace radnet::cases {

/// Appends the irradiances of `part` (later positions) to `all`, adding its ray counts.
void appendLoads(orbits::EnvironmentLoads& all, const orbits::EnvironmentLoads& part);

/// Columns of the irradiances: `part`'s column j becomes `all`'s column columns[j] (`all`
/// sized n × P on first use), ray counts added. The positions of one configuration of
/// turning parts placed among the others.
void placeLoads(orbits::EnvironmentLoads& all, const orbits::EnvironmentLoads& part, const std::vector<int>& columns,
                Eigen::Index positions);
/// Adds `part`'s irradiances (same shape: loads of other nodes or positions, zero elsewhere)
/// and ray counts to `all`'s.
void addLoads(orbits::EnvironmentLoads& all, const orbits::EnvironmentLoads& part);
/// `all`'s irradiance columns `columns`, for a configuration's band solves.
orbits::EnvironmentLoads loadColumns(const orbits::EnvironmentLoads& all, const std::vector<int>& columns);
/// The band solves' results of `part` placed at `columns` of `all` (sized on first use);
/// residuals and iterations the largest, methods joined.
void placeBands(SweepResult& all, const SweepResult& part, const std::vector<int>& columns);

/// Appends `part` (a later design case's sweep) to `all`.
void appendSweep(SweepResult& all, const SweepResult& part);

/// Appends `part` (a later design case's temperatures and heat flows) to `all`.
void appendThermal(ThermalSolution& all, const ThermalSolution& part);

/// The time weights of positions [first, end) of the sweep's orbit cases [first_case,
/// end_case) for orbit means: the periodic trapezoid rule within each orbit case (eclipse
/// entries and exits make the positions uneven), each case weighted by the time its sweep
/// spans; they sum to 1. Without a sweep: the trapezoid of `times` (a transient without an
/// orbit), or equal weights.
Eigen::VectorXd timeWeights(const SweepResult* sweep, const std::vector<double>& times, Eigen::Index positions,
                            int first_case = 0, int end_case = -1);

/// Orbit minimum, time-weighted mean and maximum of each row of `t` (n×P) with weights `w` (P).
struct OrbitStatistics {
  Eigen::VectorXd min, mean, max;
};
OrbitStatistics orbitStatistics(const Eigen::MatrixXd& t, const Eigen::VectorXd& w);

}  // namespace radnet::cases
