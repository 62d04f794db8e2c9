#ifndef ACCELCAL_PROBLEMS_PROBLEM_SUPPORT_H_
#define ACCELCAL_PROBLEMS_PROBLEM_SUPPORT_H_

// What every problem binary does around its pipeline: parse flags (an unknown flag or
// a stray argument is bad input: one line, exit 2), show only the binary's own flags
// under --help, keep glog quiet unless --v is raised, and turn a failed Status into one
// line on stderr with exit status 2.

#include <gflags/gflags.h>
#include <glog/logging.h>

#include <cstring>
#include <iostream>
#include <string>

#include "common/status.h"

namespace accelcal {

constexpr int kExitBadInput = 2;

inline int ExitWithError(const char* program, const Status& status) {
  std::cerr << program << ": error: " << status.message() << "\n";
  return kExitBadInput;
}

// Returns false (after printing one line) when the command line is not usable.
// `source_fragment` selects the flags --help lists (the binary's own source file).
inline bool InitProblem(const char* program, const char* usage, const char* source_fragment,
                        int* argc, char*** argv) {
  gflags::SetUsageMessage(usage);
  for (int i = 1; i < *argc; ++i) {
    const char* argument = (*argv)[i];
    if (std::strcmp(argument, "--help") == 0 || std::strcmp(argument, "-help") == 0 ||
        std::strcmp(argument, "-h") == 0) {
      gflags::ShowUsageWithFlagsRestrict(program, source_fragment);
      std::exit(0);
    }
  }
  // Unknown flags are kept in argv instead of ending the program with status 1, so we
  // can report them like any other bad input.
  gflags::AllowCommandLineReparsing();
  gflags::ParseCommandLineFlags(argc, argv, true);
  if (*argc > 1) {
    std::cerr << program << ": error: unknown flag or argument '" << (*argv)[1]
              << "'; see " << program << " --help\n";
    return false;
  }
  FLAGS_logtostderr = true;
  if (FLAGS_v <= 0) FLAGS_minloglevel = google::GLOG_WARNING;
  google::InitGoogleLogging(program);
  return true;
}

}  // namespace accelcal

#endif  // ACCELCAL_PROBLEMS_PROBLEM_SUPPORT_H_
