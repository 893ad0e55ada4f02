#include "retriangulate.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

namespace camplace::testing {

using core::Vec3;

namespace {

/// The point with weights `w` on the corners `ids` (weights summing to 1), computed from the
/// corner of lowest id and non-zero weight as origin, the others in ascending order: the same
/// numbers on every triangle that shares those corners, and exact on a plane x, y or z = const.
Vec3 weighted_point(const core::TriangleMesh& mesh, std::array<int, 3> ids,
                    std::array<double, 3> w) {
  std::array<int, 3> order{0, 1, 2};
  // Corners of weight 0 last: a point on an edge depends on that edge's corners only.
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return std::make_pair(w[a] == 0.0, ids[a]) < std::make_pair(w[b] == 0.0, ids[b]);
  });
  const Vec3& origin = mesh.vertices[ids[order[0]]];
  Vec3 p = origin;
  for (int n = 1; n < 3; ++n) {
    const int i = order[n];
    if (w[i] != 0.0) p += w[i] * (mesh.vertices[ids[i]] - origin);
  }
  return p;
}

}  // namespace

core::TriangleMesh subdivide(const core::TriangleMesh& mesh, int k) {
  core::TriangleMesh out;
  out.vertices = mesh.vertices;
  // Key: the corners with a non-zero weight (ascending id) and their integer weights.
  std::map<std::array<int, 6>, int> made;
  for (const auto& t : mesh.triangles) {
    auto vertex = [&](int i, int j) {  // weight k − i − j on t[0], i on t[1], j on t[2]
      const std::array<int, 3> weight{k - i - j, i, j};
      std::array<std::pair<int, int>, 3> parts{};
      for (int n = 0; n < 3; ++n) parts[n] = {t[n], weight[n]};
      std::sort(parts.begin(), parts.end());
      std::array<int, 6> key{-1, 0, -1, 0, -1, 0};
      int at = 0;
      for (const auto& [id, wt] : parts) {
        if (wt == 0) continue;
        key[2 * at] = id;
        key[2 * at + 1] = wt;
        ++at;
      }
      if (at == 1) return key[0];  // a corner
      const auto found = made.find(key);
      if (found != made.end()) return found->second;
      const Vec3 p =
          weighted_point(mesh, t,
                         {static_cast<double>(weight[0]) / k, static_cast<double>(weight[1]) / k,
                          static_cast<double>(weight[2]) / k});
      out.vertices.push_back(p);
      const int id = static_cast<int>(out.vertices.size()) - 1;
      made.emplace(key, id);
      return id;
    };
    for (int j = 0; j < k; ++j) {
      for (int i = 0; i + j < k; ++i) {
        out.triangles.push_back({vertex(i, j), vertex(i + 1, j), vertex(i, j + 1)});
        if (i + j + 1 < k) {
          out.triangles.push_back({vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1)});
        }
      }
    }
  }
  return out;
}

void split_inside(core::TriangleMesh& mesh, int t, const std::array<double, 3>& w) {
  const std::array<int, 3> tri = mesh.triangles[t];
  mesh.vertices.push_back(weighted_point(mesh, tri, w));
  const int p = static_cast<int>(mesh.vertices.size()) - 1;
  mesh.triangles[t] = {tri[0], tri[1], p};
  mesh.triangles.push_back({tri[1], tri[2], p});
  mesh.triangles.push_back({tri[2], tri[0], p});
}

bool split_edge(core::TriangleMesh& mesh, int t, int e, double at) {
  const std::array<int, 3> tri = mesh.triangles[t];
  const int u = tri[e], v = tri[(e + 1) % 3], x = tri[(e + 2) % 3];
  int other = -1, corner = -1;
  for (std::size_t o = 0; o < mesh.triangles.size() && other < 0; ++o) {
    const auto& q = mesh.triangles[o];
    for (int n = 0; n < 3; ++n) {
      if (q[n] == v && q[(n + 1) % 3] == u) {
        other = static_cast<int>(o);
        corner = q[(n + 2) % 3];
      }
    }
  }
  if (other < 0) return false;
  mesh.vertices.push_back(weighted_point(mesh, {u, v, x}, {1.0 - at, at, 0.0}));
  const int m = static_cast<int>(mesh.vertices.size()) - 1;
  mesh.triangles[t] = {u, m, x};
  mesh.triangles.push_back({m, v, x});
  mesh.triangles[other] = {v, m, corner};
  mesh.triangles.push_back({m, u, corner});
  return true;
}

core::TriangleMesh random_splits(const core::TriangleMesh& mesh, std::mt19937& rng, int splits,
                                 bool slivers) {
  core::TriangleMesh out = mesh;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // A weight near 0: 10^-(3..7) with slivers.
  auto small = [&] { return std::pow(10.0, -3.0 - 4.0 * unit(rng)); };
  for (int s = 0; s < splits; ++s) {
    const int t = static_cast<int>(unit(rng) * static_cast<double>(out.triangles.size()));
    if (unit(rng) < 0.5) {
      std::array<double, 3> w{};
      if (slivers) {
        const int i = static_cast<int>(unit(rng) * 3);
        w[i] = small();
        w[(i + 1) % 3] = unit(rng) < 0.5 ? small() : (1.0 - w[i]) * (0.1 + 0.8 * unit(rng));
        w[(i + 2) % 3] = 1.0 - w[i] - w[(i + 1) % 3];
      } else {
        w = {0.1 + 0.8 * unit(rng), 0.1 + 0.8 * unit(rng), 1.0};
        const double sum = w[0] + w[1] + w[2];
        for (double& x : w) x /= sum;
      }
      split_inside(out, t, w);
      continue;
    }
    double at = slivers ? small() : 0.1 + 0.8 * unit(rng);
    if (unit(rng) < 0.5) at = 1.0 - at;
    split_edge(out, t, static_cast<int>(unit(rng) * 3), at);
  }
  return out;
}

core::SceneObject with_mesh(const core::SceneObject& object, core::TriangleMesh mesh) {
  core::SceneObject out = object;
  out.mesh = std::move(mesh);
  out.bounds = core::bounding_box(out.mesh);
  return out;
}

core::Scene cut_every_object(
    const core::Scene& scene,
    const std::function<core::TriangleMesh(const core::TriangleMesh&)>& cut) {
  core::Scene out = scene;
  auto cut_all = [&](std::vector<core::SceneObject>& objects) {
    for (core::SceneObject& o : objects) o = with_mesh(o, cut(o.mesh));
  };
  cut_all(out.static_obstacles);
  for (core::TimeStep& step : out.time_steps) {
    cut_all(step.dynamic_obstacles);
    cut_all(step.critical);
    for (core::Event& event : step.events) cut_all(event.targets);
  }
  return out;
}

}  // namespace camplace::testing
