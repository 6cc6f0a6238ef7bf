// radnet command line (docs/design.md, "Contracts"): run, check, validate.
// Exit codes: 0 success, 1 a check failed, 2 bad input, 3 numerical failure.
#include "cases/cluster/cluster.hpp"
#include "cases/config/case_file.hpp"
#include "cases/config/errors.hpp"
#include "cases/config/work_estimate.hpp"
#include "cases/output/expectations.hpp"
#include "cases/output/hdf5_writer.hpp"
#include "cases/output/export.hpp"
#include "cases/output/output_guard.hpp"
#include "cases/output/result_files.hpp"
#include "cases/output/summary.hpp"
#include "cases/pipeline/distributed.hpp"
#include "cases/pipeline/geometry_run.hpp"
#include "cases/pipeline/network_run.hpp"
#include "cases/cli/check_command.hpp"
#include "cases/cli/read_commands.hpp"
#include "cases/cli/tuned_process.hpp"
#include "cases/cli/warning_tap.hpp"

#include <CLI/CLI.hpp>

#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <filesystem>
#include <functional>
#include <cstdlib>
#include <iostream>
#include <chrono>
#include <map>
#include <optional>
#include <sstream>
#include <thread>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace {

using namespace radnet::cases;

constexpr int kExitBadInput = 2;
constexpr int kExitNumerical = 3;
constexpr int kExitOutput = 4;

struct RunOptions {
  std::vector<std::string> case_paths;
  std::string case_path, output;  // the case of this run, and -o as given
  bool quiet = false;
  bool all_nodes = false;
  int threads = 0;
  long long seed = -1;
};

std::string defaultOutput(const std::string& case_path) {
  return std::filesystem::path(case_path).stem().string() + ".h5";
}

// Under MPI every rank ends each guarded step in one agreement on the exit code (the
// largest of any rank's): a rank that failed tells the others, who stop at their next
// collective or here, and all leave with the same code (cases/cluster/cluster.hpp).
int agreed(int code) {
  const int worst = radnet::cluster::agree(code);
  if (worst != code && code == 0 && radnet::cluster::rank() == 0)
    std::cerr << "radnet: stopped: another MPI rank failed (exit " << worst << "); its message is above\n";
  return worst;
}

// Runs `body`, mapping each error channel to its exit code with a message on stderr.
template <class Body>
int guarded(Body&& body) {
  try {
    return agreed(body());
  } catch (const radnet::cluster::PeerFailure& e) {  // already agreed: no second agreement
    if (radnet::cluster::rank() == 0)
      std::cerr << "radnet: stopped: another MPI rank failed (exit " << e.code() << "); its message is above\n";
    return e.code();
  } catch (const InputError& e) {
    std::cerr << e.what() << "\n";
    return agreed(kExitBadInput);
  } catch (const OutputError& e) {
    std::cerr << "radnet: output not written: " << e.what() << "\n";
    return agreed(kExitOutput);
  } catch (const NumericalError& e) {
    std::cerr << "radnet: numerical failure: " << e.what() << "\n";
    return agreed(kExitNumerical);
  } catch (const std::invalid_argument& e) {
    std::cerr << "radnet: invalid input: " << e.what() << "\n";
    return agreed(kExitBadInput);
  } catch (const std::filesystem::filesystem_error& e) {  // a name over 255 bytes, a path over PATH_MAX, …
    std::cerr << "radnet: output not written: " << e.what() << "\n";
    return agreed(kExitOutput);
  } catch (const std::bad_alloc&) {
    std::cerr << "radnet: out of memory: the case is too large for this machine\n";
    return agreed(kExitBadInput);
  } catch (const std::exception& e) {
    std::cerr << "radnet: error: " << e.what() << "\n";
    return agreed(kExitNumerical);
  }
}

