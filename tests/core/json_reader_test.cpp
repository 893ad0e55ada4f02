// Reading JSON files (core::read_json_file) and the messages of bad input: the document read is
// the one nlohmann::json::parse gives, a key twice in one object is refused at any depth, and a
// key, name or path holding control characters cannot cut or split an error line.
#include "camplace/core/json_reader.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "camplace/core/error.hpp"
#include "scene_builder.hpp"
#include "scene_fixtures.hpp"

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

TEST(ErrorMessages, ControlCharactersAreEscapedSoTheMessageStaysOneLine) {
  const core::InputError e("dir/a\tb.json", std::string("/x\0y", 4), "key \"\n\r\b\f\x1f\x7f\"");
  EXPECT_EQ(std::string(e.what()),
            "dir/a\\tb.json: /x\\u0000y: key \"\\n\\r\\b\\f\\u001f\\u007f\"");
  EXPECT_EQ(e.file(), "dir/a\\tb.json");
  EXPECT_EQ(e.entry(), "/x\\u0000y");
  EXPECT_EQ(e.reason(), "key \"\\n\\r\\b\\f\\u001f\\u007f\"");
  // Printable text, backslashes and UTF-8 stay as they are.
  EXPECT_STREQ(core::InputError("H\xc3\xa4nel.json", "/a~1b", "C:\\x \"q\"").what(),
               "H\xc3\xa4nel.json: /a~1b: C:\\x \"q\"");
  // A reason's indented continuation lines stay lines; a break before anything else is escaped.
  EXPECT_STREQ(core::InputError("f", "", "two settings differ:\n  a: 1 → 2\nerror: x").what(),
               "f: two settings differ:\n  a: 1 → 2\\nerror: x");
  // An error made from another's reason is not escaped twice.
  EXPECT_EQ(core::OptionError("o", e.reason()).reason(), e.reason());
}

TEST(ErrorMessages, KeysAndNamesWithControlCharactersAreEscapedInSceneErrors) {
  json s = base_scene();
  s[std::string("plaus\0ibility", 13)] = json::object();
  std::string path = write_file(temp_dir("ctl-nul") + "/s.json", s.dump());
  try {
    core::load_scene(path);
    ADD_FAILURE() << "accepted a key with a NUL";
  } catch (const core::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ": /plaus\\u0000ibility: unknown field "
                                                 "\"plaus\\u0000ibility\" (expected one of: ",
                                          0),
              0u)
        << e.what();
  }
  s = base_scene();
  s["x\nerror: forged"] = json::object();
  expect_rejected(write_file(temp_dir("ctl-line") + "/s.json", s.dump()), "/x\\nerror: forged",
                  "unknown field \"x\\nerror: forged\"");
  s = base_scene();
  s["time_steps"][0]["events"][0]["targets"][0]["name"] = "per\nson";
  s["time_steps"][0]["events"][0]["targets"][0]["box"]["max"] = {2.4, 0.9, 3.5};
  expect_rejected(write_file(temp_dir("ctl-name") + "/s.json", s.dump()),
                  "/time_steps/0/events/0/targets/0", "target \"per\\nson\" leaves the area S");
  path = temp_dir("ctl-path") + "/no\nfile.json";
  try {
    core::load_scene(path);
    ADD_FAILURE() << "read a missing file";
  } catch (const core::InputError& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no\\nfile.json: cannot open the file"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace camplace::testing
