// Structural pre-scan of mesh files, run before CGAL's readers. CGAL trusts the counts in a
// file (a PLY list count of 4e9 makes it allocate and loop for ever, an OFF face count of 4e9
// makes it allocate 32 GB) and turns bad numbers into vague failures or silent truncation
// ("2.5" read as 2). Here every count is checked against the data actually present, and
// indices and coordinates are checked as text, so the reason can name the element.
// Plain C++ (no CGAL) so that it stays out of the heavy mesh_checks.cpp translation unit.
#include "mesh_file_scan.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace camplace::core::detail {

namespace {

using std::to_string;

std::optional<std::uint64_t> parse_unsigned(std::string_view s) {
  std::uint64_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec == std::errc::result_out_of_range && end == s.data() + s.size()) return UINT64_MAX;
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

// A token that is a number (strtod reads all of it) but not a finite one: nan, inf, 1e400.
bool is_non_finite_number(const std::string& s) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && !s.empty() && !std::isfinite(v);
}

std::vector<std::string> split(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> tokens;
  for (std::string t; in >> t;) tokens.push_back(t);
  return tokens;
}

// Checks a face's vertex index token (OFF, PLY ascii): a non-negative integer below `vertices`.
std::optional<std::string> index_defect(const std::string& what, const std::string& token,
                                        std::uint64_t vertices) {
  const std::optional<std::uint64_t> v = parse_unsigned(token);
  if (!v) return what + ": vertex index \"" + token + "\" is not a non-negative integer";
  if (*v >= vertices) {
    return what + ": vertex index " + token + " is out of range (the file has " +
           to_string(vertices) + " vertices)";
  }
  return std::nullopt;
}

// --- OFF (ascii). Vertices and faces are one per line, as CGAL's File_scanner_OFF reads them.
std::optional<std::string> off_defect(const std::string& text) {
  std::vector<std::vector<std::string>> lines;  // non-empty lines, '#' comments removed
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> tokens = split(line.substr(0, line.find('#')));
    if (!tokens.empty()) lines.push_back(std::move(tokens));
  }
  if (lines.empty()) return std::nullopt;
  const std::string keyword = lines[0][0];
  if (lines[0].size() > 1 && lines[0][1] == "BINARY") {
    // CGAL 5.5 reads the per-face colour count of binary OFF as the next face's vertex count,
    // so standard files fail, and it trusts the 32-bit counts (up to 16 GB allocated).
    return "binary OFF is not supported (convert the file to ascii OFF, PLY or STL)";
  }
  // n-dimensional variants are left to CGAL (its header checks still apply).
  if (keyword.find("OFF") == std::string::npos || keyword.find('n') != std::string::npos) {
    return std::nullopt;
  }
  std::size_t next = 1;
  std::vector<std::string> counts(lines[0].begin() + 1, lines[0].end());
  if (counts.empty() && next < lines.size()) counts = lines[next++];
  if (counts.size() < 2) return std::nullopt;
  const std::optional<std::uint64_t> nv = parse_unsigned(counts[0]), nf = parse_unsigned(counts[1]);
  if (!nv || !nf) return std::nullopt;
  const std::uint64_t available = lines.size() - next;
  if (*nv > available || *nf > available - *nv) {
    return "OFF header announces " + counts[0] + " vertices and " + counts[1] +
           " faces but the file has only " + to_string(available) + " lines of data";
  }
  const int coords = keyword.find('4') != std::string::npos ? 4 : 3;
  for (std::uint64_t v = 0; v < *nv; ++v) {
    const std::vector<std::string>& tokens = lines[next + v];
    for (std::size_t k = 0; k < tokens.size() && k < std::size_t(coords); ++k) {
      if (is_non_finite_number(tokens[k]))
        return "vertex " + to_string(v) + " has a non-finite coordinate";
    }
  }
  for (std::uint64_t f = 0; f < *nf; ++f) {
    const std::vector<std::string>& tokens = lines[next + *nv + f];
    const std::string what = "OFF face " + to_string(f);
    const std::optional<std::uint64_t> n = parse_unsigned(tokens[0]);
    if (!n) return what + ": vertex count \"" + tokens[0] + "\" is not a non-negative integer";
    if (*n > tokens.size() - 1) {
      return what + ": vertex count " + tokens[0] + " exceeds the " + to_string(tokens.size() - 1) +
             " numbers on its line";
    }
    for (std::size_t j = 1; j <= *n; ++j) {
      if (auto defect = index_defect(what, tokens[j], *nv)) return defect;
    }
  }
  return std::nullopt;
}

