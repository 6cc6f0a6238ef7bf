#include "cases/pipeline/articulated.hpp"

#include "cases/config/error_budget.hpp"
#include "cases/config/errors.hpp"
#include "cases/pipeline/radiative_network.hpp"
#include "cases/pipeline/view_factor_rows.hpp"
#include "solver/radiative/policy.hpp"
#include "geometry/exact/view_factors.hpp"
#include "geometry/scene/part_clearance.hpp"
#include "geometry/scene/swept_volume.hpp"

#include <algorithm>
#include <iterator>
#include <map>

#include <cmath>
#include <ostream>

namespace radnet::cases {
namespace {

constexpr double kRadPerDeg = 3.14159265358979323846 / 180.0;

// Components of G(θ) − G(0) below this are dropped: the base decomposition's own truncation
// (its largest dropped |λ|), or 1e-12 of its largest |λ| when it kept every pair, m².
double updateFloor(const solver::EigenPairs& pairs) {
  const double largest = pairs.rank() ? std::abs(pairs.values[0]) : 0.0;
  return std::max(pairs.dropped_bound, 1e-12 * largest);
}

}  // namespace

int Articulated::integratedRows() const {
  return static_cast<int>(std::count(base_.exact_rows.begin(), base_.exact_rows.end(), 1));
}

Articulated::Articulated(const GeometryCase& c, ArticulatedBase base, const geometry::RayCaster& base_caster,
                         const RadiativeNetwork& base_radiative, const solver::SparseRowMatrix& base_stderr,
                         const Eigen::VectorXd& base_lost_stderr, const solver::SolverSettings& settings)
    : c_(c), base_(std::move(base)), settings_(settings), area_(base_radiative.network->area()) {
  auto zero = std::make_unique<Configuration>();
  zero->angles_deg.assign(c.articulation.drives.size(), 0.0);
  zero->scene = &c.scene;
  zero->caster = &base_caster;
  zero->radiative = &base_radiative;
  zero->view_factor_stderr = base_stderr;
  zero->lost_view_factor_stderr = base_lost_stderr;
  index_[std::vector<long long>(c.articulation.drives.size(), 0)] = 0;
  configs_.push_back(std::move(zero));
  reflectance_ = Eigen::VectorXd::Zero(area_.size());
  for (const OpticalSet& set : c.optical_sets) {
    reflectance_ = reflectance_.cwiseMax((1.0 - set.emissivity.array()).matrix()).cwiseMax((1.0 - set.absorptivity.array()).matrix());
    emissivities_.push_back(set.emissivity);
  }
  for (const Drive& d : c.articulation.drives)
    moving_surfaces_.insert(moving_surfaces_.end(), d.surfaces.begin(), d.surfaces.end());
  written_meetings_ = geometry::meetingSurfaces(c.scene, moving_surfaces_);

}

void Articulated::warnCollisions(const Configuration& k, std::ostream& progress) const {
  const std::vector<std::pair<int, int>> meet = geometry::meetingSurfaces(*k.scene, moving_surfaces_);
  std::vector<std::pair<int, int>> fresh;
  std::set_difference(meet.begin(), meet.end(), written_meetings_.begin(), written_meetings_.end(),
                      std::back_inserter(fresh));
  if (fresh.empty()) return;
  const std::vector<std::string>& names = k.scene->surfaceNames();
  progress << "radnet: warning: articulation: at";
  for (size_t d = 0; d < k.angles_deg.size(); ++d)
    progress << (d ? ", " : " ") << c_.articulation.drives[d].name << " = " << k.angles_deg[d] << "°";
  progress << " the turning parts run into the spacecraft: '" << names[static_cast<size_t>(fresh[0].first)]
           << "' meets '" << names[static_cast<size_t>(fresh[0].second)] << "'";
  if (fresh.size() > 1) progress << " (and " << fresh.size() - 1 << " other pair(s))";
  progress << "; the results there are of interpenetrating geometry (move the axis, or limit the angles)\n";
}

// The base estimate with the turning rows of a configuration's scene: the integrated ones
// integrated again, their node pairs a turn can change alone (changesWithTurn: every other
// row faces away from what turns, so its entries stay the base's, and so do the other pairs
// of a turning row), with auto's plan: a row whose pairs the turn made dearer than its rays
// (a wing turned to face the bus: 30,000 occluded pairs, 1.4 s) has its rays traced again in
// this configuration instead, as the base's ray rows do where a turn can redirect them (the
// first time, its rays are cast in the scene as written into the plan). The ray counts go
// into `rays`.
geometry::ViewFactorEstimate Articulated::turnedRows(const geometry::Scene& scene, const geometry::RayCaster& caster,
                                                     const std::vector<Eigen::Isometry3d>& motion,
                                                     Eigen::VectorXd& rays) {
  const size_t n = base_.rows.size();
  geometry::ViewFactorEstimate estimate;
  const geometry::ViewFactorEstimate* from = &base_.estimate;
  std::vector<char> recast = base_.ray_rows;
  if (std::find(base_.exact_rows.begin(), base_.exact_rows.end(), 1) != base_.exact_rows.end()) {
    geometry::ExactOptions opt = plannedExactOptions(c_);
    opt.rows = base_.exact_rows;
    opt.node_pairs = [this](int i, int j) { return base_.changesWithTurn(i, j); };
    const geometry::ExactResult ex = geometry::exactViewFactors(scene, opt);
    pairs_ += ex.pairs_unoccluded + ex.pairs_occluded;
    std::vector<char> integrated(n, 0);
    for (size_t i = 0; i < n; ++i) {
      integrated[i] = base_.exact_rows[i] && !ex.sampled_rows[i];
      recast[i] = recast[i] || (base_.exact_rows[i] && ex.sampled_rows[i]);
    }
    estimate = overlaidRows(*from, ex, integrated);
    from = &estimate;
  }
  if (std::find(recast.begin(), recast.end(), 1) == recast.end()) return *from;
  std::vector<char> unplanned(n, 0);  // integrated rows this turn sends to rays the first time
  for (size_t i = 0; i < n; ++i) unplanned[i] = recast[i] && base_.plan.per_replica[i] == 0;
  if (std::find(unplanned.begin(), unplanned.end(), 1) != unplanned.end())
    geometry::addPlannedRows(*configs_.front()->caster, base_.may_change, unplanned, base_.plan);
  const geometry::ViewFactorResult vf = geometry::recastRows(caster, base_.plan, base_.may_change, motion, recast);
  rays_ += vf.total_rays;
  for (size_t i = 0; i < n; ++i)
    if (recast[i]) rays[static_cast<Eigen::Index>(i)] = double(vf.rays[i]);
  return geometry::withSampledRows(*from, vf, recast);
}


// `base` with rows `rows` overlaid by `fresh`: in each, the entries of node pairs that can
// change taken from `fresh`, the others kept; F_blocked from `fresh` (its pairs with inactive
// sides are all integrated again), F_space what the row leaves, its σ summed as the exact
// method's.
geometry::ViewFactorEstimate Articulated::overlaidRows(const geometry::ViewFactorEstimate& base,
                                                       const geometry::ViewFactorEstimate& fresh,
                                                       const std::vector<char>& rows) const {
  using Sparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;
  const Eigen::Index n = base.view_factors.rows();
  // Row by row into the compressed arrays (no triplets: at tens of thousands of nodes F has
  // millions of entries, each configuration): an overlaid row is the base's entries no turn
  // changes and the fresh ones it does, two disjoint column-ordered lists merged.
  auto merge = [&](const Sparse& kept, const Sparse& turned) {
    Sparse m(n, n);
    m.reserve(kept.nonZeros() + turned.nonZeros());
    for (Eigen::Index i = 0; i < n; ++i) {
      m.startVec(i);
      const bool overlaid = rows[static_cast<size_t>(i)] != 0;
      const auto changes = [&](Eigen::Index j) { return base_.changesWithTurn(static_cast<int>(i), static_cast<int>(j)); };
      Sparse::InnerIterator k(kept, i);
      Sparse::InnerIterator t(turned, overlaid ? i : 0);
      const auto skip = [&] {
        while (k && overlaid && changes(k.col())) ++k;
        while (overlaid && t && !changes(t.col())) ++t;
      };
      for (skip(); k || (overlaid && t); skip()) {
        const bool from_kept = k && (!overlaid || !t || k.col() < t.col());
        Sparse::InnerIterator& it = from_kept ? k : t;
        m.insertBack(i, it.col()) = it.value();
        ++it;
      }
    }
    m.finalize();
    return m;
  };
  geometry::ViewFactorEstimate out;
  Sparse f = merge(base.view_factors, fresh.view_factors), e = merge(base.standard_error, fresh.standard_error);
  out.view_factors.swap(f);
  out.standard_error.swap(e);
  out.space = base.space, out.space_error = base.space_error;
  out.blocked = base.blocked, out.blocked_error = base.blocked_error;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!rows[static_cast<size_t>(i)]) continue;
    out.blocked[i] = fresh.blocked[i], out.blocked_error[i] = fresh.blocked_error[i];
    out.space[i] = std::max(0.0, 1.0 - out.view_factors.row(i).sum() - out.blocked[i]);
    out.space_error[i] = out.standard_error.row(i).sum() + out.blocked_error[i];
  }
  return out;
}

