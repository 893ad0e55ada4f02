// The sizes of a scene's lists are bounded (each refusal names the limit), and the keep-out
// check at load stays fast at the limit: the boxes' number no longer buys minutes of work.
#include <gtest/gtest.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "camplace/core/error.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/core/table_text.hpp"
#include "scene_builder.hpp"
#include "scene_fixtures.hpp"

namespace camplace::testing {
namespace {

using nlohmann::json;

std::string write_scene(const json& scene, const std::string& name) {
  return write_file(temp_dir("limits-" + name) + "/scene.json", scene.dump());
}

/// 32 keep-out boxes: one over the middle of the room [1, 3]×[1, 2]×[1, 2], the others small
/// cubes in a row along the floor's edge y ∈ [2.8, 2.9].
json boxes(int n) {
  json list = json::array();
  list.push_back({{"min", {1, 1, 1}}, {"max", {3, 2, 2}}});
  for (int i = 1; i < n; ++i) {
    const double x = 0.1 * i;
    list.push_back({{"min", {x, 2.8, 0.1}}, {"max", {x + 0.05, 2.9, 0.15}}});
  }
  return list;
}

TEST(SceneLimits, EveryListIsBoundedAndTheRefusalNamesTheLimit) {
  json s = base_scene();
  s["cameras"]["keep_out"] = boxes(33);
  expect_rejected(write_scene(s, "keep-out"), "/cameras/keep_out",
                  "at most 32 keep-out boxes, found 33");
  s = base_scene();
  json mounts = json::array();
  for (int i = 0; i < 257; ++i) {
    mounts.push_back({{"name", "m" + std::to_string(i)},
                      {"corner", {0, 0, 3}},
                      {"edges", {{1, 0, 0}, {0, 1, 0}}}});
  }
  s["cameras"]["mounts"] = mounts;
  expect_rejected(write_scene(s, "mounts"), "/cameras/mounts", "at most 256 mounts, found 257");
  s = base_scene();
  s["static_obstacles"] = json::array();
  for (int i = 0; i < 10001; ++i) {
    s["static_obstacles"].push_back({{"box", {{"min", {0, 0, 0}}, {"max", {0.1, 0.1, 0.1}}}}});
  }
  expect_rejected(write_scene(s, "objects"), "/static_obstacles",
                  "at most 10000 objects in one list, found 10001");
  s = base_scene();
  const json event = s["time_steps"][0]["events"][0];
  s["time_steps"][0]["events"] = json::array();
  for (int i = 0; i < 1001; ++i) s["time_steps"][0]["events"].push_back(event);
  expect_rejected(write_scene(s, "events"), "/time_steps/0/events", "at most 1000 events");
  s = base_scene();
  s["time_steps"] = json::array();
  for (int i = 0; i < 100001; ++i) s["time_steps"].push_back(json::object());
  expect_rejected(write_scene(s, "steps"), "/time_steps",
                  "at most 100000 time steps, found 100001");
}

TEST(SceneLimits, TheKeepOutCheckAtTheLimitTakesMilliseconds) {
  // 20 cameras, each with its own box domain (the check runs once per distinct domain), and
  // the middle of each domain blocked, so that each check must search for a free point. It
  // tried every triple of the 6 + 6·32 planes: 0.46 s per domain, 9 s here.
  json s = base_scene();
  s["cameras"]["count"] = 20;
  s["cameras"]["keep_out"] = boxes(32);
  s["cameras"]["camera_domains"] = json::array();
  for (int i = 0; i < 20; ++i) {
    s["cameras"]["camera_domains"].push_back(
        {{"x", {0, 4 - 0.01 * i}}, {"y", {0, 3}}, {"z", {0, 3}}});
  }
  const std::string path = write_scene(s, "keep-out-time");
  const auto start = std::chrono::steady_clock::now();
  const core::Scene scene = core::load_scene(path);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 2.0);
  ASSERT_EQ(scene.cameras.keep_out.size(), 32u);
  // The nearest free point to (1.9, 1.4, 1.45) in the middle box: its face y = 1, 0.4 away
  // (x = 1 is 0.9 away, z = 1 0.45).
  const auto q = core::keep_out_repair(scene.cameras.domains[0], scene.cameras.keep_out,
                                       core::Vec3(1.9, 1.4, 1.45));
  ASSERT_TRUE(q);
  EXPECT_EQ(*q, core::Vec3(1.9, 1, 1.45));
  // Every domain covered: refused naming the first camera's domain.
  s["cameras"]["keep_out"].push_back({{"min", {-1, -1, -1}}, {"max", {5, 4, 4}}});
  s["cameras"]["keep_out"].erase(1);
  expect_rejected(write_scene(s, "keep-out-covered"), "/cameras/camera_domains/0",
                  "cover the whole placement domain of camera 0");
}

TEST(TableText, CsvFieldsAreQuotedAsRfc4180Says) {
  EXPECT_EQ(core::csv_field("cameras"), "cameras");
  EXPECT_EQ(core::csv_field(""), "");
  EXPECT_EQ(core::csv_field("a,b"), "\"a,b\"");
  EXPECT_EQ(core::csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(core::csv_field("two\nlines"), "\"two\nlines\"");
  EXPECT_EQ(core::csv_field("cr\r"), "\"cr\r\"");
  EXPECT_EQ(core::csv_field(" padded"), "\" padded\"");
}

TEST(TableText, ThousandsAreGroupedByCommas) {
  EXPECT_EQ(core::thousands(0), "0");
  EXPECT_EQ(core::thousands(999), "999");
  EXPECT_EQ(core::thousands(1000), "1,000");
  EXPECT_EQ(core::thousands(7138), "7,138");
  EXPECT_EQ(core::thousands(-1980), "-1,980");
  EXPECT_EQ(core::thousands(1234567890123LL), "1,234,567,890,123");
  EXPECT_EQ(core::thousands(-9223372036854775807LL - 1), "-9,223,372,036,854,775,808");
}

TEST(TableText, CsvRecordsReadBackEveryFieldTheWriterQuotes) {
  // Every awkward field, written by csv_field, comes back as it was (the records by hand).
  const std::vector<std::string> fields = {"plain",    "",        "a,b", "say \"hi\"", "two\nlines",
                                           "cr\r\nlf", " padded", "\"",  ",\n,"};
  std::string text;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    text += (i == 0 ? "" : ",") + core::csv_field(fields[i]);
  }
  text += "\nlast,row\r\n";
  const auto records = core::csv_records(text);
  ASSERT_EQ(records.size(), 2u);
  EXPECT_EQ(records[0], fields);
  EXPECT_EQ(records[1], (std::vector<std::string>{"last", "row"}));
  // No final line break; an empty text; an empty record.
  EXPECT_EQ(core::csv_records("a,b"), (std::vector<std::vector<std::string>>{{"a", "b"}}));
  EXPECT_TRUE(core::csv_records("").empty());
  EXPECT_EQ(core::csv_records("\n"), (std::vector<std::vector<std::string>>{{""}}));
}

TEST(TableText, CsvRecordsRefuseADamagedText) {
  auto message = [](const std::string& text) {
    try {
      core::csv_records(text);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message("a,b\nc,\"open"),
            "record 2: a double quote is not closed before the end of the file");
  EXPECT_EQ(message("a,b\"c"),
            "record 1: a double quote inside a field that is not quoted as a whole");
  EXPECT_EQ(message("\"a\"b,c"), "record 1: text after a field's closing double quote");
}

TEST(TableText, MarkdownCellsCannotEndTheCellOrTheRow) {
  EXPECT_EQ(core::md_cell("plain"), "plain");
  EXPECT_EQ(core::md_cell("a|b"), "a\\|b");
  EXPECT_EQ(core::md_cell("back\\slash"), "back\\\\slash");
  EXPECT_EQ(core::md_cell("two\nlines\r\nthree\rfour"), "two<br>lines<br>three<br>four");
  EXPECT_EQ(core::md_cell(std::string("tab\tnul") + '\0' + "x"), "tab nul x");
}

}  // namespace
}  // namespace camplace::testing
