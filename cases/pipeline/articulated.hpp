#pragma once
// Parts that turn during the orbit (docs/solver.md, "Moving parts"). The rows of F a turning
// part can change (its own nodes' and those of every node facing the cylinder it sweeps) are
// cast as rays in every configuration, the base included, with the same rays (seed) each time:
// what does not move comes out identical, so G(θ) − G(0) holds only what the turn changed.
// Each configuration's pairs are a low-rank update of the one decomposition of G(0)
// (solver/radiative/pair_update.hpp); its loads, band solves and GR are its own.
#include "cases/config/geometry_case.hpp"
#include "cases/pipeline/design_run.hpp"
#include "cases/pipeline/results.hpp"
#include "geometry/rays/ray_caster.hpp"
#include "geometry/rays/recast_rows.hpp"
#include "solver/radiative/pair_update.hpp"

#include <iosfwd>
#include <map>
#include <memory>
#include <optional>
#include <vector>

namespace radnet::cases {

/// One arrangement of the turning parts: every moving drive at one angle.
struct Configuration {
  std::vector<double> angles_deg;  ///< per moving drive (GeometryCase::articulation.drives), deg
  std::unique_ptr<geometry::Scene> own_scene;  ///< the parts turned (null: the base's scene)
  std::unique_ptr<geometry::RayCaster> own_caster;
  RadiativeNetwork own_radiative;
  const geometry::Scene* scene = nullptr;
  const geometry::RayCaster* caster = nullptr;
  const RadiativeNetwork* radiative = nullptr;
  solver::SparseRowMatrix view_factor_stderr;  ///< σ of its F, –
  Eigen::VectorXd lost_view_factor_stderr;     ///< σ of its F_space + F_blocked, –
  std::vector<BandCores> cores;                ///< per optical set, made when first asked
  std::vector<std::optional<solver::ExchangeFactors>> exchange;  ///< per optical set
  solver::PairUpdateStats update;
};

/// The base F with the rows a turning part can change recomputed in every configuration:
/// those the run integrated by the exact method integrated again on each configuration's
/// scene (their pairs alone), the rest cast as rays, and each row's rays.
struct ArticulatedBase {
  geometry::ViewFactorEstimate estimate;  ///< before the reciprocity correction
  Eigen::VectorXd rays;                   ///< per row: its variance weight
  std::vector<char> rows;                 ///< per node: recomputed in every configuration
  std::vector<int> changed;               ///< the same, as indices
  std::vector<char> exact_rows;           ///< of rows, those integrated again in each configuration
  std::vector<char> ray_rows;             ///< of rows, those whose rays are traced again
  geometry::RecastPlan plan;              ///< the ray rows' rays and what no turn can redirect
  geometry::RayMayChange may_change;      ///< which rays a turn can redirect
  std::vector<char> turning_node;                ///< per node: on a moving drive's parts
  std::vector<Eigen::AlignedBox3d> node_box;     ///< per node, its triangles' box as written, m
  std::vector<Eigen::AlignedBox3d> swept_boxes;  ///< the box of every turning entry's swept cylinder, m
  /// Whether the entries of nodes i and j can change as the parts turn: one of them turns, or
  /// the box holding both (and so every line between them) meets a swept cylinder's box.
  bool changesWithTurn(int i, int j) const;
};

/// Which rays the case's drives can redirect: from a fixed node, a ray meeting a cylinder a
/// moving part sweeps; from a moving node, one meeting the cylinder the rest of the scene
/// (other drives' sweeps included) sweeps about its own drive's axis.
geometry::RayMayChange redirectableRays(const GeometryCase& c);

/// The nodes whose rows may change as the case's moving drives turn.
std::vector<char> turningRows(const GeometryCase& c);

/// Replaces the turning rows of `estimate` by rays on the as-written scene (the base every
/// configuration differs from), updating `rays`; with `sampled_rows` (the exact method's
/// rows left to rays, per node) only the turning rows among those: the others stay the
/// run's integrated rows, integrated again in every configuration.
ArticulatedBase articulatedBase(const GeometryCase& c, const geometry::RayCaster& caster,
                                geometry::ViewFactorEstimate estimate, Eigen::VectorXd rays,
                                const std::vector<char>& sampled_rows, std::ostream& progress);

class Articulated {
 public:
  /// @param base_caster, base_radiative  the as-written scene's (outlive this)
  Articulated(const GeometryCase& c, ArticulatedBase base, const geometry::RayCaster& base_caster,
              const RadiativeNetwork& base_radiative, const solver::SparseRowMatrix& base_stderr,
              const Eigen::VectorXd& base_lost_stderr, const solver::SolverSettings& settings);

