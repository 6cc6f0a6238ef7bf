// What fresh memory costs on this machine: 64 MB mapped, touched once a page, unmapped,
// three times in a row, with 4 kB pages and with transparent huge pages (MADV_HUGEPAGE).
// On the project's virtual machines (Firecracker with free-page reporting) a page the
// guest has not used lately costs the host a fault as well: the first touch, not the
// arithmetic, is what a stage that builds large fresh tables pays (docs/benchmarks.md,
// "Fresh memory"). Usage: bench_first_touch [MB]
#include <sys/mman.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>

namespace {

double seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

int main(int argc, char** argv) {
  const size_t megabytes = argc > 1 ? static_cast<size_t>(std::atol(argv[1])) : 64;
  const size_t bytes = megabytes << 20;
  std::printf("| pages | pass | first touch, ms/MB | memset after, ms/MB |\n|---|---|---|---|\n");
  for (const bool huge : {false, true})
    for (int pass = 0; pass < 3; ++pass) {
      void* mapped = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
      if (mapped == MAP_FAILED) return 1;
      char* p = static_cast<char*>(mapped);
      if (huge) madvise(p, bytes, MADV_HUGEPAGE);
      const double t0 = seconds();
      for (size_t i = 0; i < bytes; i += 4096) p[i] = 1;
      const double t1 = seconds();
      std::memset(p, 2, bytes);
      const double t2 = seconds();
      std::printf("| %s | %d | %.3f | %.3f |\n", huge ? "2 MB (THP)" : "4 kB", pass + 1,
                  (t1 - t0) * 1e3 / static_cast<double>(megabytes), (t2 - t1) * 1e3 / static_cast<double>(megabytes));
      munmap(p, bytes);
    }
  return 0;
}
