#pragma once
// CLI11 validators shared by the sub-commands: every numeric option is checked for its range
// and every enum option for its names before any work starts; a failure reads
// "error: command line: --option: reason".
#include <CLI/CLI.hpp>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>

#include "camplace/core/error.hpp"
#include "camplace/core/names.hpp"

namespace camplace::app {

/// Accepts finite numbers in [lo, hi]; the message is `reason`, by default "must lie in
/// [lo, hi]".
template <class T>
CLI::Validator in_range(T lo, T hi, std::string reason = "") {
  std::ostringstream shown;  // 6 significant digits: "[0, 1.79769e+308]", not 309 digits
  shown << "[" << lo << ", " << hi << "]";
  const std::string range = shown.str();
  if (reason.empty()) reason = "must lie in " + range;
  return CLI::Validator(
      [lo, hi, reason](std::string& input) -> std::string {
        T value{};
        if (!CLI::detail::lexical_cast(input, value)) return "not a number: \"" + input + "\"";
        if constexpr (std::is_floating_point_v<T>) {
          if (!std::isfinite(value)) return reason;
        }
        return value >= lo && value <= hi ? std::string() : reason;
      },
      range);
}

/// Accepts the names of an enum of core/names.hpp ("center", "conservative").
template <class Enum>
CLI::Validator one_of() {
  return CLI::IsMember(core::names_of<Enum>());
}

/// The enumerator named by a value that one_of<Enum>() accepted.
template <class Enum>
Enum parse_enum(const std::string& name) {
  return *core::from_name<Enum>(name);
}

/// "I/N" of --shard (study, plan): 1 ≤ I ≤ N. Throws core::OptionError naming --shard.
inline std::pair<int, int> parse_shard(const std::string& text) {
  const std::string reason =
      "must be I/N with whole numbers 1 ≤ I ≤ N (e.g. 2/8), not \"" + text + "\"";
  const std::size_t slash = text.find('/');
  const auto number = [&](const std::string& digits) {
    if (digits.empty() || digits.size() > 6 ||
        digits.find_first_not_of("0123456789") != std::string::npos) {
      throw core::OptionError("shard", reason);
    }
    return std::stoi(digits);
  };
  if (slash == std::string::npos) throw core::OptionError("shard", reason);
  const int index = number(text.substr(0, slash)), count = number(text.substr(slash + 1));
  if (index < 1 || index > count) throw core::OptionError("shard", reason);
  return {index, count};
}

}  // namespace camplace::app
