#pragma once
// Scenes with one object crossing a face of the area S (SPEC §2: obstacles and critical objects
// may extend beyond S), for the voxel and the exact pipelines' tests (tests/voxel/
// beyond_area_test.cpp, tests/exact/beyond_area_exact_test.cpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>

#include "camplace/core/camera.hpp"
#include "camplace/core/scene.hpp"
#include "scene_builder.hpp"

namespace camplace::testing::beyond {

using core::Box3;
using core::Vec3;

/// The kind of the object that crosses a face of S.
enum class Kind { static_obstacle, masked_dynamic, modelled_dynamic };
constexpr std::array<Kind, 3> kKinds{Kind::static_obstacle, Kind::masked_dynamic,
                                     Kind::modelled_dynamic};
inline const char* kind_name(Kind k) {
  return k == Kind::static_obstacle ? "static" : k == Kind::masked_dynamic ? "masked" : "modelled";
}

inline const Box3 kArea{Vec3(0, 0, 0), Vec3(4, 3, 3)};

/// The face of S: axis 0..2, side 0 (min) or 1 (max); face = 2·axis + side.
struct Face {
  int axis, side;
};
inline Face face_of(int f) { return {f / 2, f % 2}; }

/// A crossing scene: what the tests need to know besides the scene itself.
struct Crossing {
  core::Scene scene;
  Box3 outside_part;  ///< the crossing box's part outside S (the whole box beyond the face)
  bool crossing_is_box = true;
  core::CameraConfig config;
};

/// A box reaching from `out` metres beyond face f to `in` metres inside S along the face's
/// axis; across it, a random interval of S's extent (widened by 0.5 m, so it may cross other
/// faces as well).
inline Box3 crossing_box(std::mt19937& rng, Face f, double out, double in) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Box3 b;
  for (int a = 0; a < 3; ++a) {
    if (a == f.axis) {
      const double face = f.side ? kArea.max[a] : kArea.min[a];
      const double s = f.side ? 1.0 : -1.0;  // outward
      b.min[a] = std::min(face + s * out, face - s * in);
      b.max[a] = std::max(face + s * out, face - s * in);
    } else {
      const double lo = kArea.min[a] - 0.5, size = kArea.max[a] - kArea.min[a] + 1.0;
      const double w = 0.5 + unit(rng) * 1.5;
      const double start = lo + unit(rng) * (size - w);
      b.min[a] = start;
      b.max[a] = start + w;
    }
  }
  return b;
}

