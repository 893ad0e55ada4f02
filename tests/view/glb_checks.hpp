#pragma once
// Checks of an exported glTF file parsed back with tinygltf, shared by the voxel and the exact
// export tests: what a glTF validator checks (accessor bounds against the data, buffer ranges,
// primitive modes) and camplace's conventions (node counts per role, y-up conversion, camera
// poses, every position in S but those of obstacles and critical objects (drawn whole, may extend
// beyond S), segments between the extras' closest points).
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cstring>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/view/export.hpp"

namespace camplace::testing {

/// glTF (y up) → camplace (z up), the inverse of the documented (x, y, z) → (x, z, −y).
inline core::Vec3 from_gltf(const core::Vec3& p) { return {p.x(), -p.z(), p.y()}; }

inline tinygltf::Model load_glb(const std::string& path) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = loader.LoadBinaryFromFile(&model, &err, &warn, path);
  EXPECT_TRUE(ok) << path << ": " << err;
  EXPECT_TRUE(err.empty()) << err;
  EXPECT_TRUE(warn.empty()) << warn;
  return model;
}

/// The VEC3 float data of an accessor, after checking its bounds are exactly those of the data.
inline std::vector<core::Vec3> vec3_data(const tinygltf::Model& m, int index) {
  const tinygltf::Accessor& a = m.accessors.at(index);
  EXPECT_EQ(a.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
  EXPECT_EQ(a.type, TINYGLTF_TYPE_VEC3);
  const tinygltf::BufferView& view = m.bufferViews.at(a.bufferView);
  const tinygltf::Buffer& buffer = m.buffers.at(view.buffer);
  const std::size_t stride = view.byteStride ? view.byteStride : 3 * sizeof(float);
  EXPECT_LE(view.byteOffset + view.byteLength, buffer.data.size());
  EXPECT_LE(a.byteOffset + (a.count - 1) * stride + 3 * sizeof(float), view.byteLength);
  std::vector<core::Vec3> out;
  std::array<float, 3> lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
  for (std::size_t i = 0; i < a.count; ++i) {
    float xyz[3];
    std::memcpy(xyz, buffer.data.data() + view.byteOffset + a.byteOffset + i * stride, sizeof xyz);
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min(lo[c], xyz[c]);
      hi[c] = std::max(hi[c], xyz[c]);
    }
    out.emplace_back(xyz[0], xyz[1], xyz[2]);
  }
  EXPECT_EQ(a.minValues.size(), 3u);
  EXPECT_EQ(a.maxValues.size(), 3u);
  for (int c = 0; c < 3 && a.minValues.size() == 3 && a.maxValues.size() == 3; ++c) {
    EXPECT_EQ(a.minValues[c], lo[c]) << "accessor " << index;
    EXPECT_EQ(a.maxValues[c], hi[c]) << "accessor " << index;
  }
  return out;
}

inline std::string role_of(const tinygltf::Node& node) {
  return node.extras.Has("role") ? node.extras.Get("role").Get<std::string>() : "";
}

inline core::Vec3 vec3_of(const tinygltf::Value& v) {
  return {v.Get(0).GetNumberAsDouble(), v.Get(1).GetNumberAsDouble(), v.Get(2).GetNumberAsDouble()};
}

/// The node counts per role the scene implies for a state (docs/export.md).
inline std::map<std::string, int> expected_roles(const core::Scene& scene,
                                                 const core::StateIndex& s) {
  const core::TimeStep& step = scene.time_steps[s.time_step];
  return {{"static_obstacle", static_cast<int>(scene.static_obstacles.size())},
          {"dynamic_obstacle", static_cast<int>(step.dynamic_obstacles.size())},
          {"critical_object", static_cast<int>(step.critical.size())},
          {"target", static_cast<int>(step.events[s.event].targets.size())},
          {"model", 1},
          {"camera", scene.cameras.count},
          {"fov", scene.cameras.count},
          {"true_distance", 1},
          {"model_distance", 1}};
}

