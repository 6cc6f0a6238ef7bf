#pragma once
// The network's rows shared out over MPI ranks (docs/mpi.md, "Rows shared out"): past
// kSharedRowsMinNodes, under mpirun, each rank casts, corrects and keeps only its rows of F,
// σ_F, G and GR's direct part (node i on rank i mod R), so that no rank holds the n × n
// matrices; vectors and the n × k eigenvectors stay whole on every rank.
#include "cases/config/geometry_case.hpp"
#include "geometry/rays/view_factors.hpp"
#include "geometry/reciprocity.hpp"
#include "solver/parallel.hpp"

#include <Eigen/SparseCore>

namespace radnet::cases {

/// From this many nodes up a distributed run shares out the rows: above every size at which
/// the solver forms a dense G or GR (policy: 8,000), and where the matrices start to weigh.
inline constexpr int kSharedRowsMinNodes = 10000;

/// Whether this run shares out the rows: more than one MPI rank, at least kSharedRowsMinNodes
/// nodes, and a case whose stages all work on shared rows (no specular or transmissive
/// surfaces, no parts that turn, no temperatures, no optical samples, no dense matrices
/// asked for in the file); otherwise every rank holds everything, as before.
bool sharesRows(const GeometryCase& c);

/// This process's share of the rows (the MPI collectives as its joins).
solver::RowShare clusterRowShare();

/// m without the rows `share` does not hold (swapped in place: no second full copy).
void keepHeldRows(Eigen::SparseMatrix<double, Eigen::RowMajor>& m, const solver::RowShare& share);

/// F and σ of `estimate` without the rows `share` does not hold (the vectors stay whole).
void keepHeldRows(geometry::ViewFactorEstimate& estimate, const solver::RowShare& share);

/// Each rank cast the rows it holds: the per-node vectors and ray counts joined on every
/// rank, F and σ left as the held rows (seconds: the slowest rank's).
void joinHeldRowVectors(geometry::ViewFactorResult& vf);

/// Each row's largest σ_F, whole on every rank (the held rows' from their holders).
Eigen::VectorXd rowLargestStderr(const Eigen::Ref<const Eigen::SparseMatrix<double, Eigen::RowMajor>>& sigma,
                                 const solver::RowShare& share);

}  // namespace radnet::cases
