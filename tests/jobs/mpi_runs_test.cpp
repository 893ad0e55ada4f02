// The MPI messages of a study's runs (jobs/mpi_runs.hpp): the bytes as specified, and back.
#include "camplace/jobs/mpi_runs.hpp"

#include <gtest/gtest.h>

#include <string>

namespace camplace::testing {
namespace {

using namespace std::string_literals;

TEST(MpiRunMessages, LaunchIsOutputFileThenArgumentsSeparatedByNul) {
  jobs::ProcessLaunch launch;
  launch.output_file = "out/log.txt";
  launch.args = {"optimize", "scene.json", "", "--seed", "3"};
  const std::string payload = jobs::mpi::encode_launch(launch);
  EXPECT_EQ(payload, "out/log.txt\0optimize\0scene.json\0\0--seed\0003"s);
  const jobs::ProcessLaunch back = jobs::mpi::decode_launch(payload);
  EXPECT_EQ(back.output_file, launch.output_file);
  EXPECT_EQ(back.args, launch.args);
}

TEST(MpiRunMessages, LaunchWithoutArguments) {
  jobs::ProcessLaunch launch;
  launch.output_file = "log";
  EXPECT_EQ(jobs::mpi::encode_launch(launch), "log");
  const jobs::ProcessLaunch back = jobs::mpi::decode_launch("log");
  EXPECT_EQ(back.output_file, "log");
  EXPECT_TRUE(back.args.empty());
}

TEST(MpiRunMessages, OutcomeIsTwoFlagsThenFailure) {
  EXPECT_EQ(jobs::mpi::encode_outcome({false, ""}, false), "00");
  EXPECT_EQ(jobs::mpi::encode_outcome({true, ""}, false), "01");
  EXPECT_EQ(jobs::mpi::encode_outcome({false, "exit status 1"}, true), "10exit status 1");
}

}  // namespace
}  // namespace camplace::testing