/// Everything a validator would check in one exported state, plus camplace's conventions.
inline void check_state_file(const core::Scene& scene, const core::CameraConfig& config,
                             const view::ExportedState& state, const std::string& path) {
  SCOPED_TRACE(path);
  const tinygltf::Model m = load_glb(path);
  EXPECT_EQ(m.asset.version, "2.0");
  EXPECT_TRUE(m.asset.extras.Has("up_axis_conversion"));
  ASSERT_EQ(m.scenes.size(), 1u);
  EXPECT_EQ(m.scenes[0].extras.Get("d_true").GetNumberAsDouble(), state.result.d_true);
  EXPECT_EQ(m.scenes[0].extras.Get("weight").GetNumberAsDouble(), state.result.weight);
  EXPECT_EQ(m.cameras.size(), config.size());

  std::map<std::string, int> roles;
  const core::Box3 tolerant{scene.area.min - core::Vec3::Constant(1e-5),
                            scene.area.max + core::Vec3::Constant(1e-5)};
  // Obstacles and critical objects may extend beyond S (SPEC §2) and are drawn whole: each such
  // node holds its object's whole mesh (same bounds, same enclosed volume); everything else (the
  // model, the FOVs clipped to S, the targets) lies in S. A segment's `from` end lies on a
  // critical object (possibly outside S), its `to` end on a target or the model (in S).
  const core::TimeStep& step = scene.time_steps[state.state.time_step];
  std::map<std::string, const core::SceneObject*> drawn_whole;
  // By role and entry (names may repeat; a step's default critical objects share their entries
  // with its dynamic obstacles).
  for (const auto& o : scene.static_obstacles) drawn_whole["static_obstacle " + o.entry] = &o;
  for (const auto& o : step.dynamic_obstacles) drawn_whole["dynamic_obstacle " + o.entry] = &o;
  for (const auto& o : step.critical) drawn_whole["critical_object " + o.entry] = &o;
  core::Box3 critical_bounds{core::Vec3::Constant(1e300), core::Vec3::Constant(-1e300)};
  for (const auto& o : step.critical) {
    critical_bounds.min = critical_bounds.min.cwiseMin(o.bounds.min - core::Vec3::Constant(1e-5));
    critical_bounds.max = critical_bounds.max.cwiseMax(o.bounds.max + core::Vec3::Constant(1e-5));
  }
  for (int index : m.scenes[0].nodes) {
    const tinygltf::Node& node = m.nodes.at(index);
    const std::string role = role_of(node);
    ++roles[role];
    const bool empty = node.extras.Has("empty") && node.extras.Get("empty").Get<bool>();
    EXPECT_EQ(node.mesh < 0, empty) << node.name;
    if (role == "camera") {
      // Pose: the glTF camera looks along local −Z with +Y up.
      const auto& c = config.at(node.extras.Get("index").GetNumberAsInt());
      ASSERT_EQ(node.rotation.size(), 4u);
      const Eigen::Quaterniond q(node.rotation[3], node.rotation[0], node.rotation[1],
                                 node.rotation[2]);
      EXPECT_NEAR((from_gltf(q * core::Vec3(0, 0, -1)) - core::view_direction(c)).norm(), 0, 1e-9);
      EXPECT_NEAR((from_gltf(q * core::Vec3(0, 1, 0)) - core::up_vector(c)).norm(), 0, 1e-9);
      ASSERT_EQ(node.translation.size(), 3u);
      EXPECT_NEAR(
          (from_gltf(core::Vec3(node.translation[0], node.translation[1], node.translation[2])) -
           c.position)
              .norm(),
          0, 1e-12);
      ASSERT_GE(node.camera, 0);
      EXPECT_NEAR(m.cameras[node.camera].perspective.yfov, 2 * scene.cameras.models[0].half_angle,
                  1e-12);
      continue;
    }
    if (node.mesh < 0) continue;
    const tinygltf::Mesh& mesh = m.meshes.at(node.mesh);
    core::TriangleMesh world;  // the node's triangles back in camplace's frame
    for (const tinygltf::Primitive& p : mesh.primitives) {
      std::vector<core::Vec3> points;
      for (const core::Vec3& v : vec3_data(m, p.attributes.at("POSITION")))
        points.push_back(from_gltf(v));
      if (p.attributes.count("NORMAL")) vec3_data(m, p.attributes.at("NORMAL"));
      if (p.mode == TINYGLTF_MODE_LINE) {
        // The segment: its ends are the extras' closest points, inside S, |from − to| = d.
        ASSERT_EQ(points.size(), 2u);
        const core::Vec3 from = vec3_of(node.extras.Get("from")),
                         to = vec3_of(node.extras.Get("to"));
        EXPECT_NEAR((points[0] - from).norm(), 0, 1e-6);
        EXPECT_NEAR((points[1] - to).norm(), 0, 1e-6);
        EXPECT_NEAR((from - to).norm(), node.extras.Get("length_m").GetNumberAsDouble(), 1e-9);
        EXPECT_TRUE(critical_bounds.contains(from)) << from.transpose();
        EXPECT_TRUE(tolerant.contains(to)) << to.transpose();
        continue;
      }
      ASSERT_EQ(p.mode, TINYGLTF_MODE_TRIANGLES);
      EXPECT_EQ(points.size() % 3, 0u);
      for (std::size_t i = 0; i + 2 < points.size(); i += 3) {
        const int first = static_cast<int>(world.vertices.size());
        world.vertices.insert(world.vertices.end(), points.begin() + i, points.begin() + i + 3);
        world.triangles.push_back({first, first + 1, first + 2});
      }
    }
    if (role == "true_distance" || role == "model_distance") continue;  // end markers
    const auto whole = drawn_whole.find(
        role + " " + (node.extras.Has("entry") ? node.extras.Get("entry").Get<std::string>() : ""));
    if (whole != drawn_whole.end()) {
      const core::SceneObject& o = *whole->second;
      const core::Box3 b = core::bounding_box(world);
      EXPECT_NEAR((b.min - o.bounds.min).norm(), 0, 1e-5) << node.name;
      EXPECT_NEAR((b.max - o.bounds.max).norm(), 0, 1e-5) << node.name;
      EXPECT_NEAR(core::signed_volume(world), core::signed_volume(o.mesh),
                  1e-5 * (1 + std::abs(core::signed_volume(o.mesh))))
          << node.name;
      continue;
    }
    for (const core::Vec3& q : world.vertices) EXPECT_TRUE(tolerant.contains(q)) << node.name;
    if (role == "model") {
      // The merged boundary encloses the model's volume as the pipeline reported it.
      EXPECT_NEAR(core::signed_volume(world), state.result.model_volume,
                  1e-5 * (1 + state.result.model_volume));
    }
  }
  roles.erase("");
  EXPECT_EQ(roles, expected_roles(scene, state.state));
  EXPECT_EQ(roles, state.nodes);
}

}  // namespace camplace::testing
