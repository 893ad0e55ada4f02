#include "retriangulate.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "scene_builder.hpp"

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

namespace {

/// The convex prism over the quadrilateral (x, z) = (0.3, −0.6), (6, −0.6), (6, −0.35),
/// (3, −0.35), for y in [−0.5, 0.5]: 8 corners, 6 faces, 12 triangles oriented outward.
core::SceneObject prism_object() {
  core::SceneObject o;
  o.name = o.entry = "prism";
  const std::array<std::array<double, 2>, 4> q{
      {{0.3, -0.6}, {6.0, -0.6}, {6.0, -0.35}, {3.0, -0.35}}};
  for (double y : {-0.5, 0.5}) {
    for (const auto& xz : q) o.mesh.vertices.emplace_back(xz[0], y, xz[1]);
  }
  const std::array<std::array<int, 4>, 6> faces{
      {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}}};
  Vec3 centre = Vec3::Zero();
  for (const Vec3& v : o.mesh.vertices) centre += v / 8.0;
  for (const auto& f : faces) {
    for (const std::array<int, 3> t : {std::array<int, 3>{f[0], f[1], f[2]}, {f[0], f[2], f[3]}}) {
      const Vec3 &a = o.mesh.vertices[t[0]], &b = o.mesh.vertices[t[1]], &c = o.mesh.vertices[t[2]];
      const bool outward = (b - a).cross(c - a).dot((a + b + c) / 3.0 - centre) > 0;
      o.mesh.triangles.push_back(outward ? t : std::array<int, 3>{t[0], t[2], t[1]});
    }
  }
  o.bounds = core::bounding_box(o.mesh);
  return o;
}

}  // namespace

core::Scene slab_scene() {
  const core::Box3 area{Vec3(0.1, -1.1, -1.1), Vec3(4.1, 1.1, 1.1)};
  core::Scene scene =
      simple_scene(area, {20, 11, 11}, 1, 30.0,
                   {box_object("critical", Vec3(3.6, 0.7, 0.5), Vec3(3.8, 0.9, 0.7))},
                   {box_object("target", Vec3(1.5, 0.7, 0.5), Vec3(1.7, 0.9, 0.7))});
  scene.static_obstacles.push_back(box_object("slab", Vec3(0.2, -0.5, -0.5), Vec3(3.5, 0.5, -0.3)));
  return scene;
}

core::Scene prism_scene() {
  const core::Box3 area{Vec3(0.1, -1.1, -1.1), Vec3(6.1, 1.1, 1.1)};
  core::Scene scene =
      simple_scene(area, {30, 11, 11}, 1, 30.0,
                   {box_object("critical", Vec3(3.6, 0.7, 0.5), Vec3(3.8, 0.9, 0.7))},
                   {box_object("target", Vec3(1.5, 0.7, 0.5), Vec3(1.7, 0.9, 0.7))});
  scene.static_obstacles.push_back(prism_object());
  return scene;
}

}  // namespace camplace::testing
