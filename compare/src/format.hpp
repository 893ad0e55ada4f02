#pragma once
// Number and resolution formatting shared by the reports (fixed digits, so reruns are
// byte-identical). Private to compare.
#include <array>
#include <cstdio>
#include <string>

namespace camplace::compare::detail {

/// v with a fixed number of decimals ("%.*f").
inline std::string num(double v, int digits = 6) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

/// "NXxNYxNZ".
inline std::string resolution_text(const std::array<int, 3>& n) {
  return std::to_string(n[0]) + "x" + std::to_string(n[1]) + "x" + std::to_string(n[2]);
}

}  // namespace camplace::compare::detail
