#ifndef ACCELCAL_IO_CLEANUP_H_
#define ACCELCAL_IO_CLEANUP_H_

// What an interrupted run leaves behind: nothing. Every temporary file or folder that the
// atomic writers (io/atomic_file.h) create is registered here until it is renamed into
// place or removed, and so is every child process (io/subprocess.h). A problem binary
// calls InstallInterruptCleanup() first thing: SIGINT, SIGTERM and SIGHUP are then taken
// by a thread of their own (sigwait, so the cleanup runs outside a signal handler and may
// allocate), which stops the children, removes what is registered and ends the process by
// the same signal. SIGXFSZ (a file-size limit, ulimit -f) is ignored, so that a write
// beyond the limit fails with EFBIG and takes the writer's own error path instead of
// killing the process mid-write.

#include <sys/types.h>

#include <functional>
#include <string>

namespace accelcal {

// Call once, before any other thread is started (the threads inherit the blocked mask).
void InstallInterruptCleanup();

// Registration, under one lock shared with the cleanup thread.
void RegisterTemporary(const std::string& path);  // a file or a folder (removed whole)
void ForgetTemporary(const std::string& path);
void RegisterChild(pid_t pid);
void ForgetChild(pid_t pid);

// Runs `step` while the cleanup thread cannot run, e.g. the renames that swap a folder into
// place, so that an interruption sees either the state before the step or the one after.
void WithCleanupHeld(const std::function<void()>& step);

}  // namespace accelcal

#endif  // ACCELCAL_IO_CLEANUP_H_
