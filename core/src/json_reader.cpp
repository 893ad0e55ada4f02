#include "camplace/core/json_reader.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

namespace camplace::core {

namespace {

/// Builds the document from the parser's events, as nlohmann::json::parse does, and notes the
/// first key given twice in one object (nlohmann would keep one of the two silently). A key is
/// looked up in the object being built only, so reading takes O(n log n) for n values (a parse
/// callback cannot do that: nlohmann's callback parser rescans the parent container at each end
/// of an object, quadratic for a long array or object of objects). Iterative, like nlohmann's
/// parser: nesting depth costs heap, not stack.
class DocumentBuilder {
 public:
  using json = nlohmann::json;

  explicit DocumentBuilder(json& root) : root_(root) {}

  bool null() { return put(nullptr); }
  bool boolean(bool value) { return put(value); }
  bool number_integer(json::number_integer_t value) { return put(value); }
  bool number_unsigned(json::number_unsigned_t value) { return put(value); }
  bool number_float(json::number_float_t value, const json::string_t&) { return put(value); }
  bool string(json::string_t& value) { return put(std::move(value)); }
  bool binary(json::binary_t&) { return false; }  // only binary formats have these
  bool start_object(std::size_t) { return open(json::object()); }
  bool start_array(std::size_t) { return open(json::array()); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }
  bool key(json::string_t& name) {
    auto [it, added] = open_.back()->get_ref<json::object_t&>().emplace(std::move(name), nullptr);
    if (!added && duplicate_.empty()) duplicate_ = it->first;
    member_ = &it->second;
    return true;
  }
  bool parse_error(std::size_t, const std::string&, const json::exception& e) {
    // parse errors, and numbers that overflow a double (e.g. 1e999, which would be inf)
    error_ = e.what();
    return false;
  }

  const std::string& error() const { return error_; }
  const std::string& duplicate() const { return duplicate_; }

 private:
  /// Stores `value` where the parser is (the root, the end of an array or the member of the
  /// last key) and returns it.
  json* place(json&& value) {
    if (open_.empty()) {
      root_ = std::move(value);
      return &root_;
    }
    json& parent = *open_.back();
    if (parent.is_array()) {
      parent.push_back(std::move(value));
      return &parent.back();
    }
    *member_ = std::move(value);
    return member_;
  }
  template <class Value>
  bool put(Value&& value) {
    place(json(std::forward<Value>(value)));
    return true;
  }
  // Pointers to open containers stay valid: an array grows only at its end, after its open
  // last element is closed, and std::map never moves its elements.
  bool open(json&& container) {
    open_.push_back(place(std::move(container)));
    return true;
  }
  bool close() {
    open_.pop_back();
    return true;
  }

  json& root_;
  std::vector<json*> open_;  ///< the containers being read, outermost first
  json* member_ = nullptr;   ///< the value of the last key read
  std::string error_, duplicate_;
};

}  // namespace

nlohmann::json read_json_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(path, "", "is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "cannot open the file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse_json_text(buffer.str(), path);
}

nlohmann::json parse_json_text(const std::string& text, const std::string& name) {
  nlohmann::json doc;
  DocumentBuilder builder(doc);
  nlohmann::json::sax_parse(text, &builder);
  if (!builder.error().empty()) throw InputError(name, "", "not valid JSON: " + builder.error());
  if (!builder.duplicate().empty()) {
    throw InputError(
        name, "",
        "not valid JSON: the key \"" + builder.duplicate() + "\" appears twice in one object");
  }
  return doc;
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