// --- OBJ: only what CGAL reads vaguely (non-finite vertices, non-integer or huge indices).
std::optional<std::string> obj_defect(const std::string& text) {
  std::istringstream in(text);
  std::uint64_t vertices = 0, faces = 0;
  // The largest absolute index and its face; checked at the end, as vertices may come later.
  long long largest = 0;
  std::uint64_t largest_face = 0;
  for (std::string line; std::getline(in, line);) {
    const std::vector<std::string> tokens = split(line.substr(0, line.find('#')));
    if (tokens.empty()) continue;
    if (tokens[0] == "v") {
      for (std::size_t k = 1; k < tokens.size() && k <= 3; ++k) {
        if (is_non_finite_number(tokens[k]))
          return "vertex " + to_string(vertices) + " has a non-finite coordinate";
      }
      ++vertices;
    } else if (tokens[0] == "f") {
      for (std::size_t j = 1; j < tokens.size(); ++j) {
        const std::string index = tokens[j].substr(0, tokens[j].find('/'));
        long long v = 0;
        const auto [end, ec] = std::from_chars(index.data(), index.data() + index.size(), v);
        const std::string what = "OBJ face " + to_string(faces) + ": vertex index ";
        if (ec == std::errc::result_out_of_range) return what + index + " is out of range";
        if (ec != std::errc() || end != index.data() + index.size()) {
          return what + "\"" + index + "\" is not an integer";
        }
        if (v == 0 || (v < 0 && std::uint64_t(-(v + 1)) >= vertices))
          return what + index + " is out of range";
        if (v > largest) largest = v, largest_face = faces;
      }
      ++faces;
    }
  }
  if (std::uint64_t(largest) > vertices) {
    return "OBJ face " + to_string(largest_face) + ": vertex index " + to_string(largest) +
           " is out of range (the file has " + to_string(vertices) + " vertices)";
  }
  return std::nullopt;
}

// --- PLY: header, then a walk over the body checking every count against the data left.
struct PlyType {
  int size = 0;  // bytes in the binary formats
  bool integer = false, is_signed = false;
};

std::optional<PlyType> ply_type(const std::string& name) {
  static const std::map<std::string, PlyType> types = {
      {"char", {1, true, true}},    {"int8", {1, true, true}},     {"uchar", {1, true, false}},
      {"uint8", {1, true, false}},  {"short", {2, true, true}},    {"int16", {2, true, true}},
      {"ushort", {2, true, false}}, {"uint16", {2, true, false}},  {"int", {4, true, true}},
      {"int32", {4, true, true}},   {"uint", {4, true, false}},    {"uint32", {4, true, false}},
      {"float", {4, false, true}},  {"float32", {4, false, true}}, {"double", {8, false, true}},
      {"float64", {8, false, true}}};
  const auto it = types.find(name);
  if (it == types.end()) return std::nullopt;
  return it->second;
}

