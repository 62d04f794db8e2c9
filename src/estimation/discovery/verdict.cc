#include "estimation/discovery/verdict.h"

namespace accelcal {

const char* VerdictCode(Verdict verdict) {
  switch (verdict) {
    case Verdict::kExplained:
      return "explained";
    case Verdict::kMissing:
      return "missing";
    case Verdict::kUnexplained:
      return "unexplained";
    case Verdict::kCannotTellApart:
      return "cannot_tell_apart";
  }
  return "explained";
}

}  // namespace accelcal
