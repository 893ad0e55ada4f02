#pragma once
// The exact model against the brute-force sensor model of tests/support (an independent
// implementation of SPEC §3): at random points away from every boundary, p ∈ M exactly when no
// camera reports it free and it lies inside no obstacle (SPEC §4, filter off).
#include <gtest/gtest.h>

#include <random>

#include "camplace/core/camera.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/exact/evaluator.hpp"
#include "reference.hpp"

namespace camplace::testing {

struct Agreement {
  int checked = 0, inside = 0, mismatches = 0;
};

// Compares the kept models of `eval` (every state) at `samples` random points per state.
inline Agreement compare_with_oracle(const core::Scene& scene, const core::CameraConfig& config,
                                     const exact::ExactEvaluation& eval, int samples,
                                     std::mt19937& rng) {
  const auto states = core::states(scene);
  Agreement a;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (std::size_t s = 0; s < states.size(); ++s) {
    // Without the filter M ⊇ targets (SPEC §4), so the model never over-estimates.
    EXPECT_LE(eval.states[s].d_model, eval.states[s].d_true + 1e-12) << "state " << s;
    const auto& step = scene.time_steps[states[s].time_step];
    for (int i = 0; i < samples; ++i) {
      const core::Vec3 p =
          scene.area.min +
          core::Vec3(unit(rng), unit(rng), unit(rng)).cwiseProduct(scene.area.max - scene.area.min);
      bool ambiguous = false, non_free = true;
      for (int c = 0; c < int(config.size()); ++c) {
        const auto label =
            reference_label(scene, states[s].time_step, states[s].event, config[c], p, 1e-6, c);
        ambiguous |= label.ambiguous;
        if (label.label == voxel::Label::free) non_free = false;
      }
      bool in_obstacle = false;
      for (const auto& o : scene.static_obstacles) in_obstacle |= reference_inside(o.mesh, p);
      for (const auto& o : step.dynamic_obstacles) in_obstacle |= reference_inside(o.mesh, p);
      if (ambiguous) continue;
      const bool expected = non_free && !in_obstacle;
      ++a.checked;
      a.inside += expected;
      if (eval.models[s].contains(p) != expected) {
        ++a.mismatches;
        ADD_FAILURE() << "state " << s << " point (" << p.transpose() << "): exact "
                      << eval.models[s].contains(p) << ", oracle " << expected;
      }
    }
  }
  return a;
}

// The same for the exact evaluation of `config`.
inline Agreement compare_with_oracle(const core::Scene& scene, const core::CameraConfig& config,
                                     int samples, std::mt19937& rng) {
  exact::ExactOptions options;
  options.keep_models = true;
  return compare_with_oracle(scene, config, exact::evaluate_exact(scene, config, options), samples,
                             rng);
}

}  // namespace camplace::testing
