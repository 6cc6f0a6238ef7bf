#pragma once
// What radnet may write over, checked before anything is computed (docs/design.md,
// "Contracts"), and temporary files removed when a signal ends the run.
#include <string>
#include <vector>

namespace radnet::cases {

/// Refuses (InputError, exit 2), before any computing, an output that could not be written or
/// should not be: a missing or unwritable directory; an existing target that is not a regular
/// file (a device, a FIFO, a directory: the rename would replace it); a target that is one of
/// `inputs` (the case file, its includes, the result read); a name with an input's extension
/// (.yaml, .yml, .xmf: the sidecar's own, .off, .obj, .stl, .ply); and the same for the
/// sidecar `<stem>.xmf` when `with_sidecar`.
void checkOutputTarget(const std::string& output, const std::vector<std::string>& inputs, bool with_sidecar);

/// Temporary files a signal must not leave behind: registered while they are being written.
/// Up to 8 at a time; paths longer than 4 KiB are not registered (and so not cleaned up).
void registerTemporary(const std::string& path);
void unregisterTemporary(const std::string& path);

/// Installs handlers for SIGINT, SIGTERM and SIGHUP that remove the registered temporary files
/// and then end the process as the signal would have.
void removeTemporariesOnSignal();

}  // namespace radnet::cases
