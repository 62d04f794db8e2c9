// "Unexplained" says what remains by its shape (issue 33, item 1), on the two-axis tilt table.
// Each shape class is hidden on x in simulated data (the simulator's disturbances, as
// `simulate --set` makes them), on at least two designs where the class
// makes sense, at about 10 sigma of its signature (the chi-square the shape would remove from
// the baseline's span, 1, cos theta, sin theta); over 30 seeds the verdict must be
// "unexplained" with the first remaining shape of the hidden class in at least 80% of them.
// And over 1000 null datasets of mixed designs the whole procedure must say anything but
// "explained" at most alpha + 2 sd of the time.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <utility>

#include "common/format.h"
#include "discovery_seed.h"
#include "estimation/tilt_table/discovery.h"
#include "io/scenario_json.h"
#include "simulation/scenario.h"

namespace accelcal {
namespace {

constexpr int kSeeds = 30;
constexpr int kSamples = 2000;
constexpr double kSignature = 100.0;  // (10 sigma)^2

enum class Design {
  kSweep,
  kStatic,
  kForthAndBack,
  kForthAndBackTwice,
  kStaticForthAndBack,
  kStaticForthAndBackTwice,
  kTwoTurns,
  kStaticTwice
};

const char* DesignName(Design design) {
  switch (design) {
    case Design::kSweep:
      return "a sweep from 0 to 2 pi";
    case Design::kStatic:
      return "24 positions held, 15 degrees apart";
    case Design::kForthAndBack:
      return "a sweep from 0 to 2 pi and back";
    case Design::kForthAndBackTwice:
      return "a sweep from 0 to 2 pi and back, twice";
    case Design::kStaticForthAndBack:
      return "12 positions held going up, 12 coming down";
    case Design::kStaticForthAndBackTwice:
      return "6 positions held going up, 6 coming down, twice";
    case Design::kTwoTurns:
      return "a sweep of two turns";
    case Design::kStaticTwice:
      return "12 positions held, twice round";
  }
  return "";
}

TiltSchedule Schedule(Design design, int samples) {
  TiltSchedule schedule;
  schedule.sample_count = samples;
  switch (design) {
    case Design::kSweep:
      break;
    case Design::kStatic:
      schedule.kind = TiltSchedule::Kind::kStaticPositions;
      for (int p = 0; p < 24; ++p) schedule.positions_rad.push_back(p * M_PI / 12.0);
      break;
    case Design::kForthAndBack:
    case Design::kForthAndBackTwice: {
      const int cycles = design == Design::kForthAndBack ? 1 : 2;
      schedule.kind = TiltSchedule::Kind::kList;
      for (int i = 0; i < samples; ++i) {
        const double phase = std::fmod(cycles * static_cast<double>(i) / samples, 1.0);
        schedule.angles_rad.push_back(2.0 * M_PI * (1.0 - std::abs(2.0 * phase - 1.0)));
      }
      break;
    }
    case Design::kStaticForthAndBackTwice:
      // Up through 0, 60, ..., 300 degrees, down through 330, 270, ..., 30; twice.
      schedule.kind = TiltSchedule::Kind::kStaticPositions;
      for (int cycle = 0; cycle < 2; ++cycle) {
        for (int p = 0; p < 6; ++p) schedule.positions_rad.push_back(p * M_PI / 3.0);
        for (int p = 5; p >= 0; --p) schedule.positions_rad.push_back((p + 0.5) * M_PI / 3.0);
      }
      break;
    case Design::kStaticForthAndBack:
      // Up through 0, 30, ..., 330 degrees, then down through 345, 315, ..., 15.
      schedule.kind = TiltSchedule::Kind::kStaticPositions;
      for (int p = 0; p < 12; ++p) schedule.positions_rad.push_back(p * M_PI / 6.0);
      for (int p = 11; p >= 0; --p) schedule.positions_rad.push_back((p + 0.5) * M_PI / 6.0);
      break;
    case Design::kTwoTurns:
      schedule.theta_end_rad = 4.0 * M_PI;
      break;
    case Design::kStaticTwice:
      schedule.kind = TiltSchedule::Kind::kStaticPositions;
      for (int p = 0; p < 24; ++p) schedule.positions_rad.push_back((p % 12) * M_PI / 6.0);
      break;
  }
  return schedule;
}

Scenario ScenarioFor(Design design, int samples) {
  Scenario scenario;
  EXPECT_TRUE(LoadDefaultScenario(&scenario).ok());
  scenario.tilt = Schedule(design, samples);
  return scenario;
}

// The hidden shape's --set assignments at a size (m/s^2; for the clipping, how far below g the
// axis clips), through the simulator's disturbances (simulation/disturbances.h).
using Assignments = std::string (*)(double size, double gravity_mps2);

Scenario WithShape(Scenario scenario, Assignments assignments, double size) {
  EXPECT_TRUE(
      ApplyScenarioOverrides(assignments(size, scenario.truth.gravity_mps2), &scenario).ok());
  return scenario;
}

// The chi-square the shape hidden at `size` removes on x beyond the baseline's span there (1,
// cos theta, sin theta): the disturbances draw nothing from the simulator's noise, so the same
// seed with and without them differs by the shape alone.
double Signature(const Scenario& scenario, Assignments assignments, double size) {
  const CalibrationTest plain = SimulateScenario(scenario, 1).test;
  const CalibrationTest shaped = SimulateScenario(WithShape(scenario, assignments, size), 1).test;
  const int n = plain.size();
  Eigen::MatrixXd basis(n, 3);
  Eigen::VectorXd column(n);
  for (int i = 0; i < n; ++i) {
    basis.row(i) << 1.0, std::cos(plain.theta_rad[i]), std::sin(plain.theta_rad[i]);
    column[i] = shaped.measured_x[i] - plain.measured_x[i];
  }
  const Eigen::VectorXd fitted = basis * basis.colPivHouseholderQr().solve(column);
  return (column - fitted).squaredNorm() / scenario.truth.TrueNoiseVarianceX();
}

// The size at which the shape's signature is kSignature, by bisection on [0, upper] (the
// signature grows with the size).
double SizeAtTenSigma(const Scenario& scenario, Assignments assignments, double upper) {
  double low = 0.0, high = upper;
  for (int iteration = 0; iteration < 40; ++iteration) {
    const double middle = 0.5 * (low + high);
    (Signature(scenario, assignments, middle) < kSignature ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

std::string ThetaHarmonic(double size, double) {
  return StringPrintf("theta_harmonic_order=2,theta_harmonic_x=%.17g", size);
}
std::string WarmUpThenCoolDown(double size, double) {
  return StringPrintf("bias_warmup_x=%.17g", size);
}
std::string StepAtFortyPercent(double size, double) {
  return StringPrintf("bias_step_at=0.4,bias_step_x=%.17g", size);
}
std::string Hysteresis(double size, double) {
  return StringPrintf("bias_hysteresis_x=%.17g", size);
}
std::string ClippedNearOneG(double below_g, double gravity_mps2) {
  return StringPrintf("full_scale_x=%.17g", gravity_mps2 - below_g);
}
// The sixth of 24 positions (5.5/24 of the test): not one at the ends of the axis's range.
std::string OnePositionMoved(double size, double) {
  return StringPrintf("position_offset_at=0.229,position_offset_x=%.17g", size);
}

struct ShapeCase {
  const char* id;
  const char* name;
  Assignments assignments;
  double upper;  // of the size's bisection
  Design design;
  ShapeClass shape_class;
  const char* in_description;  // what the first line must say besides its class ("" none)
};

const ShapeCase kCases[] = {
    {"OrientationOnASweep", "a 2-theta harmonic", ThetaHarmonic, 5.0, Design::kSweep,
     ShapeClass::kOrientation, "theta harmonic"},
    {"OrientationOnPositions", "a 2-theta harmonic", ThetaHarmonic, 5.0, Design::kStatic,
     ShapeClass::kOrientation, "theta harmonic"},
    // Over one turn a warm-up and cool-down is much like the scale's cos theta; over two it is
    // not.
    {"WarmUpOnTwoTurns", "a warm-up then a cool-down", WarmUpThenCoolDown, 5.0, Design::kTwoTurns,
     ShapeClass::kTime, "rises then falls"},
    {"WarmUpOnPositionsTwice", "a warm-up then a cool-down", WarmUpThenCoolDown, 5.0,
     Design::kStaticTwice, ShapeClass::kTime, "rises then falls"},
    {"StepOnASweep", "a step at 40% of the test", StepAtFortyPercent, 5.0, Design::kSweep,
     ShapeClass::kTime, "a step"},
    {"StepOnPositions", "a step at 40% of the test", StepAtFortyPercent, 5.0, Design::kStatic,
     ShapeClass::kTime, "a step"},
    // Up then down once, the direction is a step at the middle of the test, 0.87 correlated
    // with bias_drift_x: in some seeds the drift takes most of it. Twice up and down, the two
    // are nearly orthogonal.
    {"TurnDirectionForthAndBack", "hysteresis", Hysteresis, 5.0, Design::kForthAndBack,
     ShapeClass::kTurnDirection, "turns up"},
    {"TurnDirectionForthAndBackTwice", "hysteresis", Hysteresis, 5.0, Design::kForthAndBackTwice,
     ShapeClass::kTurnDirection, "turns up"},
    {"TurnDirectionOnPositionsTwice", "hysteresis", Hysteresis, 5.0,
     Design::kStaticForthAndBackTwice, ShapeClass::kTurnDirection, "turns up"},
    {"FullScaleOnASweep", "x clipped near +-1 g", ClippedNearOneG, 5.0, Design::kSweep,
     ShapeClass::kFullScale, "1 g on x"},
    {"FullScaleForthAndBack", "x clipped near +-1 g", ClippedNearOneG, 5.0, Design::kForthAndBack,
     ShapeClass::kFullScale, "1 g on x"},
    {"FullScaleOnPositions", "x clipped near +-1 g", ClippedNearOneG, 5.0, Design::kStatic,
     ShapeClass::kFullScale, "1 g on x"},
    {"OnePositionHeld", "one position moved", OnePositionMoved, 5.0, Design::kStatic,
     ShapeClass::kPoseOrder, "position held"},
    {"OnePositionForthAndBack", "one position moved", OnePositionMoved, 5.0,
     Design::kStaticForthAndBack, ShapeClass::kPoseOrder, "position held"},
};

void PrintTo(const ShapeCase& c, std::ostream* os) {
  *os << c.name << " on " << DesignName(c.design);
}

// The first remaining shape is of the hidden class, and says what it must.
bool NamesTheShape(const DiscoveryResult& result, const ShapeCase& c) {
  if (result.verdict_code != Verdict::kUnexplained || result.remaining_checks.empty()) return false;
  const ResidualCheck& first = result.checks[result.remaining_checks[0]];
  return first.shape_class == c.shape_class && first.axis == 0 && !first.advice.empty() &&
         first.description.find(c.in_description) != std::string::npos;
}

class HiddenShapeTest : public testing::TestWithParam<ShapeCase> {};

TEST_P(HiddenShapeTest, IsNamedFirstInAtLeastEightyPercentOfSeeds) {
  const ShapeCase& c = GetParam();
  const Scenario plain = ScenarioFor(c.design, kSamples);
  const double size = SizeAtTenSigma(plain, c.assignments, c.upper);
  const Scenario scenario = WithShape(plain, c.assignments, size);
  int honest = 0, misses = 0;
  std::string named, example;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const SimulatedData data = SimulateScenario(scenario, seed);
    const DiscoveryResult result = DiscoverSeed(data);
    if (NamesTheShape(result, c)) {
      if (honest++ == 0) named = "seed " + std::to_string(seed) + ": " + result.remaining[0];
    } else if (misses < 3) {
      ++misses;
      example += "\nseed " + std::to_string(seed) + ": " + result.verdict.substr(0, 400);
    }
  }
  std::printf("%s on %s (size %.3g): named first in %d of %d seeds\n  %s\n", c.name,
              DesignName(c.design), size, honest, kSeeds, named.c_str());
  EXPECT_GE(honest, 0.8 * kSeeds) << c.name << "; the first misses:" << example;
}

INSTANTIATE_TEST_SUITE_P(TwoAxisShapes, HiddenShapeTest, testing::ValuesIn(kCases),
                         [](const testing::TestParamInfo<ShapeCase>& info) {
                           return std::string(info.param.id);
                         });

// The whole procedure on null data of the eight designs (small tests, to keep it fast): any
// verdict but "explained" at most alpha + 2 sd of the time over 1000 datasets. And each new
// check on its own keeps its level: p <= 0.05 at most 5% + 3 sd of the time it runs. The
// procedure's level alone would hardly see a check that forgot its Bonferroni factor (Holm
// spreads alpha/4 over some 30 checks); this does.
TEST(TwoAxisShapes, NullRateOverMixedDesignsIsAtMostAlpha) {
  constexpr int kDatasets = 1000;
  const Design designs[] = {Design::kSweep,
                            Design::kStatic,
                            Design::kForthAndBack,
                            Design::kForthAndBackTwice,
                            Design::kStaticForthAndBack,
                            Design::kStaticForthAndBackTwice,
                            Design::kTwoTurns,
                            Design::kStaticTwice};
  constexpr int kDesigns = sizeof(designs) / sizeof(designs[0]);
  const auto start = std::chrono::steady_clock::now();
  int not_explained = 0;
  std::string example;
  // Per new class: how often its checks ran, and how often at p <= 0.05.
  const ShapeClass new_classes[] = {ShapeClass::kTurnDirection, ShapeClass::kFullScale,
                                    ShapeClass::kPoseOrder};
  std::map<ShapeClass, std::pair<int, int>> level;
  for (int d = 0; d < kDatasets; ++d) {
    const Design design = designs[d % kDesigns];
    const Scenario scenario = ScenarioFor(design, 400);
    const DiscoveryResult result = DiscoverSeed(SimulateScenario(scenario, 5000 + d));
    if (result.verdict_code != Verdict::kExplained) {
      ++not_explained;
      if (example.empty()) example = std::string(DesignName(design)) + ": " + result.verdict;
    }
    for (const ResidualCheck& check : result.checks) {
      ++level[check.shape_class].first;
      level[check.shape_class].second += check.p_value <= 0.05;
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double alpha = DiscoveryOptions().alpha;
  const double sd = std::sqrt(alpha * (1.0 - alpha) / kDatasets);
  std::printf("null: %d of %d not explained (alpha %.2g, bound %.1f), %.1f s\n", not_explained,
              kDatasets, alpha, (alpha + 2.0 * sd) * kDatasets, seconds);
  EXPECT_LE(not_explained, (alpha + 2.0 * sd) * kDatasets) << "e.g. " << example;
  for (const ShapeClass shape_class : new_classes) {
    const auto [runs, at_five_percent] = level[shape_class];
    std::printf("%s checks: p <= 0.05 in %d of %d\n", ShapeClassName(shape_class), at_five_percent,
                runs);
    EXPECT_GT(runs, 0) << ShapeClassName(shape_class);
    EXPECT_LE(at_five_percent, 0.05 * runs + 3.0 * std::sqrt(0.05 * 0.95 * runs))
        << ShapeClassName(shape_class);
  }
}

}  // namespace
}  // namespace accelcal
