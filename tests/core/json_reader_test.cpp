// Reading JSON files (core::read_json_file): the document read is the one nlohmann::json::parse
// gives, and a key twice in one object is refused at any depth.
#include "camplace/core/json_reader.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "camplace/core/error.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using nlohmann::json;

/// The message of the InputError read_json_file throws for `text` ("" when it reads it).
std::string reading_error(const std::string& text, const std::string& name) {
  const std::string path = write_file(temp_dir("json-" + name) + "/f.json", text);
  try {
    core::read_json_file(path);
  } catch (const core::InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.entry(), "");
    return e.reason();
  }
  return "";
}

TEST(JsonReading, GivesTheDocumentNlohmannParses) {
  const std::string text = R"({"b": [1, -2, 18446744073709551615, 2.5e-3, 1e300, "s\u00e9\n",
    true, false, null, [], {}, [[{"z": {"y": []}}]]], "a": {"k": "v", "e": {}}, "": 0,
    "h\u00e4nel": "x"})";
  const std::string path = write_file(temp_dir("json-same") + "/f.json", text);
  const json read = core::read_json_file(path);
  EXPECT_EQ(read, json::parse(text));
  EXPECT_TRUE(read["b"][2].is_number_unsigned());
  EXPECT_TRUE(read["b"][1].is_number_integer());
  EXPECT_EQ(core::read_json_file(write_file(temp_dir("json-scalar") + "/f.json", " 7 ")), json(7));
}

TEST(JsonReading, KeyTwiceInOneObjectIsRefusedAtEveryDepth) {
  const std::string twice = "not valid JSON: the key \"area\" appears twice in one object";
  EXPECT_EQ(reading_error(R"({"area": 1, "voxels": 2, "area": 3})", "root"), twice);
  EXPECT_EQ(reading_error(R"({"a": {"b": 1, "c": {"area": 1, "area": {}}}})", "nested"), twice);
  EXPECT_EQ(
      reading_error(R"({"a": [1, {"x": 0}, {"area": 1, "b": 2, "area": 3}], "c": 4})", "in_array"),
      twice);
  std::string deep = R"({"area": 0, "d": )";
  for (int i = 0; i < 200; ++i) deep += i % 2 ? "[" : R"({"k": )";
  deep += R"({"area": [], "area": null})";
  for (int i = 199; i >= 0; --i) deep += i % 2 ? "]" : "}";
  EXPECT_EQ(reading_error(deep + "}", "deep"), twice);
  // The first key given twice in the file is named.
  EXPECT_EQ(reading_error(R"({"x": {"area": 1, "area": 2}, "voxels": 1, "voxels": 2})", "first"),
            twice);
  // A malformed file is reported as such even when a key came twice before the error.
  EXPECT_EQ(
      reading_error(R"({"area": 1, "area": 2, )", "broken")
          .rfind(
              "not valid JSON: [json.exception.parse_error.101] parse error at line 1, column 24",
              0),
      0u);
  EXPECT_EQ(reading_error(R"({"area": 1, "area": 1e999})", "overflow"),
            "not valid JSON: [json.exception.out_of_range.406] number overflow parsing '1e999'");
  // The same key in other objects (siblings, parent and child) is no repetition.
  EXPECT_EQ(reading_error(R"({"area": {"area": 1}, "b": [{"area": 1}, {"area": {"area": 2}}]})",
                          "siblings"),
            "");
}

}  // namespace
}  // namespace camplace::testing
