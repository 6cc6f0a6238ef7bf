#include "cases/output/output_guard.hpp"

#include "cases/config/errors.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <string>

namespace radnet::cases {
namespace {

namespace fs = std::filesystem;

void checkOne(const std::string& target, const std::vector<std::string>& inputs, const std::string& what) {
  const fs::path path = fs::absolute(target);
  const fs::path dir = path.parent_path();
  if (!fs::is_directory(dir)) throw InputError(target, 0, 0, what + ": directory '" + dir.string() + "' does not exist");
  // A folder that refuses writing (permissions, a read-only mount) is the output failing, exit 4.
  if (::access(dir.c_str(), W_OK) != 0)
    throw OutputError(what + ": directory '" + dir.string() + "' is not writable (" + std::strerror(errno) + ")");
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
  for (const char* input : {".yaml", ".yml", ".off", ".obj", ".stl", ".ply"})
    if (extension == input)
      throw InputError(target, 0, 0, what + ": a '" + extension + "' name is an input's: radnet writes HDF5 "
                                   "(.h5) and its ParaView files beside it; give another name");
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);  // follows a symbolic link to what it names
  if (!ec && fs::exists(status) && !fs::is_regular_file(status))
    throw InputError(target, 0, 0, what + " exists and is not a regular file: radnet replaces only regular "
                                 "files (writing means renaming over the target)");
  for (const std::string& input : inputs)
    if (fs::exists(input) && fs::exists(path) && fs::equivalent(input, path, ec))
      throw InputError(target, 0, 0, what + " is the input '" + input + "': it would be overwritten");
}

// Signal-safe storage: fixed buffers, a slot is in use while its first byte is not 0.
constexpr int kSlots = 256;  // a result, its sidecars, a design case each: far fewer
constexpr size_t kPathMax = 4096;
char temporaries[kSlots][kPathMax];
std::atomic<bool> slot_used[kSlots];

// While a set of files is renamed into place, a signal waits: the run then ends with the
// new set whole, never the new .h5 beside the old .xmf.
std::atomic<bool> publishing{false};
std::atomic<int> deferred_signal{0};

void removeRegistered() {
  for (int k = 0; k < kSlots; ++k)
    if (slot_used[k].load()) ::unlink(temporaries[k]);
}

extern "C" void onSignal(int signal_number) {
  if (publishing.load()) {
    deferred_signal.store(signal_number);
    return;
  }
  removeRegistered();
  std::signal(signal_number, SIG_DFL);
  std::raise(signal_number);
}

// `text` into a new temporary beside `path`, created exclusively and without following a
// symlink (as the .h5's temporary, hdf5_writer.cpp): a planted name is passed over, never
// written through. Returns the temporary's path (registered for removal on a signal).
std::string writeTemporary(const std::string& path, const std::string& text) {
  std::string temp;
  int fd = -1;
  for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
    temp = path + ".tmp-" + std::to_string(::getpid()) + (attempt ? "-" + std::to_string(attempt) : "");
    fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0 && errno != EEXIST) break;
  }
  if (fd < 0) throw OutputError("cannot create '" + temp + "': " + std::strerror(errno));
  registerTemporary(temp);
  const auto fail = [&](const std::string& why) {
    ::close(fd);
    std::remove(temp.c_str());
    unregisterTemporary(temp);
    throw OutputError("cannot write '" + temp + "': " + why);  // a full disk shows here, not as a short file
  };
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail(n == 0 ? "nothing written" : std::strerror(errno));
    done += static_cast<size_t>(n);
  }
  // fsync: the rename must not publish a name whose data a crash of the machine would lose.
  if (::fsync(fd) != 0) fail(std::strerror(errno));
  if (::close(fd) != 0) {
    fd = -1;
    std::remove(temp.c_str());
    unregisterTemporary(temp);
    throw OutputError("cannot write '" + temp + "': " + std::strerror(errno));
  }
  return temp;
}

}  // namespace

