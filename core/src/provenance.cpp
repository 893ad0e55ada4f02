// Provenance of results: build, content hashes, host and time.
#include "camplace/core/provenance.hpp"

#include <openssl/evp.h>
#include <unistd.h>

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
  SceneHashes out;
  out.scene = sha256_file(scene.file);
  std::string all = out.scene;
  for (const std::string& mesh : scene.mesh_files) {
    out.meshes.emplace_back(mesh, sha256_file(mesh));
    all += "\n" + out.meshes.back().second;
  }
  out.combined = sha256_hex(all);
  return out;
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
