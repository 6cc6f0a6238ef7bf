#pragma once
// The pipeline's share of work across MPI ranks (docs/mpi.md): each stage computes the
// items it owns (cluster::owns, round robin) and these join the parts on every rank. The
// items a rank does not own are +0.0 in its part, and joining takes each owner's bits
// (cluster::join): every rank ends with the single-process numbers bit for bit. With one
// rank, no-ops.
#include "cases/config/case_file.hpp"
#include "cases/pipeline/packing.hpp"
#include "cases/pipeline/stages.hpp"
#include "geometry/rays/view_factors.hpp"
#include "orbits/loads.hpp"
#include "solver/radiative/eigenpairs.hpp"

#include <Eigen/Dense>

#include <string>
#include <vector>

namespace radnet::cases {

/// Every rank must run the same case: a fingerprint of what this rank read (the case file's
/// bytes, its included files, each node's area from the meshes) is compared across the
/// ranks. @throws InputError (on every rank) when they differ, e.g. a file changed on one
/// machine's disk or ranks started in different directories.
void checkSameCase(const std::string& case_path, const LoadedCase& c);

/// Each rank cast the rows it owns: F, σ, F_space, F_blocked and the ray counts of every
/// row on every rank (seconds: the slowest rank's). @throws cluster::PeerFailure
void joinViewFactorRows(geometry::ViewFactorResult& vf);

/// Each rank loaded its sun positions and planet nodes (EnvironmentOptions): every load
/// on every rank; ray counts summed, planet casts and times the largest rank's.
void joinLoads(orbits::EnvironmentLoads& loads);

/// Rank 0 decomposed G: its eigenpairs (and status) on every rank.
void shareEigenPairs(solver::EigenPairs& pairs);

/// Design case k's thermal outcome, solved by rank `owner`, on every rank (bit for bit).
void shareThermal(ThermalOutcome& outcome, int owner);

/// Joins these matrices (each its own shape on every rank; an element given by one rank).
void joinOverRanks(const std::vector<Eigen::MatrixXd*>& matrices);

/// Each stage's time, replaced by the slowest rank's (the wall time the run waited for).
void slowestRankTimings(StageTimings& timings);

}  // namespace radnet::cases
