#ifndef ACCELCAL_IO_DATOS_TXT_H_
#define ACCELCAL_IO_DATOS_TXT_H_

// The course's datos.txt: one "key = [a b]" line per quantity, in Spanish, e.g.
//
//   Posición inicial = [0 0]
//   Velocidad inicial = [1 3]
//   varianza del ruido de los acelerómetros = [0.25 0.64]
//
// Lines are recognised by their key, not their position. Keys are matched whole, without
// case or accents (UTF-8 or Latin-1), with any spacing ('_' counts as a space); the short
// "varianza del ruido" and the English keys ("initial position", "initial velocity",
// "noise variance") are accepted too, and any other key ("Posición final") is refused with
// its line. Values are two
// numbers separated by blanks, a comma or a semicolon. A missing key, an unknown or
// repeated key, unbalanced brackets, a count other than two, or a non-positive
// variance fails with the line number.

#include <string>

#include "common/measurements.h"
#include "common/status.h"

namespace accelcal {

Status ParseDatosTxt(const std::string& text, RunConditions* conditions);

// The datos.txt text of `conditions`, in the course's keys and spelling (UTF-8), every number
// written so that it reads back exactly.
std::string DatosTxt(const RunConditions& conditions);

}  // namespace accelcal

#endif  // ACCELCAL_IO_DATOS_TXT_H_
