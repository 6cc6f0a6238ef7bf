// The base of a run with turning parts (articulated.hpp, ArticulatedBase): which rows a turn
// can change, which of them are integrated again in every configuration and which recast,
// and the base estimate they start from.
#include "cases/pipeline/articulated.hpp"

#include "cases/config/error_budget.hpp"
#include "cases/config/work_estimate.hpp"
#include "cases/pipeline/view_factor_rows.hpp"
#include "geometry/exact/view_factors.hpp"
#include "geometry/scene/swept_volume.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <ostream>

namespace radnet::cases {
namespace {

// The box holding a swept cylinder: along each axis its centre ± the half length's and the
// radius's reach.
Eigen::AlignedBox3d cylinderBox(const geometry::SweptCylinder& c) {
  const Eigen::Vector3d centre = c.point + 0.5 * (c.axial_min + c.axial_max) * c.axis;
  const double half = 0.5 * (c.axial_max - c.axial_min);
  Eigen::Vector3d reach;
  for (int k = 0; k < 3; ++k)
    reach[k] = half * std::abs(c.axis[k]) + c.radius * std::sqrt(std::max(0.0, 1.0 - c.axis[k] * c.axis[k]));
  return Eigen::AlignedBox3d(centre - reach, centre + reach);
}

// The case's ray options for turning rows. `method: exact` sets no target for rays: they
// are sampled all the same, to the error budget's target (rays given in the case are kept).
geometry::ViewFactorOptions turningRayOptions(const GeometryCase& c) {
  geometry::ViewFactorOptions opt = c.view_factors.monte_carlo;
  if (!c.view_factors.rays_pinned && !(opt.target_error > 0)) opt.target_error = kViewFactorShare * c.solver.accuracy;
  return opt;
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

// Rays drawn of an integrated row to find the share a turn can redirect (its binomial σ at
// most 0.016 at 1,024: enough to weigh costs that differ tenfold).
constexpr std::int64_t kRedirectPilotRays = 1024;

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

namespace {

// The boxes changesWithTurn reads: the turning nodes, every node's box, the swept cylinders'.
void layOutTurningBoxes(const GeometryCase& c, ArticulatedBase& base) {
  const geometry::Scene& scene = c.scene;
  base.turning_node.assign(scene.nodes().size(), 0);
  base.node_box.assign(scene.nodes().size(), Eigen::AlignedBox3d());
  for (size_t d = 0; d < c.articulation.drives.size(); ++d) {
    const Drive& drive = c.articulation.drives[d];
    for (int i : drive.nodes) base.turning_node[static_cast<size_t>(i)] = 1;
    for (const std::vector<int>& entry : entries(c, static_cast<int>(d)))
      base.swept_boxes.push_back(cylinderBox(geometry::sweptCylinder(scene, entry, drive.point, drive.direction)));
  }
  for (size_t i = 0; i < scene.nodes().size(); ++i)
    for (int f : scene.nodes()[i].faces)
      for (const Eigen::Vector3d& v : scene.faces()[static_cast<size_t>(f)].v) base.node_box[i].extend(v);
}

// Which of the run's integrated turning rows to integrate again in every configuration: those
// whose changing pairs (integrated once here, as a configuration would) auto's plan predicts
// to cost no more than tracing again the row's redirectable rays: the rays auto predicts for a
// row (rowRays) times the share of them a turn can redirect, from the row's first rays drawn,
// not traced (casting every turning row to its target to count them was 2.35 s of the
// 2,006-node wings' 8 s articulation stage; of the 886 rows whose pairs took measurable time,
// the pairs were a median 135 times cheaper than the rays, 5 % under 36 times, 4 dearer).
// `method: exact` integrates them all. The others go to rays.
std::vector<char> rowsToIntegrate(const GeometryCase& c, const ArticulatedBase& base,
                                  const std::vector<char>& sampled_rows, const geometry::ViewFactorOptions& ray_options) {
  const size_t n = base.rows.size();
  std::vector<char> exact(n, 0);
  if (sampled_rows.size() != n) return exact;
  for (size_t i = 0; i < n; ++i) exact[i] = base.rows[i] && !sampled_rows[i];
  if (c.view_factors.method != ViewFactorMethod::Auto) return exact;
  geometry::ExactOptions opt = plannedExactOptions(c);
  opt.rows = exact;
  opt.node_pairs = [&base](int i, int j) { return base.changesWithTurn(i, j); };
  const geometry::ExactResult ex = geometry::exactViewFactors(c.scene, opt);
  const std::vector<double> share = geometry::redirectableShares(c.scene, ray_options, base.may_change, exact,
                                                                 std::max(1, int(kRedirectPilotRays / ray_options.replicas)));
  for (size_t i = 0; i < n; ++i) {
    const double pairs_ns = ex.row_nanoseconds.size() == n ? double(ex.row_nanoseconds[i]) : 0.0;
    const double rays_ns = share[i] * rowRays(c) * geometry::kSecondsPerRay * 1e9;
    exact[i] = exact[i] && !ex.sampled_rows[i] && pairs_ns <= rays_ns;
  }
  return exact;
}

}  // namespace

ArticulatedBase articulatedBase(const GeometryCase& c, const geometry::RayCaster& caster,
                                geometry::ViewFactorEstimate estimate, Eigen::VectorXd rays,
                                const std::vector<char>& sampled_rows, std::ostream& progress) {
  ArticulatedBase base;
  base.rows = turningRows(c);
  const size_t n = base.rows.size();
  for (size_t i = 0; i < n; ++i)
    if (base.rows[i]) base.changed.push_back(static_cast<int>(i));
  base.may_change = redirectableRays(c);
  layOutTurningBoxes(c, base);
  // The rows left to rays cast once, with what a turn can redirect (the plan every configuration
  // traces again). An integrated row is added to the plan by the first configuration whose turn
  // makes its pairs dearer than its rays (auto's plan, again: Articulated::turnedRows).
  geometry::ViewFactorOptions opt = turningRayOptions(c);
  base.exact_rows = rowsToIntegrate(c, base, sampled_rows, opt);
  base.ray_rows.assign(n, 0);
  for (size_t i = 0; i < n; ++i) base.ray_rows[i] = base.rows[i] && !base.exact_rows[i];
  opt.cast_rows = base.ray_rows;
  const geometry::ViewFactorResult vf = geometry::castPlannedRows(caster, opt, base.may_change, base.plan);
  std::int64_t traced = 0;
  int exact_count = 0;
  for (size_t i = 0; i < n; ++i) {
    exact_count += base.exact_rows[i];
    if (!base.ray_rows[i]) continue;
    rays[static_cast<Eigen::Index>(i)] = double(vf.rays[i]);
    traced += base.plan.traced[i];
  }
  base.estimate = geometry::withSampledRows(estimate, vf, base.ray_rows);
  base.rays = std::move(rays);
  progress << "radnet: articulation: " << base.changed.size() << " of " << n
           << " rows can change as the parts turn (their own and those facing the cylinders they sweep): "
           << exact_count << " integrated again in every configuration (the pairs a turn can change), "
           << base.changed.size() - static_cast<size_t>(exact_count) << " cast as rays (" << traced
           << " rays a turn can redirect, traced again in every configuration)\n";
  return base;
}

// Otherwise nothing that turns can come between them.
bool ArticulatedBase::changesWithTurn(int i, int j) const {
  if (turning_node[static_cast<size_t>(i)] || turning_node[static_cast<size_t>(j)]) return true;
  const Eigen::AlignedBox3d both = node_box[static_cast<size_t>(i)].merged(node_box[static_cast<size_t>(j)]);
  for (const Eigen::AlignedBox3d& swept : swept_boxes)
    if (both.intersects(swept)) return true;
  return false;
}

ArticulatedBase turningBase(const GeometryCase& c, const geometry::RayCaster& caster, const Eigen::VectorXd& area,
                            const geometry::ViewFactorEstimate& estimate, const Eigen::VectorXd& rays,
                            GeometryRunResult& r, std::ostream& progress) {
  StageTimer timer(r.timings, Stage::Articulation);
  ArticulatedBase base =
      articulatedBase(c, caster, estimate, rays, r.exact ? r.exact->sampled_row_mask : std::vector<char>{}, progress);
  r.correction = geometry::enforceReciprocity(area, base.estimate, base.rays);
  r.raw_view_factors = base.estimate.view_factors;
  r.view_factor_stderr = base.estimate.standard_error;
  r.row_stderr_max = solver::rowLargestEntries(r.view_factor_stderr, r.view_factor_stderr.rows());
  r.lost_view_factor_stderr =
      (base.estimate.space_error.array().square() + base.estimate.blocked_error.array().square()).sqrt();
  return base;
}

}  // namespace radnet::cases
