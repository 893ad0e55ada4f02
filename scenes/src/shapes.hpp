#pragma once
// The objects the scene families make: tetrahedra, finer pyramids of the same volume, random
// pyramids, and the few additions to the paper's basic setup some families need (more
// furniture, a third robot pose, a two-link robot, more places for a person). Private to scenes.
#include <array>
#include <random>
#include <string>
#include <vector>

#include "camplace/core/geometry.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::scenes::detail {

using Tetra = std::array<core::Vec3, 4>;  ///< base triangle (points 0, 1, 2) and apex (point 3)

struct NamedTetra {
  std::string name;
  Tetra points;
};

/// The tetrahedron as the scene loader makes it of a "tetrahedron" entry (the 4 points in the
/// given order, turned outward), so the scene writer writes it as one.
core::SceneObject tetra_object(const NamedTetra& t);

/// v with each coordinate rounded to micrometres (generated vertices: readable files).
core::Vec3 rounded(const core::Vec3& v);

/// The tetrahedron `t` with `facets` facets (even, ≥ 4) and the same volume: the pyramid with
/// the same apex over a regular polygon in the base triangle's plane; `facets` = 4 gives `t`.
core::SceneObject finer(const NamedTetra& t, int facets);

/// Splits `total` facets over `parts` objects: even counts ≥ 4, as equal as possible, the
/// larger ones first.
std::vector<int> split_facets(int total, int parts);

struct PyramidShape {
  double radius_lo, radius_hi;  ///< circumradius of the regular base polygon (m)
  double height_lo, height_hi;  ///< z-extent (m)
  double lean;                  ///< apex offset from the axis, fraction of the radius
  bool upright;                 ///< base on the floor (else base on top, apex on the floor)
};

/// Draws pyramids with the given facet counts at random places in `area` until each has its
/// bounding box 0.1 m away from every box in `avoid` (and from the ones drawn before) and
/// 0.05 m inside the walls. Empty when one finds no place.
std::vector<core::SceneObject> place_randomly(std::mt19937& rng, const std::vector<int>& facets,
                                              const PyramidShape& shape, const std::string& name,
                                              std::vector<core::Box3> avoid,
                                              const core::Box3& area);

/// The bounding boxes of `objects`, in order.
std::vector<core::Box3> boxes_of(const std::vector<core::SceneObject>& objects);

/// The smallest target part's volume and z-extent, each rounded down to 6 decimals (never
/// above the true value): a component holding a whole part is never smaller (data/README.md,
/// "plausibility").
core::Plausibility smallest_target(const core::Scene& s);

// ---------------------------------------------------------------------------------------------
// Additions to the paper's basic setup (data/paper_basic.json), in its area S = [0,4]x[0,3]x[0,3].

/// The paper's area S, from which static_objects stretches its extra furniture to a base's.
const core::Box3& paper_area();

/// 3 more pieces of furniture for static_objects, along the walls of S, clear of the robot and
/// of the persons of the basic setup.
std::vector<NamedTetra> extra_static();

/// The basic robot (pedestal, upper arm, forearm) turned toward +x, the third pose of
/// unmodelled_events: the pedestal and the upper arm's base triangle as in `pose0` (the basic
/// setup's first time step), the new apex and forearm.
std::vector<core::SceneObject> robot_toward_x(const std::vector<core::SceneObject>& pose0);

/// The robot of 2 tetrahedra (the basic pedestal and one arm) of dynamic_steps at step h: the
/// arm points at 180° − 30°·h (from −x toward the persons over +y), its tip at 0.95 m; pedestal
/// and arm base as in `pose0`.
std::vector<core::SceneObject> two_link_robot(const std::vector<core::SceneObject>& pose0,
                                              int step);

/// The basic person of 2 tetrahedra at the extra place `place` (3 or 4; places 0-2 are the
/// basic setup's), computed as the basic file's numbers were.
std::vector<core::SceneObject> extra_person(int place);

/// Event weights for L = 1..5 events, summing to 1 (L = 3: the basic setup's 0.5, 0.3, 0.2).
std::vector<double> event_weights(int events);

}  // namespace camplace::scenes::detail