/// A random scene over S = 4×3×3 m with one object of kind `kind` crossing face f (a box, or a
/// tetrahedron with two vertices outside S and two inside), two targets per event (two events)
/// in the half of S away from the face, and for static crossings a small dynamic obstacle in S
/// as the critical object (for dynamic crossings the crossing object is the critical one,
/// partly outside S). Cameras: 0 inside S aimed at the crossing object, 1 outside S behind the
/// crossing object's outside part aimed into S (its rays to S pass through that part), 2 either
/// inside the outside part (blind) or elsewhere outside S looking at S's centre.
inline Crossing crossing_scene(std::mt19937& rng, int face, Kind kind) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Face f = face_of(face);
  const double out = 0.4 + 1.2 * unit(rng), in = 0.3 + 0.7 * unit(rng);
  Crossing c;
  const Box3 box = crossing_box(rng, f, out, in);
  core::SceneObject crossing;
  c.crossing_is_box = unit(rng) < 0.7;
  if (c.crossing_is_box) {
    crossing = box_object("crossing", box.min, box.max);
  } else {
    // Two vertices beyond the face, two inside S, within the box.
    auto point = [&](bool beyond) {
      Vec3 p;
      for (int a = 0; a < 3; ++a) p[a] = box.min[a] + unit(rng) * (box.max[a] - box.min[a]);
      const double face_at = f.side ? kArea.max[f.axis] : kArea.min[f.axis];
      const double s = f.side ? 1.0 : -1.0;
      p[f.axis] = face_at + (beyond ? s : -s) * (0.1 + unit(rng) * ((beyond ? out : in) - 0.1));
      return p;
    };
    for (;;) {
      const Vec3 a = point(true), b = point(true), d = point(false), e = point(false);
      if (std::abs((b - a).cross(d - a).dot(e - a)) > 0.05) {
        crossing = tetra_object("crossing", a, b, d, e);
        break;
      }
    }
  }
  c.outside_part = box;
  const double face_at = f.side ? kArea.max[f.axis] : kArea.min[f.axis];
  (f.side ? c.outside_part.min : c.outside_part.max)[f.axis] = face_at;

  // Targets: in the far half of S along the face's axis (clear of the crossing object, which
  // reaches at most 1 m into S).
  auto target = [&](const std::string& name) {
    Vec3 lo, hi;
    for (int a = 0; a < 3; ++a) {
      double from = kArea.min[a] + 0.1, to = kArea.max[a] - 0.1;
      if (a == f.axis) {
        if (f.side) {
          to = kArea.min[a] + 0.45 * (kArea.max[a] - kArea.min[a]);
        } else {
          from = kArea.max[a] - 0.45 * (kArea.max[a] - kArea.min[a]);
        }
      }
      const double w = 0.2 + unit(rng) * 0.4;
      lo[a] = from + unit(rng) * (to - from - w);
      hi[a] = lo[a] + w;
    }
    return box_object(name, lo, hi);
  };
  core::Scene& s = c.scene;
  s = simple_scene(kArea, {12, 9, 9}, 3, 25.0 + 35.0 * unit(rng), {}, {});
  s.time_steps.clear();
  core::TimeStep step;
  if (kind == Kind::static_obstacle) {
    s.static_obstacles.push_back(crossing);
    // A small critical box in the far half, not touching the targets (they are in other cells
    // with high probability; overlap would be legal for labels and distances alike).
    Vec3 lo = kArea.center() - Vec3::Constant(0.15);
    lo[f.axis] = f.side ? kArea.min[f.axis] + 0.1 : kArea.max[f.axis] - 0.4;
    step.dynamic_obstacles.push_back(box_object("robot", lo, lo + Vec3::Constant(0.3)));
  } else {
    step.dynamic_obstacles.push_back(crossing);
  }
  step.critical = step.dynamic_obstacles;
  for (int l = 0; l < 2; ++l) {
    core::Event e;
    e.weight = 0.5;
    e.targets.push_back(target("target a"));
    e.targets.push_back(target("target b"));
    step.events.push_back(e);
  }
  s.time_steps.push_back(step);
  const bool pyramid = unit(rng) < 0.5;
  for (core::CameraModel& m : s.cameras.models) {
    m.fov = pyramid ? core::FovShape::pyramid : core::FovShape::cone;
    m.sides = 3 + static_cast<int>(unit(rng) * 6);
  }
  s.dynamic_mode =
      kind == Kind::modelled_dynamic ? core::DynamicMode::modelled : core::DynamicMode::masked;

  auto aim = [&](const Vec3& from, const Vec3& at, double jitter_deg) {
    const Vec3 d = at - from;
    const double yaw = std::atan2(d.y(), d.x()) * 180.0 / 3.14159265358979323846;
    const double pitch =
        std::atan2(d.z(), std::hypot(d.x(), d.y())) * 180.0 / 3.14159265358979323846;
    return camera_at(from, yaw + jitter_deg * (2 * unit(rng) - 1),
                     std::clamp(pitch + jitter_deg * (2 * unit(rng) - 1), -89.0, 89.0));
  };
  auto random_in = [&](const Box3& b) {
    return Vec3(b.min.x() + unit(rng) * (b.max.x() - b.min.x()),
                b.min.y() + unit(rng) * (b.max.y() - b.min.y()),
                b.min.z() + unit(rng) * (b.max.z() - b.min.z()));
  };
  // Camera 0: inside S, looking toward the crossing object (masked: rays that first meet its
  // outside part beyond a voxel occupy the voxel).
  Box3 inner{kArea.min + Vec3::Constant(0.2), kArea.max - Vec3::Constant(0.2)};
  (f.side ? inner.min : inner.max)[f.axis] = kArea.center()[f.axis];
  c.config.push_back(aim(random_in(inner), box.center(), 15.0));
  // Camera 1: outside S, behind the outside part (farther out along the face's normal, across it
  // within the box's span), looking into S: its rays to S go through the outside part.
  {
    Vec3 p = random_in(box);
    const double s = f.side ? 1.0 : -1.0;
    p[f.axis] = face_at + s * (out + 0.2 + unit(rng) * 0.8);
    c.config.push_back(aim(p, kArea.center(), 10.0));
  }
  // Camera 2: half of the time inside the outside part (blind: sees nothing), else outside S on
  // another side, looking at S's centre.
  if (unit(rng) < 0.5 && c.crossing_is_box) {
    Box3 part = c.outside_part;
    part.min += Vec3::Constant(0.05);
    part.max -= Vec3::Constant(0.05);
    c.config.push_back(aim(random_in(part), kArea.center(), 30.0));
  } else {
    const int a = (f.axis + 1 + static_cast<int>(unit(rng) * 2)) % 3;
    Vec3 p = random_in(kArea);
    p[a] = unit(rng) < 0.5 ? kArea.min[a] - 0.3 - unit(rng) : kArea.max[a] + 0.3 + unit(rng);
    c.config.push_back(aim(p, kArea.center(), 10.0));
  }
  return c;
}

/// The same scene with every box obstacle clipped to S (for the check that the parts outside S
/// decide labels: a pipeline that ignored them would be caught). Non-box objects are kept.
inline core::Scene clipped_to_area(const Crossing& c) {
  core::Scene s = c.scene;
  auto clip = [&](core::SceneObject& o) {
    if (!c.crossing_is_box || o.name != "crossing") return;
    o = box_object(o.name, o.bounds.min.cwiseMax(kArea.min), o.bounds.max.cwiseMin(kArea.max));
  };
  for (auto& o : s.static_obstacles) clip(o);
  for (auto& step : s.time_steps) {
    for (auto& o : step.dynamic_obstacles) clip(o);
    for (auto& o : step.critical) clip(o);
  }
  return s;
}

/// Random cameras anywhere in S grown by 1.5 m (inside and outside S, some inside the crossing
/// object's outside part), looking anywhere.
inline core::CameraConfig random_wide_config(std::mt19937& rng, const core::Scene& scene) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  core::CameraConfig config;
  for (int i = 0; i < scene.cameras.count; ++i) {
    const Vec3 lo = scene.area.min - Vec3::Constant(1.5),
               size = scene.area.size() + Vec3::Constant(3);
    const Vec3 p = lo + Vec3(unit(rng), unit(rng), unit(rng)).cwiseProduct(size);
    config.push_back(camera_at(p, -180 + 360 * unit(rng), -90 + 180 * unit(rng)));
  }
  return config;
}

}  // namespace camplace::testing::beyond
