// The exact true distance d(C, O_u) against hand-computed values.
#include "camplace/core/distance.hpp"

#include <gtest/gtest.h>

#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using core::Vec3;

TEST(TrueDistance, SeparatedBoxesGiveExactFraction) {
  const auto a = box_object("a", {0, 0, 0}, {1, 1, 1});
  const auto b = box_object("b", {1.5, 2, 0}, {2, 3, 1});  // gap 0.5 in x, 1 in y
  const auto d = core::solids_squared_distance({&a.mesh}, {&b.mesh});
  EXPECT_EQ(d.fraction, "5/4");
  EXPECT_DOUBLE_EQ(d.value, 1.25);
}

TEST(TrueDistance, TouchingNestedAndOverlappingAreZero) {
  const auto a = box_object("a", {0, 0, 0}, {1, 1, 1});
  const auto touching = box_object("t", {1, 0, 0}, {2, 1, 1});
  const auto nested = box_object("n", {0.25, 0.25, 0.25}, {0.5, 0.5, 0.5});
  EXPECT_EQ(core::solids_squared_distance({&a.mesh}, {&touching.mesh}).value, 0.0);
  EXPECT_EQ(core::solids_squared_distance({&a.mesh}, {&nested.mesh}).value, 0.0);
  EXPECT_EQ(core::solids_squared_distance({&nested.mesh}, {&a.mesh}).fraction, "0/1");
}

TEST(TrueDistance, TetrahedronApexAboveBoxFace) {
  const auto box = box_object("box", {0, 0, 0}, {1, 1, 1});
  const auto tet = tetra_object("t", {0.5, 0.5, 1.1}, {0.2, 0.2, 2}, {0.8, 0.2, 2}, {0.5, 0.9, 2});
  const auto d = core::solids_squared_distance({&box.mesh}, {&tet.mesh});
  EXPECT_NEAR(d.value, 0.01, 1e-15);  // apex 0.1 above the top face
  // The union's distance is its nearest member's.
  const auto far = box_object("far", {3, 3, 3}, {3.5, 3.5, 3.5});
  EXPECT_NEAR(core::solids_squared_distance({&far.mesh, &box.mesh}, {&tet.mesh}).value, 0.01,
              1e-15);
}

}  // namespace
}  // namespace camplace::testing
