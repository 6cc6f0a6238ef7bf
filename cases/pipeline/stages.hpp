#pragma once
// The stages of a run, named once: the pipeline times them, /report records them as
// `time_<name>_s` attributes and the summary prints them (docs/hdf5-layout.md).
#include <cstddef>
#include <string_view>
#include <utility>
#include <vector>

namespace radnet::cases {

enum class Stage {
  AabbTree,            ///< building the ray-casting tree
  ViewFactors,         ///< ray casting or contour integration, and the reciprocity correction
  Network,             ///< validating the network and forming G
  Eigendecomposition,  ///< the one decomposition of G
  Articulation,        ///< turning parts: each configuration's rows of F, its network and its update of the pairs
  BandSolves,          ///< every band solve of the run (all positions at once)
  ExchangeFactors,     ///< GR and GR to space
  Orbit,               ///< propagating the orbit(s) and finding eclipse events
  EnvironmentLoads,    ///< direct solar, albedo and Earth-IR irradiance per node and position
  Thermal,             ///< temperatures (steady or transient)
  Uncertainty,         ///< propagating the view-factor, load and truncation errors
  OpticalUncertainty,  ///< `uncertainty:` samples of α and ε and the sensitivities
  Output,              ///< writing the HDF5 file and its companions
};

/// Snake-case name of a stage, e.g. "band_solves".
std::string_view stageName(Stage stage);

/// Wall time per stage, s; a stage timed several times (one per orbit case) accumulates.
class StageTimings {
 public:
  void add(Stage stage, double seconds);
  /// (stage, seconds) in the order the stages first ran.
  const std::vector<std::pair<Stage, double>>& entries() const { return entries_; }
  /// Adds every stage of `other` (a design case's) to these, times and counts.
  void addAll(const StageTimings& other);
  /// Replaces the time of entry `index` (of entries()), s: e.g. by the slowest MPI rank's.
  void setSeconds(std::size_t index, double seconds) { entries_.at(index).second = seconds; }
  /// How many times `stage` was timed (e.g. eigendecompositions of G), 0 if never.
  int count(Stage stage) const;

 private:
  void add(Stage stage, double seconds, int times);
  std::vector<std::pair<Stage, double>> entries_;
  std::vector<int> counts_;  ///< per entry, how many timings it sums
};

/// Times one stage from construction to stop() (or destruction).
class StageTimer {
 public:
  StageTimer(StageTimings& timings, Stage stage);
  ~StageTimer();
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;
  /// Records the time so far (once).
  void stop();
  /// Leaves out `seconds` spent inside the stage on other work (the raw estimate written out).
  void exclude(double seconds) { start_s_ += seconds; }

 private:
  StageTimings& timings_;
  Stage stage_;
  double start_s_;
  bool stopped_ = false;
};

}  // namespace radnet::cases
