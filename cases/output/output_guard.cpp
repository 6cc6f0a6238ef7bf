#include "cases/output/output_guard.hpp"

#include "cases/config/errors.hpp"

#include <unistd.h>
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>

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
constexpr int kSlots = 8;
constexpr size_t kPathMax = 4096;
char temporaries[kSlots][kPathMax];
std::atomic<bool> slot_used[kSlots];

extern "C" void onSignal(int signal_number) {
  for (int k = 0; k < kSlots; ++k)
    if (slot_used[k].load()) ::unlink(temporaries[k]);
  std::signal(signal_number, SIG_DFL);
  std::raise(signal_number);
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
  for (int s : {SIGINT, SIGTERM, SIGHUP}) std::signal(s, onSignal);
}

}  // namespace radnet::cases
