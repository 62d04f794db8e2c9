// The progress a long run shows on stderr: the time-left arithmetic and its wording, how
// often a line is written (with a clock the test moves by hand), the terminal's rewritten
// line, and how the counts reach it from several threads. (That counting changes nothing a
// study computes: MonteCarlo.ResultsDoNotDependOnTheThreadCount in simulation_test.)

#include "common/progress.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "reporting/progress_printer.h"
#include "simulation/monte_carlo.h"

namespace accelcal {
namespace {

// A clock the test sets; the printer reads it through a pointer.
struct FakeClock {
  double now_s = 100.0;
  ProgressPrinter::Clock Function() {
    return [this] { return now_s; };
  }
};

// The first line after 1 s, then one every 5 s.
ProgressStyle StyleOf(bool terminal, bool show = true) {
  ProgressStyle style;
  style.show = show;
  style.terminal = terminal;
  style.first_line_s = 1.0;
  style.interval_s = 5.0;
  return style;
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream stream(text);
  for (std::string line; std::getline(stream, line);) lines.push_back(line);
  return lines;
}

TEST(FormatDuration, TenthsUnderTenSecondsThenTheTwoLargestUnits) {
  EXPECT_EQ(FormatDuration(0.04), "0.0 s");
  EXPECT_EQ(FormatDuration(4.24), "4.2 s");
  EXPECT_EQ(FormatDuration(35.4), "35 s");
  EXPECT_EQ(FormatDuration(105.0), "1 min 45 s");
  EXPECT_EQ(FormatDuration(120.2), "2 min");
  EXPECT_EQ(FormatDuration(7500.0), "2 h 5 min");
  EXPECT_EQ(FormatDuration(7200.0), "2 h");
  EXPECT_EQ(FormatDuration(-3.0), "0.0 s");  // a clock never runs backwards, but be safe
}

TEST(ProgressLine, TheTimeLeftIsTheElapsedTimeScaledByWhatRemains) {
  // A quarter done in 35 s: three quarters take 105 s more.
  EXPECT_EQ(ProgressLine("power", "trials", 120, 480, 35.0),
            "power: 120/480 trials (25%), 35 s elapsed, about 1 min 45 s left");
  EXPECT_EQ(ProgressLine("coverage", "trials", 2, 3, 10.0),
            "coverage: 2/3 trials (66%), 10 s elapsed, about 5.0 s left");
  EXPECT_EQ(ProgressLine("power", "trials", 480, 480, 140.0),
            "power: 480/480 trials (100%), done in 2 min 20 s");
  EXPECT_EQ(ProgressLine("power", "trials", 0, 480, 3.0),
            "power: 0/480 trials (0%), 3.0 s elapsed, time left not known yet");
}

TEST(ProgressPrinter, WritesAnEarlyLineThenOneLinePerIntervalAndTheLastOnce) {
  FakeClock clock;
  std::ostringstream out;
  ProgressPrinter printer("power", "trials", StyleOf(false), &out, clock.Function());
  clock.now_s += 0.5;
  printer.Update(1, 100);  // before first_line_s: nothing
  EXPECT_EQ(out.str(), "");
  clock.now_s += 0.5;
  printer.Update(2, 100);  // 1 s in: the early estimate
  clock.now_s += 4.0;
  printer.Update(10, 100);  // 4 s after it: too soon
  clock.now_s += 1.0;
  printer.Update(12, 100);  // 5 s after it
  clock.now_s += 0.1;
  printer.Update(100, 100);  // the last, however soon
  printer.Update(100, 100);  // and only once
  EXPECT_EQ(Lines(out.str()), (std::vector<std::string>{
                                  "power: 2/100 trials (2%), 1.0 s elapsed, about 49 s left",
                                  "power: 12/100 trials (12%), 6.0 s elapsed, about 44 s left",
                                  "power: 100/100 trials (100%), done in 6.1 s",
                              }));
}

TEST(ProgressPrinter, RewritesOneLineOnATerminalAndEndsIt) {
  FakeClock clock;
  std::ostringstream out;
  {
    ProgressPrinter printer("null_rate", "datasets", StyleOf(true), &out, clock.Function());
    clock.now_s += 10.0;
    printer.Update(1, 10);
    clock.now_s += 10.0;
    printer.Update(9, 10);
  }  // stopped before the end: the destructor ends the line
  // The shorter second line blanks the 5 characters the first leaves on the screen.
  EXPECT_EQ(out.str(),
            "\rnull_rate: 1/10 datasets (10%), 10 s elapsed, about 1 min 30 s left"
            "\rnull_rate: 9/10 datasets (90%), 20 s elapsed, about 2.2 s left     \n");
}

// A step's start and end ("analyze: step 3/5 ..."), written in the style given.
std::string StepText(bool terminal) {
  FakeClock clock;
  std::ostringstream out;
  ProgressPrinter printer("analyze", "steps", StyleOf(terminal), &out, clock.Function());
  printer.StartStep(3, 5, "discovery");
  clock.now_s += 1.3;
  printer.EndStep();
  return out.str();
}

TEST(ProgressPrinter, StepsShareALineOnATerminalAndTakeALineEachInAFile) {
  EXPECT_EQ(StepText(true),
            "\ranalyze: step 3/5 discovery ...\ranalyze: step 3/5 discovery, done in 1.3 s\n");
  EXPECT_EQ(StepText(false),
            "analyze: step 3/5 discovery ...\nanalyze: step 3/5 discovery, done in 1.3 s\n");
}

TEST(ProgressPrinter, ShowsNothingAndAsksForNoCountsWhenOff) {
  FakeClock clock;
  std::ostringstream out;
  ProgressPrinter printer("power", "trials", StyleOf(false, false), &out, clock.Function());
  EXPECT_FALSE(printer.Callback());
  clock.now_s += 100.0;
  printer.Update(100, 100);
  printer.StartStep(1, 2, "x");
  printer.EndStep();
  EXPECT_EQ(out.str(), "");
}

TEST(ProgressStyleFor, AutoShowsOnlyOnATerminalAndOtherWordsAreRefused) {
  ProgressStyle style;
  ASSERT_TRUE(ProgressStyleFor("auto", false, &style).ok());
  EXPECT_FALSE(style.show);
  ASSERT_TRUE(ProgressStyleFor("auto", true, &style).ok());
  EXPECT_TRUE(style.show);
  EXPECT_TRUE(style.terminal);
  ASSERT_TRUE(ProgressStyleFor("always", false, &style).ok());
  EXPECT_TRUE(style.show);
  EXPECT_FALSE(style.terminal);
  EXPECT_GE(style.interval_s, 2.0);  // a log file gets at most a line every few seconds
  ASSERT_TRUE(ProgressStyleFor("never", true, &style).ok());
  EXPECT_FALSE(style.show);
  const Status bad = ProgressStyleFor("sometimes", true, &style);
  EXPECT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("auto, always or never"), std::string::npos) << bad.message();
}

// Trials finishing on several threads reach the callback one at a time, each count once,
// in order: the printer needs no lock of its own.
TEST(ProgressCounter, PassesEveryCountInOrderFromSeveralThreads) {
  std::vector<std::pair<int64_t, int64_t>> seen;
  ProgressCounter counter([&](int64_t done, int64_t total) { seen.emplace_back(done, total); },
                          2000);
  MonteCarloOptions monte_carlo;
  monte_carlo.trials = 2000;
  monte_carlo.threads = 4;
  monte_carlo.progress = &counter;
  RunTrials(monte_carlo, [](int) {});
  ASSERT_EQ(seen.size(), 2000u);
  for (size_t i = 0; i < seen.size(); ++i) {
    EXPECT_EQ(seen[i].first, static_cast<int64_t>(i) + 1);
    EXPECT_EQ(seen[i].second, 2000);
  }
}

TEST(ProgressPart, MapsAPartsCountIntoTheWholeJob) {
  std::vector<std::pair<int64_t, int64_t>> seen;
  const ProgressFn whole = [&](int64_t done, int64_t total) { seen.emplace_back(done, total); };
  ProgressPart(whole, 0, 30)(5, 10);
  ProgressPart(whole, 10, 30)(20, 20);
  EXPECT_EQ(seen, (std::vector<std::pair<int64_t, int64_t>>{{5, 30}, {30, 30}}));
  EXPECT_FALSE(ProgressPart(ProgressFn(), 0, 30));
}

}  // namespace
}  // namespace accelcal
