#include "cases/pipeline/packing.hpp"

#include <cstdint>
#include <cstring>
#include <stdexcept>

namespace radnet::cases {
namespace {

class Writer {
 public:
  void raw(const void* data, std::size_t bytes) { out_.append(static_cast<const char*>(data), bytes); }
  void count(std::size_t n) {
    const auto v = static_cast<std::uint64_t>(n);
    raw(&v, sizeof v);
  }
  void value(double v) { raw(&v, sizeof v); }
  void value(int v) { raw(&v, sizeof v); }
  void value(bool v) { value(static_cast<int>(v)); }
  void value(const std::string& s) {
    count(s.size());
    raw(s.data(), s.size());
  }
  void value(const Eigen::MatrixXd& m) {
    count(static_cast<std::size_t>(m.rows()));
    count(static_cast<std::size_t>(m.cols()));
    raw(m.data(), sizeof(double) * static_cast<std::size_t>(m.size()));
  }
  void value(const Eigen::VectorXd& v) {
    count(static_cast<std::size_t>(v.size()));
    raw(v.data(), sizeof(double) * static_cast<std::size_t>(v.size()));
  }
  void value(const std::vector<double>& v) {
    count(v.size());
    raw(v.data(), sizeof(double) * v.size());
  }
  void value(const std::vector<std::string>& v) {
    count(v.size());
    for (const std::string& s : v) value(s);
  }
  std::string take() { return std::move(out_); }

 private:
  std::string out_;
};

class Reader {
 public:
  explicit Reader(const std::string& in) : in_(in) {}
  void raw(void* data, std::size_t bytes) {
    if (bytes > in_.size() - at_) throw std::runtime_error("a packed thermal solution ends early");
    std::memcpy(data, in_.data() + at_, bytes);
    at_ += bytes;
  }
  std::size_t count() {
    std::uint64_t v = 0;
    raw(&v, sizeof v);
    if (v > in_.size()) throw std::runtime_error("a packed thermal solution has a count beyond its size");
    return static_cast<std::size_t>(v);
  }
  void value(double& v) { raw(&v, sizeof v); }
  void value(int& v) { raw(&v, sizeof v); }
  void value(bool& v) {
    int k = 0;
    value(k);
    v = k != 0;
  }
  void value(std::string& s) {
    s.resize(count());
    raw(s.data(), s.size());
  }
  void value(Eigen::MatrixXd& m) {
    const std::size_t rows = count(), cols = count();
    m.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
    raw(m.data(), sizeof(double) * rows * cols);
  }
  void value(Eigen::VectorXd& v) {
    v.resize(static_cast<Eigen::Index>(count()));
    raw(v.data(), sizeof(double) * static_cast<std::size_t>(v.size()));
  }
  void value(std::vector<double>& v) {
    v.resize(count());
    raw(v.data(), sizeof(double) * v.size());
  }
  void value(std::vector<std::string>& v) {
    v.resize(count());
    for (std::string& s : v) value(s);
  }
  bool done() const { return at_ == in_.size(); }

 private:
  const std::string& in_;
  std::size_t at_ = 0;
};

// One field list for both directions: `io` is a Writer or a Reader, `t` const or not.
template <class IO, class Thermal>
void fields(IO& io, Thermal& t) {
  io.value(t.node_names);
  io.value(t.radiative_nodes);
  auto& s = t.solve;
  for (auto* m : {&s.temperature, &s.temperature_rate, &s.rate_roundoff, &s.dissipation, &s.heater_power,
                  &s.emissivity, &s.absorptivity, &s.applied_loads})
    io.value(*m);
  io.value(s.heater_duty);
  io.value(s.message);
  for (auto* v : {&s.newton_iterations, &s.factorisations, &s.orbits, &s.heater_switches, &s.orbits_per_period,
                  &s.exchange_updates})
    io.value(*v);
  io.value(s.heater_cycle_unlocked);  // what a periodic transient concluded travels with it
  io.value(s.max_residual_w);
  io.value(s.periodic_residual_k);
  io.value(t.mode);
  io.value(t.times_s);
  io.value(t.heater_names);
  io.value(t.heater_rated_w);
  io.value(t.case_heater_duty);
  io.value(t.solar_load_scale);
  io.value(t.ir_load_scale);
  auto& f = t.heat.flows;
  for (auto* m : {&f.emitted, &f.radiative, &f.conducted, &f.dissipation, &f.heater, &f.stored, &f.boundary,
                  &f.roundoff})
    io.value(*m);
  io.value(t.heat.max_imbalance_w);
  io.value(t.heat.max_relative_imbalance);
  io.value(t.temperature_stderr);
  io.value(t.temperature_stderr_method);
}

}  // namespace

std::string packThermal(const ThermalOutcome& outcome) {
  Writer w;
  fields(w, outcome.thermal);
  w.value(static_cast<int>(outcome.thermal.solve.status));
  w.value(outcome.log);
  w.count(outcome.timings.entries().size());
  for (const auto& [stage, seconds] : outcome.timings.entries()) {
    w.value(static_cast<int>(stage));
    w.value(seconds);
  }
  return w.take();
}

ThermalOutcome unpackThermal(const std::string& bytes) {
  Reader r(bytes);
  ThermalOutcome outcome;
  fields(r, outcome.thermal);
  int status = 0;
  r.value(status);
  outcome.thermal.solve.status = static_cast<solver::Status>(status);
  r.value(outcome.log);
  for (std::size_t k = r.count(); k > 0; --k) {
    int stage = 0;
    double seconds = 0.0;
    r.value(stage);
    r.value(seconds);
    outcome.timings.add(static_cast<Stage>(stage), seconds);
  }
  if (!r.done()) throw std::runtime_error("a packed thermal solution runs on past its fields");
  return outcome;
}

}  // namespace radnet::cases
