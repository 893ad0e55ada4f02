// Scene writing: the inverse of the scene loader (scene_parser.cpp, SPEC §2).
#include "camplace/core/scene_writer.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <vector>

#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/core/names.hpp"
#include "scene_format.hpp"

namespace camplace::core {

namespace {

using Json = nlohmann::ordered_json;

Json vec_json(const Vec3& v) { return Json::array({v.x(), v.y(), v.z()}); }

/// A whole number as a JSON integer (30, as hand-written scene files have it), else the double.
Json number_json(double v) {
  if (v == std::trunc(v) && std::abs(v) < 1e15) return Json(static_cast<long long>(v));
  return Json(v);
}

/// v rounded to `digits` significant decimal digits (to_chars/from_chars: no locale).
double round_to_digits(double v, int digits) {
  char buffer[64];
  const auto written =
      std::to_chars(buffer, buffer + sizeof buffer, v, std::chars_format::scientific, digits - 1);
  double r = v;
  std::from_chars(buffer, written.ptr, r);
  return r;
}

/// The degree value the loader reads back as exactly `radians` (d · kDegree), the shortest in
/// decimal: 30 for the radians of "30".
Json degrees_json(double radians) {
  // d ↦ d · kDegree is monotone and each rounding moves the result by at most half an ulp, so
  // every d the loader turns into `radians` lies within 2 ulps of radians / kDegree.
  const double nearest = radians / kDegree;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> exact;
  double d = nearest;
  for (int k = 0; k < 4; ++k) d = std::nextafter(d, -kInf);
  for (int k = 0; k < 9; ++k, d = std::nextafter(d, kInf)) {
    if (d * kDegree == radians) exact.push_back(d);
  }
  // Nearest first: of two equally short decimals the one closer to radians / kDegree (0, never a
  // denormal whose product also rounds to 0).
  std::stable_sort(exact.begin(), exact.end(), [&](double a, double b) {
    return std::abs(a - nearest) < std::abs(b - nearest);
  });
  // No degree value gives these radians (they were not read from a scene file): the nearest.
  if (exact.empty()) return number_json(nearest);
  for (int digits = 1; digits <= 17; ++digits) {
    for (const double candidate : exact) {
      const double rounded = round_to_digits(candidate, digits);
      if (rounded * kDegree == radians) return number_json(rounded);
    }
  }
  return number_json(exact.front());  // 17 digits always read back exactly
}

Json interval_json(const Interval& iv) { return Json::array({iv.lo, iv.hi}); }

Json degrees_interval_json(const Interval& iv) {
  return Json::array({degrees_json(iv.lo), degrees_json(iv.hi)});
}

bool same_interval(const Interval& a, const Interval& b) { return a.lo == b.lo && a.hi == b.hi; }

bool same_domain(const CameraDomain& a, const CameraDomain& b) {
  return same_interval(a.x, b.x) && same_interval(a.y, b.y) && same_interval(a.z, b.z) &&
         same_interval(a.yaw, b.yaw) && same_interval(a.pitch, b.pitch) &&
         same_interval(a.roll, b.roll) && a.mount.has_value() == b.mount.has_value() &&
         (!a.mount || a.mount->name == b.mount->name);
}

/// A preset's name when the domain is exactly that preset, else {x, y, z[, yaw_deg, pitch_deg]}.
Json domain_json(const Box3& area, const CameraDomain& d) {
  if (d.mount) return Json{{"mount", d.mount->name}};
  for (const char* preset : {"room", "ceiling", "upper_fourth"}) {
    if (same_domain(d, *domain_preset(area, preset))) return preset;
  }
  const CameraDomain unrestricted;
  Json j;
  j["x"] = interval_json(d.x);
  j["y"] = interval_json(d.y);
  j["z"] = interval_json(d.z);
  if (!same_interval(d.yaw, unrestricted.yaw)) j["yaw_deg"] = degrees_interval_json(d.yaw);
  if (!same_interval(d.pitch, unrestricted.pitch)) j["pitch_deg"] = degrees_interval_json(d.pitch);
  if (!same_interval(d.roll, unrestricted.roll)) j["roll_deg"] = degrees_interval_json(d.roll);
  return j;
}

/// A model's keys (without name and count): the fov and its angles, the range (far, or
/// [near, far] with a near plane).
void add_model_json(Json& j, const CameraModel& m) {
  if (m.fov == FovShape::frustum) {
    j["fov"] = name_of(m.fov);
    j["horizontal_deg"] = degrees_json(m.horizontal);
    j["vertical_deg"] = degrees_json(m.vertical);
  } else {
    j["half_angle_deg"] = degrees_json(m.half_angle);
    j["fov"] = name_of(m.fov);
    j["sides"] = m.sides;
  }
  if (m.near > 0.0) {
    CAMPLACE_ASSERT(m.range.has_value());
    j["range"] = Json::array({m.near, *m.range});
  } else if (m.range) {
    j["range"] = *m.range;
  }
  if (m.cost) j["cost"] = *m.cost;
}

Json cameras_json(const Scene& scene) {
  const CameraSpec& c = scene.cameras;
  CAMPLACE_ASSERT(c.count >= 1 && c.domains.size() == static_cast<std::size_t>(c.count));
  CAMPLACE_ASSERT(c.models.size() == static_cast<std::size_t>(c.count));
  Json j;
  j["count"] = c.count;
  if (!c.mounts.empty()) {
    Json mounts = Json::array();
    const Mount unrestricted;
    for (const Mount& m : c.mounts) {
      Json mj;
      mj["name"] = m.name;
      mj["corner"] = Json::array({m.corner.x(), m.corner.y(), m.corner.z()});
      mj["edges"] = Json::array(
          {Json::array({m.u.x(), m.u.y(), m.u.z()}), Json::array({m.v.x(), m.v.y(), m.v.z()})});
      if (!same_interval(m.yaw, unrestricted.yaw)) mj["yaw_deg"] = degrees_interval_json(m.yaw);
      if (!same_interval(m.pitch, unrestricted.pitch))
        mj["pitch_deg"] = degrees_interval_json(m.pitch);
      if (!same_interval(m.roll, unrestricted.roll)) mj["roll_deg"] = degrees_interval_json(m.roll);
      mounts.push_back(mj);
    }
    j["mounts"] = mounts;
  }
  if (!c.keep_out.empty()) {
    Json boxes = Json::array();
    for (const KeepOut& k : c.keep_out) {
      Json kj;
      if (k.name != k.entry) kj["name"] = k.name;
      kj["min"] = Json::array({k.box.min.x(), k.box.min.y(), k.box.min.z()});
      kj["max"] = Json::array({k.box.max.x(), k.box.max.y(), k.box.max.z()});
      boxes.push_back(kj);
    }
    j["keep_out"] = boxes;
  }
  bool listed = false;
  if (c.one_model() && c.models.front().name.empty()) {
    add_model_json(j, c.models.front());
  } else {
    // The catalogue in order of first use; per-model counts when the cameras come grouped in
    // that order, else a list naming each camera's model.
    std::vector<const CameraModel*> catalogue;
    std::vector<int> uses;
    bool grouped = true;
    for (const CameraModel& m : c.models) {
      CAMPLACE_ASSERT(!m.name.empty());
      auto it = std::find_if(catalogue.begin(), catalogue.end(),
                             [&](const CameraModel* k) { return k->name == m.name; });
      if (it == catalogue.end()) {
        catalogue.push_back(&m);
        uses.push_back(1);
      } else {
        grouped = grouped && it + 1 == catalogue.end();
        ++uses[it - catalogue.begin()];
      }
    }
    Json models = Json::array();
    for (std::size_t k = 0; k < catalogue.size(); ++k) {
      Json m;
      m["name"] = catalogue[k]->name;
      add_model_json(m, *catalogue[k]);
      if (grouped) m["count"] = uses[k];
      models.push_back(m);
    }
    j["models"] = models;
    if (!grouped) listed = true;
  }
  bool shared = true;
  for (const CameraDomain& d : c.domains) shared = shared && same_domain(d, c.domains.front());
  if (listed) {
    // The list names each camera's model and, when they differ, its domain.
    Json list = Json::array();
    for (int i = 0; i < c.count; ++i) {
      Json entry;
      entry["model"] = c.models[i].name;
      if (!shared) entry["domain"] = domain_json(scene.area, c.domains[i]);
      list.push_back(entry);
    }
    j["list"] = list;
    if (shared) j["domain"] = domain_json(scene.area, c.domains.front());
  } else if (shared) {
    j["domain"] = domain_json(scene.area, c.domains.front());
  } else {
    Json list = Json::array();
    for (const CameraDomain& d : c.domains) list.push_back(domain_json(scene.area, d));
    j["camera_domains"] = list;
  }
  return j;
}

bool is_box(const TriangleMesh& mesh) {
  if (mesh.vertices.size() != 8) return false;
  const Vec3& lo = mesh.vertices.front();
  const Vec3& hi = mesh.vertices.back();
  if (!(lo.array() < hi.array()).all()) return false;
  const TriangleMesh box = detail::box_mesh(lo, hi);
  return mesh.vertices == box.vertices && mesh.triangles == box.triangles;
}

bool is_tetrahedron(const TriangleMesh& mesh) {
  if (mesh.vertices.size() != 4) return false;
  TriangleMesh tetra = detail::tetrahedron_mesh(mesh.vertices);
  // Turned outward as the loader does (validate_and_orient).
  if (signed_volume(tetra) < 0) {
    for (auto& t : tetra.triangles) std::swap(t[1], t[2]);
  }
  return mesh.triangles == tetra.triangles;
}

Json object_json(const SceneObject& o) {
  Json j;
  j["name"] = o.name;
  if (is_tetrahedron(o.mesh)) {
    Json points = Json::array();
    for (const Vec3& v : o.mesh.vertices) points.push_back(vec_json(v));
    j["tetrahedron"] = points;
  } else if (is_box(o.mesh)) {
    j["box"] = {{"min", vec_json(o.mesh.vertices.front())},
                {"max", vec_json(o.mesh.vertices.back())}};
  } else {
    Json vertices = Json::array(), triangles = Json::array();
    for (const Vec3& v : o.mesh.vertices) vertices.push_back(vec_json(v));
    for (const auto& t : o.mesh.triangles) triangles.push_back(Json::array({t[0], t[1], t[2]}));
    j["mesh"] = {{"vertices", vertices}, {"triangles", triangles}};
  }
  return j;
}

Json objects_json(const std::vector<SceneObject>& objects) {
  Json list = Json::array();
  for (const SceneObject& o : objects) list.push_back(object_json(o));
  return list;
}

bool same_objects(const std::vector<SceneObject>& a, const std::vector<SceneObject>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (a[k].name != b[k].name || a[k].entry != b[k].entry ||
        a[k].mesh.vertices != b[k].mesh.vertices || a[k].mesh.triangles != b[k].mesh.triangles) {
      return false;
    }
  }
  return true;
}

Json time_step_json(const TimeStep& step) {
  Json j;
  j["t"] = step.t;
  j["dynamic_obstacles"] = objects_json(step.dynamic_obstacles);
  // The loader's default (SPEC §2) copies the dynamic obstacles, entries included.
  if (!same_objects(step.critical, step.dynamic_obstacles)) {
    j["critical"] = objects_json(step.critical);
  }
  Json events = Json::array();
  for (const Event& e : step.events) {
    events.push_back({{"weight", e.weight}, {"targets", objects_json(e.targets)}});
  }
  j["events"] = events;
  return j;
}

}  // namespace

nlohmann::ordered_json scene_json(const Scene& scene, const std::string& description) {
  Json doc;
  if (!description.empty()) doc["description"] = description;
  doc["area"] = {{"min", vec_json(scene.area.min)}, {"max", vec_json(scene.area.max)}};
  doc["voxels"] = Json::array({scene.voxels[0], scene.voxels[1], scene.voxels[2]});
  doc["cameras"] = cameras_json(scene);
  doc["static_obstacles"] = objects_json(scene.static_obstacles);
  Json steps = Json::array();
  for (const TimeStep& step : scene.time_steps) steps.push_back(time_step_json(step));
  doc["time_steps"] = steps;
  doc["dynamic_mode"] = name_of(scene.dynamic_mode);
  const Plausibility& p = scene.plausibility;
  if (p.min_volume != 0.0 || p.min_height != 0.0) {
    doc["plausibility"] = {{"min_volume", p.min_volume}, {"min_height", p.min_height}};
  }
  return doc;
}

std::string scene_text(const Scene& scene, const std::string& description) {
  return scene_json(scene, description).dump(1) + "\n";
}

void write_scene(const Scene& scene, const std::string& path, const std::string& description) {
  write_file_atomically(path, scene_text(scene, description));
}

}  // namespace camplace::core
