#include "io/index_clock_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/format.h"

namespace accelcal {
namespace {

constexpr int kToleranceBlocks = 8;
// A crystal's error is some 20 to 2000 ppm; a fitted rate further than this from every usual
// rate is stated without a nominal one.
constexpr double kMaxDriftFromNominal = 0.005;
// The output data rates of common IMUs: decades of 1, 2, 5 and 1.25 (Bosch, Analog Devices),
// ST's 12.5 * 2^k rounded (26, 52, 104, 208, 416, 833, 1666, 3332, 6664), powers of two and
// Shimmer's 204.8 Hz (imucal's example).
constexpr double kUsualRatesHz[] = {1,    2,    5,    10,   12.5, 20,   25,    26,   50,
                                    52,   100,  104,  125,  128,  200,  204.8, 208,  250,
                                    256,  400,  416,  500,  512,  800,  833,   1000, 1024,
                                    1600, 1666, 2000, 3200, 3332, 4000, 6664,  8000};

struct Point {
  double x;  // index - first index
  double y;  // host time - first host time, s
};

// z-component of (b - a) x (c - a): positive when a, b, c turn counter-clockwise.
double Cross(const Point& a, const Point& b, const Point& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

}  // namespace

Status FitIndexClock(const std::vector<double>& index, const std::vector<double>& host_time_s,
                     IndexClockFit* fit, std::vector<double>* timestamp_s) {
  *fit = IndexClockFit();
  const size_t n = index.size();
  if (n < 2 || host_time_s.size() != n)
    return Status::Error("the sample-number column needs two samples or more to time them");
  for (size_t j = 0; j < n; ++j) {
    if (index[j] != std::floor(index[j])) {
      return Status::Error(StringPrintf(
          "sample %zu: sample number %.9g is not a whole number; the index column must count "
          "the samples",
          j + 1, index[j]));
    }
    if (j > 0 && !(index[j] > index[j - 1])) {
      return Status::Error(StringPrintf(
          "sample %zu: sample number %.9g does not increase from the previous sample's %.9g (a "
          "counter that wraps, or rows out of order); the index column must count the samples",
          j + 1, index[j], index[j - 1]));
    }
    if (j > 0) fit->dropped_samples += static_cast<long long>(index[j] - index[j - 1]) - 1;
  }
  if (fit->dropped_samples > static_cast<long long>(n)) {
    return Status::Error(StringPrintf(
        "the sample numbers run from %.9g to %.9g over %zu samples: more samples skipped than "
        "read, so the column does not count these samples",
        index.front(), index.back(), n));
  }
  std::vector<Point> points(n);
  double mean_x = 0.0;
  for (size_t j = 0; j < n; ++j) {
    points[j] = {index[j] - index[0], host_time_s[j] - host_time_s[0]};
    mean_x += points[j].x / n;
  }
  // Andrew's monotone chain: the lower hull of points sorted by x.
  std::vector<Point> hull;
  for (const Point& p : points) {
    while (hull.size() >= 2 && Cross(hull[hull.size() - 2], hull.back(), p) <= 0.0) hull.pop_back();
    hull.push_back(p);
  }
  size_t edge = 0;
  while (edge + 2 < hull.size() && hull[edge + 1].x < mean_x) ++edge;
  const double slope_s = (hull[edge + 1].y - hull[edge].y) / (hull[edge + 1].x - hull[edge].x);
  if (!(slope_s > 0.0)) {
    return Status::Error(
        "the host times do not advance with the sample numbers; the index column must count the "
        "samples in the order they were received");
  }
  const double intercept_s = hull[edge].y - slope_s * hull[edge].x;
  const double span = points.back().x;
  std::vector<double> least_delay(kToleranceBlocks, std::numeric_limits<double>::infinity());
  for (const Point& p : points) {
    const double delay_s = p.y - (intercept_s + slope_s * p.x);
    fit->largest_delay_s = std::max(fit->largest_delay_s, delay_s);
    const int block =
        std::min(kToleranceBlocks - 1, static_cast<int>(kToleranceBlocks * p.x / span));
    least_delay[block] = std::min(least_delay[block], delay_s);
  }
  double gap_s = 0.0;
  for (double d : least_delay) {
    if (std::isfinite(d)) gap_s = std::max(gap_s, d);
  }
  fit->rate_hz = 1.0 / slope_s;
  fit->rate_tolerance_hz = (gap_s / (0.5 * span)) / (slope_s * slope_s);
  fit->origin_s = host_time_s[0] + intercept_s - slope_s * index[0];
  for (double rate_hz : kUsualRatesHz) {
    if (std::abs(fit->rate_hz / rate_hz - 1.0) <= kMaxDriftFromNominal) {
      fit->nominal_rate_hz = rate_hz;
      fit->clock_drift_ppm = (fit->rate_hz / rate_hz - 1.0) * 1e6;
    }
  }
  timestamp_s->resize(n);
  for (size_t j = 0; j < n; ++j)
    (*timestamp_s)[j] = host_time_s[0] + intercept_s + slope_s * points[j].x;
  return Status::Ok();
}

std::string DescribeIndexClockFit(const IndexClockFit& fit) {
  std::string text =
      StringPrintf("at a fitted %.8g Hz (+- %.2g Hz", fit.rate_hz, fit.rate_tolerance_hz);
  if (fit.nominal_rate_hz > 0.0) {
    text += StringPrintf(
        "; the device clock %+.0f ppm from a nominal %g Hz, as the host counts "
        "time",
        fit.clock_drift_ppm, fit.nominal_rate_hz);
  } else {
    text += "; no usual rate within 0.5%";
  }
  return text + StringPrintf("), %lld dropped sample%s", fit.dropped_samples,
                             fit.dropped_samples == 1 ? "" : "s");
}

}  // namespace accelcal
