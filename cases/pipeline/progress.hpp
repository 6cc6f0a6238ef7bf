#pragma once
// Progress of a long stage on stderr.
#include <functional>
#include <iosfwd>

namespace radnet::cases {

/// Progress of one stage; (done, total) as the geometry and orbit loops report them. On a
/// terminal (std::cerr on a tty) a bar "radnet: <stage> [###   ] NN % (done/total <unit>)"
/// redrawn in place about 50 times; elsewhere (a log file, a pipe) plain lines at 0, 25, 50,
/// 75 and 100 %.
std::function<void(int, int)> progressBar(std::ostream& out, const char* stage, const char* unit);

/// Progress of a temperature solve, (orbit, outputs done in it, outputs per orbit) as
/// solver::ThermalOptions::progress reports them: a line "radnet: temperatures: orbit 2,
/// output 38/76, 95 s" at most every `interval_s`, so a solve shorter than that prints none.
std::function<void(int, int, int)> thermalProgress(std::ostream& out, double interval_s = 10.0);

}  // namespace radnet::cases
