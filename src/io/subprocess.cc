#include "io/subprocess.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>

#include "io/cleanup.h"

extern char** environ;

namespace accelcal {

Status RunProgram(const std::vector<std::string>& argv, double timeout_s, int* exit_status) {
  if (argv.empty()) return Status::Error("no program to run");
  std::vector<char*> arguments;
  for (const std::string& argument : argv) arguments.push_back(const_cast<char*>(argument.c_str()));
  arguments.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  // Our signal mask blocks SIGINT/SIGTERM/SIGHUP for the cleanup thread; the child must
  // not inherit it, nor our ignored SIGXFSZ.
  sigset_t empty;
  sigemptyset(&empty);
  sigset_t defaults;
  sigemptyset(&defaults);
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP, SIGXFSZ, SIGPIPE}) {
    sigaddset(&defaults, signal_number);
  }
  posix_spawnattr_setsigmask(&attributes, &empty);
  posix_spawnattr_setsigdefault(&attributes, &defaults);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);

  pid_t pid = -1;
  int error = 0;
  WithCleanupHeld([&] {
    error = posix_spawnp(&pid, arguments[0], &actions, &attributes, arguments.data(), environ);
    if (error == 0) RegisterChild(pid);
  });
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  if (error != 0) {
    return Status::Error("cannot start " + argv[0] + " (" + std::strerror(error) + ")");
  }
  int status = 0;
  pid_t waited;
  bool timed_out = false;
  const auto start = std::chrono::steady_clock::now();
  while (true) {
    waited = waitpid(pid, &status, timeout_s > 0.0 ? WNOHANG : 0);
    if (waited < 0 && errno == EINTR) continue;
    if (waited != 0) break;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (elapsed > timeout_s) {
      kill(pid, SIGKILL);
      timed_out = true;
      do {
        waited = waitpid(pid, &status, 0);
      } while (waited < 0 && errno == EINTR);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ForgetChild(pid);
  if (timed_out) {
    return Status::Error(argv[0] + " did not finish within " +
                         std::to_string(static_cast<int>(timeout_s)) + " s and was stopped");
  }
  if (waited < 0)
    return Status::Error("lost track of " + argv[0] + " (" + std::strerror(errno) + ")");
  *exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return Status::Ok();
}

}  // namespace accelcal
