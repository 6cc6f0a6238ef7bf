#include "cases/config/solver_block.hpp"

namespace radnet::cases {

const char* toString(ViewFactorMethod method) {
  switch (method) {
    case ViewFactorMethod::Auto: return "auto";
    case ViewFactorMethod::Exact: return "exact";
    case ViewFactorMethod::MonteCarlo: return "monte_carlo";
  }
  return "?";
}

solver::SolverSettings parseSolverSettings(const YamlDocument& doc, const YAML::Node& node) {
  solver::SolverSettings s;
  if (!node.IsDefined() || node.IsNull()) return s;
  doc.expectMap(node, "solver", {"rank", "tolerance", "refine", "max_rank", "eigensolver", "view_factors", "accuracy"});
  if (node["accuracy"]) s.accuracy = doc.number(node["accuracy"], "solver.accuracy (relative)", 1e-6, 0.5);
  if (node["rank"]) s.rank = static_cast<int>(doc.integer(node["rank"], "solver.rank", 1, 1 << 30));
  if (node["tolerance"]) s.tolerance = doc.number(node["tolerance"], "solver.tolerance", 1e-15, 1.0);
  s.tolerance_given = node["tolerance"].IsDefined();
  if (node["rank"] && node["tolerance"])
    throw doc.error(node["tolerance"], "solver: give either 'rank' or 'tolerance', not both");
  if (node["refine"]) s.refine = doc.boolean(node["refine"], "solver.refine");
  if (node["max_rank"]) s.max_rank = static_cast<int>(doc.integer(node["max_rank"], "solver.max_rank", 1, 1 << 30));
  if (node["eigensolver"]) {
    const std::string m = doc.choice(node["eigensolver"], "solver.eigensolver", {"auto", "dense", "lanczos"});
    s.method = m == "auto"    ? solver::EigenMethod::Auto
               : m == "dense" ? solver::EigenMethod::Dense
                              : solver::EigenMethod::Lanczos;
  }
  return s;
}

ViewFactorSettings parseViewFactorSettings(const YamlDocument& doc, const YAML::Node& vf) {
  ViewFactorSettings s;
  if (!vf) return s;
  const std::string what = "solver.view_factors";
  geometry::ViewFactorOptions& mc = s.monte_carlo;
  doc.expectMap(vf, what,
                {"rays", "seed", "target_error", "replicas", "sampling", "method", "tolerance", "max_blockers"});
  if (vf["rays"]) mc.rays_per_node = doc.integer(vf["rays"], what + ".rays", 64, 2000000000LL);
  s.rays_pinned = vf["rays"] || vf["target_error"];
  if (vf["seed"]) mc.seed = static_cast<std::uint64_t>(doc.integer(vf["seed"], what + ".seed", 0, 1LL << 62));
  if (vf["target_error"]) mc.target_error = doc.number(vf["target_error"], what + ".target_error", 1e-7, 0.5);
  if (vf["replicas"]) mc.replicas = static_cast<int>(doc.integer(vf["replicas"], what + ".replicas", 2, 1024));
  if (mc.rays_per_node < mc.replicas) throw doc.error(vf, what + ": rays must be at least the number of replicas");
  if (vf["sampling"])
    mc.sampling = doc.choice(vf["sampling"], what + ".sampling", {"sobol", "random"}) == "sobol"
                      ? geometry::Sampling::Sobol
                      : geometry::Sampling::Random;
  if (vf["method"]) {
    // "contour" was the earlier deterministic method; the exact method replaces it.
    const std::string m = doc.choice(vf["method"], what + ".method", {"auto", "exact", "monte_carlo", "contour"});
    s.method = m == "auto" ? ViewFactorMethod::Auto
               : m == "monte_carlo" ? ViewFactorMethod::MonteCarlo
                                    : ViewFactorMethod::Exact;
  }
  // A key that is accepted must act: the ray keys do nothing when no row is cast, nor the
  // tolerance when nothing is integrated.
  if (s.method == ViewFactorMethod::Exact)
    for (const char* key : {"rays", "seed", "target_error", "replicas", "sampling"})
      if (vf[key])
        throw doc.error(vf[key], what + "." + key + " has no effect with method: exact (it casts no rays); " +
                                     "remove it, or use method: auto");
  if (s.method == ViewFactorMethod::MonteCarlo && vf["tolerance"])
    throw doc.error(vf["tolerance"], what + ".tolerance is the exact method's target and has no effect with " +
                                         "method: monte_carlo; give rays or target_error instead");
  if (vf["tolerance"]) s.exact.tolerance = doc.number(vf["tolerance"], what + ".tolerance", 1e-12, 0.1);
  s.tolerance_pinned = static_cast<bool>(vf["tolerance"]);
  if (vf["max_blockers"]) {
    if (s.method != ViewFactorMethod::Auto)
      throw doc.error(vf["max_blockers"], what + ".max_blockers applies to method: auto only");
    s.exact.max_blockers = static_cast<int>(doc.integer(vf["max_blockers"], what + ".max_blockers", 0, 1000000));
  }
  return s;
}

}  // namespace radnet::cases
