#pragma once
// Outcome of a numerical procedure. Caller mistakes throw std::invalid_argument;
// numerical outcomes (no convergence, divergence, singular systems) are a status,
// as in Spectra's CompInfo, so a sweep can report them instead of crashing.
#include <string>

namespace radnet::solver {

enum class Status {
  Converged,     ///< met its tolerance (or an exact direct solve succeeded)
  NotConverged,  ///< hit its iteration limit without meeting the tolerance
  Diverged,      ///< the iteration grew without bound (e.g. truncated G' with spectral radius > 1)
  Singular,      ///< a matrix that must be inverted is (numerically) singular
  NonFinite      ///< a NaN or infinity appeared
};

inline const char* toString(Status s) {
  switch (s) {
    case Status::Converged: return "converged";
    case Status::NotConverged: return "not converged";
    case Status::Diverged: return "diverged";
    case Status::Singular: return "singular";
    case Status::NonFinite: return "non-finite";
  }
  return "unknown";
}

}  // namespace radnet::solver
