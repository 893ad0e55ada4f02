// jobs::ChildProcess: a child started without a shell, its output in a file, and how it ended
// as the study reports it (exit status, signal, failed exec, interrupted exit 128 + signal).
#include "camplace/jobs/process.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <optional>
#include <string>
#include <thread>

#include "command.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

/// `/bin/sh -c script` with its output in a fresh file of the test's folder.
jobs::ProcessLaunch shell(const std::string& script, const std::string& name) {
  jobs::ProcessLaunch launch;
  launch.args = {"-c", script};
  launch.output_file = temp_dir("jobs-process") + "/" + name + ".txt";
  return launch;
}

TEST(ChildProcess, OutputGoesToTheFileAndStatusZeroIsNoFailure) {
  const jobs::ProcessLaunch launch = shell("echo hello; echo world", "hello");
  const jobs::ProcessOutcome ended = jobs::run_process("/bin/sh", launch);
  EXPECT_EQ(ended.failure, "");
  EXPECT_FALSE(ended.interrupted);
  EXPECT_EQ(read_text(launch.output_file), "hello\nworld\n");
}

TEST(ChildProcess, NonZeroExitStatusIsAFailure) {
  const jobs::ProcessOutcome ended = jobs::run_process("/bin/sh", shell("exit 3", "exit3"));
  EXPECT_EQ(ended.failure, "exit status 3");
  EXPECT_FALSE(ended.interrupted);
}

TEST(ChildProcess, DeathBySignalNamesTheSignal) {
  const jobs::ProcessOutcome ended = jobs::run_process("/bin/sh", shell("kill -9 $$", "kill9"));
  EXPECT_EQ(ended.failure, "killed by signal 9 (Killed)");
  EXPECT_FALSE(ended.interrupted);
}

TEST(ChildProcess, ExitWith128PlusSigtermIsInterruptedNotFailed) {
  const jobs::ProcessOutcome ended = jobs::run_process("/bin/sh", shell("exit 143", "exit143"));
  EXPECT_EQ(ended.failure, "");
  EXPECT_TRUE(ended.interrupted);
}

TEST(ChildProcess, MissingProgramCouldNotBeStarted) {
  const jobs::ProcessOutcome ended =
      jobs::run_process("/nonexistent/camplace", shell("true", "missing"));
  EXPECT_EQ(ended.failure,
            "could not be started: /nonexistent/camplace: No such file or directory");
}

TEST(ChildProcess, UnwritableOutputFileThrows) {
  jobs::ProcessLaunch launch = shell("true", "unused");
  launch.output_file = "/nonexistent/dir/log.txt";
  EXPECT_THROW(jobs::ChildProcess("/bin/sh", launch), std::runtime_error);
}

TEST(ChildProcess, PollReportsNothingWhileTheChildRuns) {
  jobs::ChildProcess child("/bin/sh", shell("sleep 0.3", "sleep"));
  EXPECT_FALSE(child.poll().has_value());
  std::optional<jobs::ProcessOutcome> ended;
  for (int i = 0; i < 500 && !ended; ++i) {
    ended = child.poll();
    if (!ended) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(ended.has_value());
  EXPECT_EQ(ended->failure, "");
}

}  // namespace
}  // namespace camplace::testing
