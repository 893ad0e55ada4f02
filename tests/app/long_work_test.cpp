// Long work a user can bound and watch: the memory estimate refused before any work,
// --max-seconds, signals while an evaluator is set up, progress on stderr, out of memory, and the
// one shape of `evaluate --json`.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "command.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

namespace fs = std::filesystem;

CommandResult run(const std::string& args) { return run_camplace(CAMPLACE_BINARY, args); }

/// The command with MemAvailable faked as `kb` (app/memory_estimate.hpp).
CommandResult run_with_memory(const std::string& kb, const std::string& args) {
  return run_camplace("CAMPLACE_MEM_AVAILABLE_KB=" + kb + " " + CAMPLACE_BINARY, args);
}

const std::string kData = std::string(CAMPLACE_SOURCE_DIR) + "/data/";
const std::string kBasic =
    kData + "paper_basic.json --cameras " + kData + "paper_basic_corners.json";

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The estimate of app/memory_estimate.hpp for `evaluate` on paper_basic (16x12x12: V = 2304
// voxels, T = 2 time steps, S = 6 states, C = 6 cameras, 80 triangles: 2 static tetrahedra, 2
// steps × 3 robot tetrahedra, 2 steps × 3 events × 2 person tetrahedra, 4 each; K = 1 thread):
//   V·T·17 = 78336, V·S = 13824, K·V·16 = 36864, C·K·80·320 = 153600, diagnostics V·(C + 6) =
//   27648; sum 310272 bytes = 303.0 kB.
// So 302 kB available refuses it and 304 kB lets it run.
TEST(LongWork, MemoryEstimateRefusesWhatExceedsTheAvailableMemory) {
  const CommandResult refused = run_with_memory("302", "evaluate " + kBasic + " --threads 1");
  EXPECT_EQ(refused.exit_code, 1) << refused.output;
  // 310272 B = 0.30 MiB, 302 kB = 0.29 MiB; no option sized the grid: the scene did.
  EXPECT_TRUE(has(refused.output,
                  "error: the scene's voxels 16x12x12 with 6 cameras needs about 0.30 MiB, more "
                  "than the 0.29 MiB available"))
      << refused.output;
  const CommandResult ran = run_with_memory("304", "evaluate " + kBasic + " --threads 1");
  EXPECT_EQ(ran.exit_code, 0) << ran.output;

  // 512x512x128: V = 33554432; V·(34 + 6 + 16 + 12) + 153600 = 2281854976 B = 2.13 GiB.
  const CommandResult big =
      run_with_memory("1048576", "evaluate " + kBasic + " --resolution 512x512x128 --threads 1");
  EXPECT_EQ(big.exit_code, 1) << big.output;
  EXPECT_TRUE(has(big.output,
                  "error: --resolution 512x512x128 with 6 cameras needs about 2.13 GiB, more than "
                  "the 1.00 GiB available"))
      << big.output;

  // optimize with 2 threads: V·(34 + 6 + 2·16) + 6·2·80·320 = 2416226304 B = 2.25 GiB; nothing
  // is written.
  const std::string dir = temp_dir("memory-optimize");
  const CommandResult optimize = run_with_memory(
      "1048576", "optimize " + kData +
                     "paper_basic.json --resolution 512x512x128 --threads 2 --out " + dir + "/out");
  EXPECT_EQ(optimize.exit_code, 1) << optimize.output;
  EXPECT_TRUE(has(optimize.output,
                  "error: --resolution 512x512x128 with 6 cameras needs about 2.25 GiB, more than "
                  "the 1.00 GiB available"))
      << optimize.output;
  EXPECT_FALSE(fs::exists(dir + "/out"));

  // export: as evaluate without the diagnostics: V·56 + 153600 = 1879201792 B = 1.75 GiB.
  const CommandResult exported = run_with_memory(
      "1048576",
      "export " + kBasic + " --resolution 512x512x128 --threads 1 --out " + dir + "/export");
  EXPECT_EQ(exported.exit_code, 1) << exported.output;
  EXPECT_TRUE(has(exported.output,
                  "error: --resolution 512x512x128 with 6 cameras needs about "
                  "1.75 GiB, more than the 1.00 GiB available"))
      << exported.output;
}

// The exact pipeline's estimate (app/memory_estimate.hpp) for paper_basic with one thread: C = 6
// cameras, T = 28 triangles of the largest state (2 static tetrahedra, 3 robot tetrahedra, 2
// person tetrahedra) + 24 of the 6 distinct person tetrahedra = 52;
//   96 MiB + 1·6·3.8 MiB·52^0.38 = 207967325 B = 0.19 GiB (198.3 MiB).
// So 150,000 kB (0.14 GiB) refuses it before any work and 250,000 kB lets it run.
TEST(LongWork, ExactMemoryEstimateRefusesWhatExceedsTheAvailableMemory) {
  const CommandResult refused =
      run_with_memory("150000", "evaluate " + kBasic + " --pipeline exact --threads 1");
  EXPECT_EQ(refused.exit_code, 1) << refused.output;
  EXPECT_TRUE(has(refused.output,
                  "error: the exact pipeline with 6 cameras, 1 thread and up to 28 triangles per "
                  "state needs about 0.19 GiB, more than the 0.14 GiB available; use fewer "
                  "threads (--threads) or coarser meshes"))
      << refused.output;
  EXPECT_FALSE(has(refused.output, "Err"));
  const CommandResult ran =
      run_with_memory("250000", "evaluate " + kBasic + " --pipeline exact --threads 1");
  EXPECT_EQ(ran.exit_code, 0) << ran.output;
}

/// Starts `camplace args...` with stdout and stderr into `log`.
template <class... Args>
pid_t start(const std::string& log, Args... args) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::freopen(log.c_str(), "w", stdout);
    std::freopen(log.c_str(), "a", stderr);
    ::execl(CAMPLACE_BINARY, CAMPLACE_BINARY, args..., static_cast<char*>(nullptr));
    ::_exit(127);
  }
  return pid;
}

