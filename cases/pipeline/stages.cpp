#include "cases/pipeline/stages.hpp"

#include <chrono>

namespace radnet::cases {
namespace {

double nowSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

std::string_view stageName(Stage stage) {
  switch (stage) {
    case Stage::AabbTree: return "aabb_tree";
    case Stage::ViewFactors: return "view_factors";
    case Stage::Network: return "network";
    case Stage::Eigendecomposition: return "eigendecomposition";
    case Stage::Articulation: return "articulation";
    case Stage::BandSolves: return "band_solves";
    case Stage::ExchangeFactors: return "exchange_factors";
    case Stage::Orbit: return "orbit";
    case Stage::EnvironmentLoads: return "environment_loads";
    case Stage::Thermal: return "thermal";
    case Stage::Uncertainty: return "uncertainty";
    case Stage::OpticalUncertainty: return "optical_uncertainty";
    case Stage::Output: return "output";
  }
  return "unknown";
}

void StageTimings::add(Stage stage, double seconds) { add(stage, seconds, 1); }

void StageTimings::add(Stage stage, double seconds, int times) {
  for (size_t k = 0; k < entries_.size(); ++k)
    if (entries_[k].first == stage) {
      entries_[k].second += seconds;
      counts_[k] += times;
      return;
    }
  entries_.emplace_back(stage, seconds);
  counts_.push_back(times);
}

int StageTimings::count(Stage stage) const {
  for (size_t k = 0; k < entries_.size(); ++k)
    if (entries_[k].first == stage) return counts_[k];
  return 0;
}

StageTimer::StageTimer(StageTimings& timings, Stage stage) : timings_(timings), stage_(stage), start_s_(nowSeconds()) {}

StageTimer::~StageTimer() { stop(); }

void StageTimer::stop() {
  if (stopped_) return;
  stopped_ = true;
  timings_.add(stage_, nowSeconds() - start_s_);
}

void StageTimings::addAll(const StageTimings& other) {
  for (size_t k = 0; k < other.entries_.size(); ++k)
    add(other.entries_[k].first, other.entries_[k].second, other.counts_[k]);
}

}  // namespace radnet::cases
