#pragma once
// Every band-solve method of issue 12 on one scene, timed and scored against dense LU in the
// same run: one Markdown section (bench_solver: box rooms; bench_solver_satellites: the
// satellites of bench/cases, read from radnet's HDF5 output).
#include "solver/radiative/network.hpp"

#include <Eigen/Dense>

#include <ostream>
#include <string>

namespace radnet::bench {

struct BandScene {
  std::string title;             ///< the section's heading, before ": n = … nodes"
  const solver::Network& net;
  Eigen::VectorXd reflectance;   ///< ρ of the band solved, –
  Eigen::MatrixXd initial_exitance;  ///< M_o (n × P), W/m²
  /// The error budget's solver tolerance for this scene (rows refined to it, and the
  /// a-posteriori rank's targets); 1e-3 for scenes without a budget.
  double budget_tolerance = 1e-3;
  /// Lanczos pairs for the decay plot and the k rows (all pairs by the dense solver when 0).
  int lanczos_pairs = 0;
};

/// Times and scores every method on the scene; writes its section to `md` and its
/// eigenvalue decay (|λ_i|/|λ_1| per computed pair) as CSV rows "title,n,i,value" to `decay`.
void compareBandMethods(const BandScene& scene, std::ostream& md, std::ostream& decay);

/// The CPU model of this machine, from /proc/cpuinfo.
std::string cpuModel();

}  // namespace radnet::bench