std::unique_ptr<Configuration> Articulated::make(const std::vector<double>& angles, std::ostream& progress) {
  auto k = std::make_unique<Configuration>();
  k->angles_deg = angles;
  k->own_scene = std::make_unique<geometry::Scene>(c_.scene);
  for (size_t d = 0; d < angles.size(); ++d) {
    const Drive& drive = c_.articulation.drives[d];
    k->own_scene->rotateSurfaces(drive.surfaces, drive.point, drive.direction, angles[d] * kRadPerDeg);
  }
  k->own_caster = std::make_unique<geometry::RayCaster>(*k->own_scene);
  std::vector<Eigen::Isometry3d> motion(area_.size(), Eigen::Isometry3d::Identity());
  for (size_t d = 0; d < angles.size(); ++d) {  // each drive's nodes turn with its parts
    const Drive& drive = c_.articulation.drives[d];
    const Eigen::Isometry3d turn = Eigen::Translation3d(drive.point) *
                                   Eigen::AngleAxisd(angles[d] * kRadPerDeg, drive.direction) *
                                   Eigen::Translation3d(-drive.point);
    for (int i : drive.nodes) motion[static_cast<size_t>(i)] = turn;
  }
  Eigen::VectorXd rays = base_.rays;
  const geometry::ViewFactorEstimate estimate = turnedRows(*k->own_scene, *k->own_caster, motion, rays);
  geometry::ReciprocityCorrection correction = geometry::enforceReciprocity(area_, estimate, rays);
  RadiativeNetwork& net = k->own_radiative;
  net.network = buildNetwork(c_, area_, correction);
  const solver::EigenPairs& pairs0 = configs_.front()->radiative->pairs;
  const Eigen::SparseMatrix<double> change =
      solver::conductanceChange(*configs_.front()->radiative->network, *net.network, base_.changed);
  net.pairs = solver::policy::measuredPairs(*net.network,
                                           solver::updatedPairs(pairs0, change, updateFloor(pairs0), 1, &k->update),
                                           reflectance_, settings_, emissivities_);
  k->view_factor_stderr = estimate.standard_error;
  k->lost_view_factor_stderr =
      (estimate.space_error.array().square() + estimate.blocked_error.array().square()).sqrt();
  k->scene = k->own_scene.get();
  k->caster = k->own_caster.get();
  k->radiative = &k->own_radiative;
  warnCollisions(*k, progress);
  return k;
}

