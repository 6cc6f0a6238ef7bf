#pragma once
// The exact method's pair values as computed per emitting patch, and their packing for
// sharing out over processes (ExactOptions::part/parts).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace radnet::geometry {

// 16 B: 15.7 M of them on a 6,144-node room wait to be summed into F and σ. The error
// estimate keeps float's seven digits (it is a bound's order of magnitude, and sets weights).
struct PairValue {
  PairValue(int q_, double exchange_area_m2, double error_m2)
      : q(q_), error(static_cast<float>(error_m2)), exchange_area(exchange_area_m2) {}
  int q;
  float error;           // the error estimate of exchange_area, m²
  double exchange_area;  // A_P F_PQ, m²
};

struct PairCounts {
  std::int64_t culled = 0, hidden = 0, unoccluded = 0, occluded = 0;
  std::int64_t by_quadrature = 0;  ///< unoccluded pairs settled by the ladder of point rules
  long long evaluations = 0;
};

/// This process's part of the pair values and counts, packed: the counts, then per emitting
/// patch it integrated [patch, count, (q, exchange area, error)…].
std::vector<double> packPart(const std::vector<std::vector<PairValue>>& values, const PairCounts& counts,
                             const std::vector<int>& mine);

/// Every process's parts back into `values`, the counts summed.
PairCounts unpackParts(const std::vector<double>& all, std::vector<std::vector<PairValue>>& values);

}  // namespace radnet::geometry
