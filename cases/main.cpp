// radnet command line (DESIGN.md §3): run, check, validate.
// Exit codes: 0 success, 1 a check failed, 2 bad input, 3 numerical failure.
#include "cases/errors.hpp"
#include "cases/expectations.hpp"
#include "cases/network_case.hpp"
#include "cases/geometry_case.hpp"
#include "cases/run_geometry.hpp"
#include "cases/run_network.hpp"
#include "cases/yaml_support.hpp"

#include <CLI/CLI.hpp>

#include <filesystem>
#include <optional>
#include <iostream>
#include <sstream>
#include <unistd.h>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace {

using namespace radnet::cases;

constexpr int kExitCheckFailed = 1;
constexpr int kExitBadInput = 2;
constexpr int kExitNumerical = 3;

// A case of either form: network given directly, or geometry with ray-cast view factors.
struct LoadedCase {
  std::optional<NetworkCase> network;
  std::optional<GeometryCase> geometry;
  size_t nodeCount() const { return network ? network->names.size() : geometry->scene.nodes().size(); }
  const std::vector<Expectation>& expectations() const {
    return network ? network->expectations : geometry->expectations;
  }
};

LoadedCase loadCase(const std::string& path) {
  const YamlDocument doc = YamlDocument::load(path);
  if (!doc.root().IsMap())
    throw doc.error(doc.root(), "expected a case: a mapping with 'name' and either 'network' or 'geometry'");
  LoadedCase c;
  if (isNetworkCase(doc) && isGeometryCase(doc))
    throw doc.error(doc.root()["geometry"], "case: give either 'network' or 'geometry', not both");
  if (isNetworkCase(doc)) c.network = loadNetworkCase(doc);
  else if (isGeometryCase(doc)) c.geometry = loadGeometryCase(doc);
  else throw doc.error(doc.root(), "case: missing 'geometry' (surfaces and materials) or 'network' (view factors given)");
  return c;
}

std::string defaultOutput(const std::string& case_path) {
  return std::filesystem::path(case_path).stem().string() + ".h5";
}

// Fails early, before any computing, when the output cannot be written.
void checkOutputPath(const std::string& out) {
  const std::filesystem::path dir = std::filesystem::absolute(out).parent_path();
  if (!std::filesystem::is_directory(dir))
    throw InputError(out, 0, 0, "output directory '" + dir.string() + "' does not exist");
  if (::access(dir.c_str(), W_OK) != 0) throw InputError(out, 0, 0, "output directory '" + dir.string() + "' is not writable");
}

// Runs `body`, mapping each error channel to its exit code with a message on stderr.
template <class Body>
int guarded(Body&& body) {
  try {
    return body();
  } catch (const InputError& e) {
    std::cerr << e.what() << "\n";
    return kExitBadInput;
  } catch (const NumericalError& e) {
    std::cerr << "radnet: numerical failure: " << e.what() << "\n";
    return kExitNumerical;
  } catch (const std::invalid_argument& e) {
    std::cerr << "radnet: invalid input: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::bad_alloc&) {
    std::cerr << "radnet: out of memory: the case is too large for this machine\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << "radnet: error: " << e.what() << "\n";
    return kExitNumerical;
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"radnet: thermal radiation network solver for spacecraft"};
  app.require_subcommand(1);

  std::string run_case, run_output;
  bool quiet = false;
  int threads = 0;
  long long seed = -1;
  auto* run = app.add_subcommand("run", "run a case: network, eigenpairs, band solves; write HDF5");
  run->add_option("case", run_case, "case file (YAML)")->required();
  run->add_option("-o,--output", run_output, "output HDF5 file (default: <case name>.h5 in this directory)");
  run->add_flag("-q,--quiet", quiet, "no progress on stderr");
  run->add_option("--threads", threads, "worker threads (0: all cores)")->check(CLI::NonNegativeNumber);
  run->add_option("--seed", seed, "random seed for ray casting (overrides the case)");

  std::vector<std::string> check_cases;
  auto* check = app.add_subcommand("check", "run cases with an 'expect:' block; exit 1 on any regression");
  check->add_option("cases", check_cases, "case files (YAML)")->required();

  std::string validate_case;
  auto* validate = app.add_subcommand("validate", "parse and validate a case only");
  validate->add_option("case", validate_case, "case file (YAML)")->required();

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return kExitBadInput;
  }

  std::ostringstream sink;
  if (*run) {
    return guarded([&] {
      LoadedCase c = loadCase(run_case);
      std::ostream& progress = quiet ? static_cast<std::ostream&>(sink) : std::cerr;
      const std::string out = run_output.empty() ? defaultOutput(run_case) : run_output;
      checkOutputPath(out);
      if (c.network) {
        const NetworkRunResult r = runNetworkCase(*c.network, progress);
        writeNetworkResult(*c.network, r, out);
        printNetworkSummary(*c.network, r, std::cout);
      } else {
        GeometryCase& g = *c.geometry;
        if (threads > 0) {
          g.view_factors.threads = threads;
#ifdef _OPENMP
          omp_set_num_threads(threads);  // the orbit loads' parallel loops too
#endif
        }
        if (seed >= 0) {  // every random stream of the run: view factors, shadow and planet rays
          g.view_factors.seed = static_cast<std::uint64_t>(seed);
          if (g.orbit) g.orbit->environment.seed = static_cast<std::uint64_t>(seed);
        }
        const GeometryRunResult r = runGeometryCase(g, !quiet, progress);
        writeGeometryResult(g, r, out);
        printGeometrySummary(g, r, std::cout);
      }
      if (!quiet) std::cerr << "radnet: wrote " << out << "\n";
      return 0;
    });
  }
  if (*validate) {
    return guarded([&] {
      const LoadedCase c = loadCase(validate_case);
      std::cout << validate_case << ": valid (" << c.nodeCount() << " nodes)\n";
      return 0;
    });
  }
  // check: every case with an `expect:` block runs; the worst outcome decides the exit code.
  int worst = 0, failed_total = 0, checked = 0;
  for (const auto& path : check_cases) {
    const int code = guarded([&] {
      const LoadedCase c = loadCase(path);
      std::cout << "== " << path << "\n";
      if (c.expectations().empty()) {
        std::cout << "SKIP (no 'expect:' block)\n";
        return 0;
      }
      ++checked;
      int failed = 0;
      if (c.network) {
        const NetworkRunResult r = runNetworkCase(*c.network, sink);
        failed = evaluateExpectations(
            c.expectations(), [&](const Expectation& x) { return lookupNetworkResult(*c.network, r, x); }, std::cout);
      } else {
        const GeometryRunResult r = runGeometryCase(*c.geometry, false, sink);
        failed = evaluateExpectations(
            c.expectations(), [&](const Expectation& x) { return lookupGeometryResult(r, x); }, std::cout);
      }
      failed_total += failed;
      return failed ? kExitCheckFailed : 0;
    });
    worst = std::max(worst, code);
  }
  if (checked == 0 && worst == 0) {
    std::cerr << "radnet check: none of the cases has an 'expect:' block: nothing was checked\n";
    return kExitBadInput;
  }
  std::cout << (failed_total == 0 && worst == 0 ? "all checks passed" : "checks FAILED") << " (" << checked
            << " case(s) checked)\n";
  return worst;
}
