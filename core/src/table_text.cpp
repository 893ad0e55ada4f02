#include "camplace/core/table_text.hpp"

#include <stdexcept>

namespace camplace::core {

std::string thousands(long long n) {
  std::string digits = std::to_string(n < 0 ? -(n + 1) + 1ull : static_cast<unsigned long long>(n));
  for (int i = static_cast<int>(digits.size()) - 3; i > 0; i -= 3) digits.insert(i, ",");
  return n < 0 ? "-" + digits : digits;
}

std::vector<std::vector<std::string>> csv_records(const std::string& text) {
  std::vector<std::vector<std::string>> records;
  std::vector<std::string> record;
  std::string field;
  // Where the scanner is in the current field: before its first character, inside an unquoted
  // field, inside quotes, or just after the closing quote.
  enum class At { start, plain, quoted, closed } at = At::start;
  auto fail = [&](const std::string& why) {
    throw std::invalid_argument("record " + std::to_string(records.size() + 1) + ": " + why);
  };
  auto end_record = [&] {
    record.push_back(std::move(field));
    field.clear();
    records.push_back(std::move(record));
    record.clear();
    at = At::start;
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (at == At::quoted) {
      if (c != '"') {
        field += c;
      } else if (i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else {
        at = At::closed;
      }
      continue;
    }
    if (c == ',') {
      record.push_back(std::move(field));
      field.clear();
      at = At::start;
    } else if (c == '\n' || (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n')) {
      if (c == '\r') ++i;
      end_record();
    } else if (c == '"') {
      if (at != At::start) fail("a double quote inside a field that is not quoted as a whole");
      at = At::quoted;
    } else {
      if (at == At::closed) fail("text after a field's closing double quote");
      field += c;
      at = At::plain;
    }
  }
  if (at == At::quoted) fail("a double quote is not closed before the end of the file");
  if (at != At::start || !record.empty() || !field.empty()) end_record();
  return records;
}

}  // namespace camplace::core