// --threads and --seed apply to every parallel loop and every random stream of the run.
void applyRunOptions(RunOptions o, GeometryCase& g) {
  // More threads than cores computes nothing sooner and, under a memory limit, fails to
  // start them (1024 threads' stacks under a 4 GB cap: libgomp exits 1). The results do not
  // depend on the count (every node and position has its own random stream).
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  if (o.threads > cores) {
    if (!o.quiet)
      std::cerr << "radnet: warning: --threads " << o.threads << " but this machine has " << cores
                << " cores: running " << cores << " threads\n";
    o.threads = cores;
  }
  if (o.threads > 0) {
    g.view_factors.monte_carlo.threads = o.threads;
#ifdef _OPENMP
    omp_set_num_threads(o.threads);  // the orbit loads' parallel loops too
#endif
    // solver/parallel.hpp's std::threads (uncertainty row blocks, optical samples) read it.
    setenv("OMP_NUM_THREADS", std::to_string(o.threads).c_str(), 1);
  }
  if (o.seed >= 0) {  // view factors, shadow and planet rays
    g.view_factors.monte_carlo.seed = static_cast<std::uint64_t>(o.seed);
    for (DesignCase& d : g.design_cases)
      if (d.orbit) d.orbit->environment.seed = static_cast<std::uint64_t>(o.seed);
    if (g.optical_uncertainty) g.optical_uncertainty->seed = static_cast<std::uint64_t>(o.seed);
  }
}

// -o: a file for one case; an existing directory receives <case stem>.h5 for each case.
std::string outputFor(const RunOptions& o) {
  if (o.output.empty()) return defaultOutput(o.case_path);
  if (std::filesystem::is_directory(o.output))
    return (std::filesystem::path(o.output) / defaultOutput(o.case_path)).string();
  if (o.case_paths.size() > 1)
    throw InputError(o.output, 0, 0,
                     "-o names one file but " + std::to_string(o.case_paths.size()) +
                         " cases are run: give an existing directory, or run them one by one");
  return o.output;
}

// What an output may not overwrite: the case file and its includes.
std::vector<std::string> inputsOf(const std::string& case_path, const LoadedCase& c) {
  std::vector<std::string> inputs = {case_path};
  if (c.geometry) for (const auto& [file, text] : c.geometry->included) inputs.push_back(file);
  if (c.imported) inputs.push_back(c.imported->source);
  return inputs;
}

// Under MPI every rank runs the case (sharing out its work) and rank 0 alone writes the
// files, prints progress and the summary.
int runCommand(const RunOptions& o) {
  LoadedCase c = loadCase(o.case_path);
  checkSameCase(o.case_path, c);  // under MPI: every rank read the same files
  const bool writer = radnet::cluster::rank() == 0;
  std::ostringstream sink;
  WarningTap tap(o.quiet || !writer ? static_cast<std::ostream&>(sink) : std::cerr);
  std::ostream& progress = tap.stream();
  const std::string out = outputFor(o);
  if (writer) checkOutputTarget(out, inputsOf(o.case_path, c), c.geometry.has_value());
  double write_s = 0.0;
  if (c.network) {
    const NetworkRunResult r = runNetworkCase(*c.network, progress);
    if (writer) writeNetworkResult(*c.network, r, out, tap.warnings());
    printNetworkSummary(*c.network, r, std::cout, o.all_nodes);
  } else if (c.imported) {
    const ImportRunResult r = runImportedCase(*c.imported, progress);
    if (writer) writeImportedResult(*c.imported, r, out, tap.warnings());
    printImportedSummary(*c.imported, r, std::cout, o.all_nodes);
  } else {
    applyRunOptions(o, *c.geometry);
    // Opened before the run, which writes its raw view factors there as soon as they are
    // final instead of holding them to the end (a failed run removes the temporary file).
    std::optional<Hdf5Writer> h5;
    if (writer) h5.emplace(out);
    const GeometryRunResult r =
        runGeometryCase(*c.geometry, !o.quiet && writer, progress, h5 ? rawEstimateInto(*h5) : RawEstimateWriter());
    const auto t0 = std::chrono::steady_clock::now();
    // Rows shared out over MPI ranks: the others join each block of the file's matrices.
    h5 ? writeGeometryResult(*c.geometry, r, *h5, out, tap.warnings()) : writeSharedMatrices(nullptr, r);
    write_s = r.raw_estimate_write_seconds +
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    printGeometrySummary(*c.geometry, r, std::cout, o.all_nodes);
  }
  // Said even under -q: a quiet run's warnings are in the file, and the user is told so.
  if (writer && !tap.warnings().empty())
    std::cerr << "radnet: " << tap.warnings().size() << " warning(s)" << (o.quiet ? "" : " above")
              << " (kept in " << out << " /report/warnings)\n";
  // The file's own /report cannot hold the time spent writing it: it is said here.
  if (!o.quiet && writer)
    std::cerr << "radnet: wrote " << out << (write_s > 0 ? " in " + std::to_string(write_s) + " s" : "") << "\n";
  return 0;
}

