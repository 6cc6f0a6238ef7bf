#pragma once
// Deflating a dataset's chunks on all cores (HDF5 1.10 runs its filters on one): chunks are
// filled and compressed in parallel in batches (bounded memory) and handed to HDF5 finished,
// in order, so the file does not depend on the thread count. Readers see an ordinary deflated
// dataset. A chunk of nothing but zero bytes is not written: HDF5 reads a chunk never
// written as the fill value, 0.
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace radnet::cases {

/// Fills chunk k's bytes (`chunk_bytes` of them, zeroed beforehand).
using ChunkBytesFill = std::function<void(long long k, unsigned char* bytes)>;
/// Writes chunk k's deflated bytes (zlib stream, deflate level 1).
using ChunkBytesWrite = std::function<void(long long k, const std::vector<unsigned char>& deflated)>;

/// Deflates chunks 0 … count − 1 and writes each that is not all zeros, in order.
/// @throws OutputError when compression fails
void deflateChunks(long long count, std::size_t chunk_bytes, const ChunkBytesFill& fill, const ChunkBytesWrite& write,
                   const std::string& what);

/// Fills chunk k of a row-major array of `rank` (1 or 2) dimensions `dims` with element size
/// `element_bytes` into `bytes` (chunk dims `chunk`, edge chunks zero-padded as HDF5 stores them).
void copyChunk(const unsigned char* data, int rank, const unsigned long long* dims, const unsigned long long* chunk,
               std::size_t element_bytes, long long k, unsigned char* bytes);

}  // namespace radnet::cases
