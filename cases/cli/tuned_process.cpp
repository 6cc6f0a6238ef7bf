#include "cases/cli/tuned_process.hpp"

#include <cstdlib>
#include <initializer_list>
#include <unistd.h>

namespace radnet::cases {

// The process environment that runs fast on this kind of machine, set once by starting the
// process again (glibc and libgomp read it only at start-up; bench: docs/benchmarks.md):
// - large buffers on transparent huge pages (GLIBC_TUNABLES=glibc.malloc.hugetlb=1): on
//   virtual machines a page fault costs ~10 µs, 2.4 s to first touch 1 GB of 4 kB pages, and
//   F, G and their copies are fresh memory;
// - OpenMP threads that sleep when idle (OMP_WAIT_POLICY=passive): a worker spinning after a
//   parallel region takes the core's other hyperthread from the serial code that follows.
// Together they took the 1,536-node room from 4.0 s to 1.9 s. Not under mpirun (its
// launcher owns the process); whatever the user set is kept; RADNET_SAME_PROCESS=1 turns
// it off. If exec fails, the run goes on as it is.
void restartTuned(char** argv) {
  if (std::getenv("RADNET_SAME_PROCESS")) return;
  for (const char* mpi : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"})
    if (std::getenv(mpi)) return;
  setenv("RADNET_SAME_PROCESS", "1", 1);  // the restarted process does not restart again
  bool changed = false;
  if (!std::getenv("GLIBC_TUNABLES")) changed = setenv("GLIBC_TUNABLES", "glibc.malloc.hugetlb=1", 1) == 0;
  if (!std::getenv("OMP_WAIT_POLICY") && !std::getenv("GOMP_SPINCOUNT"))
    changed = (setenv("OMP_WAIT_POLICY", "passive", 1) == 0) || changed;
  if (changed) execv("/proc/self/exe", argv);
}

}  // namespace radnet::cases
