#include "io/imucal_session.h"

#include <array>
#include <string>

#include "io/csv_reader.h"
#include "io/input_text.h"
#include "io/line_stream.h"

namespace accelcal {
namespace {

constexpr size_t kMaxLineBytes = 1 << 12;  // a row is 8 numbers and a label

std::string AllLabels() {
  std::string labels;
  for (const char* label : kFerrarisSectionLabels)
    labels += (labels.empty() ? "" : ", ") + std::string(label);
  return labels;
}

// One axis of one section. The mean is the plain sum over N, as imucal's numpy.mean: with
// integer counts the sum is exact and the mean rounded once. The variance comes from sums of
// the values less the section's first one, so that a large constant offset (32768 counts on
// an unsigned ADC) does not cancel the digits of the spread.
struct AxisSums {
  double sum = 0.0;
  double shift = 0.0;
  double shifted_sum = 0.0;
  double shifted_square_sum = 0.0;

  void Add(double value, bool first) {
    if (first) shift = value;
    sum += value;
    const double d = value - shift;
    shifted_sum += d;
    shifted_square_sum += d * d;
  }
  double Mean(long long n) const { return sum / static_cast<double>(n); }
  double Variance(long long n) const {
    if (n < 2) return 0.0;
    const double nd = static_cast<double>(n);
    const double centred = shifted_square_sum - shifted_sum * shifted_sum / nd;
    return centred > 0.0 ? centred / (nd - 1.0) : 0.0;
  }
};

struct SectionSums {
  long long count = 0;
  long long first_line = 0;
  long long last_line = 0;
  std::array<AxisSums, 6> axes;  // acc x, y, z, gyr x, y, z
};

class SessionLineParser {
 public:
  SessionLineParser()
      : csv_({{"part", false},
              {"samples"},
              {"acc_x"},
              {"acc_y"},
              {"acc_z"},
              {"gyr_x"},
              {"gyr_y"},
              {"gyr_z"}}) {}

  Status ParseLine(std::string_view line) {
    CsvLineParser::LineKind kind;
    ACCELCAL_RETURN_IF_ERROR(csv_.ParseLine(line, &kind));
    if (kind != CsvLineParser::LineKind::kRow) return Status::Ok();
    const std::string_view label = csv_.text(0);
    int section = 0;
    while (section < kFerrarisSectionCount && label != kFerrarisSectionLabels[section]) ++section;
    if (section == kFerrarisSectionCount) {
      return Status::Error("line " + std::to_string(csv_.line_number()) + ", column 'part': '" +
                           EchoInput(label) + "' is not a section of a Ferraris session (" +
                           AllLabels() + "); relabel or remove the row");
    }
    SectionSums& sums = sections_[section];
    const bool first = sums.count == 0;
    if (first) sums.first_line = csv_.line_number();
    sums.last_line = csv_.line_number();
    ++sums.count;
    for (int c = 0; c < 6; ++c) sums.axes[c].Add(csv_.number(2 + c), first);
    return Status::Ok();
  }

  Status UnterminatedLastLine(std::string_view rest) const {
    return csv_.UnterminatedLastLine(rest);
  }

  Status Finish(FerrarisSession* session) const {
    ACCELCAL_RETURN_IF_ERROR(csv_.Finish());
    for (int s = 0; s < kFerrarisSectionCount; ++s) {
      const SectionSums& sums = sections_[s];
      if (sums.count == 0) {
        return Status::Error(std::string("no row is labelled '") + kFerrarisSectionLabels[s] +
                             "': a Ferraris session needs all nine sections (" + AllLabels() +
                             "); record and label the missing one");
      }
      FerrarisSectionData& data = session->sections[s];
      data.first_line = sums.first_line;
      data.last_line = sums.last_line;
      data.accelerometer.sample_count = data.gyroscope.sample_count = static_cast<int>(sums.count);
      for (int k = 0; k < 3; ++k) {
        data.accelerometer.mean[k] = sums.axes[k].Mean(sums.count);
        data.accelerometer.variance[k] = sums.axes[k].Variance(sums.count);
        data.gyroscope.mean[k] = sums.axes[3 + k].Mean(sums.count);
        data.gyroscope.variance[k] = sums.axes[3 + k].Variance(sums.count);
      }
    }
    return Status::Ok();
  }

 private:
  CsvLineParser csv_;
  std::array<SectionSums, kFerrarisSectionCount> sections_;
};

}  // namespace

Status ParseImucalSession(std::string_view text, FerrarisSession* session) {
  *session = FerrarisSession();
  SessionLineParser parser;
  size_t begin = 0;
  while (begin < text.size()) {
    const size_t end = text.find('\n', begin);
    if (end == std::string_view::npos) return parser.UnterminatedLastLine(text.substr(begin));
    ACCELCAL_RETURN_IF_ERROR(parser.ParseLine(text.substr(begin, end - begin)));
    begin = end + 1;
  }
  return parser.Finish(session);
}

Status ReadImucalSession(const std::string& path, FerrarisSession* session) {
  *session = FerrarisSession();
  SessionLineParser parser;
  ACCELCAL_RETURN_IF_ERROR(StreamTextLines(
      path, "an annotated Ferraris session", kMaxLineBytes,
      [&parser](std::string_view line) { return parser.ParseLine(line); },
      [&parser](std::string_view rest) { return parser.UnterminatedLastLine(rest); }));
  return parser.Finish(session).WithContext(path);
}

}  // namespace accelcal
