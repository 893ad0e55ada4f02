// glTF 2.0 through tinygltf (no hand-written glTF).
#include "gltf_builder.hpp"

#include <algorithm>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace camplace::view::detail {

tinygltf::Value to_value(const nlohmann::ordered_json& j) {
  if (j.is_object()) {
    tinygltf::Value::Object object;
    for (const auto& [key, value] : j.items()) object[key] = to_value(value);
    return tinygltf::Value(std::move(object));
  }
  if (j.is_array()) {
    tinygltf::Value::Array array;
    for (const auto& value : j) array.push_back(to_value(value));
    return tinygltf::Value(std::move(array));
  }
  if (j.is_boolean()) return tinygltf::Value(j.get<bool>());
  if (j.is_number_integer()) return tinygltf::Value(j.get<int>());
  if (j.is_number()) return tinygltf::Value(j.get<double>());
  if (j.is_string()) return tinygltf::Value(j.get<std::string>());
  return tinygltf::Value();
}

GltfBuilder::GltfBuilder() {
  model_.asset.version = "2.0";
  model_.asset.generator = "camplace export (tinygltf)";
  model_.buffers.emplace_back();
  model_.scenes.emplace_back();
  model_.scenes[0].name = "camplace";
  model_.defaultScene = 0;
}

int GltfBuilder::material(const std::string& name, const std::array<double, 4>& rgba,
                          bool double_sided) {
  tinygltf::Material m;
  m.name = name;
  m.pbrMetallicRoughness.baseColorFactor = {rgba[0], rgba[1], rgba[2], rgba[3]};
  m.pbrMetallicRoughness.metallicFactor = 0.0;
  m.pbrMetallicRoughness.roughnessFactor = 0.8;
  if (rgba[3] < 1.0) m.alphaMode = "BLEND";
  m.doubleSided = double_sided;
  model_.materials.push_back(m);
  return static_cast<int>(model_.materials.size()) - 1;
}

int GltfBuilder::vec3_accessor(const std::vector<float>& xyz) {
  auto& data = model_.buffers[0].data;
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = data.size();
  view.byteLength = xyz.size() * sizeof(float);
  view.target = TINYGLTF_TARGET_ARRAY_BUFFER;
  const auto* bytes = reinterpret_cast<const unsigned char*>(xyz.data());
  data.insert(data.end(), bytes, bytes + view.byteLength);
  model_.bufferViews.push_back(view);

  tinygltf::Accessor accessor;
  accessor.bufferView = static_cast<int>(model_.bufferViews.size()) - 1;
  accessor.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  accessor.count = xyz.size() / 3;
  accessor.type = TINYGLTF_TYPE_VEC3;
  // Bounds of the stored floats themselves (the glTF spec requires them for POSITION).
  accessor.minValues.assign(3, std::numeric_limits<double>::infinity());
  accessor.maxValues.assign(3, -std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < xyz.size(); ++i) {
    accessor.minValues[i % 3] = std::min<double>(accessor.minValues[i % 3], xyz[i]);
    accessor.maxValues[i % 3] = std::max<double>(accessor.maxValues[i % 3], xyz[i]);
  }
  model_.accessors.push_back(accessor);
  return static_cast<int>(model_.accessors.size()) - 1;
}

int GltfBuilder::triangle_mesh(const std::string& name, const core::TriangleMesh& mesh,
                               int material, bool world) {
  std::vector<float> positions, normals;
  for (const auto& t : mesh.triangles) {
    core::Vec3 p[3];
    for (int c = 0; c < 3; ++c) {
      p[c] = world ? to_gltf(mesh.vertices[t[c]]) : mesh.vertices[t[c]];
    }
    core::Vec3 n = (p[1] - p[0]).cross(p[2] - p[0]);
    n = n.norm() > 0 ? n.normalized() : core::Vec3::UnitY();
    for (int c = 0; c < 3; ++c) {
      for (int a = 0; a < 3; ++a) {
        positions.push_back(static_cast<float>(p[c][a]));
        normals.push_back(static_cast<float>(n[a]));
      }
    }
  }
  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  primitive.material = material;
  primitive.attributes["POSITION"] = vec3_accessor(positions);
  primitive.attributes["NORMAL"] = vec3_accessor(normals);
  tinygltf::Mesh m;
  m.name = name;
  m.primitives.push_back(primitive);
  model_.meshes.push_back(m);
  return static_cast<int>(model_.meshes.size()) - 1;
}

