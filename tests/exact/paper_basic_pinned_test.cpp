// The exact results of paper_basic with the corner cameras, pinned: d_true², d_model² and the
// model volume of all six states as exact fractions (tests/exact/paper_basic_corners_exact.json,
// computed once before the exact pipeline was made faster), so that no change to how the pipeline
// computes can change an answer. The pinned values are cross-checked against the brute-force
// sensor model of tests/support (an independent implementation of SPEC §3), as in
// oracle_test.cpp: the kept model holds only points the reference puts in M, its volume is the
// one its boundary encloses, and the model point closest to the critical objects lies at the
// pinned d_model, with M there and no point of M closer by the reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/geometry.hpp"
#include "camplace/exact/evaluator.hpp"
#include "reference.hpp"

namespace camplace {
namespace {

using core::Vec3;

const std::string kSource = CAMPLACE_SOURCE_DIR;

/// An exact fraction "p/q" (any number of digits) as a double, to about 1e-15 relative.
double fraction_value(const std::string& fraction) {
  const auto slash = fraction.find('/');
  auto part = [](const std::string& digits) {
    const std::size_t lead = std::min<std::size_t>(digits.size(), 18);
    return std::pair<double, int>(std::stod(digits.substr(0, lead)), int(digits.size() - lead));
  };
  const auto [num, num_exp] = part(fraction.substr(0, slash));
  const auto [den, den_exp] = part(fraction.substr(slash + 1));
  return num / den * std::pow(10.0, num_exp - den_exp);
}

// Closest points by Ericson, Real-Time Collision Detection, §5.1.5 and §5.1.9 (double).
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

std::pair<Vec3, Vec3> closest_on_segments(const Vec3& p1, const Vec3& q1, const Vec3& p2,
                                          const Vec3& q2) {
  const Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0, t = 0;
  if (a <= 1e-300 && e <= 1e-300) return {p1, p2};
  if (a <= 1e-300) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 1e-300) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return {p1 + d1 * s, p2 + d2 * t};
}

/// The closest pair of points (on the first mesh, on the second) of two disjoint triangle sets.
std::pair<Vec3, Vec3> closest_points(const core::TriangleMesh& m1, const core::TriangleMesh& m2) {
  std::pair<Vec3, Vec3> best;
  double best_sq = std::numeric_limits<double>::infinity();
  auto consider = [&](const Vec3& x, const Vec3& y) {
    const double d = (x - y).squaredNorm();
    if (d < best_sq) {
      best_sq = d;
      best = {x, y};
    }
  };
  for (const auto& t1 : m1.triangles) {
    const std::array<Vec3, 3> a{m1.vertices[t1[0]], m1.vertices[t1[1]], m1.vertices[t1[2]]};
    for (const auto& t2 : m2.triangles) {
      const std::array<Vec3, 3> b{m2.vertices[t2[0]], m2.vertices[t2[1]], m2.vertices[t2[2]]};
      for (int i = 0; i < 3; ++i) {
        consider(a[i], closest_on_triangle(a[i], b[0], b[1], b[2]));
        consider(closest_on_triangle(b[i], a[0], a[1], a[2]), b[i]);
        for (int j = 0; j < 3; ++j) {
          const auto [x, y] = closest_on_segments(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3]);
          consider(x, y);
        }
      }
    }
  }
  return best;
}

class PaperBasicPinned : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new core::Scene(core::load_scene(kSource + "/data/paper_basic.json"));
    config_ = new core::CameraConfig(
        core::load_camera_config(kSource + "/data/paper_basic_corners.json", *scene_));
    exact::ExactOptions options;
    options.keep_models = true;
    eval_ = new exact::ExactEvaluation(exact::evaluate_exact(*scene_, *config_, options));
    std::ifstream in(kSource + "/tests/exact/paper_basic_corners_exact.json");
    pinned_ = new nlohmann::json(nlohmann::json::parse(in));
  }
  static void TearDownTestSuite() {
    delete scene_;
    delete config_;
    delete eval_;
    delete pinned_;
  }

  /// The reference sensor model's verdict on p in state s: 1 in M (no camera sees p free, p in
  /// no obstacle), 0 not in M, −1 too close to a boundary to tell.
  static int reference_in_model(int s, const Vec3& p) {
    core::Scene scene = *scene_;
    core::use_exact_models(scene.cameras);  // the exact pipeline's FOV (SPEC §1)
    const auto& r = eval_->states[s];
    bool non_free = true;
    for (const auto& cam : *config_) {
      const auto label = testing::reference_label(scene, r.time_step, r.event, cam, p, 1e-7);
      if (label.ambiguous) return -1;
      if (label.label == voxel::Label::free) non_free = false;
    }
    const auto& step = scene.time_steps[r.time_step];
    bool in_obstacle = false;
    for (const auto& o : scene.static_obstacles)
      in_obstacle |= testing::reference_inside(o.mesh, p);
    for (const auto& o : step.dynamic_obstacles)
      in_obstacle |= testing::reference_inside(o.mesh, p);
    return non_free && !in_obstacle ? 1 : 0;
  }

  /// Squared distance from p to the critical objects of state s.
  static double critical_sq_distance(int s, const Vec3& p) {
    double d = std::numeric_limits<double>::infinity();
    for (const auto& o : scene_->time_steps[eval_->states[s].time_step].critical)
      d = std::min(d, core::point_solid_sq_distance(o.mesh, p));
    return d;
  }

  static core::Scene* scene_;
  static core::CameraConfig* config_;
  static exact::ExactEvaluation* eval_;
  static nlohmann::json* pinned_;
};

