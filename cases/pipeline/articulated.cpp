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

std::vector<char> turningRows(const GeometryCase& c) {
  std::vector<char> rows(c.scene.nodes().size(), 0);
  for (const Drive& d : c.articulation.drives) {
    for (int i : d.nodes) rows[static_cast<size_t>(i)] = 1;
    const std::vector<char> facing =
        geometry::nodesFacing(c.scene, geometry::sweptCylinder(c.scene, d.surfaces, d.point, d.direction));
    for (size_t i = 0; i < rows.size(); ++i) rows[i] = rows[i] || facing[i];
  }
  return rows;
}

namespace {

// Every ray of a recast row is tested against each cylinder (a hot path): beyond this many
// geometry entries (a CAD assembly of hundreds of parts) they share one cylinder.
constexpr size_t kMaxEntryCylinders = 8;

// The scene's surfaces grouped by geometry entry (the surface name up to its first '.': a
// grid's cells, a box's faces), those of `drive` (or, with drive < 0, of no drive) only; one
// group of them all beyond kMaxEntryCylinders entries.
std::vector<std::vector<int>> entries(const GeometryCase& c, int drive) {
  const std::vector<std::string>& names = c.scene.surfaceNames();
  std::vector<int> owner(names.size(), -1);
  for (size_t d = 0; d < c.articulation.drives.size(); ++d)
    for (int s : c.articulation.drives[d].surfaces) owner[static_cast<size_t>(s)] = static_cast<int>(d);
  std::map<std::string, std::vector<int>> by_entry;
  for (size_t s = 0; s < names.size(); ++s)
    if (owner[s] == drive) by_entry[names[s].substr(0, names[s].find('.'))].push_back(static_cast<int>(s));
  std::vector<std::vector<int>> out;
  for (auto& [name, surfaces] : by_entry) out.push_back(std::move(surfaces));
  if (out.size() > kMaxEntryCylinders) {
    for (size_t k = 1; k < out.size(); ++k) out.front().insert(out.front().end(), out[k].begin(), out[k].end());
    out.resize(1);
  }
  return out;
}

// `around` grown to hold the cylinder `other` (about another axis) at every angle of its own:
// its bounding sphere, taken about `around`'s axis.
void holdSweep(geometry::SweptCylinder& around, const geometry::SweptCylinder& other) {
  const Eigen::Vector3d mid = other.point + 0.5 * (other.axial_min + other.axial_max) * other.axis;
  const double reach = std::hypot(other.radius, 0.5 * (other.axial_max - other.axial_min));
  const Eigen::Vector3d to = mid - around.point;
  const double t = to.dot(around.axis);
  around.axial_min = std::min(around.axial_min, t - reach);
  around.axial_max = std::max(around.axial_max, t + reach);
  around.radius = std::max(around.radius, (to - t * around.axis).norm() + reach);
}

bool meetsAny(const std::vector<geometry::SweptCylinder>& cylinders, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  for (const geometry::SweptCylinder& c : cylinders)
    if (c.meets(o, d)) return true;
  return false;
}

}  // namespace

geometry::RayMayChange redirectableRays(const GeometryCase& c) {
  // One cylinder per geometry entry (tighter than one per drive: a wing's, not the span of both).
  const geometry::Scene& scene = c.scene;
  const std::vector<Drive>& drives = c.articulation.drives;
  std::vector<int> drive_of(scene.nodes().size(), -1);
  std::vector<geometry::SweptCylinder> sweeps;  // every turning entry about its drive's axis
  std::vector<std::vector<geometry::SweptCylinder>> rest(drives.size());  // what drive d's parts may meet
  for (size_t d = 0; d < drives.size(); ++d) {
    for (int i : drives[d].nodes) drive_of[static_cast<size_t>(i)] = static_cast<int>(d);
    for (const std::vector<int>& entry : entries(c, static_cast<int>(d)))
      sweeps.push_back(geometry::sweptCylinder(scene, entry, drives[d].point, drives[d].direction));
  }
  for (size_t d = 0; d < drives.size(); ++d) {
    for (const std::vector<int>& entry : entries(c, -1))
      rest[d].push_back(geometry::sweptCylinder(scene, entry, drives[d].point, drives[d].direction));
    for (size_t e = 0; e < drives.size(); ++e) {  // another drive's parts, at any of its angles
      if (e == d) continue;
      for (const std::vector<int>& entry : entries(c, static_cast<int>(e))) {
        geometry::SweptCylinder held = geometry::sweptCylinder(scene, {}, drives[d].point, drives[d].direction);
        held.axial_min = INFINITY, held.axial_max = -INFINITY;
        holdSweep(held, geometry::sweptCylinder(scene, entry, drives[e].point, drives[e].direction));
        rest[d].push_back(held);
      }
    }
  }
  return [drive_of, sweeps, rest](int node, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
    const int d = drive_of[static_cast<size_t>(node)];
    return meetsAny(d >= 0 ? rest[static_cast<size_t>(d)] : sweeps, origin, direction);
  };
}