// Every case runs, each into its own file; the worst outcome decides the exit code.
int runCommands(RunOptions o) {
  // Two cases with the same file stem would write the same output: the second would replace
  // the first without a word. Refused before anything runs.
  std::map<std::string, std::string> output_of;
  const int clash = guarded([&] {
    for (const std::string& path : o.case_paths) {
      o.case_path = path;
      const std::string out = std::filesystem::weakly_canonical(outputFor(o)).string();
      const auto [it, fresh] = output_of.emplace(out, path);
      if (!fresh)
        throw InputError(path, 0, 0, "writes " + out + ", as " + it->second + " does: give the cases different "
                                     "file names or run them into different directories");
    }
    return 0;
  });
  if (clash) return clash;
  // Every case is read and its output checked before the first one runs: a bad case among
  // several is refused with nothing written, not after the good ones have written theirs.
  if (o.case_paths.size() > 1) {
    int refused = 0;
    for (const std::string& path : o.case_paths) {
      o.case_path = path;
      refused = std::max(refused, guarded([&] {
                           const LoadedCase c = loadCase(path);
                           if (radnet::cluster::rank() == 0)
                             checkOutputTarget(outputFor(o), inputsOf(path, c), c.geometry.has_value());
                           return 0;
                         }));
    }
    if (refused) {
      std::cerr << "radnet: no case was run: every case is read before the first runs\n";
      return refused;
    }
  }
  int worst = 0;
  for (const std::string& path : o.case_paths) {
    if (o.case_paths.size() > 1) std::cout << "== " << path << "\n" << std::flush;
    o.case_path = path;
    worst = std::max(worst, guarded([&] { return runCommand(o); }));
  }
  return worst;
}