core::Scene* PaperBasicPinned::scene_ = nullptr;
core::CameraConfig* PaperBasicPinned::config_ = nullptr;
exact::ExactEvaluation* PaperBasicPinned::eval_ = nullptr;
nlohmann::json* PaperBasicPinned::pinned_ = nullptr;

TEST_F(PaperBasicPinned, EveryStateKeepsItsExactFractions) {
  const auto& states = (*pinned_)["states"];
  ASSERT_EQ(eval_->states.size(), 6u);
  ASSERT_EQ(states.size(), 6u);
  for (std::size_t s = 0; s < states.size(); ++s) {
    const auto& r = eval_->states[s];
    const auto& p = states[s];
    EXPECT_EQ(r.time_step, p["time_step"].get<int>()) << "state " << s;
    EXPECT_EQ(r.event, p["event"].get<int>()) << "state " << s;
    EXPECT_EQ(r.d_true_sq_exact, p["d_true_sq_exact"].get<std::string>()) << "state " << s;
    EXPECT_EQ(r.d_model_sq_exact, p["d_model_sq_exact"].get<std::string>()) << "state " << s;
    EXPECT_EQ(r.model_volume_exact, p["model_volume_exact"].get<std::string>()) << "state " << s;
    EXPECT_EQ(r.components, p["components"].get<int>()) << "state " << s;
    // components_removed is not pinned: since the pipeline discards pieces that certainly fail
    // the filter between cameras (each counted once, docs/files.md), it counts fewer, larger
    // pieces than the final model held before (the file's counts); the kept model is the same.
    // The doubles are the fractions rounded.
    EXPECT_NEAR(r.d_model * r.d_model, fraction_value(r.d_model_sq_exact), 1e-14) << "state " << s;
    EXPECT_NEAR(r.model_volume, fraction_value(r.model_volume_exact), 1e-15) << "state " << s;
  }
}

TEST_F(PaperBasicPinned, KeptModelAgreesWithTheBruteForceSensorModel) {
  std::mt19937 rng(10);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto& states = (*pinned_)["states"];
  for (std::size_t s = 0; s < eval_->states.size(); ++s) {
    const exact::ExactModel& model = eval_->models[s];
    const core::TriangleMesh boundary = model.boundary_mesh();
    const double volume = fraction_value(states[s]["model_volume_exact"].get<std::string>());
    ASSERT_GT(volume, 0.0) << "state " << s;
    // The pinned volume is the volume the model's boundary encloses.
    EXPECT_NEAR(core::signed_volume(boundary), volume, 1e-12) << "state " << s;
    // Random points in the kept model's bounding box: every one the exact model holds lies in M
    // by the reference, and the share it holds estimates the pinned volume.
    const core::Box3 box = core::bounding_box(boundary);
    const int samples = 400;
    int inside = 0;
    for (int i = 0; i < samples; ++i) {
      const Vec3 p = box.min + Vec3(unit(rng), unit(rng), unit(rng)).cwiseProduct(box.size());
      if (!model.contains(p)) continue;
      ++inside;
      EXPECT_NE(reference_in_model(int(s), p), 0) << "state " << s << " (" << p.transpose() << ")";
    }
    const double box_volume = box.size().prod(), share = volume / box_volume;
    const double sigma = std::sqrt(share * (1 - share) / samples);
    EXPECT_NEAR(double(inside) / samples, share, 4 * sigma) << "state " << s;
  }
}

TEST_F(PaperBasicPinned, ClosestModelPointLiesAtThePinnedDistance) {
  std::mt19937 rng(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto& states = (*pinned_)["states"];
  for (std::size_t s = 0; s < eval_->states.size(); ++s) {
    const double d_sq = fraction_value(states[s]["d_model_sq_exact"].get<std::string>());
    const double d = std::sqrt(d_sq);
    core::TriangleMesh critical;  // the critical objects as one triangle set
    for (const auto& o : scene_->time_steps[eval_->states[s].time_step].critical) {
      const int base = int(critical.vertices.size());
      critical.vertices.insert(critical.vertices.end(), o.mesh.vertices.begin(),
                               o.mesh.vertices.end());
      for (const auto& t : o.mesh.triangles)
        critical.triangles.push_back({base + t[0], base + t[1], base + t[2]});
    }
    // The witness: the point q of the model's boundary closest to C (double arithmetic, no CGAL).
    const auto [q, c] = closest_points(eval_->models[s].boundary_mesh(), critical);
    EXPECT_NEAR((q - c).squaredNorm(), d_sq, 1e-9) << "state " << s;
    EXPECT_NEAR(critical_sq_distance(int(s), q), d_sq, 1e-9) << "state " << s;
    // Around q (radius 2 cm): the reference finds M, and none of it closer to C than d_model.
    int in_model = 0, closer = 0;
    for (int i = 0; i < 300; ++i) {
      Vec3 u(normal(rng), normal(rng), normal(rng));
      const Vec3 p = q + 0.02 * std::cbrt(unit(rng)) * u.normalized();
      const int ref = reference_in_model(int(s), p);
      if (ref != 1) continue;
      ++in_model;
      if (std::sqrt(critical_sq_distance(int(s), p)) < d - 1e-6) ++closer;
    }
    EXPECT_GT(in_model, 0) << "state " << s;
    EXPECT_EQ(closer, 0) << "state " << s;
  }
}

}  // namespace
}  // namespace camplace
