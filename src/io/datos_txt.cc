#include "io/datos_txt.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <sstream>
#include <utility>
#include <vector>

#include "common/format.h"
#include "io/csv_reader.h"
#include "io/input_text.h"

namespace accelcal {
namespace {

enum class Key { kInitialPosition, kInitialVelocity, kNoiseVariance, kUnknown };

// Lower-case ASCII with the accented vowels of Spanish folded, whether the file is
// UTF-8 (two bytes, 0xC3 then the Latin-1 code minus 0x40) or Latin-1 (one byte).
std::string FoldKey(const std::string& text) {
  auto fold = [](unsigned char latin1) -> char {
    switch (latin1) {
      case 0xE1:
      case 0xC1:
        return 'a';
      case 0xE9:
      case 0xC9:
        return 'e';
      case 0xED:
      case 0xCD:
        return 'i';
      case 0xF3:
      case 0xD3:
        return 'o';
      case 0xFA:
      case 0xDA:
      case 0xFC:
      case 0xDC:
        return 'u';
      case 0xF1:
      case 0xD1:
        return 'n';
      default:
        return '?';
    }
  };
  std::string folded;
  bool pending_space = false;
  for (size_t i = 0; i < text.size(); ++i) {
    unsigned char c = static_cast<unsigned char>(text[i]);
    char out;
    if (c == 0xC3 && i + 1 < text.size()) {
      out = fold(static_cast<unsigned char>(text[++i]) + 0x40);
    } else if (c >= 0x80) {
      out = fold(c);
    } else if (std::isspace(c) || c == '_') {
      pending_space = !folded.empty();
      continue;
    } else {
      out = static_cast<char>(std::tolower(c));
    }
    if (pending_space) folded.push_back(' ');
    pending_space = false;
    folded.push_back(out);
  }
  return folded;
}

// The whole keys, folded (FoldKey). Matching a word inside the key instead would read
// "Posición final = [459.84 59.99]" as the initial position. "varianza del ruido" is the
// short form earlier files (and tests) use; the English keys are datos_english.txt's
// (tests/fuzz/seeds) and scenario.json's names with '_' for ' '.
Key Classify(const std::string& folded_key) {
  static const std::array<std::pair<const char*, Key>, 7> kKeys = {{
      {"posicion inicial", Key::kInitialPosition},
      {"initial position", Key::kInitialPosition},
      {"velocidad inicial", Key::kInitialVelocity},
      {"initial velocity", Key::kInitialVelocity},
      {"varianza del ruido de los acelerometros", Key::kNoiseVariance},
      {"varianza del ruido", Key::kNoiseVariance},
      {"noise variance", Key::kNoiseVariance},
  }};
  for (const auto& [name, key] : kKeys) {
    if (folded_key == name) return key;
  }
  return Key::kUnknown;
}

// Blanks around a key or value, for quoting it.
std::string Trim(const std::string& text) {
  const size_t begin = text.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return "";
  return text.substr(begin, text.find_last_not_of(" \t\r") - begin + 1);
}

constexpr std::array<const char*, 3> kKeyNames = {"Posición inicial", "Velocidad inicial",
                                                  "varianza del ruido de los acelerómetros"};

}  // namespace

Status ParseDatosTxt(const std::string& text, RunConditions* conditions) {
  std::array<bool, 3> seen = {false, false, false};
  std::array<std::array<double, 2>, 3> values{};
  // Lines that end in '\r' alone (old Mac files) are lines all the same.
  std::istringstream stream(text.find('\n') == std::string::npos && text.find('\r') != std::string::npos
                                ? [&] {
                                    std::string lines = text;
                                    std::replace(lines.begin(), lines.end(), '\r', '\n');
                                    return lines;
                                  }()
                                : text);
  std::string line;
  int line_number = 0;
  while (std::getline(stream, line)) {
    ++line_number;
    if (line_number == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = "line " + std::to_string(line_number);
    const size_t equals = line.find('=');
    if (equals == std::string::npos) {
      return Status::Error(where + ": expected 'key = [x y]', found no '='");
    }
    const Key key = Classify(FoldKey(line.substr(0, equals)));
    if (key == Key::kUnknown) {
      return Status::Error(where + ": unknown key '" + EchoInput(Trim(line.substr(0, equals))) +
                           "'; expected Posición inicial, Velocidad inicial or varianza del "
                           "ruido de los acelerómetros (or initial position, initial velocity, "
                           "noise variance)");
    }
    const int k = static_cast<int>(key);
    if (seen[k]) return Status::Error(where + ": '" + kKeyNames[k] + "' is given twice");
    const std::string value = line.substr(equals + 1);
    const size_t open = value.find('[');
    const size_t close = value.find(']');
    const size_t open_count = std::count(value.begin(), value.end(), '[');
    const size_t close_count = std::count(value.begin(), value.end(), ']');
    if (open == std::string::npos || close == std::string::npos || close < open ||
        open_count != 1 || close_count != 1) {
      return Status::Error(where + ": unbalanced brackets in '" + kKeyNames[k] +
                           "'; write the value as [x y]");
    }
    std::string inside = value.substr(open + 1, close - open - 1);
    for (char& c : inside) {
      if (c == ',' || c == ';' || c == '\t') c = ' ';
    }
    std::istringstream tokens(inside);
    std::vector<std::string> numbers;
    for (std::string token; tokens >> token;) numbers.push_back(token);
    if (numbers.size() != 2) {
      return Status::Error(where + ": '" + kKeyNames[k] + "' has " +
                           std::to_string(numbers.size()) +
                           (numbers.size() == 1 ? " value" : " values") +
                           ", expected 2 ([x y]; decimal commas are not supported)");
    }
    for (int i = 0; i < 2; ++i) {
      if (!ParseFiniteNumber(numbers[i], &values[k][i])) {
        return Status::Error(where + ": '" + EchoInput(numbers[i]) + "' in '" + kKeyNames[k] +
                             "' is not a finite number");
      }
    }
    if (key == Key::kNoiseVariance && (values[k][0] <= 0.0 || values[k][1] <= 0.0)) {
      return Status::Error(where + ": noise variances must be positive, got [" +
                           EchoInput(numbers[0]) + " " + EchoInput(numbers[1]) + "]");
    }
    seen[k] = true;
  }
  std::string missing;
  for (int k = 0; k < 3; ++k) {
    if (!seen[k]) missing += std::string(missing.empty() ? "" : ", ") + kKeyNames[k];
  }
  if (!missing.empty()) return Status::Error("missing " + missing);
  conditions->initial_position_x_m = values[0][0];
  conditions->initial_position_y_m = values[0][1];
  conditions->initial_velocity_x_mps = values[1][0];
  conditions->initial_velocity_y_mps = values[1][1];
  conditions->noise_variance_x = values[2][0];
  conditions->noise_variance_y = values[2][1];
  conditions->has_gravity = false;
  return Status::Ok();
}

std::string DatosTxt(const RunConditions& conditions) {
  auto pair = [](double first, double second) {
    return "[" + RoundTripDouble(first) + " " + RoundTripDouble(second) + "]";
  };
  return "Posici\xC3\xB3n inicial = " +
         pair(conditions.initial_position_x_m, conditions.initial_position_y_m) +
         "\nVelocidad inicial = " +
         pair(conditions.initial_velocity_x_mps, conditions.initial_velocity_y_mps) +
         "\nvarianza del ruido de los aceler\xC3\xB3metros = " +
         pair(conditions.noise_variance_x, conditions.noise_variance_y) + "\n";
}

}  // namespace accelcal