ArticulatedBase articulatedBase(const GeometryCase& c, const geometry::RayCaster& caster,
                                geometry::ViewFactorEstimate estimate, Eigen::VectorXd rays, std::ostream& progress) {
  ArticulatedBase base;
  base.rows = turningRows(c);
  for (size_t i = 0; i < base.rows.size(); ++i)
    if (base.rows[i]) base.changed.push_back(static_cast<int>(i));
  base.may_change = redirectableRays(c);
  geometry::ViewFactorOptions opt = c.view_factors.monte_carlo;
  opt.cast_rows = base.rows;
  // `method: exact` sets no target for rays: the recast rows are sampled all the same, to the
  // error budget's target (rays given in the case are kept as given).
  if (!c.view_factors.rays_pinned && !(opt.target_error > 0)) opt.target_error = kViewFactorShare * c.solver.accuracy;
  const geometry::ViewFactorResult vf = geometry::castPlannedRows(caster, opt, base.may_change, base.plan);
  for (int i : base.changed) rays[i] = double(vf.rays[static_cast<size_t>(i)]);
  base.estimate = geometry::withSampledRows(estimate, vf, base.rows);
  base.rays = std::move(rays);
  std::int64_t traced = 0;
  for (std::int64_t t : base.plan.traced) traced += t;
  progress << "radnet: articulation: " << base.changed.size() << " of " << base.rows.size()
           << " rows can change as the parts turn (their own and those facing the cylinders they sweep): "
           << vf.total_rays << " rays, of which " << traced << " a turn can redirect, traced again in every "
           << "configuration\n";
  return base;
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
  const geometry::ViewFactorResult vf = geometry::recastRows(*k->own_caster, base_.plan, base_.may_change, motion);
  rays_ += vf.total_rays;
  const geometry::ViewFactorEstimate estimate = geometry::withSampledRows(base_.estimate, vf, base_.rows);
  Eigen::VectorXd rays = base_.rays;
  for (int i : base_.changed) rays[i] = double(vf.rays[static_cast<size_t>(i)]);
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
  for (Eigen::Index d = 0; d < moving; ++d) {
    const std::vector<double> drive = a.drives[static_cast<size_t>(d)].angles(positions);
    for (Eigen::Index p = 0; p < P; ++p) angles(p, d) = drive[static_cast<size_t>(p)];
  }
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

ArticulatedBase turningBase(const GeometryCase& c, const geometry::RayCaster& caster, const Eigen::VectorXd& area,
                            const geometry::ViewFactorEstimate& estimate, const Eigen::VectorXd& rays,
                            GeometryRunResult& r, std::ostream& progress) {
  StageTimer timer(r.timings, Stage::Articulation);
  ArticulatedBase base = articulatedBase(c, caster, estimate, rays, progress);
  r.correction = geometry::enforceReciprocity(area, base.estimate, base.rays);
  r.raw_view_factors = base.estimate.view_factors;
  r.view_factor_stderr = base.estimate.standard_error;
  r.row_stderr_max = solver::rowLargestEntries(r.view_factor_stderr, r.view_factor_stderr.rows());
  r.lost_view_factor_stderr =
      (base.estimate.space_error.array().square() + base.estimate.blocked_error.array().square()).sqrt();
  return base;
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
  out.recast_rows = a->recastRows();
  return out;
}

}  // namespace radnet::cases
