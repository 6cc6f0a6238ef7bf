#include "geometry/exact/pair_values.hpp"

namespace radnet::geometry {

using std::size_t;

std::vector<double> packPart(const std::vector<std::vector<PairValue>>& values, const PairCounts& c,
                             const std::vector<int>& mine) {
  std::vector<double> out = {double(c.culled),        double(c.hidden),      double(c.unoccluded), double(c.occluded),
                             double(c.by_quadrature), double(c.evaluations), double(mine.size())};
  for (int a : mine) {
    const std::vector<PairValue>& v = values[static_cast<size_t>(a)];
    out.push_back(a);
    out.push_back(static_cast<double>(v.size()));
    for (const PairValue& p : v) out.insert(out.end(), {double(p.q), p.exchange_area, p.error});
  }
  return out;
}

PairCounts unpackParts(const std::vector<double>& all, std::vector<std::vector<PairValue>>& values) {
  PairCounts total;
  for (size_t at = 0; at < all.size();) {
    total.culled += static_cast<std::int64_t>(all[at]);
    total.hidden += static_cast<std::int64_t>(all[at + 1]);
    total.unoccluded += static_cast<std::int64_t>(all[at + 2]);
    total.occluded += static_cast<std::int64_t>(all[at + 3]);
    total.by_quadrature += static_cast<std::int64_t>(all[at + 4]);
    total.evaluations += static_cast<long long>(all[at + 5]);
    const auto patches = static_cast<size_t>(all[at + 6]);
    at += 7;
    for (size_t k = 0; k < patches; ++k) {
      std::vector<PairValue>& v = values[static_cast<size_t>(all[at])];
      const auto count = static_cast<size_t>(all[at + 1]);
      at += 2;
      v.clear();
      for (size_t j = 0; j < count; ++j, at += 3) v.push_back({static_cast<int>(all[at]), all[at + 1], all[at + 2]});
    }
  }
  return total;
}

}  // namespace radnet::geometry
