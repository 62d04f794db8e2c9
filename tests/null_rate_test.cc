// The null-rate study: discovery's false-discovery rate on null data stays within alpha
// plus its Monte Carlo error on two 2000-sample designs, the counts do not depend on the
// thread count, and the null scenarios are null.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "io/scenario_json.h"
#include "models/effects.h"
#include "studies/null_rate_study.h"

namespace accelcal {
namespace {

Scenario Course() {
  Scenario course;
  EXPECT_TRUE(LoadDefaultScenario(&course).ok());
  return course;
}

TEST(NullRateStudy, FalseDiscoveryRateIsWithinAlphaOnTwoDesigns) {
  NullRateOptions options;
  options.designs = {"n2000", "half_circle"};
  options.noise_factors = {1.0};
  options.alphas = {0.05};
  options.datasets = 200;
  options.threads = 0;
  NullRateResult result;
  const Status status = RunNullRateStudy(Course(), options, &result);
  ASSERT_TRUE(status.ok()) << status.message();
  ASSERT_EQ(result.cells.size(), 2u);
  ASSERT_EQ(result.pooled.size(), 1u);
  for (const NullRateCell& cell : result.cells) {
    std::printf("%s: %d/%d not explained (effects %d, noise %d, checks %d, ambiguous %d)\n",
                cell.design.c_str(), cell.not_explained, cell.verdicts, cell.with_effects,
                cell.with_noise_findings, cell.with_flagged_checks, cell.cannot_tell_apart);
    EXPECT_EQ(cell.errors, 0) << cell.design;
  }
  const PooledNullRate& pooled = result.pooled[0];
  EXPECT_EQ(pooled.verdicts, 400);
  const double sd = std::sqrt(0.05 * 0.95 / pooled.verdicts);
  EXPECT_LE(pooled.rate, 0.05 + 3 * sd) << pooled.not_explained << " of " << pooled.verdicts;
}

TEST(NullRateStudy, CountsDoNotDependOnTheThreadCount) {
  NullRateOptions options;
  // A large alpha, so that some of the few datasets are flagged and the counts say something.
  options.designs = {"n2000", "half_circle"};
  options.noise_factors = {4.0};
  options.alphas = {0.01, 0.45};
  options.datasets = 8;
  NullRateResult one;
  NullRateResult two;
  options.threads = 1;
  ASSERT_TRUE(RunNullRateStudy(Course(), options, &one).ok());
  options.threads = 2;
  ASSERT_TRUE(RunNullRateStudy(Course(), options, &two).ok());
  ASSERT_EQ(one.cells.size(), two.cells.size());
  int not_explained = 0;
  for (size_t c = 0; c < one.cells.size(); ++c) {
    not_explained += one.cells[c].not_explained;
    EXPECT_EQ(one.cells[c].not_explained, two.cells[c].not_explained);
    EXPECT_EQ(one.cells[c].verdict_counts, two.cells[c].verdict_counts);
    EXPECT_EQ(one.cells[c].effects_named, two.cells[c].effects_named);
    EXPECT_EQ(one.cells[c].checks_flagged, two.cells[c].checks_flagged);
  }
  std::printf("%d of %d verdicts (dataset, alpha) not explained\n", not_explained,
              4 * options.datasets);
}

TEST(NullRateStudy, NullScenarioKeepsOnlyBiasAndScale) {
  Scenario course = Course();
  ASSERT_TRUE(ApplyScenarioOverrides("angle_offset=0.004,noise_ar1_x=0.5", &course).ok());
  for (const std::string& name : NullRateDesignNames()) {
    Scenario null;
    ASSERT_TRUE(MakeNullScenario(course, name, 4.0, &null).ok()) << name;
    for (const ParameterInfo& info : ParameterCatalogue()) {
      EXPECT_EQ(null.truth.parameters[info.parameter],
                info.baseline ? course.truth.parameters[info.parameter] : info.neutral)
          << name << " " << info.name;
    }
    EXPECT_FALSE(null.truth.disturbances.any()) << name;
    EXPECT_EQ(null.truth.stated_noise_variance_x, 4.0 * course.truth.stated_noise_variance_x);
    EXPECT_EQ(null.truth.TrueNoiseVarianceY(), null.truth.stated_noise_variance_y);
    EXPECT_EQ(TiltAngles(null.tilt).size(), name == "course" ? 20001u : 2000u) << name;
  }
  Scenario ignored;
  EXPECT_FALSE(MakeNullScenario(course, "full_circle", 1.0, &ignored).ok());
  EXPECT_FALSE(MakeNullScenario(course, "n2000", 0.0, &ignored).ok());
}

}  // namespace
}  // namespace accelcal
