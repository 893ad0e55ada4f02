#pragma once
// Private to view/: a glTF 2.0 model built with tinygltf (Debian's libtinygltf) and written as
// binary glTF. Positions given in camplace's world frame (z up) are converted to glTF's y up:
// glTF (X, Y, Z) = (x, z, −y), a rotation by −90° about x (docs/export.md).
#include <tiny_gltf.h>

#include <array>
#include <nlohmann/json.hpp>
#include <string>

#include "camplace/core/geometry.hpp"

namespace camplace::view::detail {

/// camplace world (z up) → glTF (y up).
inline core::Vec3 to_gltf(const core::Vec3& p) { return {p.x(), p.z(), -p.y()}; }
/// glTF (y up) → camplace world (z up).
inline core::Vec3 from_gltf(const core::Vec3& p) { return {p.x(), -p.z(), p.y()}; }

/// A JSON value as a tinygltf extras value.
tinygltf::Value to_value(const nlohmann::ordered_json& j);

class GltfBuilder {
 public:
  GltfBuilder();
  /// A metallic-roughness material; translucent = alpha blending (rgba[3] < 1).
  int material(const std::string& name, const std::array<double, 4>& rgba, bool double_sided);
  /// A flat-shaded triangle mesh (one vertex per triangle corner, face normals). `world`: the
  /// mesh is in camplace's world frame and converted to y up; otherwise its coordinates are
  /// kept (a node's local frame).
  int triangle_mesh(const std::string& name, const core::TriangleMesh& mesh, int material,
                    bool world = true);
  /// A line segment from a to b (world frame) with small octahedra of `marker_radius` (m) at
  /// both ends.
  int segment_mesh(const std::string& name, const core::Vec3& a, const core::Vec3& b,
                   int line_material, int marker_material, double marker_radius);
  /// A perspective camera (radians, metres); aspect_ratio: width / height, 0 = not given.
  int perspective_camera(const std::string& name, double yfov, double znear, double zfar,
                         double aspect_ratio = 0.0);
  /// A root node of the scene; mesh/camera −1 for none; rotation as x, y, z, w (glTF frame).
  int node(const std::string& name, int mesh, const nlohmann::ordered_json& extras, int camera = -1,
           const std::array<double, 4>& rotation = {0, 0, 0, 1},
           const core::Vec3& translation = core::Vec3::Zero());
  void set_asset_extras(const nlohmann::ordered_json& extras);
  void set_scene_extras(const nlohmann::ordered_json& extras);
  /// The binary glTF file.
  std::string glb();

 private:
  /// A float VEC3 accessor over `xyz` (3 floats per element) with its min/max.
  int vec3_accessor(const std::vector<float>& xyz);
  tinygltf::Model model_;
};

}  // namespace camplace::view::detail
