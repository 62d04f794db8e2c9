// The exact rank selection of long sequences in bounded memory (common/streaming_rank.h) and the
// fast number formatting of common/format.h, against std::nth_element and printf.

#include "common/streaming_rank.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "common/format.h"

namespace accelcal {
namespace {

// The value of rank `rank` of `values`, found by passes over them as a stream.
double Selected(const std::vector<double>& values, uint64_t rank, double hint_low, double hint_high,
                int* passes) {
  StreamingRankSelector selector(hint_low, hint_high);
  for (int pass = 0; pass < 10; ++pass) {
    for (double value : values) selector.Add(value);
    if (selector.FinishPass(rank)) break;
  }
  *passes = selector.passes();
  return selector.value();
}

double NthElement(std::vector<double> values, uint64_t rank) {
  std::nth_element(values.begin(), values.begin() + static_cast<long>(rank), values.end());
  return values[rank];
}

// Magnitudes near g with a noise of 3e-3 m/s^2, more than the first pass keeps: exact in two
// passes (the hint's bin holds few enough), for the median and for ranks near the ends.
TEST(StreamingRankSelector, MatchesNthElementOnMillionsOfNoisyMagnitudes) {
  std::mt19937_64 random(7);
  std::normal_distribution<double> noise(9.81, 3e-3);
  std::vector<double> values(3000000);
  for (double& value : values) value = noise(random);
  for (uint64_t rank : {uint64_t{1500000}, uint64_t{0}, uint64_t{2999999}, uint64_t{123457}}) {
    int passes = 0;
    EXPECT_EQ(Selected(values, rank, 4.9, 19.6, &passes), NthElement(values, rank)) << rank;
    EXPECT_LE(passes, 2) << rank;
  }
}

// A quantised log: millions of equal values (far more than a pass keeps) and a few others.
TEST(StreamingRankSelector, IsExactOnMillionsOfEqualValues) {
  std::vector<double> values(2500000, 9.80665);
  for (size_t j = 0; j < 1000; ++j) values[j * 7] = 9.80665 + 0.001 * (j % 5) - 0.002;
  int passes = 0;
  EXPECT_EQ(Selected(values, values.size() / 2, 4.9, 19.6, &passes),
            NthElement(values, values.size() / 2));
  EXPECT_LE(passes, 4);
}

// The value outside the hint (a log in another unit): one pass more, still exact.
TEST(StreamingRankSelector, IsExactOutsideTheHint) {
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> uniform(0.0, 3.0);
  std::vector<double> values(2200000);
  for (double& value : values) value = uniform(random);
  int passes = 0;
  EXPECT_EQ(Selected(values, values.size() / 2, 4.9, 19.6, &passes),
            NthElement(values, values.size() / 2));
  EXPECT_LE(passes, 4);
  // A short sequence: the first pass keeps it all.
  const std::vector<double> few(values.begin(), values.begin() + 1001);
  EXPECT_EQ(Selected(few, 500, 4.9, 19.6, &passes), NthElement(few, 500));
}

// Small buffers (the streamed noise-floor detector's: 2^16 bins, 2^19 kept; here 2^8 and 2^4,
// so that every pass narrows): no hint (0 to +inf), exact within 64 / 8 + 1 passes, ranks at the
// ends and in the middle, with many equal values and zeros.
TEST(StreamingRankSelector, IsExactWithSmallBuffersAndNoHint) {
  std::mt19937_64 random(13);
  std::chi_squared_distribution<double> chi2(100.0);
  std::vector<double> values(200000);
  for (size_t j = 0; j < values.size(); ++j)
    values[j] = j % 11 == 0 ? 0.0 : j % 13 == 0 ? 7.5 : chi2(random) / 100.0;
  for (uint64_t rank : {uint64_t{0}, uint64_t{10000}, uint64_t{100000}, uint64_t{199999}}) {
    StreamingRankSelector selector(0.0, std::numeric_limits<double>::infinity(), 8, 4);
    int passes = 0;
    for (; passes < 20; ++passes) {
      for (double value : values) selector.Add(value);
      if (selector.FinishPass(rank)) break;
    }
    EXPECT_EQ(selector.value(), NthElement(values, rank)) << rank;
    EXPECT_LE(selector.passes(), 9) << rank;
  }
}

// AppendRoundTripDouble and AppendGeneral write printf's digits, over values of every size.
TEST(FastFormat, WritesPrintfsDigits) {
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-30, 30);
  std::vector<double> values = {0.0,
                                -0.0,
                                1.0,
                                0.1,
                                0.64,
                                1e-5,
                                123456789012345678.0,
                                9.80665,
                                32768.0,
                                1.0 / 3.0,
                                2.0 / 3.0,
                                5e-324,
                                1.7976931348623157e308};
  for (int j = 0; j < 200000; ++j)
    values.push_back(mantissa(random) * std::pow(10.0, exponent(random)));
  for (double value : values) {
    std::string fast;
    AppendRoundTripDouble(value, &fast);
    ASSERT_EQ(fast, RoundTripDouble(value)) << value;
    for (int precision : {3, 6, 9}) {
      std::string general;
      AppendGeneral(value, precision, &general);
      ASSERT_EQ(general, StringPrintf("%.*g", precision, value)) << value;
    }
  }
}

}  // namespace
}  // namespace accelcal
