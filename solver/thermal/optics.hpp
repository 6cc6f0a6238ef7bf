#pragma once
// Surface optics that change with temperature (docs/solver.md, "Optics against temperature"):
// ε(T) and α(T) per node, as a table or as two branches with hysteresis (thermochromic VO₂
// radiators). The radiative network's one eigendecomposition still serves: a new emissivity
// vector is a new diagonal S = diag((1 − ε)/A) on the same eigenpairs, so GR for it costs a
// new k×k core and the n×n product (O(n k² + n² k)), never a new decomposition. The caller
// gives that product as `exchange`; the solvers here decide when to ask for it.
// The environment's absorbed loads, computed once with the nominal optics, follow each node's
// own optics to first order: q_solar,i α_i(T)/α_i⁰ and q_IR,i ε_i(T)/ε_i⁰ (exact for what the
// node absorbs directly; the part reflected onto it from other nodes keeps their nominal optics).
#include "solver/thermal/network.hpp"

#include <Eigen/Dense>

#include <functional>
#include <vector>

namespace radnet::solver {

/// A property against temperature: one table, or a warming and a cooling branch.
struct OpticalCurve {
  TemperatureTable warming;  ///< the table (followed both ways when `cooling` is empty), K → –
  TemperatureTable cooling;  ///< the branch followed while cooling; empty: no hysteresis
  bool hysteresis() const { return !cooling.temperature_k.empty(); }
  /// The value at temperature t (K) of a surface that had `previous`: the table; with
  /// hysteresis the play operator: `previous` held between the branches, pushed by whichever
  /// it crosses, clamp(previous, min(w(t), c(t)), max(w(t), c(t))).
  double next(double previous, double t_k) const;
  /// The value of a surface that starts at t (K): the warming branch.
  double start(double t_k) const { return warming.at(t_k); }
};


struct TemperatureOptics {
  std::vector<int> nodes;                 ///< the nodes with a curve (each once)
  std::vector<OpticalCurve> emissivity;   ///< per entry of `nodes`; an empty warming table: ε constant
  std::vector<OpticalCurve> absorptivity; ///< per entry of `nodes`; an empty warming table: α constant
  Eigen::VectorXd nominal_emissivity;     ///< (n) ε the network's GR and the IR loads were computed with
  Eigen::VectorXd nominal_absorptivity;   ///< (n) α the solar and albedo loads were computed with
  /// GR of the network for an emissivity vector (n): the caller's radiative network on its
  /// one eigendecomposition.
  std::function<ExchangeUpdate(const Eigen::VectorXd&)> exchange;
  /// A transient asks for a new GR once some ε has moved by more than this since the last (–):
  /// between updates a node's exchange is off by at most this share of its ε.
  double emissivity_step = 1e-4;
  /// A steady state is solved when every ε and α agrees with its temperature to this (–):
  /// a node's temperature is then within T Δε / (4 ε) of its own (3e-5 K at 300 K, ε = 0.35).
  /// Tighter than the Newton solve resolves on a steep table (1e-9 of the balance moves T by
  /// ~1e-7 K, and ε by the table's slope times that) it would never be met.
  double steady_tolerance = 1e-7;
};

/// The optics of every node at one moment, and the ε the network's GR stands for.
struct OpticsState {
  Eigen::VectorXd emissivity, absorptivity;  ///< (n), –
  Eigen::VectorXd emissivity_in_gr;          ///< (n), –: what net.gr was formed with
  int exchange_updates = 0;                  ///< GRs formed since the start

  /// The optics of surfaces starting at temperatures t (warming branch); GR formed for them.
  void start(ThermalNetwork& net, const Eigen::VectorXd& t);
  /// Moves the optics to temperatures t (the play operator where there is hysteresis).
  void follow(const TemperatureOptics& optics, const Eigen::VectorXd& t);
  /// Forms GR in `net` for the current ε when it has moved by more than `step` from
  /// emissivity_in_gr (0: whenever it differs). True when it did.
  bool refreshExchange(ThermalNetwork& net, double step);
  /// The loads at the current optics minus the nominal ones: (α/α⁰ − 1) q_solar + (ε/ε⁰ − 1) q_ir, W (n),
  /// with the ε of the GR (so that a node's emission and IR absorption use one ε).
  Eigen::VectorXd loadCorrection(const TemperatureOptics& optics, const Eigen::VectorXd& q_solar,
                                 const Eigen::VectorXd& q_ir) const;
};

/// A transient step's optics: ε and α of the memory `accepted` moved to the step's predicted
/// end temperatures (the memory itself moves only with accepted steps), into `step`, whose GR
/// in `net` is formed again when some ε moved by emissivity_step. Evaluated at the predicted
/// end, not the start, the optics lag the temperatures by the prediction's error (O(h²)),
/// not a whole step. True when GR changed.
bool stepOptics(const OpticsState& accepted, const Eigen::VectorXd& t_predicted, ThermalNetwork& net, OpticsState& step);

/// The emissivity and absorptivity targets at temperatures t from a state (the play operator).
void opticsAt(const TemperatureOptics& optics, const OpticsState& from, const Eigen::VectorXd& t,
              Eigen::VectorXd& emissivity, Eigen::VectorXd& absorptivity);

}  // namespace radnet::solver
