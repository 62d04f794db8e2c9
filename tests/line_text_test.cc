// common/line_text.h: one rule for any text that reaches a line-oriented output (issue 45), and
// the command line's quoting that keeps it one line (io/provenance.h).

#include "common/line_text.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "io/provenance.h"

namespace accelcal {
namespace {

TEST(EscapeForLine, LeavesOrdinaryTextAndUtf8AsTheyAre) {
  EXPECT_EQ(EscapeForLine("../shared/data/imu_tk-xsens/xsens_acc.mat"),
            "../shared/data/imu_tk-xsens/xsens_acc.mat");
  EXPECT_EQ(EscapeForLine("Messung \xC3\xBC \xE2\x82\xAC \xF0\x9F\x93\x88 a\\b"),
            "Messung \xC3\xBC \xE2\x82\xAC \xF0\x9F\x93\x88 a\\b");
  EXPECT_FALSE(NeedsLineEscape("plain path with spaces, quotes ' \" and $"));
}

TEST(EscapeForLine, EscapesEveryLineBreakAndControlCharacter) {
  EXPECT_EQ(EscapeForLine("a\nb\rc\td"), "a\\nb\\rc\\td");
  EXPECT_EQ(EscapeForLine(std::string("x\0y\x1b[2J\x7f", 8)), "x\\x00y\\x1B[2J\\x7F");
  // Unicode's next-line, line and paragraph separators, which YAML breaks lines at.
  EXPECT_EQ(EscapeForLine("a\xC2\x85"
                          "b\xE2\x80\xA8"
                          "c\xE2\x80\xA9"
                          "d"),
            "a\\u0085b\\u2028c\\u2029d");
  EXPECT_TRUE(NeedsLineEscape("a\nb"));
  EXPECT_TRUE(NeedsLineEscape("\xE2\x80\xA8"));
}

TEST(EscapeForLine, EscapesBytesThatAreNotUtf8SoTheOutputIs) {
  EXPECT_EQ(EscapeForLine("a\xff"
                          "b"),
            "a\\xFFb");
  EXPECT_EQ(EscapeForLine("cut \xE2\x80"), "cut \\xE2\\x80");
  EXPECT_EQ(EscapeForLine("overlong \xC0\xAF"), "overlong \\xC0\\xAF");
  EXPECT_EQ(EscapeForLine("surrogate \xED\xA0\x80"), "surrogate \\xED\\xA0\\x80");
  EXPECT_EQ(EscapeForLine("lone \x80"), "lone \\x80");
}

TEST(CommandLine, AnArgumentWithALineBreakIsQuotedOnOneLineAsBashReadsItBack) {
  std::vector<std::string> arguments = {"/usr/bin/apply", "--in=run\nt_s,a.csv", "--out=x y",
                                        "it's", "a\\nb\t\xE2\x80\xA8"};
  std::vector<char*> argv;
  for (std::string& argument : arguments) argv.push_back(argument.data());
  RecordCommandLine(static_cast<int>(argv.size()), argv.data());
  const std::string& line = CommandLine();
  EXPECT_FALSE(NeedsLineEscape(line)) << EscapeForLine(line);
  EXPECT_EQ(line, "apply $'--in=run\\nt_s,a.csv' '--out=x y' 'it'\\''s' $'a\\\\nb\\t\\u2028'");
  // bash reads every word back as it was given (the script through a quoted here-document, so
  // that only bash interprets it).
  const std::string script = "printf '%s\\0' " + line.substr(line.find(' ') + 1);
  FILE* pipe = popen(
      ("/bin/bash -c " + std::string("\"$(cat <<'ACCELCAL_EOF'\n") + script + "\nACCELCAL_EOF\n)\"")
          .c_str(),
      "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char buffer[256];
  for (size_t n; (n = fread(buffer, 1, sizeof(buffer), pipe)) > 0;) output.append(buffer, n);
  pclose(pipe);
  std::vector<std::string> words;
  for (size_t start = 0, end; (end = output.find('\0', start)) != std::string::npos;
       start = end + 1) {
    words.push_back(output.substr(start, end - start));
  }
  EXPECT_EQ(words, std::vector<std::string>(arguments.begin() + 1, arguments.end()));
}

}  // namespace
}  // namespace accelcal
