#include "camplace/optimize/objective.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace camplace::optimize {

const std::vector<std::string>& objective_names() {
  static const std::vector<std::string> names = {"err", "err+volume", "err+touching-volume"};
  return names;
}

std::string objective_help() {
  return "  err         Err alone (the paper's objective), default\n"
         "  err+volume  Err; on the plateau where the model touches the critical objects in every\n"
         "              state, ties of Err ordered by the model's volume (smaller first)\n"
         "  err+touching-volume  Err, plus for each state whose model touches the critical\n"
         "              objects (d_model = 0) its term ω·d_true² once more, scaled by the "
         "fraction\n"
         "              of S its model fills: where some states' model touches the robot whatever\n"
         "              the cameras, the solver still sees which cameras carve more of it\n";
}

double tie_break_fitness(double err, double tie_breaker) {
  static_assert(sizeof(double) == sizeof(std::uint64_t) && std::numeric_limits<double>::is_iec559,
                "tie_break_fitness needs IEEE-754 binary64 doubles");
  static_assert(kTieBreakBits > 0 && kTieBreakBits < 52, "the tie-breaker lives in the mantissa");
  if (!(err >= 0.0) || !std::isfinite(err)) return err;
  // Why the order is lexicographic (objective.hpp): for finite doubles x, y ≥ +0, x < y exactly
  // when their bit patterns, read as unsigned integers, satisfy bits(x) < bits(y) (IEEE 754:
  // sign 0, then the biased exponent, then the mantissa; subnormals and +0 included). Replacing
  // the lowest k = kTieBreakBits bits of bits(err) by q < 2^k gives the integer
  // (bits(err) >> k) · 2^k + q, whose order is the lexicographic order of (bits(err) >> k, q);
  // bits(err) >> k is non-decreasing in err, so Err values in different blocks of 2^k
  // consecutive doubles keep their order whatever their q. Only mantissa bits change (k < 52),
  // so the exponent, hence finiteness, sign and magnitude within 2^(k−52) relative, stay.
  err += 0.0;  // −0 → +0, whose sign bit is clear
  const double t = std::isnan(tie_breaker) ? 1.0 : std::clamp(tie_breaker, 0.0, 1.0);
  constexpr std::uint64_t kLevels = std::uint64_t{1} << kTieBreakBits;
  const std::uint64_t q =
      std::min(static_cast<std::uint64_t>(t * static_cast<double>(kLevels)), kLevels - 1);
  std::uint64_t bits = 0;
  std::memcpy(&bits, &err, sizeof bits);
  bits = (bits & ~(kLevels - 1)) | q;
  double fitness = 0.0;
  std::memcpy(&fitness, &bits, sizeof fitness);
  return fitness;
}

}  // namespace camplace::optimize