  /// The configuration of each position (made when first met) and every drive's angle there
  /// (P × drives: the moving drives, then the fixed ones), deg.
  std::vector<int> configure(const std::vector<orbits::SweepPosition>& positions, Eigen::MatrixXd& angles,
                             StageTimings& timings, std::ostream& progress);
  int size() const { return static_cast<int>(configs_.size()); }
  const Configuration& at(int k) const { return *configs_.at(static_cast<size_t>(k)); }
  /// Configuration k's band cores for optical set `optics` (made when first asked).
  const BandCores& cores(int k, int optics, StageTimings& timings);
  /// Configuration k's GR for optical set `optics` (formed when first asked).
  /// @throws NumericalError when it cannot be formed
  const solver::ExchangeFactors& exchange(int k, int optics, StageTimings& timings);
  /// Summed over the configurations made: recast rays, integrated patch pairs.
  std::int64_t rays() const { return rays_; }
  std::int64_t pairs() const { return pairs_; }
  int recastRows() const { return static_cast<int>(base_.changed.size()); }
  int integratedRows() const;
  /// Per node: 1 when its row (and what it receives) can change as the parts turn.
  const std::vector<char>& rows() const { return base_.rows; }
  int largestUpdateRank() const;

 private:
  int configurationOf(const std::vector<double>& angles, StageTimings& timings, std::ostream& progress);
  std::unique_ptr<Configuration> make(const std::vector<double>& angles, std::ostream& progress);
  geometry::ViewFactorEstimate turnedRows(const geometry::Scene& scene, const geometry::RayCaster& caster,
                                          const std::vector<Eigen::Isometry3d>& motion, Eigen::VectorXd& rays);
  geometry::ViewFactorEstimate overlaidRows(const geometry::ViewFactorEstimate& base,
                                            const geometry::ViewFactorEstimate& fresh,
                                            const std::vector<char>& rows) const;
  /// A warning when configuration k's parts meet the fixed spacecraft where they did not as written.
  void warnCollisions(const Configuration& k, std::ostream& progress) const;

  const GeometryCase& c_;
  ArticulatedBase base_;
  const solver::SolverSettings& settings_;
  Eigen::VectorXd area_;
  std::vector<std::unique_ptr<Configuration>> configs_;
  std::map<std::vector<long long>, int> index_;  ///< angles in µdeg → configuration
  Eigen::VectorXd reflectance_;               ///< per node, the largest ρ of either band and any optical set
  std::vector<Eigen::VectorXd> emissivities_;  ///< every optical set's ε (the GR probes')
  std::vector<int> moving_surfaces_;
  std::vector<std::pair<int, int>> written_meetings_;  ///< moving/fixed surfaces that meet as written
  std::int64_t rays_ = 0, pairs_ = 0;
};

/// The base of a run with turning parts: articulatedBase, and the run's F corrected from it
/// (r.correction, raw F and σ's). Timed as articulation.
ArticulatedBase turningBase(const GeometryCase& c, const geometry::RayCaster& caster, const Eigen::VectorXd& area,
                            const geometry::ViewFactorEstimate& estimate, const Eigen::VectorXd& rays,
                            GeometryRunResult& r, std::ostream& progress);

/// What the configurations were, for the output (`a` null: fixed angles only, the names alone).
ArticulationResult articulationResult(const GeometryCase& c, Articulated* a, StageTimings& timings);

}  // namespace radnet::cases
