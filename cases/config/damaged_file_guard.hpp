#pragma once
// A damaged file can crash the library that reads it before any check of ours runs: HDF5 1.10
// segfaults in H5HG_read on a corrupt global heap (the variable-length strings of /nodes/name),
// found by tests/fuzz_outputs.py flipping bytes of a result. Results (export, report) and
// imported files (an ESATAN TMD) are read through it. The read is tried first in a child
// process; a child ended by a signal means the file is damaged, and the parent says so.
#include <functional>
#include <string>

namespace radnet::cases {

/// Runs `read` (which reads `path` and nothing else) in a forked child. Returns normally when
/// the child finished, by a return or by an exception (the parent's own read then reports it
/// with its location). @throws InputError naming `path` when a signal ended the child.
void tryReadInChild(const std::string& path, const std::function<void()>& read);

}  // namespace radnet::cases
