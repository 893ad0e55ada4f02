// Mesh files through assimp, and the "units"/"up_axis" keys of file objects.
#include "mesh_assimp.hpp"

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <filesystem>
#include <map>
#include <utility>
#include <vector>

#include "camplace/core/error.hpp"
#include "camplace/core/json_reader.hpp"
#include "mesh_checks.hpp"

namespace camplace::core::detail {

namespace {

Eigen::Matrix4d to_eigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d out;
  out << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3,
      m.d4;
  return out;
}

}  // namespace

TriangleMesh read_assimp_mesh_file(const std::string& path, const std::string& scene_file,
                                   const std::string& entry, bool ignore_collada_up) {
  auto fail = [&](const std::string& reason) {
    throw InputError(scene_file, entry, "mesh file " + path + " cannot be read: " + reason);
  };
  std::error_code ec;
  const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
  if (ec) fail(ec.message());
  if (bytes == 0) fail("the file is empty");
  if (bytes > kMaxAssimpFileBytes) {
    fail("the file has " + std::to_string(bytes) + " bytes, more than the " +
         std::to_string(kMaxAssimpFileBytes) + " accepted");
  }
  Assimp::Importer importer;
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, ignore_collada_up);
  // Points and lines are dropped by SortByPType + RemoveComponent; ValidateDataStructure rejects
  // out-of-range indices and the like from a corrupt file before we read the arrays.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                  aiProcess_SortByPType | aiProcess_ValidateDataStructure);
  if (scene == nullptr) {
    const std::string reason = importer.GetErrorString();
    fail(reason.empty() ? "assimp could not read it" : reason);
  }
  if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0 || scene->mRootNode == nullptr) {
    fail("the file holds no complete scene (no meshes)");
  }
  TriangleMesh mesh;
  // Equal coordinates (after the node transforms) become one vertex: formats such as glTF store
  // a vertex once per face normal, which would leave every face a separate open patch.
  std::map<std::array<double, 3>, int> index_of;
  std::size_t elements = 0;
  // Depth-first over the node tree without recursion (a hostile file can nest deeply).
  std::vector<std::pair<const aiNode*, Eigen::Matrix4d>> stack{
      {scene->mRootNode, to_eigen(scene->mRootNode->mTransformation)}};
  while (!stack.empty()) {
    const auto [node, transform] = stack.back();
    stack.pop_back();
    for (unsigned i = 0; i < node->mNumMeshes; ++i) {
      if (node->mMeshes[i] >= scene->mNumMeshes) fail("a node refers to a missing mesh");
      const aiMesh* part = scene->mMeshes[node->mMeshes[i]];
      elements += std::size_t(part->mNumVertices) + part->mNumFaces;
      if (elements > 2 * kMaxAssimpElements) {
        fail("more than " + std::to_string(2 * kMaxAssimpElements) +
             " vertices and triangles together (node instances counted)");
      }
      std::vector<int> local(part->mNumVertices);
      for (unsigned v = 0; v < part->mNumVertices; ++v) {
        const aiVector3D& p = part->mVertices[v];
        const Eigen::Vector4d q = transform * Eigen::Vector4d(p.x, p.y, p.z, 1.0);
        const Vec3 w = q.head<3>() / q.w();
        if (!w.allFinite()) fail("a vertex has a non-finite coordinate");
        const auto [it, added] =
            index_of.emplace(std::array<double, 3>{w.x(), w.y(), w.z()}, int(mesh.vertices.size()));
        if (added) mesh.vertices.push_back(w);
        local[v] = it->second;
      }
      for (unsigned f = 0; f < part->mNumFaces; ++f) {
        const aiFace& face = part->mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines carry no surface
        std::array<int, 3> t{};
        for (int k = 0; k < 3; ++k) {
          if (face.mIndices[k] >= part->mNumVertices) fail("a face uses a vertex out of range");
          t[k] = local[face.mIndices[k]];
        }
        mesh.triangles.push_back(t);
      }
    }
    for (unsigned c = 0; c < node->mNumChildren; ++c) {
      const aiNode* child = node->mChildren[c];
      if (child != nullptr) stack.emplace_back(child, transform * to_eigen(child->mTransformation));
    }
  }
  if (mesh.triangles.empty()) fail("the file holds no triangles");
  return mesh;
}

MeshFileOptions parse_mesh_file_options(const JsonNode& object) {
  MeshFileOptions options;
  for (const char* key : {"units", "up_axis"}) {
    if (object.has(key) && !object.has("file")) {
      object.at(key).fail(std::string("\"") + key + "\" applies only to a \"file\" object");
    }
  }
  if (object.has("units")) {
    const JsonNode u = object.at("units");
    const std::string units = u.string();
    static const std::map<std::string, double> kScale{
        {"m", 1.0}, {"cm", 0.01}, {"mm", 0.001}, {"in", 0.0254}};
    const auto it = kScale.find(units);
    if (it == kScale.end()) u.fail("unknown units \"" + units + "\" (expected m, cm, mm or in)");
    options.unit_scale = it->second;
  }
  if (object.has("up_axis")) {
    const JsonNode a = object.at("up_axis");
    const std::string up = a.string();
    if (up == "file") {
      options.up = MeshFileOptions::UpAxis::file;
    } else if (up == "z") {
      options.up = MeshFileOptions::UpAxis::z;
    } else if (up == "y") {
      options.up = MeshFileOptions::UpAxis::y;
    } else {
      a.fail("unknown up_axis \"" + up + "\" (expected file, z or y)");
    }
  }
  return options;
}

}  // namespace camplace::core::detail