int Articulated::configurationOf(const std::vector<double>& angles, StageTimings& timings, std::ostream& progress) {
  std::vector<long long> key;
  for (double a : angles) key.push_back(std::llround(a * 1e6));
  if (auto it = index_.find(key); it != index_.end()) return it->second;
  StageTimer timer(timings, Stage::Articulation);
  configs_.push_back(make(angles, progress));
  index_[key] = size() - 1;
  return size() - 1;
}

std::vector<int> Articulated::configure(const std::vector<orbits::SweepPosition>& positions, Eigen::MatrixXd& angles,
                                        StageTimings& timings, std::ostream& progress) {
  const Articulation& a = c_.articulation;
  const Eigen::Index P = static_cast<Eigen::Index>(positions.size());
  const Eigen::Index moving = static_cast<Eigen::Index>(a.drives.size());
  angles.resize(P, moving + static_cast<Eigen::Index>(a.fixed_drives.size()));
  angles.leftCols(moving) = a.movingAngles(positions);
  for (size_t f = 0; f < a.fixed_drives.size(); ++f) angles.col(moving + static_cast<Eigen::Index>(f)).setConstant(a.fixed_drives[f].second);
  std::vector<int> config(static_cast<size_t>(P));
  const int before = size();
  for (Eigen::Index p = 0; p < P; ++p) {
    std::vector<double> at(static_cast<size_t>(moving));
    for (Eigen::Index d = 0; d < moving; ++d) at[static_cast<size_t>(d)] = angles(p, d);
    config[static_cast<size_t>(p)] = configurationOf(at, timings, progress);
  }
  if (size() > before)
    progress << "radnet: articulation: " << size() - before << " new configuration(s) of the turning parts ("
             << size() << " in all), each a rank-" << largestUpdateRank() << " (at most) update of the one "
             << "decomposition\n";
  return config;
}

