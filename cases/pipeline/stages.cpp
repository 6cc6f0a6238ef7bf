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

void StageTimings::add(Stage stage, double seconds) {
  for (auto& [s, total] : entries_)
    if (s == stage) {
      total += seconds;
      return;
    }
  entries_.emplace_back(stage, seconds);
}

StageTimer::StageTimer(StageTimings& timings, Stage stage) : timings_(timings), stage_(stage), start_s_(nowSeconds()) {}

StageTimer::~StageTimer() { stop(); }

void StageTimer::stop() {
  if (stopped_) return;
  stopped_ = true;
  timings_.add(stage_, nowSeconds() - start_s_);
}

void StageTimings::addAll(const StageTimings& other) {
  for (const auto& [stage, seconds] : other.entries()) add(stage, seconds);
}

}  // namespace radnet::cases
