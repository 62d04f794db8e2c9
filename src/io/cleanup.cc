#include "io/cleanup.h"

#include <pthread.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <mutex>
#include <set>
#include <thread>

namespace accelcal {
namespace {

struct Registry {
  std::recursive_mutex mutex;
  std::set<std::string> temporaries;
  std::set<pid_t> children;
};

Registry& TheRegistry() {
  static Registry* registry = new Registry;  // never destroyed: the cleanup thread may outlive main
  return *registry;
}

void CleanUpNow() {
  Registry& registry = TheRegistry();
  // Held until the process ends: nothing may be registered or renamed after this.
  registry.mutex.lock();
  for (const pid_t child : registry.children) kill(child, SIGTERM);
  for (const pid_t child : registry.children) waitpid(child, nullptr, 0);
  for (const std::string& path : registry.temporaries) {
    // A writer of the main thread may still add a file to a temporary folder while it is
    // removed; a few passes catch it (the writer itself fails once the folder is gone).
    std::error_code error;
    for (int pass = 0; pass < 8 && std::filesystem::symlink_status(path, error).type() !=
                                       std::filesystem::file_type::not_found;
         ++pass) {
      std::filesystem::remove_all(path, error);
    }
  }
}

}  // namespace

void InstallInterruptCleanup() {
  static std::once_flag once;
  std::call_once(once, [] {
    signal(SIGXFSZ, SIG_IGN);
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    sigaddset(&signals, SIGHUP);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);
    std::thread([signals] {
      int signal_number = 0;
      while (sigwait(&signals, &signal_number) != 0) {
      }
      CleanUpNow();
      // End the process by the same signal, so that the caller sees how it ended.
      signal(signal_number, SIG_DFL);
      sigset_t one;
      sigemptyset(&one);
      sigaddset(&one, signal_number);
      pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
      raise(signal_number);
      _exit(128 + signal_number);
    }).detach();
  });
}

void RegisterTemporary(const std::string& path) {
  Registry& registry = TheRegistry();
  const std::lock_guard<std::recursive_mutex> lock(registry.mutex);
  registry.temporaries.insert(path);
}

void ForgetTemporary(const std::string& path) {
  Registry& registry = TheRegistry();
  const std::lock_guard<std::recursive_mutex> lock(registry.mutex);
  registry.temporaries.erase(path);
}

void RegisterChild(pid_t pid) {
  Registry& registry = TheRegistry();
  const std::lock_guard<std::recursive_mutex> lock(registry.mutex);
  registry.children.insert(pid);
}

void ForgetChild(pid_t pid) {
  Registry& registry = TheRegistry();
  const std::lock_guard<std::recursive_mutex> lock(registry.mutex);
  registry.children.erase(pid);
}

void WithCleanupHeld(const std::function<void()>& step) {
  Registry& registry = TheRegistry();
  const std::lock_guard<std::recursive_mutex> lock(registry.mutex);
  step();
}

}  // namespace accelcal
