#ifndef ACCELCAL_ESTIMATION_DISCOVERY_VERDICT_H_
#define ACCELCAL_ESTIMATION_DISCOVERY_VERDICT_H_

// The four answers of discovery, one vocabulary for every sensor geometry (the tilt table's
// estimation/tilt_table/discovery.h, the triad's estimation/triad/triad_discovery.h).

namespace accelcal {

// The four answers. kExplained: the baseline explains the data. kMissing: effects (or a
// noise model) the model has are missing, and the extended model explains the data.
// kUnexplained: structure remains that no effect of the model explains (with or
// without named effects). kCannotTellApart: the named effects include one that another
// candidate explains about equally well.
enum class Verdict { kExplained, kMissing, kUnexplained, kCannotTellApart };
const char* VerdictCode(
    Verdict verdict);  // "explained", "missing", "unexplained", "cannot_tell_apart"

}  // namespace accelcal

#endif  // ACCELCAL_ESTIMATION_DISCOVERY_VERDICT_H_
