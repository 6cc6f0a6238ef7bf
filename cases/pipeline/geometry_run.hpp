#pragma once
// The pipeline of a geometry case: scene → view factors (ray casting or contour
// integration) → reciprocity/closure correction → network → one eigendecomposition →
// exchange factors → orbit sweep (loads, band solves) → temperatures.
#include "cases/config/geometry_case.hpp"
#include "cases/pipeline/results.hpp"

#include <iosfwd>

namespace radnet::cases {

/// Runs the case. With `write_raw` the raw estimate is written as soon as it is final and not
/// held to the end (GeometryRunResult::raw_estimate_written): on the 6,144-node room 0.75 GB
/// that would otherwise sit beside G and GR; the correction then overwrites F in place where
/// it can (geometry::enforceReciprocityInPlace). @throws NumericalError (exit 3)
GeometryRunResult runGeometryCase(const GeometryCase& c, bool show_progress, std::ostream& progress,
                                  const RawEstimateWriter& write_raw = {});

}  // namespace radnet::cases
