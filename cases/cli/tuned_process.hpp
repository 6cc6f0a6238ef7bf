#pragma once
// The process environment radnet runs fastest in (huge pages, sleeping OpenMP workers),
// set by starting the process again once (tuned_process.cpp says why and what measured).

namespace radnet::cases {

/// Called first in main(): may replace the process by itself with the environment set.
void restartTuned(char** argv);

}  // namespace radnet::cases
