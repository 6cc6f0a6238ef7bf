#pragma once
// Progress of a long stage on stderr.
#include <functional>
#include <iosfwd>

namespace radnet::cases {

/// A progress line "radnet: <stage> NN % (done/total <unit>)", redrawn in place about
/// 50 times per stage; (done, total) as the geometry and orbit loops report them.
std::function<void(int, int)> progressBar(std::ostream& out, const char* stage, const char* unit);

}  // namespace radnet::cases
