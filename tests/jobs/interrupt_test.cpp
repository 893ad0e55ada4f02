// jobs::InterruptSignals: the first SIGTERM sets the flag and is recorded; the exit status is
// 128 + the signal. (Sets process-wide state: the last file of jobs_tests.)
#include "camplace/jobs/interrupt.hpp"

#include <gtest/gtest.h>

#include <csignal>

namespace camplace::testing {
namespace {

TEST(InterruptSignals, SigtermSetsTheFlagAndTheExitStatus) {
  {
    const jobs::InterruptSignals signals;
    if (jobs::InterruptSignals::received() == 0) {
      EXPECT_EQ(jobs::interrupted_exit_status(), 130);  // no signal recorded: as after Ctrl-C
    }
    std::raise(SIGTERM);  // handled: the process goes on
    EXPECT_TRUE(jobs::InterruptSignals::flag().load());
    EXPECT_EQ(jobs::InterruptSignals::received(), SIGTERM);
    EXPECT_EQ(jobs::interrupted_exit_status(), 128 + SIGTERM);
  }
  // The handlers are restored: SIGTERM ignored here so the test survives checking that.
  std::signal(SIGTERM, SIG_IGN);
  std::raise(SIGTERM);
  std::signal(SIGTERM, SIG_DFL);
}

TEST(WorkDescription, IsWhatWasSet) {
  jobs::set_work_description("evaluate --resolution 16x12x12");
  EXPECT_EQ(jobs::work_description(), "evaluate --resolution 16x12x12");
}

}  // namespace
}  // namespace camplace::testing
