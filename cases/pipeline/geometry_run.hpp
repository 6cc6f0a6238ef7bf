#pragma once
// The pipeline of a geometry case: scene → view factors (ray casting or contour
// integration) → reciprocity/closure correction → network → one eigendecomposition →
// exchange factors → orbit sweep (loads, band solves) → temperatures.
#include "cases/config/geometry_case.hpp"
#include "cases/pipeline/results.hpp"

#include <iosfwd>

namespace radnet::cases {

/// Runs the case. @throws NumericalError (exit 3)
GeometryRunResult runGeometryCase(const GeometryCase& c, bool show_progress, std::ostream& progress);

}  // namespace radnet::cases
