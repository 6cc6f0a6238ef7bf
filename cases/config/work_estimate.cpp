#include "cases/config/work_estimate.hpp"

#include "geometry/exact/view_factors.hpp"
#include "geometry/rays/recast_rows.hpp"
#include "geometry/rays/view_factors.hpp"
#include "orbits/sweep.hpp"
#include "solver/radiative/policy.hpp"

#include <sys/resource.h>
#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <random>
#include <set>
#include <sstream>

namespace radnet::cases {
namespace {

std::string gigabytes(double bytes) {
  std::ostringstream s;
  s.precision(3);
  s << bytes / 1e9 << " GB";
  return s.str();
}

// A process limit, bytes; 0 when there is none.
double resourceLimit(int resource) {
  struct rlimit limit {};
  if (::getrlimit(resource, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return 0;
  return static_cast<double>(limit.rlim_cur);
}

// The cgroup v2 memory limit of this process ("max" or absent: none).
double cgroupLimit() {
  std::ifstream in("/sys/fs/cgroup/memory.max");
  std::string text;
  if (!(in >> text) || text == "max") return 0;
  try {
    return std::stod(text);
  } catch (const std::exception&) {
    return 0;
  }
}

// The configurations the turning parts take: the distinct rows of the drives' binned angles
// over every design case's positions (Articulation::movingAngles, what
// Articulated::configure makes of them), and the geometry as written. The sweeps are flown
// here as the run flies them (a few milliseconds); counting every step of every drive
// instead (360° / step) took a steered dish's ±30° table for 73 configurations where it
// makes 13, and its estimate to 5.2 GB for a run that peaks at 0.37 GB (refused outright
// below that on a dense network). Over a million positions (refused for their results'
// memory) or where a sweep cannot be flown (refused where it is parsed), every step counts.
double turningConfigurations(const GeometryCase& c, double positions) {
  const std::vector<Drive>& drives = c.articulation.drives;
  double every_step = 1.0;
  for (const Drive& d : drives) every_step *= d.step_deg > 0 ? std::floor(360.0 / d.step_deg) + 1.0 : positions;
  every_step = std::min(every_step, positions + 1.0);
  if (positions > 1e6) return every_step;
  std::set<std::vector<double>> seen{std::vector<double>(drives.size(), 0.0)};
  try {
    for (const DesignCase& d : c.design_cases) {
      if (!d.orbit) continue;
      for (const OrbitCase& oc : d.orbit->cases) {
        if (!oc.orbit) continue;
        const Eigen::MatrixXd angles =
            c.articulation.movingAngles(orbits::sweepOrbit(*oc.orbit, d.orbit->attitude, d.orbit->sweep));
        for (Eigen::Index p = 0; p < angles.rows(); ++p) {
          const Eigen::RowVectorXd row = angles.row(p);
          seen.emplace(row.data(), row.data() + row.size());
        }
      }
    }
  } catch (const std::exception&) {
    return every_step;
  }
  return static_cast<double>(seen.size());
}

}  // namespace

double physicalMemory() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 0.0;
}

MemoryLimit memoryLimit() {
  MemoryLimit best;
  const auto consider = [&](double bytes, const std::string& what) {
    if (bytes > 0 && (best.bytes <= 0 || bytes < best.bytes)) best = {bytes, what + " of " + gigabytes(bytes)};
  };
  consider(physicalMemory(), "this machine's memory");
  consider(resourceLimit(RLIMIT_AS), "the process's address-space limit (ulimit -v)");
  consider(resourceLimit(RLIMIT_DATA), "the process's data limit (ulimit -d)");
  consider(cgroupLimit(), "the cgroup's memory.max");
  return best;
}

void checkSceneMemory(const YamlDocument& doc, const YAML::Node& where, const std::string& what, double triangles) {
  const MemoryLimit memory = memoryLimit();
  const double need = kSceneBytesPerTriangle * triangles;
  if (memory.bytes <= 0 || need <= memory.bytes) return;
  std::ostringstream m;
  m << what << ": the scene reaches " << triangles << " triangles, about " << gigabytes(need)
    << " of memory for the triangles alone, more than " << memory.source
    << ": coarser subdivisions or meshes (a repeated alias builds its surface again each time)";
  throw doc.error(where, m.str());
}

double facingPairShare(const geometry::Scene& scene) {
  const std::vector<geometry::Node>& nodes = scene.nodes();
  const auto n = static_cast<std::uint32_t>(nodes.size());
  if (n < 2) return 1.0;
  std::mt19937 rng(20261206u);  // fixed: the estimate, and a refusal, do not change run to run
  std::uniform_int_distribution<std::uint32_t> pick(0, n - 1);
  // A random face of the node: its centroid and its side's normal.
  const auto sample = [&](std::uint32_t i, geometry::Vec3& at, geometry::Vec3& normal) {
    const geometry::Node& node = nodes[i];
    std::uniform_int_distribution<size_t> face(0, node.faces.size() - 1);
    const geometry::Face& f = scene.faces()[static_cast<size_t>(node.faces[face(rng)])];
    at = (f.v[0] + f.v[1] + f.v[2]) / 3.0;
    normal = f.normal * static_cast<double>(node.side);
  };
  constexpr int kPairs = 100000;
  int facing = 0;
  for (int k = 0; k < kPairs; ++k) {
    const std::uint32_t i = pick(rng), j = pick(rng);
    if (i == j) continue;  // a node facing itself (concave) is one entry of n
    geometry::Vec3 ci, ni, cj, nj;
    sample(i, ci, ni);
    sample(j, cj, nj);
    facing += (cj - ci).dot(ni) > 0 && (ci - cj).dot(nj) > 0;
  }
  return static_cast<double>(facing) / kPairs;
}

double rowRays(const GeometryCase& c) {
  const geometry::ViewFactorOptions& mc = c.view_factors.monte_carlo;
  if (mc.target_error <= 0) return double(mc.rays_per_node);
  return std::clamp(geometry::kRaysPerRowUnderTarget, double(mc.min_rays_per_node), double(mc.rays_per_node));
}

std::int64_t pairEntriesCap(const GeometryCase& c, double memory_bytes) {
  if (!(memory_bytes > 0)) return -1;
  const double floor = kMinBytesPerNode * double(c.scene.nodes().size()) * double(c.optical_sets.size());
  return static_cast<std::int64_t>(std::max(0.0, kPairEntriesMemoryShare * memory_bytes - floor) / kBytesPerPairEntry);
}

double sampledRowEntries(const geometry::Scene& scene, double rays) {
  const auto n = static_cast<std::int64_t>(scene.nodes().size());
  constexpr std::int64_t kRows = 64;
  geometry::ViewFactorOptions opt;
  opt.rays_per_node = std::max<std::int64_t>(1024, std::llround(rays));
  opt.cast_rows.assign(static_cast<size_t>(n), 0);
  std::mt19937_64 rng(20261206u);  // fixed: the estimate does not change run to run
  std::vector<std::int64_t> order(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  const std::int64_t rows = std::min(n, kRows);
  for (std::int64_t k = 0; k < rows; ++k) {  // the first `rows` of a Fisher–Yates shuffle
    std::uniform_int_distribution<std::int64_t> pick(k, n - 1);
    std::swap(order[static_cast<size_t>(k)], order[static_cast<size_t>(pick(rng))]);
    opt.cast_rows[static_cast<size_t>(order[static_cast<size_t>(k)])] = 1;
  }
  const geometry::RayCaster caster(scene);
  const geometry::ViewFactorResult vf = geometry::computeViewFactors(caster, opt);
  return rows > 0 ? double(vf.view_factors.nonZeros()) / double(rows) : 0.0;
}

namespace {
// Temperatures keep GR factored (solver/thermal/jacobian.hpp) unless optics follow
// temperature or parts turn: those re-form GR densely.
bool denseThermal(const GeometryCase& c) {
  bool curves = false;
  for (const auto& [name, m] : c.materials) curves = curves || m.hasCurves();
  return c.thermal && (curves || !c.articulation.drives.empty());
}

// Bytes per entry of F's raw estimate while the network is built: the raw F and σ_F, the
// corrected F (with each cast entry's transpose: up to twice the raw entries) and its
// column-major copy, (A F)ᵀ and G, at 12 B a non-zero. Measured: the 100,002-node defaults
// peak 13.5 GB, about 110 B a raw entry above the floor.
constexpr double kSparseCopies = 10.0, kBytesPerSparseEntry = 12.0 * kSparseCopies;
// A bound above this is refined by casting a few rows (about 0.1–1 s at 100,000 nodes).
constexpr double kSampleRowsAboveBytes = 2e9;
constexpr double kSampledRowsMargin = 1.25;

// A dense network's matrices, the larger of two moments. The correction: the estimate's F and
// σ_F, the pairs (24 B each, half an entry's worth of 12 B twice) and the corrected F, all at
// 12 B a non-zero; `method: exact` corrects in place (F and σ_F, 4 B an entry for the pairs'
// variances: 28 B), while `auto` may leave rows to rays, which breaks the symmetric pattern
// that needs. The solve and the file: three n × n matrices (G, and I − S G with its solve in
// the LU; the Cholesky needs one fewer), one GR per further optical set, up to
// kDenseOutputMaxNodes the CSR copies being written (12 B a non-zero, two at a time), and σ_F
// when a sweep or temperatures read it (the raw F and σ_F are written out as soon as they are
// final). Measured: the 6,144-node room (83 % of F non-zero, auto) peaks at 0.91 GB in the
// correction (this says 1.66), the 3,456-node one at 0.51 GB writing its CSR copies (this
// says 0.53).
double denseNetworkBytes(const GeometryCase& c, double n, double facing_share, double extra_sets) {
  double estimate_entries = std::max(facing_share * n * n, n);
  if (c.view_factors.method == ViewFactorMethod::MonteCarlo)
    estimate_entries = std::min(estimate_entries, n * static_cast<double>(c.view_factors.monte_carlo.rays_per_node));
  const double correction = (c.view_factors.method == ViewFactorMethod::Exact ? 28.0 : 48.0) * estimate_entries;
  const double csr_copy = n <= double(kDenseOutputMaxNodes) ? 24.0 * estimate_entries : 0.0;
  const double solve = (c.readsViewFactorErrors() ? 12.0 : 0.0) * estimate_entries + 8.0 * n * n * (3.0 + extra_sets) + csr_copy;
  return std::max(correction, solve);
}

// F's non-zeros: every facing pair, or at most the rays of each row (monte_carlo); when that is
// large and rows are cast, auto's cap on integrated entries plus the sampled rows' entries.
double sparseNonzeros(const GeometryCase& c, double n, double facing_share, bool& sampled) {
  double nonzeros = std::max(facing_share * n * n, n);
  const ViewFactorMethod method = c.view_factors.method;
  if (method == ViewFactorMethod::MonteCarlo)
    nonzeros = std::min(nonzeros, n * static_cast<double>(c.view_factors.monte_carlo.rays_per_node));
  if (method == ViewFactorMethod::Exact || nonzeros * kBytesPerSparseEntry <= kSampleRowsAboveBytes) return nonzeros;
  const double cast = n * kSampledRowsMargin * sampledRowEntries(c.scene, rowRays(c));
  const double cap = method == ViewFactorMethod::Auto ? double(pairEntriesCap(c, memoryLimit().bytes)) : 0.0;
  if (cap < 0) return nonzeros;  // memory unknown: auto's integrated rows are not bounded
  sampled = cap + cast < nonzeros;
  return std::min(nonzeros, cap + cast);
}
}  // namespace

WorkEstimate estimateWork(const GeometryCase& c) {
  WorkEstimate w;
  const double n = static_cast<double>(c.scene.nodes().size());
  const double triangles = static_cast<double>(c.scene.faces().size());
  w.scene_bytes = kSceneBytesPerTriangle * triangles;
  const double thermal_nodes = c.thermal ? static_cast<double>(c.thermal->nodeCount()) : n;
  // A dense network (or temperatures with a dense GR: the thermal solver then holds GR and
  // its Jacobian densely): denseNetworkBytes. Measured peaks: 24 n² bytes for a 3,872-node
  // enclosure of 12 % density (an earlier build), 42 n² for the 6,144-node closed room (83 %). A sparse one: F, its raw estimate and σ, G and GR's
  // direct part at 12 B a non-zero, twice over while the correction builds them, and n × k
  // vectors (the 19,202-node satellite, F 1.3 % non-zero: 1.2 GB peak, 63 kB a node).
  const double extra_sets = static_cast<double>(c.optical_sets.size() - 1);
  w.facing_share = n > 1 ? facingPairShare(c.scene) : 1.0;
  w.sparse = !denseThermal(c) && w.facing_share < solver::policy::kSparseStorageMaxDensity;
  if (w.sparse) {
    w.nonzeros = sparseNonzeros(c, n, w.facing_share, w.rows_sampled);
    w.sparse_floor_bytes = kMinBytesPerNode * n * (1.0 + extra_sets);
    // Temperatures: the thermal network's copy of GR's direct part and the Jacobian's sparse part.
    w.dense_bytes = w.nonzeros * kBytesPerSparseEntry * (1.0 + (extra_sets + (c.thermal ? 2.0 : 0.0)) / kSparseCopies) +
                    w.sparse_floor_bytes;
  } else {
    w.dense_bytes = denseNetworkBytes(c, n, w.facing_share, extra_sets);
  }
  for (const DesignCase& d : c.design_cases) {
    if (!d.orbit) continue;
    const orbits::SweepOptions& s = d.orbit->sweep;
    // Positions per orbit and up to four inserted eclipse entries and exits per orbit.
    const double per_case = s.positions_per_orbit * s.orbits + 4.0 * std::ceil(s.orbits);
    w.positions += static_cast<long long>(std::min(per_case * static_cast<double>(d.orbit->cases.size()), 9e18));
    // Rays given: at most every one a hit point, 24 B. By the error budget: 64 kB per node at
    // a load error of 0.005 (the satellite benchmarks' peaks, docs/benchmarks.md), rays going
    // as the inverse square of the error, at most kMaxPlanetRays.
    const orbits::EnvironmentOptions& env = d.orbit->environment;
    const double budget = env.relative_error > 0 ? 64e3 * std::pow(0.005 / env.relative_error, 2) : 0.0;
    const double per_node = env.planet_rays > 0 ? 24.0 * static_cast<double>(env.planet_rays)
                                                : std::min(budget, 24.0 * static_cast<double>(orbits::kMaxPlanetRays));
    w.planet_bytes = std::max(w.planet_bytes, per_node * n);  // cast once per case, then freed
  }
  // Turning parts: each configuration keeps its scene, its network (G dense below the sparse
  // threshold), its GR and, with temperatures, the thermal network's GR.
  if (!c.articulation.drives.empty()) {
    w.configurations = turningConfigurations(c, static_cast<double>(w.positions));
    w.dense_bytes += w.configurations * (8.0 * n * n * (c.thermal ? 3.0 : 2.0) + kSceneBytesPerTriangle * triangles);
    // The rays a turn can redirect, kept from the base: at most every row's rays (what a
    // sampled row takes, rowRays), never beyond geometry::kMaxKeptRayBytes.
    const double rays = n * rowRays(c);
    w.dense_bytes += std::min(geometry::kMaxKeptRayBytes, rays * sizeof(geometry::RecastPlan::Ray));
  }
  // About 25 per-node series (loads, irradiances, heat flows, temperature; several kept twice
  // while cases are joined) and 4 per-triangle ParaView copies on two sides.
  w.position_bytes = 8.0 * static_cast<double>(w.positions) * (25.0 * thermal_nodes + 8.0 * triangles);
  return w;
}

void checkWorkEstimate(const YamlDocument& doc, GeometryCase& c, double memory_bytes) {
  MemoryLimit memory = memoryLimit();
  if (memory_bytes > 0) memory = {memory_bytes, "the given " + gigabytes(memory_bytes)};
  memory_bytes = memory.bytes;
  if (memory_bytes <= 0) return;  // unknown: nothing to compare with
  const WorkEstimate w = estimateWork(c);
  if (w.total() <= memory_bytes) return;
  if (w.sparse && w.floorTotal() <= memory_bytes) {
    std::ostringstream m;
    m << "geometry: the " << c.scene.nodes().size() << "-node sparse network may need up to " << gigabytes(w.total())
      << " (" << 100.0 * w.facing_share << " % of node pairs face each other: "
      << (w.rows_sampled ? "F's non-zeros estimated from sampled rows and auto's memory cap"
                         : "F's non-zeros are bounded, not known, before the view factors")
      << "), more than " << memory.source << "; a run that runs out stops with exit 2";
    c.warnings.push_back(m.str());
    return;
  }
  const YAML::Node& root = doc.root();
  std::string where = "geometry";
  YAML::Node at = root["geometry"];
  if (w.planet_bytes >= std::max(w.dense_bytes, w.position_bytes) && root["environment"] &&
      root["environment"]["planet_rays"]) {
    where = "environment.planet_rays", at = root["environment"]["planet_rays"];
  } else if (w.position_bytes >= std::max(w.dense_bytes, w.scene_bytes) && root["orbit"]) {
    where = "orbit", at = root["orbit"]["positions"] ? root["orbit"]["positions"] : root["orbit"];
  }
  std::ostringstream m;
  m << where << ": this case would need about " << gigabytes(w.total()) << " of memory (" << gigabytes(w.scene_bytes)
    << " for " << c.scene.faces().size() << " triangles, " << gigabytes(w.dense_bytes)
    << " for the " << c.scene.nodes().size() << "-node matrices, " << gigabytes(w.planet_bytes)
    << " for planet-ray hit points, " << gigabytes(w.position_bytes) << " for " << w.positions
    << " positions), more than " << memory.source
    << ": fewer nodes, planet rays, positions or design cases";
  throw doc.error(at, m.str());
}

}  // namespace radnet::cases
