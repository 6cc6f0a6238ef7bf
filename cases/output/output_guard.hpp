#pragma once
// What radnet may write over, checked before anything is computed (docs/design.md,
// "Contracts"), and temporary files removed when a signal ends the run.
#include <string>
#include <utility>
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
/// Up to 256 at a time; paths longer than 4 KiB are not registered (and so not cleaned up).
void registerTemporary(const std::string& path);
void unregisterTemporary(const std::string& path);

/// Installs handlers for every signal that ends a process and can be caught (SIGINT, SIGTERM,
/// SIGHUP, SIGQUIT, SIGUSR1/2, SIGALRM, SIGVTALRM, SIGPROF, SIGXCPU, SIGPIPE) that remove the
/// registered temporary files and then end the process as the signal would have; SIGXFSZ is
/// ignored, so a write past the file-size limit fails (exit 4) instead.
void removeTemporariesOnSignal();

/// Makes std::terminate (an exception escaping a destructor or a thread, a failed noexcept) an
/// exit with code `exit_code` and a message naming the exception, the registered temporaries
/// removed: never "terminate called …" and signal 6.
void exitOnTerminate(int exit_code);

/// A set of files written to temporaries beside their targets and renamed over them together
/// (publish): an error before publish leaves every old file, and a signal during publish waits
/// until the whole new set is in place. Temporaries not published are removed on destruction.
class PendingFiles {
 public:
  PendingFiles() = default;
  PendingFiles(const PendingFiles&) = delete;
  PendingFiles& operator=(const PendingFiles&) = delete;
  ~PendingFiles();
  /// A temporary written elsewhere (registered, closed) to be renamed to `target`.
  void adopt(const std::string& temp, const std::string& target);
  /// Writes `text` to a new exclusive temporary beside `target` now (OutputError on failure).
  void addText(const std::string& target, const std::string& text);
  /// Renames every temporary over its target, in the order given.
  void publish();

 private:
  std::vector<std::pair<std::string, std::string>> files_;  ///< (temporary, target)
};

/// Writes `text` to `path` through a temporary file and a rename.
void writeTextAtomically(const std::string& path, const std::string& text);
/// Writes every (path, text) through temporaries, all before any rename: a full disk or any
/// write error leaves every old file as it was.
void writeTextFilesAtomically(const std::vector<std::pair<std::string, std::string>>& files);

}  // namespace radnet::cases
