#pragma once
// Typed, checked access to a JSON document: every failure throws InputError naming the file,
// the JSON pointer of the entry and the reason.
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "camplace/core/error.hpp"
#include "camplace/core/geometry.hpp"

namespace camplace::core {

/// Reads and parses a JSON file; InputError when it cannot be read or is not JSON.
nlohmann::json read_json_file(const std::string& path);
/// Parses JSON text as read_json_file parses a file's content (a key given twice in one object
/// is an error); InputError naming `name` (the text's source, e.g. "request") when it is not
/// JSON.
nlohmann::json parse_json_text(const std::string& text, const std::string& name);

/// The shortest decimal text that reads back as exactly v (for messages: 180.0001 stays
/// 180.0001, not 180).
std::string format_number(double v);

/// A JSON value together with where it is (file and pointer).
class JsonNode {
 public:
  JsonNode(const nlohmann::json& value, std::string file, std::string pointer)
      : value_(&value), file_(std::move(file)), pointer_(std::move(pointer)) {}

  const nlohmann::json& value() const { return *value_; }
  const std::string& file() const { return file_; }
  const std::string& pointer() const { return pointer_; }
  [[noreturn]] void fail(const std::string& reason) const;

  bool has(const std::string& key) const;
  JsonNode at(const std::string& key) const;  ///< required member
  JsonNode at(std::size_t index) const;
  std::size_t array_size() const;  ///< fails unless an array
  /// Fails naming the first member not in `allowed` (catches typos such as "plausability").
  void only_keys(const std::set<std::string>& allowed) const;

  bool is_string() const { return value_->is_string(); }
  bool is_object() const { return value_->is_object(); }
  double number() const;  ///< finite number
  double number_in(double lo, double hi) const;
  int integer_in(int lo, int hi) const;
  std::string string() const;
  Vec3 vec3() const;  ///< [x, y, z] of finite numbers

 private:
  const nlohmann::json* value_;
  std::string file_, pointer_;
};

}  // namespace camplace::core
