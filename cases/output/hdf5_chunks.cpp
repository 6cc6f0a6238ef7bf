#include "cases/output/hdf5_chunks.hpp"

#include "cases/config/errors.hpp"
#include "solver/parallel.hpp"

#include <libdeflate.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <memory>
#include <string>

namespace radnet::cases {
namespace {

// Deflate level 1 as a zlib stream (what HDF5's deflate filter reads) by libdeflate, one
// compressor per thread; empty on failure. On the 6,144-node room's shuffled F, G, GR and
// σ(F) chunks libdeflate's level 1 ran 1.85× as fast as zlib's (205 against 111 MB/s, one
// core) for 2 % fewer bytes. zlib's level 4 had taken a third longer than its level 1 on a
// 6,402-node run for a file 7 % smaller.
std::vector<unsigned char> deflate(const unsigned char* raw, std::size_t bytes) {
  struct Free {
    void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
  };
  thread_local std::unique_ptr<libdeflate_compressor, Free> compressor(libdeflate_alloc_compressor(1));
  if (!compressor) return {};
  std::vector<unsigned char> out(libdeflate_zlib_compress_bound(compressor.get(), bytes));
  const std::size_t size = libdeflate_zlib_compress(compressor.get(), raw, bytes, out.data(), out.size());
  if (size == 0) return {};
  out.resize(size);
  return out;
}

// Whether a chunk is shuffled before it is deflated: when at least half its elements are
// non-zero. Shuffling puts the doubles' sign-and-exponent bytes together, which deflate packs
// where it finds little to match in whole doubles: on the 6,144-node room's dense F, G and
// GR chunks deflate ran 1.5–1.9× faster and wrote 15–30 % fewer bytes. Mostly-zero chunks
// (the sparse view factors of a spacecraft) deflate better unshuffled: shuffling every chunk
// made the 1,602-node satellite's matrices grow from 7.6 to 9.1 MB.
bool shuffles(const unsigned char* raw, std::size_t bytes, std::size_t element) {
  if (element < 2) return false;
  const std::size_t count = bytes / element;
  std::size_t non_zero = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const unsigned char* e = raw + i * element;
    non_zero += std::any_of(e, e + element, [](unsigned char c) { return c != 0; });
  }
  return 2 * non_zero >= count;
}

}  // namespace

void shuffleBytes(const unsigned char* in, std::size_t bytes, std::size_t element, unsigned char* out) {
  const std::size_t count = element > 0 ? bytes / element : 0;
  for (std::size_t b = 0; b < element; ++b)
    for (std::size_t i = 0; i < count; ++i) out[b * count + i] = in[i * element + b];
  std::memcpy(out + count * element, in + count * element, bytes - count * element);
}

void deflateChunks(long long count, std::size_t chunk_bytes, std::size_t shuffle_element_bytes,
                   const ChunkBytesFill& fill, const ChunkBytesWrite& write, const std::string& what) {
  // Batches of 64 chunks: at most 64 raw and 64 deflated chunks in memory (32 MB each way
  // for 256 × 256 doubles).
  constexpr long long kBatch = 64;
  std::vector<std::vector<unsigned char>> deflated(static_cast<size_t>(std::min(count, kBatch)));
  std::vector<char> zero(deflated.size(), 0);
  std::vector<unsigned> mask(deflated.size(), 0);
  for (long long first = 0; first < count; first += kBatch) {
    const long long batch = std::min(kBatch, count - first);
    std::atomic<bool> failed{false};
    solver::parallelFor(batch, [&](long long b) {
      std::vector<unsigned char> raw(chunk_bytes, 0);
      fill(first + b, raw.data());
      zero[static_cast<size_t>(b)] = std::all_of(raw.begin(), raw.end(), [](unsigned char c) { return c == 0; });
      if (zero[static_cast<size_t>(b)]) return;
      const bool shuffled = shuffles(raw.data(), chunk_bytes, shuffle_element_bytes);
      mask[static_cast<size_t>(b)] = shuffle_element_bytes > 1 && !shuffled ? 1u : 0u;
      if (shuffled) {
        std::vector<unsigned char> planes(chunk_bytes);
        shuffleBytes(raw.data(), chunk_bytes, shuffle_element_bytes, planes.data());
        raw.swap(planes);
      }
      deflated[static_cast<size_t>(b)] = deflate(raw.data(), raw.size());
      if (deflated[static_cast<size_t>(b)].empty()) failed = true;
    });
    if (failed) throw OutputError(what + ": compressing a chunk failed (out of memory?)");
    for (long long b = 0; b < batch; ++b)
      if (!zero[static_cast<size_t>(b)]) write(first + b, deflated[static_cast<size_t>(b)], mask[static_cast<size_t>(b)]);
  }
}

void copyChunk(const unsigned char* data, int rank, const unsigned long long* dims, const unsigned long long* chunk,
               std::size_t element_bytes, long long k, unsigned char* bytes) {
  if (rank == 1) {
    const unsigned long long begin = static_cast<unsigned long long>(k) * chunk[0];
    const unsigned long long n = std::min(chunk[0], dims[0] - begin);
    std::memcpy(bytes, data + begin * element_bytes, n * element_bytes);
    return;
  }
  const unsigned long long col_chunks = (dims[1] + chunk[1] - 1) / chunk[1];
  const unsigned long long row0 = static_cast<unsigned long long>(k) / col_chunks * chunk[0];
  const unsigned long long col0 = static_cast<unsigned long long>(k) % col_chunks * chunk[1];
  const unsigned long long rows = std::min(chunk[0], dims[0] - row0), cols = std::min(chunk[1], dims[1] - col0);
  for (unsigned long long r = 0; r < rows; ++r)
    std::memcpy(bytes + r * chunk[1] * element_bytes, data + ((row0 + r) * dims[1] + col0) * element_bytes,
                cols * element_bytes);
}

}  // namespace radnet::cases
