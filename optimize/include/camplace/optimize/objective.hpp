#pragma once
/// What the optimizer minimises. The optimizer sees only this interface (STYLE: dependencies),
/// so another pipeline can stand in for the voxel one (voxel_objective.hpp).
#include <string>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/evaluation.hpp"

namespace camplace::optimize {

/// Err of a configuration and its tie-breaker: a secondary value that orders
/// configurations of equal Err, smaller is better.
struct Score {
  double err = 0.0;          ///< m² (SPEC §4)
  double tie_breaker = 0.0;  ///< dimensionless, in [0, 1]
  /// m², ≥ 0: what objective "err+touching-volume" adds to Err (touching_volume_excess()).
  double touching_excess = 0.0;
};

/// Err of a camera configuration (m², SPEC §4) with the time split of the evaluation.
/// evaluate() must be thread-safe and deterministic.
class Objective {
 public:
  virtual ~Objective() = default;
  /// Err (m²) of config (one setting per camera); writes the evaluation's time split (ms).
  virtual double evaluate(const core::CameraConfig& config, core::Timing& timing) const = 0;
  /// Err and the tie-breaker of config, as evaluate() (thread-safe, deterministic). The
  /// default has no tie-breaker: {evaluate(), 0}.
  virtual Score score(const core::CameraConfig& config, core::Timing& timing) const {
    return {evaluate(config, timing), 0.0};
  }
  /// The default optimisation tolerance for this objective (m², SPEC §4).
  virtual double default_tolerance() const = 0;
  /// A lower bound of Err over all configurations (m²); 0 when none is known.
  virtual double err_lower_bound() const { return 0.0; }
};

/// What the solvers minimise (OptimizeOptions::objective): "err" (Err alone, the paper's
/// objective), "err+volume" (Err, ties broken by the objective's tie-breaker through
/// tie_break_fitness()) or "err+touching-volume" (Err + Score::touching_excess: the states whose
/// model touches the critical objects weigh more the more of S their model fills, so that a
/// search stuck where some states' model touches the robot sees which cameras carve more).
/// Default first.
const std::vector<std::string>& objective_names();
/// The default objective: "err". "err+volume" was considered, but measured (README, "The
/// plateau and the tie-breaker") it left the plateau sooner and then converged worse with gaco,
/// the default solver (paper_basic: 0 of 3 seeds at the proven optimum in 100 s, against 20 of 20
/// with "err"), so it stays a choice.
constexpr const char* kDefaultObjective = "err";
/// One line per objective name: what it minimises.
std::string objective_help();

/// Low bits of Err's IEEE-754 double that tie_break_fitness() hands to the tie-breaker.
constexpr int kTieBreakBits = 20;

/// The one number the solvers see for (err, tie_breaker): err with its lowest
/// kTieBreakBits bits replaced by the tie-breaker quantised to 2^kTieBreakBits levels
/// (⌊t · 2^20⌋, t clamped to [0, 1], the top level shared by t = 1). For finite err ≥ 0 the
/// fitness order is exactly the lexicographic order of (err rounded down to 32 significant bits,
/// quantised tie-breaker):
/// - Err values a < b keep their order unless they lie within one block of 2^20 consecutive
///   doubles, which needs b − a < 2^-32 · b ≈ 2.3e-10 · b (b − a < 2^-1054 for subnormal b),
///   far below any tolerance; Err values that differ only by the rounding of their sums (a few
///   ulps) are tied, as they should be;
/// - equal Err values are ordered by their tie-breakers (ties within 2^-20 stay ties);
/// - the fitness is finite, ≥ 0 and within 2^-32 · err of err (0 ≤ fitness < 2^-1054 for
///   err = 0), so solvers that use the values (simulated annealing) see Err.
/// A negative, NaN or infinite err is returned unchanged (Err ≥ 0; the run refuses non-finite
/// values, problem.cpp).
double tie_break_fitness(double err, double tie_breaker);

}  // namespace camplace::optimize