// SIGINT was ignored for a minute while a fine grid's evaluator was set up. Now every
// signal ends `evaluate` within a second, with 128 + the signal and a line saying nothing was
// written. 256x256x64 takes tens of seconds to set up.
TEST(LongWork, SignalsEndEvaluateWithinASecondDuringTheSetUp) {
  const std::string dir = temp_dir("signal-setup");
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    const std::string log = dir + "/log" + std::to_string(sig);
    const std::string scene = kData + "paper_basic.json";
    const std::string cameras = kData + "paper_basic_corners.json";
    const pid_t pid = start(log, "evaluate", scene.c_str(), "--cameras", cameras.c_str(),
                            "--resolution", "256x256x64", "--threads", "1");
    ASSERT_GT(pid, 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
    const auto sent = std::chrono::steady_clock::now();
    ASSERT_EQ(::kill(pid, sig), 0);
    const int status = wait_for(pid, 10.0);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
    ASSERT_NE(status, -1) << "evaluate did not stop after signal " << sig;
    ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
    EXPECT_EQ(WEXITSTATUS(status), 128 + sig);
    EXPECT_LT(seconds, 1.0) << sig;
    EXPECT_TRUE(has(read_text(log), "interrupted: nothing was written")) << read_text(log);
  }
}

// The same for optimize while its evaluator is set up: nothing is written, not even --out.
TEST(LongWork, SignalsEndOptimizeWithinASecondDuringTheSetUp) {
  const std::string dir = temp_dir("signal-optimize");
  const std::string log = dir + "/log", out = dir + "/out";
  const std::string scene = kData + "paper_basic.json";
  // 256x256x128: a set-up of seconds, so that the signal comes during it also on a fast machine.
  const pid_t pid = start(log, "optimize", scene.c_str(), "--resolution", "256x256x128",
                          "--threads", "1", "--out", out.c_str());
  ASSERT_GT(pid, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  const auto sent = std::chrono::steady_clock::now();
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  const int status = wait_for(pid, 10.0);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  ASSERT_NE(status, -1) << "optimize did not stop";
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM);
  EXPECT_LT(seconds, 1.0);
  EXPECT_TRUE(has(read_text(log), "interrupted: nothing was written")) << read_text(log);
  EXPECT_FALSE(fs::exists(out));
}

