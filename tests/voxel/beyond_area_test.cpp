// Obstacles and critical objects that extend beyond the area S (SPEC §2: they occlude and,
// masked, change pixels wherever they are; the model is always inside S): the voxel labels of
// both modes against the brute-force references (tests/support/reference.cpp, which know
// nothing of S) with an object crossing each face of S, for each kind of obstacle, with cameras
// inside S, outside it behind the object's outside part, and inside that outside part (blind);
// the model (interiors subtracted) and the distances against values computed independently.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>

#include "camplace/core/distance.hpp"
#include "camplace/core/err.hpp"
#include "lower_bound_reference.hpp"
#include "reference.hpp"
#include "scene_builder.hpp"

namespace camplace::testing {
namespace {

using core::Box3;
using core::Vec3;
using voxel::Label;
using voxel::LabelMode;

/// The kind of the object that crosses a face of S.
enum class Kind { static_obstacle, masked_dynamic, modelled_dynamic };
constexpr std::array<Kind, 3> kKinds{Kind::static_obstacle, Kind::masked_dynamic,
                                     Kind::modelled_dynamic};
const char* kind_name(Kind k) {
  return k == Kind::static_obstacle ? "static" : k == Kind::masked_dynamic ? "masked" : "modelled";
}

const Box3 kArea{Vec3(0, 0, 0), Vec3(4, 3, 3)};

/// The face of S: axis 0..2, side 0 (min) or 1 (max); face = 2·axis + side.
struct Face {
  int axis, side;
};
Face face_of(int f) { return {f / 2, f % 2}; }

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
Box3 crossing_box(std::mt19937& rng, Face f, double out, double in) {
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
Crossing crossing_scene(std::mt19937& rng, int face, Kind kind) {
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
core::Scene clipped_to_area(const Crossing& c) {
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

struct Tally {
  long compared = 0, ties = 0, decided_outside = 0;
  std::array<long, 3> by_label{};
};

/// Every voxel label of `mode` for every face × kind × `per_face` scenes against the reference
/// of that mode; also counts the labels that the parts outside S decide (the reference on the
/// scene clipped to S differs).
void compare_crossing_labels(LabelMode mode, unsigned seed, int per_face, Tally& tally) {
  std::mt19937 rng(seed);
  for (int face = 0; face < 6; ++face) {
    for (Kind kind : kKinds) {
      for (int n = 0; n < per_face; ++n) {
        const Crossing c = crossing_scene(rng, face, kind);
        const core::Scene clipped = clipped_to_area(c);
        const voxel::VoxelEvaluator evaluator(c.scene, {mode, {0, 0, 0}});
        const voxel::Grid& grid = evaluator.grid();
        const auto all_states = core::states(c.scene);
        for (std::size_t st = 0; st < all_states.size(); ++st) {
          const int h = all_states[st].time_step, l = all_states[st].event;
          for (int cam = 0; cam < c.scene.cameras.count; ++cam) {
            const auto labels = evaluator.labels(c.config[cam], static_cast<int>(st), cam);
            for (int v = 0; v < grid.count(); ++v) {
              auto reference = [&](const core::Scene& scene) {
                return mode == LabelMode::center
                           ? reference_label(scene, h, l, c.config[cam], grid.voxel_center(v), 1e-7,
                                             cam)
                           : reference_box_label(scene, h, l, c.config[cam], grid.voxel_box(v),
                                                 1e-7, cam);
              };
              const ReferenceLabel ref = reference(c.scene);
              if (ref.ambiguous) {
                ++tally.ties;
                continue;
              }
              ++tally.compared;
              ++tally.by_label[static_cast<int>(ref.label)];
              const ReferenceLabel inside_only = reference(clipped);
              if (!inside_only.ambiguous && inside_only.label != ref.label) {
                ++tally.decided_outside;
              }
              ASSERT_EQ(labels[v], ref.label)
                  << "face " << face << " " << kind_name(kind) << " scene " << n << " state " << st
                  << " camera " << cam << " at " << c.config[cam].position.transpose() << " voxel "
                  << v;
            }
          }
        }
      }
    }
  }
}

TEST(BeyondArea, CenterLabelsEqualReferenceWithObstaclesCrossingEachFace) {
  Tally t;
  compare_crossing_labels(LabelMode::center, 20261201, 3, t);
  EXPECT_GT(t.compared, 100 * t.ties);
  for (long n : t.by_label) EXPECT_GT(n, 1000);
  // The parts outside S decide many labels: clipping the obstacles to S would fail this test.
  EXPECT_GT(t.decided_outside, 1000);
}

TEST(BeyondArea, ConservativeLabelsEqualBoxReferenceWithObstaclesCrossingEachFace) {
  Tally t;
  compare_crossing_labels(LabelMode::conservative, 20261202, 3, t);
  EXPECT_GT(t.compared, 100 * t.ties);
  for (long n : t.by_label) EXPECT_GT(n, 1000);
  EXPECT_GT(t.decided_outside, 1000);
}

/// Random cameras anywhere in S grown by 1.5 m (inside and outside S, some inside the crossing
/// object's outside part), looking anywhere.
core::CameraConfig random_wide_config(std::mt19937& rng, const core::Scene& scene) {
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

/// Conservative mode's free voxels are free at 35 points each (the 3×3×3 lattice and 8 random
/// points) by the point reference, which needs no culling rule: soundness on crossing scenes
/// with the scenes' cameras and random ones inside and outside S.
TEST(BeyondArea, ConservativeFreeVoxelsAreFreeAtSampledPointsWithObstaclesCrossingEachFace) {
  std::mt19937 rng(20261203);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  long free_voxels = 0;
  for (int face = 0; face < 6; ++face) {
    for (Kind kind : kKinds) {
      const Crossing c = crossing_scene(rng, face, kind);
      const voxel::VoxelEvaluator evaluator(c.scene, {LabelMode::conservative, {0, 0, 0}});
      for (const core::CameraConfig& config : {c.config, random_wide_config(rng, c.scene)}) {
        const auto all_states = core::states(c.scene);
        for (std::size_t st = 0; st < all_states.size(); ++st) {
          for (int cam = 0; cam < c.scene.cameras.count; ++cam) {
            const auto labels = evaluator.labels(config[cam], static_cast<int>(st), cam);
            for (int v = 0; v < evaluator.grid().count(); ++v) {
              if (labels[v] != Label::free) continue;
              ++free_voxels;
              const Box3 box = evaluator.grid().voxel_box(v);
              for (int a = 0; a < 35; ++a) {
                const Vec3 f = a < 27 ? Vec3(a % 3, (a / 3) % 3, a / 9) / 2.0
                                      : Vec3(unit(rng), unit(rng), unit(rng));
                const Vec3 p = box.min + box.size().cwiseProduct(f);
                const ReferenceLabel ref =
                    reference_label(c.scene, all_states[st].time_step, all_states[st].event,
                                    config[cam], p, 1e-7, cam);
                ASSERT_TRUE(ref.ambiguous || ref.label == Label::free)
                    << "face " << face << " " << kind_name(kind) << " state " << st << " camera "
                    << cam << " voxel " << v << " point " << p.transpose();
              }
            }
          }
        }
      }
    }
  }
  EXPECT_GT(free_voxels, 2000);
}

/// The conservative lower bound with occupying objects (masked dynamic obstacles) crossing S:
/// equal to the brute-force reference (tests/voxel/lower_bound_reference.hpp, every voxel, no
/// index ranges), its proven voxels in every model and no Err below it, for the scene's cameras
/// and random ones inside and outside S; also with a plausibility filter.
TEST(BeyondArea, LowerBoundEqualsReferenceAndHoldsWithObjectsCrossingEachFace) {
  std::mt19937 rng(20261204);
  long proven_total = 0;
  for (int face = 0; face < 6; ++face) {
    for (Kind kind : kKinds) {
      Crossing c = crossing_scene(rng, face, kind);
      if (face % 2 == 1) c.scene.plausibility = {0.02, 0.3};
      const voxel::VoxelEvaluator evaluator(c.scene, {LabelMode::conservative, {0, 0, 0}});
      const double bound = evaluator.err_lower_bound();
      const std::string what = "face " + std::to_string(face) + " " + kind_name(kind);
      EXPECT_EQ(bound, reference_lower_bound(c.scene, evaluator.grid())) << what;
      const auto proven = reference_proven_voxels(c.scene, evaluator.grid());
      std::vector<core::CameraConfig> configs{c.config};
      for (int n = 0; n < 4; ++n) configs.push_back(random_wide_config(rng, c.scene));
      for (const core::CameraConfig& config : configs) {
        EXPECT_GE(core::lower_bound_threshold(evaluator.err(config)), bound) << what;
        for (std::size_t s = 0; s < proven.size(); ++s) {
          const auto model = evaluator.model(config, static_cast<int>(s));
          for (int v = 0; v < evaluator.grid().count(); ++v) {
            if (!proven[s][v]) continue;
            ++proven_total;
            ASSERT_EQ(model[v], 1) << what << " state " << s << " voxel " << v;
          }
        }
      }
    }
  }
  EXPECT_GT(proven_total, 1000);
}

/// Refinement (2 levels) with obstacles crossing each face: every point of S that no camera sees
/// free by the point reference and that lies in no obstacle is in a finest cell of the refined
/// model (no plausibility filter), and the refined model lies in the unrefined one.
TEST(BeyondArea, RefinedModelHoldsEveryReferenceModelPointWithObstaclesCrossingEachFace) {
  std::mt19937 rng(20261205);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  long in_model = 0;
  for (int face = 0; face < 6; ++face) {
    for (Kind kind : kKinds) {
      const Crossing c = crossing_scene(rng, face, kind);
      voxel::VoxelOptions options{LabelMode::conservative, {0, 0, 0}};
      options.refine = 2;
      const voxel::VoxelEvaluator refined(c.scene, options);
      const voxel::VoxelEvaluator base(c.scene, {LabelMode::conservative, {0, 0, 0}});
      const voxel::Grid cells = refined.leaf_grid();
      const auto all_states = core::states(c.scene);
      for (const core::CameraConfig& config : {c.config, random_wide_config(rng, c.scene)}) {
        for (std::size_t st = 0; st < all_states.size(); ++st) {
          const auto model = refined.leaf_model(config, static_cast<int>(st));
          const auto coarse = base.model(config, static_cast<int>(st));
          const auto refined_base = refined.model(config, static_cast<int>(st));
          for (std::size_t v = 0; v < coarse.size(); ++v) {
            ASSERT_LE(refined_base[v], coarse[v]) << "face " << face << " voxel " << v;
          }
          const auto& step = c.scene.time_steps[all_states[st].time_step];
          for (int i = 0; i < 150; ++i) {
            const Vec3 p =
                kArea.min + Vec3(unit(rng), unit(rng), unit(rng)).cwiseProduct(kArea.size());
            bool ambiguous = false, non_free = true;
            for (int cam = 0; cam < c.scene.cameras.count; ++cam) {
              const ReferenceLabel ref =
                  reference_label(c.scene, all_states[st].time_step, all_states[st].event,
                                  config[cam], p, 1e-7, cam);
              ambiguous |= ref.ambiguous;
              non_free = non_free && ref.label != Label::free;
            }
            bool in_obstacle = false;
            for (const auto& o : c.scene.static_obstacles)
              in_obstacle |= reference_inside(o.mesh, p);
            for (const auto& o : step.dynamic_obstacles) in_obstacle |= reference_inside(o.mesh, p);
            if (ambiguous || !non_free || in_obstacle) continue;
            ++in_model;
            std::array<int, 3> ijk{};
            for (int k = 0; k < 3; ++k) {
              ijk[k] = std::clamp(int(std::floor((p[k] - kArea.min[k]) / cells.step[k])), 0,
                                  cells.n[k] - 1);
            }
            EXPECT_TRUE(model[ijk[0] + cells.n[0] * (ijk[1] + cells.n[1] * ijk[2])])
                << "face " << face << " " << kind_name(kind) << " state " << st << " point "
                << p.transpose();
          }
        }
      }
    }
  }
  EXPECT_GT(in_model, 500);
}

/// Camera 2 inside the crossing box's outside part sees nothing in either mode, and a camera
/// outside S sees voxels of S free.
TEST(BeyondArea, CameraInsideAnOutsidePartIsBlindAndCamerasOutsideSSee) {
  for (LabelMode mode : {LabelMode::center, LabelMode::conservative}) {
    core::Scene s = simple_scene(kArea, {8, 6, 6}, 2, 40.0, {}, {});
    s.dynamic_mode = core::DynamicMode::modelled;  // the conveyor occludes (below the voxel)
    s.time_steps.front().dynamic_obstacles.push_back(
        box_object("conveyor", Vec3(-2, 1, 0), Vec3(6, 2, 0.5)));
    s.time_steps.front().critical = s.time_steps.front().dynamic_obstacles;
    s.time_steps.front().events.front().targets.push_back(
        box_object("person", Vec3(1.5, 2.2, 0.2), Vec3(1.9, 2.6, 1.8)));
    const voxel::VoxelEvaluator evaluator(s, {mode, {0, 0, 0}});
    // Inside the conveyor at x = −1.5 (outside S), looking along +x into S.
    const auto blind = evaluator.labels(camera_at(Vec3(-1.5, 1.5, 0.25), 0, 0), 0, 0);
    EXPECT_EQ(std::count(blind.begin(), blind.end(), Label::undetectable),
              static_cast<long>(blind.size()))
        << "mode " << static_cast<int>(mode);
    // Above S at (2, 1.5, 5), looking down: the voxels just below the top of S at the centre
    // are free.
    const auto above = evaluator.labels(camera_at(Vec3(2, 1.5, 5), 0, -90), 0, 0);
    const voxel::Grid& g = evaluator.grid();
    const int v = 4 + g.n[0] * (2 + g.n[1] * (g.n[2] - 1));  // centre (2.25, 1.25, 2.75)
    EXPECT_EQ(above[v], Label::free) << "mode " << static_cast<int>(mode);
  }
}

/// Voxels of S wholly inside an obstacle that reaches beyond S are removed from M (centre inside
/// in center mode, the whole voxel inside in conservative mode); by hand for a box crossing each
/// face: one camera looks away from S, so every voxel is undetectable and M is S less the removed
/// voxels. Voxels of 0.5 m; the wall reaches 0.85 m into S along the face's axis and 2 m beyond
/// it, and across from −1 m to 1.15 m (crossing the low faces of the other axes too): whole
/// voxels inside, 1 deep × 2 × 2 = 4 (conservative); centres inside (0.25 and 0.75 m from the
/// face, 0.25 and 0.75 m across), 2 × 2 × 2 = 8 (center). No centre or voxel face lies on the
/// wall's faces (no ties).
TEST(BeyondArea, InteriorsOfObstaclesCrossingEachFaceAreSubtractedFromTheModel) {
  for (int face = 0; face < 6; ++face) {
    const Face f = face_of(face);
    Box3 b;
    for (int a = 0; a < 3; ++a) {
      if (a == f.axis) {
        b.min[a] = f.side ? kArea.max[a] - 0.85 : kArea.min[a] - 2.0;
        b.max[a] = f.side ? kArea.max[a] + 2.0 : kArea.min[a] + 0.85;
      } else {
        b.min[a] = -1.0;
        b.max[a] = 1.15;
      }
    }
    for (Kind kind : kKinds) {
      for (LabelMode mode : {LabelMode::center, LabelMode::conservative}) {
        core::Scene s = simple_scene(kArea, {8, 6, 6}, 1, 30.0, {}, {});
        core::TimeStep& step = s.time_steps.front();
        const core::SceneObject wall = box_object("wall", b.min, b.max);
        if (kind == Kind::static_obstacle) {
          s.static_obstacles.push_back(wall);
          // Smaller than a voxel and clear of every centre: removes nothing.
          step.dynamic_obstacles.push_back(
              box_object("robot", Vec3(3.0, 2.0, 2.0), Vec3(3.2, 2.2, 2.2)));
        } else {
          step.dynamic_obstacles.push_back(wall);
        }
        s.dynamic_mode = kind == Kind::modelled_dynamic ? core::DynamicMode::modelled
                                                        : core::DynamicMode::masked;
        step.critical = step.dynamic_obstacles;
        step.events.front().targets.push_back(
            box_object("person", Vec3(2.6, 1.6, 1.6), Vec3(2.9, 1.9, 1.9)));
        const voxel::VoxelEvaluator evaluator(s, {mode, {0, 0, 0}});
        const core::CameraConfig config{camera_at(Vec3(10, 10, 10), 45, 45)};
        const auto model = evaluator.model(config, 0);
        const voxel::Grid& g = evaluator.grid();
        int removed = 0;
        for (int v = 0; v < g.count(); ++v) {
          const Box3 box = g.voxel_box(v);
          bool inside = true;
          for (int a = 0; a < 3; ++a) {
            if (mode == LabelMode::conservative) {
              inside = inside && box.min[a] >= b.min[a] && box.max[a] <= b.max[a];
            } else {
              inside = inside && box.center()[a] > b.min[a] && box.center()[a] < b.max[a];
            }
          }
          removed += inside;
          EXPECT_EQ(model[v], inside ? 0 : 1)
              << "face " << face << " " << kind_name(kind) << " mode " << static_cast<int>(mode)
              << " voxel " << v;
        }
        EXPECT_EQ(removed, mode == LabelMode::conservative ? 4 : 8) << "face " << face;
      }
    }
  }
}

/// d(C, M) and the true distance with a critical object partly outside S come from its mesh: a
/// conveyor from x = −3 m to x = 1 m, a target at x ∈ [3, 3.5]: d_true = 2 m by hand; d(C, M)
/// equals the minimum over the model's voxels of the box-to-box gap (by hand, per axis) from the
/// conveyor to the voxel's box (conservative) or centre (center), and in conservative mode it
/// is at most d_true (M ⊇ the target).
TEST(BeyondArea, DistancesOfACriticalObjectPartlyOutsideSComeFromItsMesh) {
  core::Scene s = simple_scene(kArea, {8, 6, 6}, 1, 60.0, {}, {});
  core::TimeStep& step = s.time_steps.front();
  step.dynamic_obstacles.push_back(box_object("conveyor", Vec3(-3, 1, 0), Vec3(1, 2, 0.5)));
  step.critical = step.dynamic_obstacles;
  step.events.front().targets.push_back(
      box_object("person", Vec3(3, 1.2, 0.2), Vec3(3.5, 1.8, 1.8)));
  EXPECT_NEAR(std::sqrt(core::true_squared_distance(s, {0, 0}).value), 2.0, 1e-12);
  for (LabelMode mode : {LabelMode::center, LabelMode::conservative}) {
    for (core::DynamicMode dyn : {core::DynamicMode::masked, core::DynamicMode::modelled}) {
      s.dynamic_mode = dyn;
      const voxel::VoxelEvaluator evaluator(s, {mode, {0, 0, 0}});
      // Outside S at x = 6 m, looking along −x into S.
      const core::CameraConfig config{camera_at(Vec3(6, 1.5, 1.5), 180, 0)};
      const auto e = evaluator.evaluate(config);
      ASSERT_EQ(e.states.size(), 1u);
      EXPECT_NEAR(e.states[0].d_true, 2.0, 1e-12);
      if (mode == LabelMode::conservative) {
        EXPECT_LE(e.states[0].d_model, 2.0 + 1e-12);
      }
      // Independent check of d(C, M): the minimum over the model's voxels of the distance from
      // the conveyor box (by hand: per-axis gaps) to the voxel's box (conservative) or centre.
      const auto model = evaluator.model(config, 0);
      const Box3 conveyor{Vec3(-3, 1, 0), Vec3(1, 2, 0.5)};
      double best = std::numeric_limits<double>::infinity();
      for (int v = 0; v < evaluator.grid().count(); ++v) {
        if (!model[v]) continue;
        const Box3 box = evaluator.grid().voxel_box(v);
        const Box3 probe = mode == LabelMode::center ? Box3{box.center(), box.center()} : box;
        double sq = 0;
        for (int a = 0; a < 3; ++a) {
          const double gap =
              std::max({0.0, probe.min[a] - conveyor.max[a], conveyor.min[a] - probe.max[a]});
          sq += gap * gap;
        }
        best = std::min(best, sq);
      }
      ASSERT_TRUE(std::isfinite(best));
      EXPECT_NEAR(e.states[0].d_model, std::sqrt(best), 1e-9)
          << "mode " << static_cast<int>(mode) << " dynamic " << static_cast<int>(dyn);
    }
  }
}

}  // namespace
}  // namespace camplace::testing
