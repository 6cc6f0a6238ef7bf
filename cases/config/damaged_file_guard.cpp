#include "cases/config/damaged_file_guard.hpp"

#include "cases/config/errors.hpp"

#include <cerrno>
#include <csignal>
#include <cstring>

#include <sys/wait.h>
#include <unistd.h>

namespace radnet::cases {

void tryReadInChild(const std::string& path, const std::function<void()>& read) {
  const pid_t child = fork();
  if (child < 0) return;  // no child to spare: the parent's read goes unguarded, as before
  if (child == 0) {
    // The default action for the crash signals: the child must not run the parent's handlers
    // (they remove the parent's registered temporaries), and _exit skips every atexit clean-up.
    for (int sig : {SIGSEGV, SIGBUS, SIGABRT, SIGFPE, SIGILL}) std::signal(sig, SIG_DFL);
    try {
      read();
    } catch (...) {
      _exit(1);
    }
    _exit(0);
  }
  int status = 0;
  while (waitpid(child, &status, 0) < 0) {
    if (errno != EINTR) return;
  }
  // Only a crash of the reader speaks of the file; SIGTERM or SIGINT to the process group
  // ends the child too, and the parent then handles its own copy.
  const bool crashed = WIFSIGNALED(status) && (WTERMSIG(status) == SIGSEGV || WTERMSIG(status) == SIGBUS ||
                                                WTERMSIG(status) == SIGABRT || WTERMSIG(status) == SIGFPE ||
                                                WTERMSIG(status) == SIGILL);
  if (crashed)
    throw InputError(path, 0, 0,
                     std::string("the file is damaged: reading it crashed the HDF5 library (") +
                         strsignal(WTERMSIG(status)) + "); it cannot be read");
}

}  // namespace radnet::cases
