// jobs::duration_text: the durations of the progress lines, computed by hand.
#include "camplace/jobs/progress.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

namespace camplace::testing {
namespace {

TEST(DurationText, SecondsBelowAMinute) {
  EXPECT_EQ(jobs::duration_text(0.0), "0s");
  EXPECT_EQ(jobs::duration_text(42.0), "42s");
  EXPECT_EQ(jobs::duration_text(59.4), "59s");
}

TEST(DurationText, MinutesAndSecondsBelowAnHour) {
  EXPECT_EQ(jobs::duration_text(60.0), "1m00s");
  EXPECT_EQ(jobs::duration_text(185.0), "3m05s");  // 3·60 + 5
  EXPECT_EQ(jobs::duration_text(3599.0), "59m59s");
}

TEST(DurationText, HoursAndMinutes) {
  EXPECT_EQ(jobs::duration_text(3600.0), "1h00m");
  EXPECT_EQ(jobs::duration_text(7800.0), "2h10m");  // 2·3600 + 10·60
}

TEST(ProgressLine, DisabledWithoutTerminalOrWish) {
  if (::isatty(2) == 1) GTEST_SKIP() << "stderr is a terminal";
  jobs::ProgressLine line("test", false);
  EXPECT_FALSE(line.enabled());
  line.update("steps", 1, 2);  // prints nothing, does not throw
  line.finish();
}

}  // namespace
}  // namespace camplace::testing
