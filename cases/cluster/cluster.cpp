#include "cases/cluster/cluster.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <new>

#ifdef RADNET_HAVE_MPI
// The C API only: without these, mpi.h in C++ pulls in the deprecated C++ bindings,
// which need a library this build does not link.
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

namespace radnet::cluster {
namespace {

int g_rank = 0;
int g_size = 1;
bool g_started = false;

#ifdef RADNET_HAVE_MPI
// MPI counts are int: large arrays go in blocks of 2^30 elements.
constexpr std::size_t kBlock = std::size_t{1} << 30;

// Started by a launcher: Open MPI's mpirun, a PMI (MPICH, Slurm's srun) or PMIx one.
bool launchedByMpirun() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(var)) return true;
  return false;
}

template <class T>
void allreduceBlocks(T* data, std::size_t count, MPI_Datatype type, MPI_Op op) {
  checkPeers();
  for (std::size_t at = 0; at < count; at += kBlock)
    MPI_Allreduce(MPI_IN_PLACE, data + at, static_cast<int>(std::min(kBlock, count - at)), type, op, MPI_COMM_WORLD);
}

// Between the steps of one exchange a rank cannot join an agreement (the others are in
// the exchange's next collective): should it run out of memory there, every rank stops
// (MPI_Abort; mpirun exits with the code, 2 as for any case too large for the machine).
template <class Allocate>
void allocateOrAbort(Allocate&& allocate) {
  try {
    allocate();
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "radnet: out of memory on MPI rank %d while exchanging results: stopping every rank\n",
                 g_rank);
    MPI_Abort(MPI_COMM_WORLD, 2);
  }
}

void broadcastBlocks(double* data, std::size_t count, int root) {
  for (std::size_t at = 0; at < count; at += kBlock)
    MPI_Bcast(data + at, static_cast<int>(std::min(kBlock, count - at)), MPI_DOUBLE, root, MPI_COMM_WORLD);
}
#endif

}  // namespace

void start(int& argc, char**& argv) {
#ifdef RADNET_HAVE_MPI
  if (g_started || !launchedByMpirun()) return;
  int provided = 0;
  // Only the main thread calls MPI; OpenMP and std::threads work inside a rank.
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  g_started = true;
#else
  (void)argc;
  (void)argv;
#endif
}

void finish() {
#ifdef RADNET_HAVE_MPI
  if (g_started) MPI_Finalize();
#endif
  g_started = false;
}

int rank() { return g_rank; }
int size() { return g_size; }
bool distributed() { return g_size > 1; }

std::vector<char> ownedMask(long long count) {
  std::vector<char> mask(static_cast<std::size_t>(std::max(0LL, count)));
  for (long long k = 0; k < count; ++k) mask[static_cast<std::size_t>(k)] = owns(k);
  return mask;
}

int agree(int code) {
#ifdef RADNET_HAVE_MPI
  if (g_started && g_size > 1) {
    int worst = code;
    MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    return worst;
  }
#endif
  return code;
}

void checkPeers() {
  const int code = agree(0);
  if (code != 0) throw PeerFailure(code);
}

void join(double* data, std::size_t count) {
#ifdef RADNET_HAVE_MPI
  static_assert(sizeof(double) == sizeof(std::uint64_t), "a double is 64 bits");
  // MPI_BOR is defined on integers: the doubles' bytes as unsigned 64-bit integers.
  if (g_size > 1) allreduceBlocks(reinterpret_cast<std::uint64_t*>(data), count, MPI_UINT64_T, MPI_BOR);
#else
  (void)data, (void)count;
#endif
}

void sum(std::int64_t* data, std::size_t count) {
#ifdef RADNET_HAVE_MPI
  if (g_size > 1) allreduceBlocks(data, count, MPI_INT64_T, MPI_SUM);
#else
  (void)data, (void)count;
#endif
}

void max(double* data, std::size_t count) {
#ifdef RADNET_HAVE_MPI
  if (g_size > 1) allreduceBlocks(data, count, MPI_DOUBLE, MPI_MAX);
#else
  (void)data, (void)count;
#endif
}

