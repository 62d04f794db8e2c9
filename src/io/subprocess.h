#ifndef ACCELCAL_IO_SUBPROCESS_H_
#define ACCELCAL_IO_SUBPROCESS_H_

// Runs another program (the plot scripts) with an argument vector: no shell ever sees the
// arguments, so a folder named "it's; rm -rf x" is a folder name and nothing else. The
// child's stdout and stderr go to /dev/null (a person reads ours), its signal mask and
// dispositions are reset, and it is stopped with us if we are interrupted (io/cleanup.h).

#include <string>
#include <vector>

#include "common/status.h"

namespace accelcal {

// Runs argv[0] (a path, or a name searched on PATH) with `argv` and waits for it, at most
// `timeout_s` seconds (0: no limit); a program still running then is killed and the call
// fails, saying so. `exit_status` is the program's exit status, or 128 + the signal that
// ended it. Fails otherwise only when the program cannot be started.
Status RunProgram(const std::vector<std::string>& argv, double timeout_s, int* exit_status);

}  // namespace accelcal

#endif  // ACCELCAL_IO_SUBPROCESS_H_