void checkOutputTarget(const std::string& output, const std::vector<std::string>& inputs, bool with_sidecar) {
  if (fs::path(output).extension() == ".xmf")
    throw InputError(output, 0, 0, "the output is the HDF5 file; its ParaView file takes the .xmf name beside it");
  checkOne(output, inputs, "output '" + output + "'");
  if (with_sidecar) {
    const fs::path p(output);
    checkOne((p.parent_path() / p.stem()).string() + ".xmf", inputs, "the ParaView file of '" + output + "'");
  }
}

void registerTemporary(const std::string& path) {
  if (path.size() >= kPathMax) return;
  for (int k = 0; k < kSlots; ++k)
    if (!slot_used[k].load()) {
      std::memcpy(temporaries[k], path.c_str(), path.size() + 1);
      slot_used[k].store(true);
      return;
    }
}

void unregisterTemporary(const std::string& path) {
  for (int k = 0; k < kSlots; ++k)
    if (slot_used[k].load() && path == temporaries[k]) slot_used[k].store(false);
}

void removeTemporariesOnSignal() {
  for (int s : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM, SIGVTALRM, SIGPROF, SIGXCPU, SIGPIPE})
    std::signal(s, onSignal);
  // Past a file-size limit a write fails with EFBIG (exit 4, the old files kept) instead of
  // the process dumping core with its temporary left behind.
  std::signal(SIGXFSZ, SIG_IGN);
}

namespace {
int terminate_exit_code = 3;

[[noreturn]] void onTerminate() {
  const char* what = "std::terminate was called";
  std::string text;
  if (const std::exception_ptr e = std::current_exception()) {
    try {
      std::rethrow_exception(e);
    } catch (const std::exception& x) {
      text = x.what();
      what = text.c_str();
    } catch (...) {
      what = "an exception of unknown type";
    }
  }
  // Straight to the descriptor: _Exit flushes no stdio buffer.
  const std::string message = std::string("radnet: internal error: ") + what + "; nothing was written\n";
  [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, message.data(), message.size());
  removeRegistered();
  std::_Exit(terminate_exit_code);
}
}  // namespace

void exitOnTerminate(int exit_code) {
  terminate_exit_code = exit_code;
  std::set_terminate(onTerminate);
}

PendingFiles::~PendingFiles() {
  for (const auto& [temp, target] : files_) {
    std::remove(temp.c_str());
    unregisterTemporary(temp);
  }
}

void PendingFiles::adopt(const std::string& temp, const std::string& target) { files_.emplace_back(temp, target); }

void PendingFiles::addText(const std::string& target, const std::string& text) {
  files_.emplace_back(writeTemporary(target, text), target);
}

void PendingFiles::publish() {
  // What would make a rename fail is looked for before the first: a target taken meanwhile
  // by a directory (or anything not a regular file) leaves every old file as it was.
  for (const auto& [temp, target] : files_) {
    struct stat taken{};
    if (::lstat(target.c_str(), &taken) == 0 && !S_ISREG(taken.st_mode) && !S_ISLNK(taken.st_mode))
      throw OutputError("cannot replace '" + target + "': it is not a regular file");
  }
  publishing.store(true);
  std::string failed;
  size_t k = 0;
  for (; k < files_.size() && failed.empty(); ++k) {
    if (std::rename(files_[k].first.c_str(), files_[k].second.c_str()) != 0)
      failed = "cannot rename '" + files_[k].first + "' to '" + files_[k].second + "': " + std::strerror(errno);
    else
      unregisterTemporary(files_[k].first);
  }
  if (failed.empty()) files_.clear();
  else files_.erase(files_.begin(), files_.begin() + static_cast<long>(k) - 1);  // the failed one onwards
  publishing.store(false);
  if (const int s = deferred_signal.exchange(0)) onSignal(s);
  if (!failed.empty()) throw OutputError(failed);
}

void writeTextFilesAtomically(const std::vector<std::pair<std::string, std::string>>& files) {
  PendingFiles pending;
  for (const auto& [path, text] : files) pending.addText(path, text);
  pending.publish();
}

void writeTextAtomically(const std::string& path, const std::string& text) { writeTextFilesAtomically({{path, text}}); }

}  // namespace radnet::cases