std::vector<double> gatherAll(const std::vector<double>& mine) {
  if (g_size == 1) return mine;
  std::vector<std::int64_t> counts(static_cast<std::size_t>(g_size), 0);
  counts[static_cast<std::size_t>(g_rank)] = static_cast<std::int64_t>(mine.size());
  sum(counts.data(), counts.size());  // agrees first
  std::int64_t total = 0;
  for (std::int64_t c : counts) total += c;
  std::vector<double> all;
#ifdef RADNET_HAVE_MPI
  allocateOrAbort([&] { all.resize(static_cast<std::size_t>(total)); });
  // One broadcast per rank: no int displacement limits however large the gather.
  std::size_t at = 0;
  for (int r = 0; r < g_size; ++r) {
    const auto c = static_cast<std::size_t>(counts[static_cast<std::size_t>(r)]);
    if (r == g_rank) std::copy(mine.begin(), mine.end(), all.begin() + static_cast<std::ptrdiff_t>(at));
    broadcastBlocks(all.data() + at, c, r);
    at += c;
  }
#endif
  return all;
}

std::vector<double> exchange(const std::vector<std::vector<double>>& send) {
  if (g_size == 1) return send.empty() ? std::vector<double>() : send[0];
  std::vector<double> received;
#ifdef RADNET_HAVE_MPI
  checkPeers();
  std::vector<long long> send_count(static_cast<std::size_t>(g_size)), recv_count(send_count.size());
  for (int r = 0; r < g_size; ++r) send_count[std::size_t(r)] = static_cast<long long>(send[std::size_t(r)].size());
  MPI_Alltoall(send_count.data(), 1, MPI_LONG_LONG, recv_count.data(), 1, MPI_LONG_LONG, MPI_COMM_WORLD);
  std::vector<std::size_t> offset(static_cast<std::size_t>(g_size) + 1, 0);
  for (int r = 0; r < g_size; ++r) offset[std::size_t(r) + 1] = offset[std::size_t(r)] + std::size_t(recv_count[std::size_t(r)]);
  allocateOrAbort([&] { received.resize(offset.back()); });
  // Every block sent and received at once (MPI counts are int: blocks of kBlock), tagged
  // by its index; a rank's own part is copied.
  std::vector<MPI_Request> requests;
  for (int r = 0; r < g_size; ++r) {
    const std::vector<double>& out = send[std::size_t(r)];
    double* in = received.data() + offset[std::size_t(r)];
    const std::size_t in_count = offset[std::size_t(r) + 1] - offset[std::size_t(r)];
    if (r == g_rank) {
      std::copy(out.begin(), out.end(), in);
      continue;
    }
    for (std::size_t at = 0, tag = 0; at < in_count; at += kBlock, ++tag) {
      requests.emplace_back();
      MPI_Irecv(in + at, static_cast<int>(std::min(kBlock, in_count - at)), MPI_DOUBLE, r, static_cast<int>(tag),
                MPI_COMM_WORLD, &requests.back());
    }
    for (std::size_t at = 0, tag = 0; at < out.size(); at += kBlock, ++tag) {
      requests.emplace_back();
      MPI_Isend(out.data() + at, static_cast<int>(std::min(kBlock, out.size() - at)), MPI_DOUBLE, r,
                static_cast<int>(tag), MPI_COMM_WORLD, &requests.back());
    }
  }
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
#endif
  return received;
}

void broadcast(double* data, std::size_t count) {
#ifdef RADNET_HAVE_MPI
  if (g_size == 1) return;
  checkPeers();
  broadcastBlocks(data, count, 0);
#else
  (void)data, (void)count;
#endif
}

void broadcast(std::string& text, int root) {
#ifdef RADNET_HAVE_MPI
  if (g_size == 1) return;
  checkPeers();
  long long length = static_cast<long long>(text.size());
  MPI_Bcast(&length, 1, MPI_LONG_LONG, root, MPI_COMM_WORLD);
  allocateOrAbort([&] { text.resize(static_cast<std::size_t>(length)); });
  for (std::size_t at = 0; at < text.size(); at += kBlock)
    MPI_Bcast(text.data() + at, static_cast<int>(std::min(kBlock, text.size() - at)), MPI_CHAR, root, MPI_COMM_WORLD);
#else
  (void)text, (void)root;
#endif
}

}  // namespace radnet::cluster
