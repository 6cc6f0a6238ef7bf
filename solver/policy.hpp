#pragma once
// The solver policy: which algorithm the pipeline uses for a network of a given size and
// a case's settings, with every threshold a named constant (docs/solver.md, "Policy").
// The pipeline (cases/pipeline) asks here; no other code decides.
#include "solver/eigenpairs.hpp"
#include "solver/exchange.hpp"
#include "solver/network.hpp"
#include "solver/settings.hpp"

#include <Eigen/Dense>

#include <vector>

namespace radnet::solver::policy {

/// EigenMethod::Auto uses the dense solver up to this many nodes: Ashdown §10 finds
/// QR-type methods faster below ~400 elements and Lanczos above.
inline constexpr int kDenseEigenMaxNodes = 400;
/// ... and whenever an explicit rank asks for more than n / kDenseEigenRankDivisor
/// pairs, where Lanczos would rebuild most of the spectrum anyway.
inline constexpr int kDenseEigenRankDivisor = 4;
/// Exact exchange factors by one dense LU (O(n³), 8 n² bytes for the factors) up to this
/// many nodes when the case asks for full accuracy; E G E + E V (C − Λ) Vᵀ E (direct exact, reflections in rank k) beyond.
inline constexpr int kDenseExchangeMaxNodes = 3000;
/// With refinement, the rank a posteriori needs only this relative residual of the rank-k
/// answer on the probes (rank_probe.hpp): from there the preconditioned CG reaches the
/// budget's 1e-4 … 1e-3 in one to three iterations (each one product with G per right-hand
/// side), while every doubling of the pairs costs more than the Lanczos run before it.
inline constexpr double kRefinedStartResidual = 1e-2;
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

/// True when GR is formed from the eigenpairs (E G E + E V (C − Λ) Vᵀ E), not by dense LU.
bool exchangeFromPairs(int n, const SolverSettings& settings);

/// The one eigendecomposition of G that serves both bands. An explicit rank is kept; a rank
/// from the tolerance is measured a posteriori on probes (rank_probe.hpp) against the
/// larger of the two bands' reflectance per node (`max_reflectance`), with the a-priori
/// bound |λ| max ρ/A ≤ τ and settings.max_rank as the limits; EigenPairs::rank_rule says which.
/// `emissivities`: every optical set's ε, the GR check's (empty: 1 − max_reflectance).
EigenPairs decomposeForBands(const Network& net, const Eigen::VectorXd& max_reflectance,
                             const SolverSettings& settings, const std::vector<Eigen::VectorXd>& emissivities = {});

/// The exchange factors GR: exact by dense LU when the settings ask for full accuracy
/// (refinement) and n ≤ kDenseExchangeMaxNodes, else E G E + E V (C − Λ) Vᵀ E.
/// ExchangeFactors::method says which; a failure is its status.
ExchangeFactors exchangeFactors(const Network& net, const EigenPairs& pairs, const Eigen::VectorXd& emissivity,
                                const SolverSettings& settings);

}  // namespace radnet::solver::policy
