// Provenance of results: build, content hashes, host and time.
#include "camplace/core/provenance.hpp"

#include <openssl/evp.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <ctime>
#include <fstream>
#include <iterator>
#include <memory>
#include <sstream>

#include "camplace/core/error.hpp"

namespace camplace::core {

std::string sha256_hex(const std::string& bytes) {
  std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
  unsigned int length = 0;
  if (EVP_Digest(bytes.data(), bytes.size(), digest.data(), &length, EVP_sha256(), nullptr) != 1) {
    throw std::runtime_error("SHA-256: OpenSSL failed");
  }
  static const char* kHex = "0123456789abcdef";
  std::string out;
  for (unsigned int i = 0; i < length; ++i) {
    out += kHex[digest[i] >> 4];
    out += kHex[digest[i] & 15];
  }
  return out;
}

std::string sha256_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "cannot open the file to hash it");
  std::ostringstream content;
  content << in.rdbuf();
  if (in.bad()) throw InputError(path, "", "cannot read the file to hash it");
  return sha256_hex(content.str());
}

SceneHashes hash_scene(const Scene& scene) {
  std::vector<std::pair<std::string, std::string>> meshes;
  for (const std::string& mesh : scene.mesh_files) meshes.emplace_back(mesh, sha256_file(mesh));
  return combine_scene_hashes(sha256_file(scene.file), std::move(meshes));
}

SceneHashes combine_scene_hashes(std::string scene_file_sha256,
                                 std::vector<std::pair<std::string, std::string>> meshes) {
  SceneHashes out;
  out.scene = std::move(scene_file_sha256);
  out.meshes = std::move(meshes);
  std::string all = out.scene;
  for (const auto& mesh : out.meshes) all += "\n" + mesh.second;
  out.combined = sha256_hex(all);
  return out;
}

namespace {
/// "sha256 1d6fa5ee238a… → 9d6df9c590de…": enough of each hash to tell them apart.
std::string hash_change(const std::string& before, const std::string& after) {
  constexpr std::size_t kShown = 12;
  return "sha256 " + before.substr(0, kShown) + "… → " + after.substr(0, kShown) + "…";
}
}  // namespace

std::vector<std::string> scene_changes(const SceneHashes& recorded, const SceneHashes& now,
                                       const std::string& scene_file) {
  std::vector<std::string> out;
  if (recorded.combined == now.combined) return out;
  if (recorded.scene != now.scene) {
    out.push_back("scene " + scene_file + " changed (" + hash_change(recorded.scene, now.scene) +
                  ")");
  }
  if (recorded.meshes.size() != now.meshes.size()) {
    out.push_back("scene " + scene_file + " uses " + std::to_string(now.meshes.size()) +
                  " mesh files, " + std::to_string(recorded.meshes.size()) + " before");
  }
  // Mesh files by position: the same content at another path is the same mesh.
  for (std::size_t i = 0; i < std::min(recorded.meshes.size(), now.meshes.size()); ++i) {
    if (recorded.meshes[i].second != now.meshes[i].second) {
      out.push_back("mesh file " + now.meshes[i].first + " changed (" +
                    hash_change(recorded.meshes[i].second, now.meshes[i].second) + ")");
    }
  }
  // The combined hashes differ although every part agrees: recorded by another rule.
  if (out.empty()) {
    out.push_back("scene " + scene_file + " changed (" +
                  hash_change(recorded.combined, now.combined) + " over the scene and its meshes)");
  }
  return out;
}

void check_same_scene(const SceneHashes& recorded, const SceneHashes& now,
                      const std::string& scene_file, const std::string& file) {
  const std::vector<std::string> changes = scene_changes(recorded, now, scene_file);
  if (changes.empty()) return;
  std::string reason = "made for another scene (or the scene changed since): ";
  for (std::size_t i = 0; i < changes.size(); ++i) reason += (i > 0 ? "; " : "") + changes[i];
  throw InputError(file, "/provenance/scene_sha256", reason);
}

std::string host_name() {
  std::array<char, 256> name{};
  if (gethostname(name.data(), name.size() - 1) != 0) return "unknown";
  return name.data();
}

std::string now_iso8601() {
  const std::time_t now = std::time(nullptr);
  std::tm local{};
  localtime_r(&now, &local);
  std::array<char, 64> text{};
  std::strftime(text.data(), text.size(), "%Y-%m-%dT%H:%M:%S%z", &local);
  return text.data();
}

Provenance make_provenance(const Scene& scene) {
  return {build_info(), scene.file, hash_scene(scene), host_name(), now_iso8601()};
}

nlohmann::ordered_json provenance_json(const Provenance& p) {
  nlohmann::ordered_json meshes = nlohmann::ordered_json::array();
  for (const auto& [path, hash] : p.scene.meshes)
    meshes.push_back({{"path", path}, {"sha256", hash}});
  return {{"camplace_version", p.build.version},
          {"commit", p.build.commit},
          {"scene", p.scene_file},
          {"scene_sha256", p.scene.combined},
          {"scene_file_sha256", p.scene.scene},
          {"mesh_files", meshes},
          {"host", p.host},
          {"started", p.started}};
}

Provenance provenance_from_json(const JsonNode& node) {
  node.only_keys({"camplace_version", "commit", "scene", "scene_sha256", "scene_file_sha256",
                  "mesh_files", "host", "started"});
  Provenance p;
  p.build.version = node.at("camplace_version").string();
  p.build.commit = node.at("commit").string();
  p.scene_file = node.at("scene").string();
  p.scene.combined = node.at("scene_sha256").string();
  p.scene.scene = node.at("scene_file_sha256").string();
  const JsonNode meshes = node.at("mesh_files");
  for (std::size_t i = 0; i < meshes.array_size(); ++i) {
    const JsonNode m = meshes.at(i);
    m.only_keys({"path", "sha256"});
    p.scene.meshes.emplace_back(m.at("path").string(), m.at("sha256").string());
  }
  p.host = node.at("host").string();
  p.started = node.at("started").string();
  return p;
}

}  // namespace camplace::core
