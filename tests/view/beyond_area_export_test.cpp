// `camplace export` with obstacles and critical objects that extend beyond the area S (SPEC §2):
// they are drawn whole (glb_checks.hpp compares each node with its object's whole mesh), the
// model and the FOVs stay in S, the d_model segment starts on the critical object outside S,
// and a glTF camera's zfar reaches every object.
#include <gtest/gtest.h>

#include "camplace/core/geometry.hpp"
#include "camplace/view/export.hpp"
#include "glb_checks.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using core::Vec3;

TEST(Export, ObjectsBeyondSAreDrawnWholeAndTheModelStaysInS) {
  // S = 4×3×3 m; a wall crossing S's face x = 4 and reaching 6 m beyond it, a masked conveyor
  // from x = −5 m to 2 m (the critical object, mostly outside S), a person in S; one camera
  // inside S, one outside it at x = −3 m.
  const core::Box3 area{Vec3(0, 0, 0), Vec3(4, 3, 3)};
  const auto conveyor = box_object("conveyor", Vec3(-5, 1, 0), Vec3(2, 1.6, 0.6));
  core::Scene scene = simple_scene(area, {8, 6, 6}, 2, 40.0, {conveyor},
                                   {box_object("person", Vec3(3, 2.2, 0.1), Vec3(3.4, 2.6, 1.8))});
  scene.static_obstacles.push_back(box_object("wall", Vec3(3.8, -2, -1), Vec3(10, 0.5, 4)));
  scene.time_steps[0].dynamic_obstacles.push_back(conveyor);
  const core::CameraConfig config{camera_at(Vec3(1, 2.5, 2.5), 0, -30),
                                  camera_at(Vec3(-3, 1.5, 2.0), 0, -15)};
  const std::string dir = temp_dir("export_beyond");
  const view::ExportResult result = view::export_scene(scene, config, {}, dir);
  ASSERT_EQ(result.states.size(), 1u);
  const view::ExportedState& s = result.states[0];
  check_state_file(scene, config, s, dir + "/" + s.glb);
  // The d_model segment: from the conveyor's nearest point to the model (conservative: the
  // conveyor's own silhouette shell, SPEC §4) — its `to` end in S.
  const core::Box3 tolerant{area.min - Vec3::Constant(1e-9), area.max + Vec3::Constant(1e-9)};
  EXPECT_TRUE(tolerant.contains(s.model_segment.b)) << s.model_segment.b.transpose();
  EXPECT_FALSE(area.contains(s.model_segment.a));  // on the conveyor, outside S
  // d_true from the conveyor's mesh: x gap 1 m, y gap 0.6 m, z overlap.
  EXPECT_NEAR(s.result.d_true, std::hypot(1.0, 0.6), 1e-12);
  // Each glTF camera's zfar reaches every corner of the wall (which ends 6 m beyond S).
  const tinygltf::Model m = load_glb(dir + "/" + s.glb);
  ASSERT_EQ(m.cameras.size(), config.size());
  for (std::size_t c = 0; c < config.size(); ++c) {
    for (const Vec3& corner : scene.static_obstacles[0].bounds.corners()) {
      EXPECT_GE(m.cameras[c].perspective.zfar, (corner - config[c].position).norm())
          << "camera " << c;
    }
  }
}

}  // namespace
}  // namespace camplace::testing