struct PlyProperty {
  std::string name;
  PlyType type;                       // the scalar, or the list items
  std::optional<PlyType> list_count;  // set for lists
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

// Reads a binary integer of `type` at `p`; false if it is negative.
bool read_binary_count(const char* p, const PlyType& type, bool big_endian, std::uint64_t& out) {
  std::uint64_t v = 0;
  for (int i = 0; i < type.size; ++i) {
    const auto byte = static_cast<unsigned char>(p[big_endian ? i : type.size - 1 - i]);
    v = (v << 8) | byte;
  }
  const std::uint64_t sign_bit = std::uint64_t(1) << (8 * type.size - 1);
  if (type.is_signed && (v & sign_bit)) return false;
  out = v;
  return true;
}

std::optional<std::string> ply_defect(const std::string& text) {
  const std::size_t header_end = text.find("end_header");
  const std::size_t body = text.find('\n', header_end);
  if (text.rfind("ply", 0) != 0 || header_end == std::string::npos || body == std::string::npos) {
    return "PLY file has no \"ply\" ... \"end_header\" header";
  }
  std::string format, line;
  std::vector<PlyElement> elements;
  std::istringstream header(text.substr(0, header_end));
  std::getline(header, line);  // "ply"
  while (std::getline(header, line)) {
    const std::vector<std::string> t = split(line);
    if (t.empty() || t[0] == "comment" || t[0] == "obj_info") continue;
    if (t[0] == "format" && t.size() >= 2) {
      format = t[1];
    } else if (t[0] == "element" && t.size() == 3) {
      const std::optional<std::uint64_t> count = parse_unsigned(t[2]);
      if (!count)
        return "PLY element " + t[1] + ": count \"" + t[2] + "\" is not a non-negative integer";
      elements.push_back({t[1], *count, {}});
    } else if (t[0] == "property" && !elements.empty() && t.size() == 3 && ply_type(t[1])) {
      elements.back().properties.push_back({t[2], *ply_type(t[1]), std::nullopt});
    } else if (t[0] == "property" && !elements.empty() && t.size() == 5 && t[1] == "list" &&
               ply_type(t[2]) && ply_type(t[2])->integer && ply_type(t[3])) {
      elements.back().properties.push_back({t[4], *ply_type(t[3]), ply_type(t[2])});
    } else {
      return "PLY header line \"" + line + "\" is not understood";
    }
  }
  const bool ascii = format == "ascii";
  if (!ascii && format != "binary_little_endian" && format != "binary_big_endian") {
    return "PLY format \"" + format + "\" is not ascii, binary_little_endian or binary_big_endian";
  }
  std::vector<std::string> tokens;
  if (ascii) tokens = split(text.substr(body + 1));
  // Data left: tokens in ascii, bytes in binary. Every element instance takes at least one.
  std::uint64_t pos = ascii ? 0 : body + 1;
  const std::uint64_t end = ascii ? tokens.size() : text.size();
  std::uint64_t vertices = 0;
  for (const PlyElement& e : elements) {
    std::uint64_t min_size = 0;
    for (const PlyProperty& p : e.properties) {
      min_size += ascii ? 1 : (p.list_count ? p.list_count->size : p.type.size);
    }
    if (min_size == 0 && e.count > 0) return "PLY element " + e.name + " has no properties";
    if (e.count > 0 && e.count > (end - pos) / min_size) {
      return "PLY element " + e.name + ": count " + to_string(e.count) +
             " exceeds the data in the file";
    }
    if (e.name == "vertex") vertices = e.count;
    for (std::uint64_t i = 0; i < e.count; ++i) {
      const std::string what = "PLY " + e.name + " " + to_string(i);
      for (const PlyProperty& p : e.properties) {
        if (pos >= end || (!ascii && end - pos < std::uint64_t(p.list_count ? p.list_count->size
                                                                            : p.type.size))) {
          return what + ": the file ends inside the element";
        }
        if (!p.list_count) {
          const bool xyz = p.name == "x" || p.name == "y" || p.name == "z";
          if (ascii && e.name == "vertex" && xyz && is_non_finite_number(tokens[pos])) {
            return "vertex " + to_string(i) + " has a non-finite coordinate";
          }
          pos += ascii ? 1 : p.type.size;
          continue;
        }
        std::uint64_t n = 0;
        if (ascii) {
          const std::optional<std::uint64_t> count = parse_unsigned(tokens[pos]);
          if (!count)
            return what + ": list count \"" + tokens[pos] + "\" is not a non-negative integer";
          n = *count;
          pos += 1;
        } else {
          if (!read_binary_count(text.data() + pos, *p.list_count, format == "binary_big_endian",
                                 n)) {
            return what + ": list count is negative";
          }
          pos += p.list_count->size;
        }
        const std::uint64_t item = ascii ? 1 : p.type.size;
        if (n > (end - pos) / item)
          return what + ": list count " + to_string(n) + " exceeds the data in the file";
        if (ascii && e.name == "face" && p.type.integer) {
          for (std::uint64_t j = 0; j < n; ++j) {
            if (auto defect = index_defect(what, tokens[pos + j], vertices)) return defect;
          }
        }
        pos += n * item;
      }
    }
  }
  return std::nullopt;
}

}  // namespace

/// Why the mesh file at `path` (format given by `ext`, lower case with the dot) cannot be read
/// safely, or nothing when its structure is sound. STL is left to CGAL, which checks its
/// triangle count against the file size.
std::optional<std::string> mesh_file_defect(const std::string& path, const std::string& ext) {
  if (ext != ".off" && ext != ".obj" && ext != ".ply") return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  std::ostringstream content;
  content << in.rdbuf();
  const std::string text = content.str();
  if (ext == ".off") return off_defect(text);
  if (ext == ".obj") return obj_defect(text);
  return ply_defect(text);
}

}  // namespace camplace::core::detail
