#include "cases/config/work_estimate.hpp"

#include "geometry/rays/recast_rows.hpp"

#include <sys/resource.h>
#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <fstream>
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

WorkEstimate estimateWork(const GeometryCase& c) {
  WorkEstimate w;
  const double n = static_cast<double>(c.scene.nodes().size());
  const double triangles = static_cast<double>(c.scene.faces().size());
  w.scene_bytes = kSceneBytesPerTriangle * triangles;
  const double thermal_nodes = c.thermal ? static_cast<double>(c.thermal->nodeCount()) : n;
  // Three dense n × n matrices of 8 bytes: GR and its working copy, and F/G when the network
  // is dense (F, its raw estimate and σ are sparse for most spacecraft: 3.7 % non-zero at
  // 6,402 nodes); one more GR per further optical set. Measured peaks: 24 n² bytes for a
  // 3,872-node enclosure of 12 % density, 18 n² at 6,402 nodes, 11 n² at 19,202 (docs/limits.md).
  w.dense_bytes = 8.0 * n * n * (3.0 + static_cast<double>(c.optical_sets.size() - 1));
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
  // threshold), its GR and, with temperatures, the thermal network's GR: at most one per
  // position, nor more than the drives' steps allow.
  if (!c.articulation.drives.empty()) {
    double configurations = 1.0;
    for (const Drive& d : c.articulation.drives) configurations *= std::floor(360.0 / d.step_deg) + 1.0;
    configurations = std::min(configurations, static_cast<double>(w.positions));
    w.dense_bytes += configurations * (8.0 * n * n * (c.thermal ? 3.0 : 2.0) + kSceneBytesPerTriangle * triangles);
    // The rays a turn can redirect, kept from the base: at most every ray of every row, and
    // never beyond geometry::kMaxKeptRayBytes.
    const double rays = n * static_cast<double>(c.view_factors.monte_carlo.rays_per_node);
    w.dense_bytes += std::min(geometry::kMaxKeptRayBytes, rays * sizeof(geometry::RecastPlan::Ray));
  }
  // About 25 per-node series (loads, irradiances, heat flows, temperature; several kept twice
  // while cases are joined) and 4 per-triangle ParaView copies on two sides.
  w.position_bytes = 8.0 * static_cast<double>(w.positions) * (25.0 * thermal_nodes + 8.0 * triangles);
  return w;
}

void checkWorkEstimate(const YamlDocument& doc, const GeometryCase& c, double memory_bytes) {
  MemoryLimit memory = memoryLimit();
  if (memory_bytes > 0) memory = {memory_bytes, "the given " + gigabytes(memory_bytes)};
  memory_bytes = memory.bytes;
  if (memory_bytes <= 0) return;  // unknown: nothing to compare with
  const WorkEstimate w = estimateWork(c);
  if (w.total() <= memory_bytes) return;
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
