#pragma once
/// The error functional of SPEC §4 (the paper's Err_{L,H}).
#include <array>
#include <vector>

#include "camplace/core/geometry.hpp"

namespace camplace::core {

/// One addend of Err: weight ω, true distance and model distance (metres).
struct ErrTerm {
  double weight = 0.0;
  double d_true = 0.0;
  double d_model = 0.0;
};

/// Err = Σ ω · (d_true − d_model)² over all states (m²).
double error_functional(const std::vector<ErrTerm>& terms);

/// Default optimisation tolerance (½ · voxel diagonal)² in m² for S cut into n voxels (SPEC §4).
double default_tolerance(const Box3& area, const std::array<int, 3>& resolution);

/// The conservative lower bound L of Err as a threshold to reach (m²): Err and L sum the same
/// terms in different orders, so an Err equal to L can come out a few units in the last place
/// above it.
double lower_bound_threshold(double err_lower_bound);

/// The Err a run must reach to succeed (SPEC §4): the tolerance; in conservative mode, where no
/// configuration goes below the lower bound L of Err, max(tolerance, lower_bound_threshold(L)).
/// m².
double success_target(bool conservative, double tolerance, double err_lower_bound);

}  // namespace camplace::core