int GltfBuilder::segment_mesh(const std::string& name, const core::Vec3& a, const core::Vec3& b,
                              int line_material, int marker_material, double marker_radius) {
  tinygltf::Mesh m;
  m.name = name;
  tinygltf::Primitive line;
  line.mode = TINYGLTF_MODE_LINE;
  line.material = line_material;
  const core::Vec3 ga = to_gltf(a), gb = to_gltf(b);
  line.attributes["POSITION"] = vec3_accessor(
      {static_cast<float>(ga.x()), static_cast<float>(ga.y()), static_cast<float>(ga.z()),
       static_cast<float>(gb.x()), static_cast<float>(gb.y()), static_cast<float>(gb.z())});
  m.primitives.push_back(line);
  // Octahedra at the ends: a 1-pixel line alone is hard to find.
  core::TriangleMesh markers;
  for (const core::Vec3& end : {a, b}) {
    const int first = static_cast<int>(markers.vertices.size());
    for (int axis = 0; axis < 3; ++axis) {
      markers.vertices.push_back(end + marker_radius * core::Vec3::Unit(axis));
      markers.vertices.push_back(end - marker_radius * core::Vec3::Unit(axis));
    }
    // Vertex 2·axis + (0: +, 1: −); one triangle per octant, outward.
    for (int sx = 0; sx < 2; ++sx) {
      for (int sy = 0; sy < 2; ++sy) {
        for (int sz = 0; sz < 2; ++sz) {
          std::array<int, 3> t{first + sx, first + 2 + sy, first + 4 + sz};
          if ((sx + sy + sz) % 2 == 1) std::swap(t[1], t[2]);
          markers.triangles.push_back(t);
        }
      }
    }
  }
  const int marker_mesh = triangle_mesh(name + " ends", markers, marker_material);
  m.primitives.push_back(model_.meshes[marker_mesh].primitives[0]);
  model_.meshes.pop_back();  // only its primitive is kept, in this mesh
  model_.meshes.push_back(m);
  return static_cast<int>(model_.meshes.size()) - 1;
}

int GltfBuilder::perspective_camera(const std::string& name, double yfov, double znear, double zfar,
                                    double aspect_ratio) {
  tinygltf::Camera camera;
  camera.name = name;
  camera.type = "perspective";
  camera.perspective.yfov = yfov;
  camera.perspective.znear = znear;
  camera.perspective.zfar = zfar;
  if (aspect_ratio > 0.0) camera.perspective.aspectRatio = aspect_ratio;
  model_.cameras.push_back(camera);
  return static_cast<int>(model_.cameras.size()) - 1;
}

int GltfBuilder::node(const std::string& name, int mesh, const nlohmann::ordered_json& extras,
                      int camera, const std::array<double, 4>& rotation,
                      const core::Vec3& translation) {
  tinygltf::Node n;
  n.name = name;
  n.mesh = mesh;
  n.camera = camera;
  if (rotation != std::array<double, 4>{0, 0, 0, 1}) {
    n.rotation.assign(rotation.begin(), rotation.end());
  }
  if (!translation.isZero(0)) n.translation = {translation.x(), translation.y(), translation.z()};
  n.extras = to_value(extras);
  model_.nodes.push_back(n);
  const int index = static_cast<int>(model_.nodes.size()) - 1;
  model_.scenes[0].nodes.push_back(index);
  return index;
}

void GltfBuilder::set_asset_extras(const nlohmann::ordered_json& extras) {
  model_.asset.extras = to_value(extras);
}

void GltfBuilder::set_scene_extras(const nlohmann::ordered_json& extras) {
  model_.scenes[0].extras = to_value(extras);
}

std::string GltfBuilder::glb() {
  tinygltf::TinyGLTF writer;
  std::ostringstream out;
  if (!writer.WriteGltfSceneToStream(&model_, out, false, true)) {
    throw std::runtime_error("tinygltf could not serialise the glTF model");
  }
  return out.str();
}

}  // namespace camplace::view::detail
