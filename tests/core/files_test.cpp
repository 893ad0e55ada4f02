// Result files: atomic writes and the temporary files a killed writer leaves behind.
#include "camplace/core/files.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

namespace fs = std::filesystem;

/// The pid of a process that has ended (a child that exited at once and was reaped).
pid_t ended_pid() {
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(0);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return pid;
}

std::string touch(const fs::path& path, std::chrono::minutes age) {
  std::ofstream(path) << "partial";
  fs::last_write_time(path, fs::file_time_type::clock::now() - age);
  return path.string();
}

TEST(Files, StaleTemporaryFilesOfEndedWritersAreRemovedWhenAFolderIsOpened) {
  const fs::path dir = temp_dir("stale-temp-files");
  const std::string dead = std::to_string(ended_pid());
  const std::string alive = std::to_string(::getppid());  // the test's parent runs
  const auto old = std::chrono::minutes(5), fresh = std::chrono::minutes(0);
  // Removed: an ended writer's file, minutes old.
  const std::string stale = touch(dir / ("run-1.json.camplace-tmp" + dead), old);
  // Kept: a running writer's; a file written moments ago (a writer of another machine on a
  // shared folder may have that pid); names that are not camplace's temporary files.
  const std::vector<std::string> kept = {touch(dir / ("run-2.json.camplace-tmp" + alive), old),
                                         touch(dir / ("run-3.json.camplace-tmp" + dead), fresh),
                                         touch(dir / ("notes.tmp" + dead), old),
                                         touch(dir / ("run-4.json.camplace-tmp" + dead + "x"), old),
                                         touch(dir / ".camplace-tmp", old),
                                         touch(dir / "run-5.json", old)};
  core::create_output_directory(dir.string(), "--out");
  EXPECT_FALSE(fs::exists(stale));
  for (const std::string& file : kept) EXPECT_TRUE(fs::exists(file)) << file;
  // A folder below is not touched.
  fs::create_directories(dir / "below");
  const std::string below = touch(dir / "below" / ("a.json.camplace-tmp" + dead), old);
  EXPECT_EQ(core::remove_stale_temp_files(dir.string()), 0);
  EXPECT_TRUE(fs::exists(below));
}

TEST(Files, AnAtomicWriteLeavesOnlyTheFile) {
  const fs::path dir = temp_dir("atomic-write");
  core::write_file_atomically((dir / "sub" / "a.json").string(), "{}\n");
  std::ifstream in(dir / "sub" / "a.json");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "{}\n");
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir / "sub")) files += entry.is_regular_file();
  EXPECT_EQ(files, 1);
}

}  // namespace
}  // namespace camplace::testing
