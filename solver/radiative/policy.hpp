#pragma once
// The solver policy: which algorithm the pipeline uses for a network of a given size and
// a case's settings, with every threshold a named constant (docs/solver.md, "Policy").
// The pipeline (cases/pipeline) asks here; no other code decides.
#include "solver/radiative/eigenpairs.hpp"
#include "solver/radiative/exchange.hpp"
#include "solver/radiative/network.hpp"
#include "solver/radiative/settings.hpp"

#include <Eigen/Dense>

#include <vector>

namespace radnet::solver::policy {

/// EigenMethod::Auto uses the dense solver up to this many nodes: Ashdown §10 finds
/// QR-type methods faster below ~400 elements and Lanczos above.
inline constexpr int kDenseEigenMaxNodes = 400;
/// `auto` falls back to the dense eigensolver when Lanczos does not converge up to this many
/// nodes: its O(n³) stays within minutes there (2,000 nodes: about 2 s on this machine).
inline constexpr int kDenseEigenFallbackMaxNodes = 8000;
/// ... and whenever an explicit rank asks for more than n / kDenseEigenRankDivisor
/// pairs, where Lanczos would rebuild most of the spectrum anyway.
inline constexpr int kDenseEigenRankDivisor = 4;
/// Exact exchange factors by one dense LU (O(n³), 8 n² bytes for the factors) up to this
/// many nodes when the case asks for full accuracy; E G E + E V (C − Λ) Vᵀ E (direct exact,
/// reflections in rank k, the rank grown until the probes' GR meets the tolerance, dense LU
/// again when it cannot) beyond. 1,000: on the 1,602-node satellite the dense LU took 0.56 s
/// of a 2.6 s run, the pairs' GR 0.05 s (rank 111, 1e-8 of GR's largest entry off the LU's);
/// a closed room's flat spectrum falls back to the LU for +0.03 s of Lanczos.
inline constexpr int kDenseExchangeMaxNodes = 1000;
/// With refinement, the rank a posteriori needs only this relative residual of the rank-k
/// answer on the probes (rank_probe.hpp): from there the preconditioned CG reaches the
/// budget's 1e-4 … 1e-3 in one to three iterations (each one product with G per right-hand
/// side), while every doubling of the pairs costs more than the Lanczos run before it.
inline constexpr double kRefinedStartResidual = 1e-2;
/// The band solve's cost model (bandSolveCost): single-thread rates measured on the CI
/// machine (docs/solver-satellite-benchmark.md: Eigen's blocked dense LU about 4e10 flop/s,
/// a sparse product with G plus the thin low-rank products about 4e9). Only their ratio
/// decides; a dense product with G runs at the dense rate.
inline constexpr double kDenseFlopsPerSecond = 4e10;
/// Lanczos on a dense G, per pair found and per n² entry of G, s: a few products with G a
/// pair, each reading all of it from memory (measured: the 6,144-node room's runs at 16, 32
/// and 200 pairs together took 11.7 s, 1.25e-9 s per pair and entry).
inline constexpr double kDenseLanczosSecondsPerPairEntry = 1.25e-9;
inline constexpr double kSparseFlopsPerSecond = 4e9;
/// Dense LU of I − S G for a band solve only up to this many nodes (8 n² bytes each for
/// I − S G and, for a sparse network, a dense copy of G: 1 GiB at the limit).
inline constexpr int kDenseBandSolveMaxNodes = 8000;
/// A corrected view-factor matrix is stored sparse when fewer than this share of its
/// entries is non-zero (sparse products then beat dense ones).
inline constexpr double kSparseStorageMaxDensity = 0.25;
/// Tolerances of a network rebuilt from view factors that the reciprocity/closure
/// correction already made symmetric and closed: only round-off may remain.
inline constexpr NetworkTolerances kCorrectedNetworkTolerances{1e-9, 1e-9};

/// The eigensolver for EigenMethod::Auto on n nodes when `rank` pairs are asked for
/// (0: from a tolerance); an explicit method is returned unchanged.
EigenMethod eigenMethod(EigenMethod requested, int n, int rank);

/// True when a view-factor matrix with `nonzeros` entries of n × n is stored sparse.
bool storeSparse(long long nonzeros, int n);

/// Predicted cost of bringing a band solve of `columns` right-hand sides from the rank-k
/// answer's residual `start_residual` to `tolerance`: preconditioned CG (iterations from the
/// contraction √start_residual per iteration, each one product with G and the thin rank-k
/// products per column) against one dense LU of I − S G and its solves.
struct BandSolveCost {
  int refine_iterations = 0;  ///< predicted CG iterations
  double refine_s = 0.0;      ///< predicted CG time, s
  double direct_s = 0.0;      ///< predicted dense LU time, s (infinite beyond kDenseBandSolveMaxNodes)
  bool direct() const { return direct_s < refine_s; }
};
BandSolveCost bandSolveCost(const Network& net, int rank, Eigen::Index columns, double start_residual,
                            double tolerance);

/// True when GR is formed from the eigenpairs (E G E + E V (C − Λ) Vᵀ E), not by dense LU.
bool exchangeFromPairs(int n, const SolverSettings& settings);

/// The one eigendecomposition of G that serves both bands. An explicit rank is kept; a rank
/// from the tolerance is measured a posteriori on probes (rank_probe.hpp) against the
/// larger of the two bands' reflectance per node (`max_reflectance`), with the a-priori
/// bound |λ| max ρ/A ≤ τ and settings.max_rank as the limits; EigenPairs::rank_rule says which.
/// `emissivities`: every optical set's ε, the GR check's (empty: 1 − max_reflectance).
EigenPairs decomposeForBands(const Network& net, const Eigen::VectorXd& max_reflectance,
                             const SolverSettings& settings, const std::vector<Eigen::VectorXd>& emissivities = {});

/// `pairs` measured on the probes (rank_probe.hpp) against `net`: probe_residual, and
/// probe_exchange_error when GR comes from the pairs and `emissivities` is not empty. For pairs
/// kept as asked (an explicit rank) or made otherwise (an update for turned parts).
EigenPairs measuredPairs(const Network& net, EigenPairs pairs, const Eigen::VectorXd& max_reflectance,
                         const SolverSettings& settings, const std::vector<Eigen::VectorXd>& emissivities);

/// The exchange factors GR: exact by dense LU when the settings ask for full accuracy
/// (refinement) and n ≤ kDenseExchangeMaxNodes, or when the pairs' measured GR error
/// exceeds the tolerance and n ≤ kDenseBandSolveMaxNodes; else E G E + E V (C − Λ) Vᵀ E.
/// ExchangeFactors::method says which; a failure is its status.
ExchangeFactors exchangeFactors(const Network& net, const EigenPairs& pairs, const Eigen::VectorXd& emissivity,
                                const SolverSettings& settings);

}  // namespace radnet::solver::policy