constexpr const char* kExamples = R"(
Examples:
  radnet run cases/examples/cubesat-3u.yaml -o cubesat.h5    one case: cubesat.h5 and cubesat.xmf
  radnet run hot.yaml cold.yaml -o results/                  several cases into a directory
  radnet run big.yaml --threads 2 --seed 7 --all             every node in the summary
  radnet validate cases/analytic/*.yaml                      parse and check only
  radnet check cases/analytic/*.yaml                         regression: exit 1 on any failure
  radnet report cubesat.h5 -o report/                        Markdown, CSV and PNG report
  radnet export cubesat.h5 --format esatan -o cubesat.d      nodes, GL and GR for another tool
Exit codes: 0 success, 1 a check failed, 2 bad input, 3 numerical failure, 4 output not written.)";

CLI::App* addRunCommand(CLI::App& app, RunOptions& run_options) {
  auto* run = app.add_subcommand("run", "run a case: network, eigenpairs, band solves; write HDF5");
  run->add_option("cases", run_options.case_paths, "case files (YAML)")->required();
  run->add_option("-o,--output", run_options.output,
                  "output HDF5 file, or an existing directory for <case stem>.h5 (default: <case stem>.h5 here)");
  run->add_flag("--all", run_options.all_nodes, "every node in the summary (default: extremes and groups above 40)");
  run->add_flag("-q,--quiet", run_options.quiet, "no progress on stderr");
  run->add_option("--threads", run_options.threads, "worker threads (0: all cores; at most 1024)")
      ->check(CLI::Range(0, 1024));  // 65535 crashed libgomp; no machine radnet runs on has more
  run->add_option("--seed", run_options.seed, "random seed for ray casting (overrides the case)")
      ->check(CLI::Validator(
          [](const std::string& text) {
            return !text.empty() && text.find_first_not_of("0123456789") == std::string::npos
                       ? std::string()
                       : "a seed is a whole number >= 0, not '" + text + "'";
          },
          "SEED >= 0"));
  return run;
}

CLI::App* addExportCommand(CLI::App& app, std::string& export_result, ExportOptions& export_options) {
  auto* exporter = app.add_subcommand("export", "write a result's nodes, GL and GR for ESATAN-TMS, SINDA/FLUINT or CSV");
  exporter->add_option("result", export_result, "radnet result (HDF5)")->required();
  exporter->add_option("--format", export_options.format, "esatan (input deck), sinda (input deck), csv or tmd (ESATAN-TMS results file)")
      ->check(CLI::IsMember({"esatan", "sinda", "csv", "tmd"}));
  exporter->add_option("-o,--output", export_options.output,
                       "deck file (default <stem>.d or <stem>.sin), or directory for csv (default <stem>-export)");
  exporter->add_option("--case", export_options.design_case, "design case (default: the first)");
  exporter->add_option("--position", export_options.position,
                       "position whose loads and conductances are written (default: the case's first)")
      ->check(CLI::NonNegativeNumber);
  exporter->add_option("--min-gr", export_options.min_gr,
                       "leave out GR_ij smaller than this share of both nodes' sum of GR (default 0: every GR)");
  return exporter;
}

// A stream buffer that drops what it is given: stdout of the ranks other than 0.
struct Discard : std::streambuf {
  int overflow(int c) override { return c; }
};

// The command line: parses, runs the subcommand, returns the exit code.
int radnetMain(int argc, char** argv) {
  CLI::App app{"radnet: thermal radiation network solver for spacecraft"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("radnet ") + RADNET_VERSION);
  app.footer(kExamples);

  RunOptions run_options;
  CLI::App* run = addRunCommand(app, run_options);

  std::vector<std::string> check_cases;
  auto* check = app.add_subcommand("check", "run cases with an 'expect:' block; exit 1 on any regression");
  check->add_option("cases", check_cases, "case files (YAML)")->required();

  std::vector<std::string> validate_cases;
  auto* validate = app.add_subcommand("validate", "parse and validate cases only");
  validate->add_option("cases", validate_cases, "case files (YAML)")->required();

  std::string export_result;
  ExportOptions export_options;
  CLI::App* exporter = addExportCommand(app, export_result, export_options);

  std::string report_result, report_dir, report_limits;
  auto* report = app.add_subcommand("report", "Markdown and CSV tables and PNG figures of a result");
  report->add_option("result", report_result, "radnet result (HDF5)")->required();
  report->add_option("-o,--output", report_dir, "directory (default: <stem>-report beside the result)");
  report->add_option("--limits", report_limits, "node limits: inline 'node: [min_K, max_K]; node: [...]' or a file of such lines (default: the case's limits:)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return kExitBadInput;
  }
  if (*run) return runCommands(run_options);
  if (*validate) return validateCommand(validate_cases, [](const std::function<int()>& body) { return guarded(body); });
  if (*report)  // one writer: rank 0 draws, the others take its exit code
    return agreed(radnet::cluster::rank() == 0
                      ? guarded([&] { return reportCommand(report_result, report_dir, report_limits); })
                      : 0);
  if (*exporter)  // one writer: rank 0 exports, the others wait for its exit code
    return guarded([&] {
      if (radnet::cluster::rank() == 0)
        for (const std::string& file : exportResult(export_result, export_options))
          std::cout << "radnet: wrote " << file << "\n";
      return 0;
    });
  return checkCommand(check_cases, [](const std::function<int()>& body) { return guarded(body); });
}

}  // namespace

int main(int argc, char** argv) {
  radnet::cases::restartTuned(argv);  // huge pages, sleeping OpenMP workers (tuned_process.hpp)
  radnet::cases::Hdf5Writer::noLibraryExitHandler();  // before any HDF5 call
  removeTemporariesOnSignal();  // Ctrl-C, kill or a closed terminal leave no OUT.h5.tmp-PID
  exitOnTerminate(kExitNumerical);  // no abort: an exit code and a message
  // Under mpirun: stdout from rank 0 only; every rank's errors reach stderr (docs/mpi.md).
  radnet::cluster::start(argc, argv);
  Discard discard;
  if (radnet::cluster::rank() != 0) std::cout.rdbuf(&discard);
  const int code = radnetMain(argc, argv);
  std::cout.flush();
  radnet::cluster::finish();
  return code;
}