TEST(LongWork, MaxSecondsStopsALongEvaluationWithAnErrorNamingIt) {
  const auto begin = std::chrono::steady_clock::now();
  const CommandResult r =
      run("evaluate " + kBasic + " --resolution 256x256x64 --threads 1 --max-seconds 0.5");
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(has(r.output,
                  "error: evaluate stopped: --max-seconds 0.5 exceeded; nothing was "
                  "written"))
      << r.output;
  EXPECT_LT(seconds, 3.0);
  // A limit it stays within changes nothing.
  const CommandResult within = run("evaluate " + kBasic + " --max-seconds 600 --json");
  ASSERT_EQ(within.exit_code, 0) << within.output;
  EXPECT_EQ(nlohmann::json::parse(within.output)["pipeline"], "voxel");
  for (const char* bad : {"0", "-1", "nan", "inf", "1e10", "soon"}) {
    const CommandResult e = run("evaluate " + kBasic + " --max-seconds " + bad);
    EXPECT_EQ(e.exit_code, 1) << bad << ": " << e.output;
    EXPECT_TRUE(has(e.output, "error: command line: --max-seconds")) << bad << ": " << e.output;
  }
}

// With --progress (stderr is no terminal here): done/total lines and an estimate, the last line
// with every state done.
TEST(LongWork, EvaluateProgressCountsStatesWithProgress) {
  const CommandResult quiet = run("evaluate " + kBasic + " --json");
  ASSERT_EQ(quiet.exit_code, 0);
  EXPECT_FALSE(has(quiet.output, "evaluate: ")) << "progress without --progress or a terminal";
  const CommandResult r = run("evaluate " + kBasic + " --progress");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "evaluate: voxel set-up 16x12x12, 0s elapsed")) << r.output;
  EXPECT_TRUE(has(r.output, "evaluate: voxel evaluation, states 6/6")) << r.output;
  EXPECT_TRUE(has(r.output, "evaluate: voxel diagnostics, states 0/6")) << r.output;
}

// An allocation that fails ends with a line naming the work and the options that sized
// it, not a bare std::bad_alloc. The address space is limited to 250 MB (ulimit -v) so that the
// set-up's first large allocation fails without touching the machine's memory; the estimate is
// bypassed by a large fake MemAvailable.
TEST(LongWork, OutOfMemoryNamesTheOptionsThatSizedTheWork) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer reserves terabytes of address space: no ulimit -v";
#endif
  const CommandResult r = run_camplace(
      "ulimit -v 250000; CAMPLACE_MEM_AVAILABLE_KB=1000000000 " + std::string(CAMPLACE_BINARY),
      "evaluate " + kBasic + " --resolution 512x512x128 --threads 1");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(has(r.output,
                  "error: out of memory: evaluate --resolution 512x512x128 with 6 "
                  "cameras, --pipeline voxel asked for more memory"))
      << r.output;
}

// `--json` had one shape for voxel and another for both. Now "voxel", "exact" and
// "differences" are always there (null where nothing ran); one pipeline's result also at the top.
TEST(LongWork, EvaluateJsonHasOneShape) {
  const CommandResult r = run("evaluate " + kBasic + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  for (const char* key : {"pipeline", "scene", "cameras_file", "voxel", "exact", "differences"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_TRUE(j["voxel"].is_object());
  EXPECT_TRUE(j["exact"].is_null());
  EXPECT_TRUE(j["differences"].is_null());
  EXPECT_EQ(j["voxel"]["err"], j["err"]);
  EXPECT_EQ(j["voxel"]["states"], j["states"]);
  EXPECT_EQ(j["voxel"]["mode"], "conservative");
}

}  // namespace
}  // namespace camplace::testing
