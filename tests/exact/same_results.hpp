#pragma once
// Two exact evaluations of the same scene and configuration, by two constructions that must give
// the same model, compared exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>

#include "camplace/exact/evaluator.hpp"

namespace camplace::testing {

/// Expects `a` and `b` to hold the same states with the same exact d_model², model volume,
/// d_true² and kept components, the same count of removed components unless
/// `removed_may_differ` (a construction that discards pieces at other times), and the same Err.
inline void expect_same_exact_results(const exact::ExactEvaluation& a,
                                      const exact::ExactEvaluation& b,
                                      bool removed_may_differ = false) {
  EXPECT_EQ(a.states.size(), b.states.size());
  for (std::size_t s = 0; s < std::min(a.states.size(), b.states.size()); ++s) {
    const auto &x = a.states[s], &y = b.states[s];
    EXPECT_EQ(x.d_model_sq_exact, y.d_model_sq_exact) << "state " << s;
    EXPECT_EQ(x.model_volume_exact, y.model_volume_exact) << "state " << s;
    EXPECT_EQ(x.d_true_sq_exact, y.d_true_sq_exact) << "state " << s;
    EXPECT_EQ(x.components, y.components) << "state " << s;
    if (!removed_may_differ) {
      EXPECT_EQ(x.components_removed, y.components_removed) << "state " << s;
    }
  }
  EXPECT_EQ(a.err, b.err);
}

}  // namespace camplace::testing
