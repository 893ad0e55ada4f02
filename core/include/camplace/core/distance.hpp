#pragma once
/// The true distance d(C, O_u) of SPEC §4, from the meshes themselves, computed exactly.
#include <string>
#include <vector>

#include "camplace/core/scene.hpp"

namespace camplace::core {

/// An exactly computed squared distance: its value rounded to double and as a fraction "p/q".
struct ExactSquaredDistance {
  double value = 0.0;
  std::string fraction;
};

/// Exact squared distance between two unions of closed solids (0 when any two touch, overlap or
/// one contains the other). Both sets must be non-empty.
ExactSquaredDistance solids_squared_distance(const std::vector<const TriangleMesh*>& a,
                                             const std::vector<const TriangleMesh*>& b);

/// d(C_h, O_u(a_lh)) for one state: critical objects of the time step vs the event's targets.
ExactSquaredDistance true_squared_distance(const Scene& scene, const StateIndex& state);

}  // namespace camplace::core
