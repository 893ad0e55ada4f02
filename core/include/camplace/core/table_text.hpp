#pragma once
/// Text fields of the tables camplace writes: CSV fields as RFC 4180 quotes them and Markdown
/// table cells that cannot end the cell or the row early, so that a name holding a comma, a
/// quote, a `|` or a line break keeps its file parseable.
#include <string>
#include <vector>

namespace camplace::core {

/// `text` as one CSV field (RFC 4180): unchanged unless it holds a comma, a double quote, a
/// carriage return or a line feed (or begins or ends with a space); then in double quotes, each
/// double quote doubled.
inline std::string csv_field(const std::string& text) {
  const bool padded = !text.empty() && (text.front() == ' ' || text.back() == ' ');
  if (text.find_first_of(",\"\r\n") == std::string::npos && !padded) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

/// `text` as one cell of a Markdown (GitHub) table: `|` and `\` escaped with a backslash, line
/// breaks (CR, LF, CR LF) as `<br>`, other control characters as a space.
inline std::string md_cell(const std::string& text) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '|' || c == '\\') {
      out += '\\';
      out += c;
    } else if (c == '\r' || c == '\n') {
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
      out += "<br>";
    } else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      out += ' ';
    } else {
      out += c;
    }
  }
  return out;
}

/// `n` with its thousands grouped by commas: 7138 → "7,138", −1980 → "-1,980".
std::string thousands(long long n);

/// The records of a CSV text as RFC 4180 writes them (csv_field): fields split on commas outside
/// double quotes, `""` inside quotes read as one quote, and line breaks (LF or CR LF) inside
/// quotes kept as part of the field. A final line break ends the last record; an empty text has
/// none. Throws std::invalid_argument ("record N: ...") for a quote left open at the end, or a
/// quote inside an unquoted field or after a closing quote.
std::vector<std::vector<std::string>> csv_records(const std::string& text);

}  // namespace camplace::core
