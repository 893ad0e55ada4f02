#pragma once
// Checks of the provenance header every report starts with, against values
// computed here independently of camplace: the SHA-256 by `sha256sum`, the host name by
// gethostname(2).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <regex>
#include <string>

#include "camplace/core/provenance.hpp"

namespace camplace::testing {

/// `sha256sum FILE`'s digest (64 hex digits), "" when it cannot run.
inline std::string sha256sum(const std::string& path) {
  FILE* pipe = popen(("sha256sum '" + path + "'").c_str(), "r");
  if (!pipe) return "";
  char buffer[65] = {0};
  const std::size_t n = std::fread(buffer, 1, 64, pipe);
  pclose(pipe);
  return std::string(buffer, n);
}

/// The report starts with `title`, then the header: camplace version and commit, the scene file
/// `scene` (as the report names it, on disk at `scene_on_disk`) with the first 12 digits of its
/// SHA-256 and, in the details, all 64; the options (containing `option`), the host and a start
/// time in ISO 8601.
inline void expect_provenance_header(const std::string& report, const std::string& title,
                                     const std::string& scene, const std::string& scene_on_disk,
                                     const std::string& option) {
  EXPECT_EQ(report.rfind(title + "\n\n| provenance | |\n|---|---|\n", 0), 0u) << report;
  EXPECT_NE(report.find("| camplace | " + core::build_info().version + ", commit `" +
                        core::build_info().commit + "` |"),
            std::string::npos)
      << report;
  const std::string digest = sha256sum(scene_on_disk);
  ASSERT_EQ(digest.size(), 64u);
  EXPECT_NE(report.find("`" + scene + "`, SHA-256 `" + digest.substr(0, 12) + "…`"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("| `" + scene + "` | " + digest + " |"), std::string::npos) << report;
  const std::size_t options = report.find("| options | ");
  ASSERT_NE(options, std::string::npos) << report;
  EXPECT_NE(report.substr(options, report.find('\n', options) - options).find(option),
            std::string::npos)
      << report;
  char host[256] = {0};
  gethostname(host, sizeof host - 1);
  EXPECT_NE(report.find("| host | " + std::string(host) + " |"), std::string::npos) << report;
  EXPECT_TRUE(std::regex_search(
      report, std::regex(R"(\| started \| \d{4}-\d\d-\d\dT\d\d:\d\d:\d\d[+-]\d{4} \|)")))
      << report;
}

}  // namespace camplace::testing
