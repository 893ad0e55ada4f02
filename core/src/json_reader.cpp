#include "camplace/core/json_reader.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

namespace camplace::core {

nlohmann::json read_json_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(path, "", "is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "cannot open the file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  // A key given twice in one object is an error (nlohmann would keep the last silently).
  std::vector<std::set<std::string>> keys;
  std::string duplicate;
  const auto check_keys = [&](int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    if (event == nlohmann::json::parse_event_t::object_start) keys.emplace_back();
    if (event == nlohmann::json::parse_event_t::object_end && !keys.empty()) keys.pop_back();
    if (event == nlohmann::json::parse_event_t::key && !keys.empty() && duplicate.empty() &&
        !keys.back().insert(parsed.get<std::string>()).second) {
      duplicate = parsed.get<std::string>();
    }
    return true;
  };
  try {
    nlohmann::json doc = nlohmann::json::parse(buffer.str(), check_keys);
    if (!duplicate.empty()) {
      throw InputError(path, "",
                       "not valid JSON: the key \"" + duplicate + "\" appears twice in one object");
    }
    return doc;
  } catch (const nlohmann::json::exception& e) {
    // parse errors, and numbers that overflow a double (e.g. 1e999, which would be inf)
    throw InputError(path, "", std::string("not valid JSON: ") + e.what());
  }
}

std::string format_number(double v) {
  char buf[64];
  for (int digits = 6; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

namespace {
std::string type_name(const nlohmann::json& v) { return v.type_name(); }
std::string escape_pointer_token(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '~')
      out += "~0";
    else if (c == '/')
      out += "~1";
    else
      out += c;
  }
  return out;
}
}  // namespace

void JsonNode::fail(const std::string& reason) const {
  throw InputError(file_, pointer_.empty() ? "/" : pointer_, reason);
}

bool JsonNode::has(const std::string& key) const {
  return value_->is_object() && value_->contains(key);
}

JsonNode JsonNode::at(const std::string& key) const {
  if (!value_->is_object()) fail("expected an object, found " + type_name(*value_));
  const auto it = value_->find(key);
  if (it == value_->end()) fail("missing required field \"" + key + "\"");
  return JsonNode(*it, file_, pointer_ + "/" + escape_pointer_token(key));
}

JsonNode JsonNode::at(std::size_t index) const {
  if (!value_->is_array()) fail("expected an array, found " + type_name(*value_));
  if (index >= value_->size()) fail("index " + std::to_string(index) + " out of range");
  return JsonNode((*value_)[index], file_, pointer_ + "/" + std::to_string(index));
}

std::size_t JsonNode::array_size() const {
  if (!value_->is_array()) fail("expected an array, found " + type_name(*value_));
  return value_->size();
}

void JsonNode::only_keys(const std::set<std::string>& allowed) const {
  if (!value_->is_object()) fail("expected an object, found " + type_name(*value_));
  for (const auto& item : value_->items()) {
    if (!allowed.count(item.key())) {
      std::string list;
      for (const auto& k : allowed) list += (list.empty() ? "" : ", ") + k;
      JsonNode(item.value(), file_, pointer_ + "/" + escape_pointer_token(item.key()))
          .fail("unknown field \"" + item.key() + "\" (expected one of: " + list + ")");
    }
  }
}

double JsonNode::number() const {
  if (!value_->is_number()) fail("expected a number, found " + type_name(*value_));
  const double v = value_->get<double>();
  if (!std::isfinite(v)) fail("number is not finite");
  return v;
}

double JsonNode::number_in(double lo, double hi) const {
  const double v = number();
  if (v < lo || v > hi) {
    fail("value " + format_number(v) + " out of range [" + format_number(lo) + ", " +
         format_number(hi) + "]");
  }
  return v;
}

int JsonNode::integer_in(int lo, int hi) const {
  if (!value_->is_number_integer()) fail("expected an integer, found " + type_name(*value_));
  if (value_->is_number_unsigned() &&
      value_->get<unsigned long long>() > static_cast<unsigned long long>(hi)) {
    fail("value " + std::to_string(value_->get<unsigned long long>()) + " out of range [" +
         std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  const auto v = value_->get<long long>();
  if (v < lo || v > hi) {
    fail("value " + std::to_string(v) + " out of range [" + std::to_string(lo) + ", " +
         std::to_string(hi) + "]");
  }
  return static_cast<int>(v);
}

std::string JsonNode::string() const {
  if (!value_->is_string()) fail("expected a string, found " + type_name(*value_));
  return value_->get<std::string>();
}

Vec3 JsonNode::vec3() const {
  if (array_size() != 3) fail("expected [x, y, z] (3 numbers)");
  return Vec3(at(std::size_t{0}).number(), at(std::size_t{1}).number(),
              at(std::size_t{2}).number());
}

}  // namespace camplace::core
