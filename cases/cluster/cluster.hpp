#pragma once
// radnet across processes (docs/mpi.md): the ranks of `mpirun -np R radnet run …`, each
// running the same case, share out view-factor rows, planet-ray nodes, sun positions and
// optical samples, and exchange the results with MPI collectives. Without mpirun (or in a
// build without MPI) there is one rank and every call here is a no-op.
//
// Failure contract: a rank that fails (bad input, numerical, output) must not leave the
// others waiting in a collective. Every data collective here is preceded by an agreement
// (an MPI_Allreduce MAX of each rank's exit code, 0 when fine); a failing rank joins the
// next agreement with its code instead (collectives match by order, not by call site), so
// every rank learns of the failure at the same point and leaves with the same code.
// This is the only file of radnet that includes mpi.h.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace radnet::cluster {

/// Another rank failed with exit code `code()`; this rank stops with the same code.
class PeerFailure : public std::runtime_error {
 public:
  explicit PeerFailure(int code)
      : std::runtime_error("another rank failed (exit " + std::to_string(code) + ")"), code_(code) {}
  int code() const { return code_; }

 private:
  int code_;
};

/// Initialises MPI when the process was started by mpirun (Open MPI's or another
/// launcher's environment says so); otherwise nothing. Call once, first thing in main().
void start(int& argc, char**& argv);
/// MPI_Finalize when started. Call once before main() returns.
void finish();

int rank();         ///< this process's rank, 0 … size() − 1 (0 without MPI)
int size();         ///< number of ranks (1 without MPI)
bool distributed(); ///< more than one rank

/// Item k (a node, a position, a sample) is this rank's: items are dealt round robin, so
/// nodes of similar cost (neighbours in a mesh) spread evenly.
inline bool owns(long long item) { return size() == 1 || item % size() == rank(); }
/// Per item of `count`, 1 where owns(item).
std::vector<char> ownedMask(long long count);

/// The agreement: every rank gives its exit code (0: fine); returns the largest. Call it
/// once from a rank's error path; the data collectives below call it themselves.
int agree(int code);
/// agree(0); @throws PeerFailure when a rank failed.
void checkPeers();

/// Joins parts in place: each element is given by at most one rank, the others hold +0.0
/// there; every rank ends with the giver's value bit for bit (−0.0 and NaN too: a bitwise
/// OR of the 64-bit patterns). @throws PeerFailure
void join(double* data, std::size_t count);
/// Element-wise sums over the ranks, in place (counts). @throws PeerFailure
void sum(std::int64_t* data, std::size_t count);
/// Element-wise maxima over the ranks, in place. @throws PeerFailure
void max(double* data, std::size_t count);
/// Every rank's `mine`, concatenated in rank order, on every rank. @throws PeerFailure
std::vector<double> gatherAll(const std::vector<double>& mine);
/// send[r] to rank r (one vector per rank); returns what every rank sent to this one,
/// concatenated in rank order (an all-to-all). @throws PeerFailure
std::vector<double> exchange(const std::vector<std::vector<double>>& send);
/// Rank 0's `data` (count given on every rank) on every rank. @throws PeerFailure
void broadcast(double* data, std::size_t count);
/// Rank `root`'s string (text or bytes) on every rank. @throws PeerFailure
void broadcast(std::string& text, int root = 0);

}  // namespace radnet::cluster