int Articulated::largestUpdateRank() const {
  int rank = 0;
  for (const auto& k : configs_) rank = std::max(rank, k->update.update_rank);
  return rank;
}

const BandCores& Articulated::cores(int k, int optics, StageTimings& timings) {
  Configuration& conf = *configs_.at(static_cast<size_t>(k));
  if (conf.cores.size() != c_.optical_sets.size()) conf.cores.resize(c_.optical_sets.size());
  BandCores& bc = conf.cores[static_cast<size_t>(optics)];
  if (!bc.solar) {
    StageTimer timer(timings, Stage::BandSolves);
    bc = bandCores(*conf.radiative, c_.optical_sets[static_cast<size_t>(optics)]);
  }
  return bc;
}

const solver::ExchangeFactors& Articulated::exchange(int k, int optics, StageTimings& timings) {
  Configuration& conf = *configs_.at(static_cast<size_t>(k));
  if (conf.exchange.size() != c_.optical_sets.size()) conf.exchange.resize(c_.optical_sets.size());
  std::optional<solver::ExchangeFactors>& ex = conf.exchange[static_cast<size_t>(optics)];
  if (!ex) {
    if (optics == 0 && conf.radiative->exchange) ex = *conf.radiative->exchange;
    else ex = exchangeFactors(*conf.radiative, c_.optical_sets[static_cast<size_t>(optics)].emissivity, settings_, timings);
  }
  return *ex;
}

ArticulationResult articulationResult(const GeometryCase& c, Articulated* a, StageTimings& timings) {
  ArticulationResult out;
  out.names = c.articulation.names();
  if (!a) return out;
  out.configuration_angle.resize(a->size(), static_cast<Eigen::Index>(c.articulation.drives.size()));
  for (int k = 0; k < a->size(); ++k) {
    const Configuration& conf = a->at(k);
    for (size_t d = 0; d < conf.angles_deg.size(); ++d)
      out.configuration_angle(k, static_cast<Eigen::Index>(d)) = conf.angles_deg[d];
    out.vertices.push_back(conf.scene->vertexMatrix());
    out.exchange.push_back(a->exchange(k, 0, timings));
    out.update_rank.push_back(conf.update.update_rank);
  }
  out.rays = a->rays();
  out.pairs = a->pairs();
  out.recast_rows = a->recastRows();
  out.integrated_rows = a->integratedRows();
  return out;
}

}  // namespace radnet::cases
