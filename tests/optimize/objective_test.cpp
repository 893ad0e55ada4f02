// The tie-breaker: tie_break_fitness() orders (Err, tie-breaker) lexicographically,
// checked against an independent reference (Err rounded down to 32 significant bits with
// std::ldexp/std::floor, the tie-breaker quantised by hand), and volume_fraction() against
// volumes computed by hand.
#include "camplace/optimize/objective.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "camplace/core/evaluation.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/optimize/encoding.hpp"
#include "camplace/optimize/voxel_objective.hpp"

namespace camplace::optimize {
namespace {

// The reference: err rounded down to a multiple of 2^(e − 32) for a normal err in [2^e, 2^(e+1)),
// of 2^-1054 for a subnormal one (its spacing 2^-1074 times 2^20); the tie-breaker quantised to
// ⌊t · 2^20⌋, at most 2^20 − 1. Arithmetic on values, not bits: independent of the code's bit
// manipulation.
double rounded_err(double err) {
  static_assert(kTieBreakBits == 20, "the reference below assumes 20 bits");
  if (err == 0.0) return 0.0;
  if (err < std::numeric_limits<double>::min()) {
    return std::ldexp(std::floor(std::ldexp(err, 1054)), -1054);
  }
  const int e = std::ilogb(err);
  return std::ldexp(std::floor(std::ldexp(err, 32 - e)), e - 32);
}

double quantised(double t) { return std::min(std::floor(t * 1048576.0), 1048575.0); }

/// -1, 0, 1 as (rounded Err, quantised tie-breaker) of a compares with that of b.
int reference_order(double err_a, double t_a, double err_b, double t_b) {
  const double ra = rounded_err(err_a), rb = rounded_err(err_b);
  if (ra != rb) return ra < rb ? -1 : 1;
  const double qa = quantised(t_a), qb = quantised(t_b);
  if (qa != qb) return qa < qb ? -1 : 1;
  return 0;
}

int order(double a, double b) { return a < b ? -1 : (a > b ? 1 : 0); }

/// Checks the fitness of one pair against the reference and the fitness's own properties.
void expect_lexicographic(double err_a, double t_a, double err_b, double t_b) {
  const double fa = tie_break_fitness(err_a, t_a), fb = tie_break_fitness(err_b, t_b);
  ASSERT_TRUE(std::isfinite(fa) && std::isfinite(fb));
  EXPECT_EQ(order(fa, fb), reference_order(err_a, t_a, err_b, t_b))
      << std::hexfloat << "Err " << err_a << " t " << t_a << " vs Err " << err_b << " t " << t_b;
  // Different Err blocks are never reordered by the tie-breaker.
  if (rounded_err(err_a) < rounded_err(err_b)) {
    EXPECT_LT(fa, fb);
  }
  // The fitness lies in [rounded Err, rounded Err + 2^-32·Err] (+ 2^-1054 below the normals).
  for (const auto& [err, f] : {std::pair{err_a, fa}, std::pair{err_b, fb}}) {
    EXPECT_GE(f, rounded_err(err));
    EXPECT_LE(f - rounded_err(err), std::ldexp(err, -32) + std::ldexp(1.0, -1054));
  }
}

TEST(TieBreakFitness, EqualErrIsOrderedByTheTieBreakerAndAZeroTieBreakerRoundsErrDown) {
  const double plateau = 1.6170854430869183;  // a Σ ω d_true², no special binary value
  EXPECT_LT(tie_break_fitness(plateau, 0.30), tie_break_fitness(plateau, 0.31));
  EXPECT_LT(tie_break_fitness(plateau, 0.0), tie_break_fitness(plateau, 1e-6));
  EXPECT_LT(tie_break_fitness(plateau, 0.5), tie_break_fitness(plateau, 1.0));
  // Closer than one level (2^-20 ≈ 9.5e-7): a tie.
  EXPECT_EQ(tie_break_fitness(plateau, 0.25), tie_break_fitness(plateau, 0.25 + 1e-7));
  EXPECT_EQ(tie_break_fitness(plateau, 0.0), rounded_err(plateau));
  EXPECT_EQ(tie_break_fitness(1.0, 0.0), 1.0);
  EXPECT_EQ(tie_break_fitness(1.0, 0.5), 1.0 + std::ldexp(1.0, -33));  // level 2^19 of 2^20
  // Out-of-range tie-breakers are clamped: t ≤ 0 is level 0, t ≥ 1 (and NaN) the top level.
  EXPECT_EQ(tie_break_fitness(2.0, -3.0), 2.0);
  EXPECT_EQ(tie_break_fitness(2.0, 7.0), tie_break_fitness(2.0, 1.0));
  EXPECT_EQ(tie_break_fitness(2.0, std::nan("")), tie_break_fitness(2.0, 1.0));
  EXPECT_EQ(tie_break_fitness(2.0, 1.0), 2.0 + (1048575.0 * std::ldexp(1.0, -51)));
}

TEST(TieBreakFitness, SmallerErrWinsWhateverTheTieBreakers) {
  // Err one block apart (2^20 ulps) or more: the best tie-breaker never overtakes.
  for (const double err : {0.046875, 0.078125, 1.6170854430869183, 12.5, 3e5}) {
    const double ulp = std::nextafter(err, 2 * err) - err;
    const double next_block = rounded_err(err) + 1048576.0 * ulp;
    EXPECT_LT(tie_break_fitness(err, 1.0), tie_break_fitness(next_block, 0.0)) << err;
    EXPECT_LT(tie_break_fitness(err, 1.0), tie_break_fitness(err * (1 + 1e-9), 0.0)) << err;
    expect_lexicographic(err, 1.0, next_block, 0.0);
  }
}

TEST(TieBreakFitness, ZeroSubnormalHugeAndLastBitDifferencesFollowTheReference) {
  const double max = std::numeric_limits<double>::max();
  const double denorm = std::numeric_limits<double>::denorm_min();
  const double tiny = std::numeric_limits<double>::min();
  const std::vector<double> errs = {0.0,
                                    -0.0,
                                    denorm,
                                    1000 * denorm,
                                    std::ldexp(1.0, -1054),
                                    tiny,
                                    std::nextafter(tiny, 1.0),
                                    1e-300,
                                    0.046875,
                                    std::nextafter(0.046875, 1.0),
                                    1.0,
                                    std::nextafter(1.0, 0.0),
                                    std::nextafter(1.0, 2.0),
                                    1.6170854430869183,
                                    1e300,
                                    std::nextafter(max, 0.0),
                                    max};
  const std::vector<double> ts = {0.0, 1e-7, 0.3, 0.75, 1.0};
  for (double a : errs) {
    for (double b : errs) {
      for (double ta : ts) {
        for (double tb : ts) expect_lexicographic(a, ta, b, tb);
      }
    }
  }
  // Err 0 stays ≥ 0 and tiny; the largest Err stays finite.
  EXPECT_EQ(tie_break_fitness(0.0, 0.0), 0.0);
  EXPECT_FALSE(std::signbit(tie_break_fitness(-0.0, 0.0)));
  EXPECT_LT(tie_break_fitness(0.0, 1.0), std::ldexp(1.0, -1054));
  EXPECT_TRUE(std::isfinite(tie_break_fitness(max, 1.0)));
  EXPECT_LE(tie_break_fitness(max, 1.0), max);
}

TEST(TieBreakFitness, RandomPairsFollowTheReference) {
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<int> exponent(-60, 60);
  // Offsets in ulps that straddle the block size 2^20.
  const std::int64_t offsets[] = {
      0, 1, 2, 1000, (1 << 19), (1 << 20) - 1, 1 << 20, (1 << 20) + 1, 1 << 21, 1 << 30};
  int lower_err_won = 0;
  for (int i = 0; i < 20000; ++i) {
    const double a = std::ldexp(1.0 + unit(rng), exponent(rng));
    double b = a;
    const std::int64_t k = offsets[i % 10];
    for (std::int64_t step = 0; step < std::min<std::int64_t>(k, 4); ++step) {
      b = std::nextafter(b, 2 * a);
    }
    if (k > 4) b = a + static_cast<double>(k) * (std::nextafter(a, 2 * a) - a);
    const double ta = unit(rng), tb = unit(rng);
    expect_lexicographic(a, ta, b, tb);
    expect_lexicographic(b, tb, a, ta);
    if (a < b && tie_break_fitness(a, ta) < tie_break_fitness(b, tb)) ++lower_err_won;
  }
  EXPECT_GT(lower_err_won, 10000);
}

TEST(TieBreakFitness, NegativeAndNonFiniteErrPassUnchanged) {
  EXPECT_EQ(tie_break_fitness(-1.5, 0.5), -1.5);
  EXPECT_TRUE(std::isinf(tie_break_fitness(std::numeric_limits<double>::infinity(), 0.5)));
  EXPECT_TRUE(std::isnan(tie_break_fitness(std::nan(""), 0.5)));
}

TEST(VolumeFraction, OnThePlateauTheWeightedModelVolumeOverSOffItZeroByHand) {
  const core::Box3 area{core::Vec3(1, 0, 0), core::Vec3(3, 2, 3)};  // 2 × 2 × 3 = 12 m³
  std::vector<core::StateResult> states(4);  // d_model 0: every model touches the robot
  states[0].weight = 0.5;
  states[0].model_volume = 2.0;
  states[1].weight = 0.25;
  states[1].model_volume = 4.0;
  states[2].weight = 0.0;  // no part of Err: neither its model nor its distance counts
  states[2].model_volume = 12.0;
  states[2].d_model = 0.7;
  states[3].weight = 0.25;
  states[3].model_volume = 6.0;
  // (0.5·2 + 0.25·4 + 0.25·6) / (1 · 12) = 3.5 / 12
  EXPECT_DOUBLE_EQ(volume_fraction(states, area), 3.5 / 12.0);
  // One weighted state whose model keeps a distance: off the plateau, Err alone decides.
  states[3].d_model = 0.3;
  EXPECT_EQ(volume_fraction(states, area), 0.0);
  states[3].d_model = 0.0;
  for (auto& s : states) s.model_volume = 12.0;
  EXPECT_DOUBLE_EQ(volume_fraction(states, area), 1.0);
  for (auto& s : states) s.weight = 0.0;
  EXPECT_EQ(volume_fraction(states, area), 0.0);
  EXPECT_EQ(volume_fraction({}, area), 0.0);
}

// data/paper_ceiling.json is the plateau scene: almost every random configuration has the
// largest Err, Σ ω d_true² (the model touches the robot in every state), while the tie-breaker
// still tells them apart. Random configurations from the encoding's bounds (seeded).
TEST(VoxelObjective, PaperCeilingConfigurationsTieOnErrButNotOnTheTieBreaker) {
  const core::Scene scene =
      core::load_scene(std::string(CAMPLACE_SOURCE_DIR) + "/data/paper_ceiling.json");
  for (const core::CameraDomain& d : scene.cameras.domains) {
    EXPECT_EQ(d.z.lo, 3.0);
    EXPECT_EQ(d.z.hi, 3.0);
    EXPECT_EQ(d.pitch.hi, 0.0);
  }
  const VoxelObjective objective(scene, voxel::VoxelOptions{});  // conservative
  const Encoding encoding(scene);
  const auto [lo, hi] = encoding.bounds();
  std::mt19937 rng(14);
  int on_plateau = 0;
  std::vector<double> tie_breakers;
  for (int i = 0; i < 40; ++i) {
    std::vector<double> x(lo.size());
    for (std::size_t k = 0; k < x.size(); ++k) {
      x[k] = std::uniform_real_distribution<double>(lo[k], hi[k])(rng);
    }
    const core::CameraConfig config = encoding.decode(x);
    const core::Evaluation evaluation = objective.evaluator().evaluate(config);
    double plateau = 0.0;
    for (const core::StateResult& s : evaluation.states) plateau += s.weight * s.d_true * s.d_true;
    core::Timing timing;
    const Score score = objective.score(config, timing);
    EXPECT_EQ(score.err, evaluation.err);
    if (score.err >= plateau * (1 - 1e-12)) {
      ++on_plateau;
      tie_breakers.push_back(score.tie_breaker);
    }
  }
  EXPECT_GE(on_plateau, 35);  // 494 of 500 in scripts/plateau_share.py
  std::sort(tie_breakers.begin(), tie_breakers.end());
  const auto distinct =
      std::unique(tie_breakers.begin(), tie_breakers.end()) - tie_breakers.begin();
  EXPECT_GE(distinct, on_plateau - 3);
}

TEST(TouchingVolumeExcess, TheTouchingStatesTermsScaledByTheirVolumeFractionByHand) {
  const core::Box3 area{core::Vec3(1, 0, 0), core::Vec3(3, 2, 3)};  // 12 m³
  auto state = [](double weight, double d_true, double d_model, double model_volume) {
    core::StateResult s;
    s.weight = weight;
    s.d_true = d_true;
    s.d_model = d_model;
    s.model_volume = model_volume;
    return s;
  };
  std::vector<core::StateResult> states = {
      state(0.5, 0.8, 0.0, 3.0),    // touches: 0.5 · 0.64 · 3/12 = 0.08
      state(0.25, 1.2, 0.0, 6.0),   // touches: 0.25 · 1.44 · 6/12 = 0.18
      state(0.25, 0.9, 0.4, 9.0),   // keeps a distance: no excess
      state(0.0, 2.0, 0.0, 12.0)};  // weight 0: no part of Err
  EXPECT_DOUBLE_EQ(touching_volume_excess(states, area), 0.08 + 0.18);
  // A model filling more than S (it cannot; clamped) counts as all of S: at most the term.
  states[1].model_volume = 30.0;
  EXPECT_DOUBLE_EQ(touching_volume_excess(states, area), 0.08 + 0.25 * 1.44);
  states[0].d_model = 1e-9;  // the least distance ends the excess of that state
  EXPECT_DOUBLE_EQ(touching_volume_excess(states, area), 0.25 * 1.44);
  EXPECT_EQ(touching_volume_excess({}, area), 0.0);
  EXPECT_EQ(touching_volume_excess(states, core::Box3{core::Vec3(0, 0, 0), core::Vec3(0, 1, 1)}),
            0.0);
}

TEST(ObjectiveNames, DefaultFirstAndHelpNamesEach) {
  ASSERT_EQ(objective_names(),
            (std::vector<std::string>{"err", "err+volume", "err+touching-volume"}));
  EXPECT_EQ(objective_names().front(), kDefaultObjective);
  for (const std::string& name : objective_names()) {
    EXPECT_NE(objective_help().find("  " + name + " "), std::string::npos) << name;
  }
}

}  // namespace
}  // namespace camplace::optimize
