#pragma once
// Deflating a dataset's chunks on all cores (HDF5 1.10 runs its filters on one): chunks are
// filled and compressed in parallel in batches (bounded memory) and handed to HDF5 finished,
// in order, so the file does not depend on the thread count. Readers see an ordinary deflated
// dataset (with HDF5's shuffle filter before deflate where the writer asks for it, skipped
// chunk by chunk through the chunk's filter mask). A chunk of nothing but zero bytes is not
// written: HDF5 reads a chunk never written as the fill value, 0.
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace radnet::cases {

/// Fills chunk k's bytes (`chunk_bytes` of them, zeroed beforehand).
using ChunkBytesFill = std::function<void(long long k, unsigned char* bytes)>;
/// Writes chunk k's deflated bytes (zlib stream, deflate level 1) with the filter mask
/// H5Dwrite_chunk records (bit 0 set: the pipeline's first filter, the shuffle, skipped).
using ChunkBytesWrite =
    std::function<void(long long k, const std::vector<unsigned char>& deflated, unsigned filter_mask)>;

/// Deflates chunks 0 … count − 1 and writes each that is not all zeros, in order. With
/// `shuffle_element_bytes` > 1 the dataset's pipeline is shuffle (H5Pset_shuffle) then
/// deflate, and a chunk whose elements are at least half non-zero is byte-shuffled first
/// (its mask 0); the others, mostly zeros, are deflated as they are (mask 1). 0: deflate
/// alone in the pipeline, every mask 0.
/// @throws OutputError when compression fails
void deflateChunks(long long count, std::size_t chunk_bytes, std::size_t shuffle_element_bytes,
                   const ChunkBytesFill& fill, const ChunkBytesWrite& write, const std::string& what);

/// HDF5's shuffle filter (H5Z_FILTER_SHUFFLE) on `bytes` bytes of elements of `element`
/// bytes: byte b of element i to b × count + i, trailing bytes (bytes mod element) kept.
void shuffleBytes(const unsigned char* in, std::size_t bytes, std::size_t element, unsigned char* out);

/// Fills chunk k of a row-major array of `rank` (1 or 2) dimensions `dims` with element size
/// `element_bytes` into `bytes` (chunk dims `chunk`, edge chunks zero-padded as HDF5 stores them).
void copyChunk(const unsigned char* data, int rank, const unsigned long long* dims, const unsigned long long* chunk,
               std::size_t element_bytes, long long k, unsigned char* bytes);

}  // namespace radnet::cases
