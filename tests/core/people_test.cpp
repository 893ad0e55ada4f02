// The parametric person model (docs/people.md): body parts against hand-computed dimensions,
// rejection of people that meet obstacles checked by an independent test, the sampled
// distributions checked statistically, weights, the shared stream and every input error.
#include "../../core/src/people.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <vector>

#include "../../core/src/mesh_checks.hpp"
#include "../../core/src/scene_format.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/geometry.hpp"

namespace camplace::testing {
namespace {

using core::Box3;
using core::SceneObject;
using core::Vec3;
using core::detail::Posture;
using nlohmann::json;

const Box3 kArea{Vec3(0, 0, 0), Vec3(4, 3, 3)};

core::detail::PeopleZone parse(const json& j, const Box3& area = kArea) {
  return core::detail::parse_people_zone(core::JsonNode(j, "scene.json", "/people/0"), area, 0);
}

void expect_error(const json& j, const std::string& entry, const std::string& reason,
                  const Box3& area = kArea) {
  try {
    parse(j, area);
    ADD_FAILURE() << "accepted " << j.dump() << " (expected " << entry << ": " << reason << ")";
  } catch (const core::InputError& e) {
    EXPECT_EQ(e.file(), "scene.json");
    EXPECT_EQ(e.entry(), entry) << e.what();
    EXPECT_NE(e.reason().find(reason), std::string::npos) << e.what();
  }
}

SceneObject box_object(const std::string& name, const std::string& entry, const Vec3& lo,
                       const Vec3& hi) {
  SceneObject o;
  o.name = name;
  o.entry = entry;
  o.mesh = core::detail::box_mesh(lo, hi);
  o.bounds = core::bounding_box(o.mesh);
  return o;
}

// Independent of CGAL's solids_intersect: a convex part meets the closed box when a vertex lies
// in the box, a triangle overlaps it (separating axes), or the part holds the box's centre.
bool meets_box(const core::TriangleMesh& m, const Box3& b) {
  for (const Vec3& v : m.vertices) {
    if (b.contains(v)) return true;
  }
  for (const auto& t : m.triangles) {
    if (core::triangle_box_overlap(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]], b))
      return true;
  }
  return core::inside_mesh(m, b.center());
}

Box3 union_bounds(const std::vector<SceneObject>& parts) {
  Box3 b = parts[0].bounds;
  for (const SceneObject& p : parts) {
    b.min = b.min.cwiseMin(p.bounds.min);
    b.max = b.max.cwiseMax(p.bounds.max);
  }
  return b;
}

const SceneObject& part(const std::vector<SceneObject>& parts, const std::string& name) {
  for (const SceneObject& p : parts) {
    if (p.name == "p/" + name) return p;
  }
  throw std::runtime_error("no part " + name);
}

// p-value of Pearson's chi-square statistic with `df` degrees of freedom.
double chi_square_p(double statistic, int df) {
  return boost::math::cdf(boost::math::complement(boost::math::chi_squared(df), statistic));
}

double chi_square(const std::vector<double>& observed, const std::vector<double>& expected) {
  double s = 0.0;
  for (std::size_t i = 0; i < observed.size(); ++i) {
    s += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
  }
  return s;
}

// p-value of the one-sample Kolmogorov–Smirnov test of `values` against uniform [lo, hi]:
// Kolmogorov's limit distribution with Stephens' correction, Q(λ) = 2 Σ (−1)^(j−1) e^(−2j²λ²),
// λ = (√n + 0.12 + 0.11/√n) · D.
double ks_uniform_p(std::vector<double> values, double lo, double hi) {
  std::sort(values.begin(), values.end());
  const double n = static_cast<double>(values.size());
  double d = 0.0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double f = (values[i] - lo) / (hi - lo);
    d = std::max({d, (i + 1) / n - f, f - i / n});
  }
  const double lambda = (std::sqrt(n) + 0.12 + 0.11 / std::sqrt(n)) * d;
  double q = 0.0;
  for (int j = 1; j <= 100; ++j)
    q += 2.0 * ((j % 2) ? 1 : -1) * std::exp(-2.0 * j * j * lambda * lambda);
  return std::clamp(q, 0.0, 1.0);
}

constexpr double kAlpha = 1e-4;  // a fixed seed's test fails only when p < kAlpha

json zone_json(const json& zone, int count, double weight = 1.0) {
  return {{"name", "p"}, {"zone", zone}, {"count", count}, {"weight", weight}, {"seed", 7}};
}

// ---------------------------------------------------------------------------------------------
// The body

TEST(PeopleBody, EveryPartIsAClosedOutwardValidMeshInsideS) {
  for (Posture posture : {Posture::standing, Posture::reaching, Posture::crouching}) {
    const auto parts =
        core::detail::person_parts(1.8, posture, Vec3(2.0, 1.5, 0.0), 0.7, "p", "/people/0");
    ASSERT_EQ(parts.size(), 13u);
    for (const SceneObject& p : parts) {
      core::TriangleMesh copy = p.mesh;
      EXPECT_NO_THROW(core::detail::validate_and_orient(copy, "scene.json", p.entry))
          << core::detail::posture_name(posture) << " " << p.name;
      EXPECT_EQ(copy.triangles, p.mesh.triangles) << p.name << " was not outward";
      EXPECT_GT(core::signed_volume(p.mesh), 0.0) << p.name;
      EXPECT_TRUE(kArea.contains(p.bounds.min) && kArea.contains(p.bounds.max)) << p.name;
      EXPECT_LE(p.mesh.triangles.size(), 28u) << p.name;
    }
  }
}

TEST(PeopleBody, StandingBodyHeightEqualsStature) {
  for (double stature : {1.535, 1.7, 1.855, 2.1}) {
    for (double heading : {0.0, 1.0, 4.0}) {
      const auto parts = core::detail::person_parts(stature, Posture::standing,
                                                    Vec3(1.0, 1.0, 0.25), heading, "p", "");
      const Box3 b = union_bounds(parts);
      EXPECT_NEAR(b.min.z(), 0.25, 1e-9);
      EXPECT_NEAR(b.max.z() - b.min.z(), stature, 1e-9);
    }
  }
}

// Drillis & Contini's landmarks for H = 1.8 m, computed by hand (docs/people.md): vertex 1.8,
// chin 0.87 H = 1.566, shoulder 0.818 H = 1.4724, elbow 0.63 H = 1.134, fingertip 0.377 H =
// 0.6786, hip 0.53 H = 0.954, knee 0.285 H = 0.513, ankle 0.039 H = 0.0702.
TEST(PeopleBody, StandingSegmentsHaveTheDocumentedLengthsAndWidths) {
  const auto parts = core::detail::person_parts(1.8, Posture::standing, Vec3::Zero(), 0.0, "p", "");
  auto expect_box = [&](const std::string& name, const Vec3& lo, const Vec3& hi) {
    const Box3& b = part(parts, name).bounds;
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(b.min[a], lo[a], 1e-12) << name << " axis " << a;
      EXPECT_NEAR(b.max[a], hi[a], 1e-12) << name << " axis " << a;
    }
  };
  // Head: octagon inscribed in the 0.11 H × 0.09 H ellipse (0.198 × 0.162 m), chin to vertex.
  const double c = std::cos(22.5 * core::kDegree);
  expect_box("head", Vec3(-0.099 * c, -0.081 * c, 1.566), Vec3(0.099 * c, 0.081 * c, 1.8));
  expect_box("neck", Vec3(-0.063, -0.063, 1.4724), Vec3(0.063, 0.063, 1.566));
  // Torso: 0.259 H = 0.4662 m wide at the shoulders, 0.13 H = 0.234 m deep.
  expect_box("torso", Vec3(-0.117, -0.2331, 0.954), Vec3(0.117, 0.2331, 1.4724));
  EXPECT_NEAR(part(parts, "torso").mesh.vertices[0].y(), -0.1719, 1e-12);  // 0.191 H / 2
  // Upper arm 0.188 H = 0.3384 m, 0.055 H = 0.099 m square, on the acromion at y = ±0.2331.
  expect_box("upper_arm_left", Vec3(-0.0495, 0.2331 - 0.0495, 1.134),
             Vec3(0.0495, 0.2331 + 0.0495, 1.4724));
  expect_box("upper_arm_right", Vec3(-0.0495, -0.2331 - 0.0495, 1.134),
             Vec3(0.0495, -0.2331 + 0.0495, 1.4724));
  // Forearm with hand 0.253 H = 0.4554 m, 0.045 H = 0.081 m square.
  expect_box("forearm_left", Vec3(-0.0405, 0.2331 - 0.0405, 0.6786),
             Vec3(0.0405, 0.2331 + 0.0405, 1.134));
  // Legs on y = ±(0.191 H − 0.09 H)/2 = ±0.0909: thigh 0.245 H = 0.441 m, 0.162 m square;
  // shank 0.246 H = 0.4428 m, 0.108 m square; foot 0.152 H = 0.2736 m long from 0.04 H = 0.072
  // m behind the ankle, 0.055 H = 0.099 m wide, 0.0702 m high.
  expect_box("thigh_right", Vec3(-0.081, -0.0909 - 0.081, 0.513),
             Vec3(0.081, -0.0909 + 0.081, 0.954));
  expect_box("shank_left", Vec3(-0.054, 0.0909 - 0.054, 0.0702),
             Vec3(0.054, 0.0909 + 0.054, 0.513));
  expect_box("foot_left", Vec3(-0.072, 0.0909 - 0.0495, 0.0),
             Vec3(0.2016, 0.0909 + 0.0495, 0.0702));
  // The footprint both feet cover: 0.2736 m × (2 · 0.0909 + 0.099) m.
  EXPECT_NEAR(core::detail::footprint_area(1.8), 0.2736 * 0.2808, 1e-12);
}

TEST(PeopleBody, ReachingPutsBothArmsForwardAtShoulderHeight) {
  const auto parts = core::detail::person_parts(1.8, Posture::reaching, Vec3::Zero(), 0.0, "p", "");
  for (const char* side : {"left", "right"}) {
    const Box3& upper = part(parts, std::string("upper_arm_") + side).bounds;
    const Box3& fore = part(parts, std::string("forearm_") + side).bounds;
    EXPECT_NEAR(upper.min.x(), 0.0, 1e-12);
    EXPECT_NEAR(upper.max.x(), 0.3384, 1e-12);
    EXPECT_NEAR(fore.min.x(), 0.3384, 1e-12);
    EXPECT_NEAR(fore.max.x(), 0.3384 + 0.4554, 1e-12);
    EXPECT_NEAR(upper.min.z(), 1.4724 - 0.0495, 1e-12);
    EXPECT_NEAR(upper.max.z(), 1.4724 + 0.0495, 1e-12);
    EXPECT_NEAR(fore.min.z(), 1.4724 - 0.0405, 1e-12);
  }
  EXPECT_NEAR(union_bounds(parts).max.z(), 1.8, 1e-9);
}

TEST(PeopleBody, CrouchingBendsTheKneesAndLowersAndLeansTheTorso) {
  const double h = 1.8, s = 40 * core::kDegree, t = 70 * core::kDegree, lean = 30 * core::kDegree;
  const auto parts = core::detail::person_parts(h, Posture::crouching, Vec3::Zero(), 0.0, "p", "");
  // Knee: the ankle (z = 0.0702) plus the shank 0.4428 m tilted 40° forward.
  const double knee_x = 0.4428 * std::sin(s), knee_z = 0.0702 + 0.4428 * std::cos(s);
  // Hip: the knee plus the thigh 0.441 m tilted 70° back from the vertical.
  const double hip_x = knee_x - 0.441 * std::sin(t), hip_z = knee_z + 0.441 * std::cos(t);
  const Box3& shank = part(parts, "shank_left").bounds;
  EXPECT_NEAR(shank.max.x(), knee_x + 0.054 * std::cos(s), 1e-12);
  // Torso leaning 30°: its lowest point is the front edge of its base, 0.117 m before the hip.
  const Box3& torso = part(parts, "torso").bounds;
  EXPECT_NEAR(torso.min.z(), hip_z - 0.117 * std::sin(lean), 1e-12);
  // Shoulder (0.2884 m above the hip along the torso) and the arms hanging from it.
  const double shoulder_z = hip_z + 0.5184 * std::cos(lean);
  const Box3& upper = part(parts, "upper_arm_left").bounds;
  EXPECT_NEAR(upper.max.z(), shoulder_z, 1e-12);
  EXPECT_NEAR(upper.min.x(), hip_x + 0.5184 * std::sin(lean) - 0.0495, 1e-12);
  const Box3 all = union_bounds(parts);
  EXPECT_NEAR(all.min.z(), 0.0, 1e-12);  // the feet stay on the floor
  EXPECT_LT(all.max.z(), 0.8 * h);
  EXPECT_GT(all.max.z(), 0.7 * h);
}

// ---------------------------------------------------------------------------------------------
// Rejection

TEST(PeopleRejection, AcceptedPeopleNeverMeetAnObstacleHalfCoveringTheZone) {
  const auto zone = parse(zone_json({{"min", {0.5, 0.5}}, {"max", {3.5, 2.5}}}, 300));
  const SceneObject table =
      box_object("table", "/static_obstacles/0", Vec3(2.0, 0.0, 0.0), Vec3(4.0, 3.0, 1.0));
  const auto events = core::detail::people_events(zone, {&table}, kArea, "scene.json", 0);
  ASSERT_EQ(events.size(), 300u);
  const auto samples = core::detail::people_samples(zone, {&table}, kArea, "scene.json", 0);
  EXPECT_GT(samples.back().candidate, 400);  // about half the candidates were rejected
  int touching_box_footprint = 0;
  for (const auto& e : events) {
    for (const SceneObject& p : e.targets) {
      EXPECT_FALSE(meets_box(p.mesh, table.bounds)) << p.name;
      EXPECT_TRUE(kArea.contains(p.bounds.min) && kArea.contains(p.bounds.max)) << p.name;
    }
  }
  for (const auto& s : samples) touching_box_footprint += s.feet.x() >= 2.0;
  EXPECT_EQ(touching_box_footprint, 0);
}

TEST(PeopleRejection, PeopleLeavingSAreRejected) {
  const auto zone = parse(zone_json({{"min", {0.0, 0.0}}, {"max", {4.0, 3.0}}}, 200));
  for (const auto& e : core::detail::people_events(zone, {}, kArea, "scene.json", 0)) {
    for (const SceneObject& p : e.targets) {
      EXPECT_TRUE(kArea.contains(p.bounds.min) && kArea.contains(p.bounds.max)) << p.name;
    }
  }
}

TEST(PeopleRejection, BlockedZoneNamesTheTimeStepAndTheObstacle) {
  // Standing people (the default) reach less than 0.4 m from their feet: none leaves S, the
  // table under the whole zone rejects them all.
  const auto zone = parse(zone_json({{"min", {1.5, 1.5}}, {"max", {2.0, 2.0}}}, 4));
  const SceneObject table =
      box_object("table", "/static_obstacles/0", Vec3(1.0, 1.0, 0.0), Vec3(2.5, 2.5, 0.5));
  const SceneObject far =
      box_object("far", "/static_obstacles/1", Vec3(3.5, 2.5, 0.0), Vec3(4.0, 3.0, 0.5));
  try {
    core::detail::people_events(zone, {&far, &table}, kArea, "scene.json", 3);
    ADD_FAILURE() << "a blocked zone was accepted";
  } catch (const core::InputError& e) {
    EXPECT_EQ(e.file(), "scene.json");
    EXPECT_EQ(e.entry(), "/people/0");
    EXPECT_EQ(e.reason(),
              "only 0 of 4 people fit at time step 3 after 1,800 candidates: the zone is blocked "
              "by obstacle \"table\" (/static_obstacles/0), which 1,800 of them met");
  }
}

TEST(PeopleRejection, AZoneWherePeopleCannotFitInSSaysSo) {
  const Box3 small{Vec3(0, 0, 0), Vec3(0.4, 0.4, 3)};
  const auto zone = parse(zone_json({{"min", {0.0, 0.0}}, {"max", {0.4, 0.4}}}, 2), small);
  try {
    core::detail::people_events(zone, {}, small, "scene.json", 0);
    ADD_FAILURE() << "accepted";
  } catch (const core::InputError& e) {
    EXPECT_EQ(e.entry(), "/people/0");
    EXPECT_EQ(e.reason(),
              "only 0 of 2 people fit at time step 0 after 1,400 candidates: the people leave the "
              "area S (1,400 of them reached beyond it)");
  }
}

// ---------------------------------------------------------------------------------------------
// Distributions (fixed seed, 1,000 people, the most a zone may ask for; fail only at p < 1e-4)

TEST(PeopleDistribution, PositionsHeightsPosturesAndYawAreUniform) {
  json j = zone_json({{"min", {1.0, 1.0}}, {"max", {3.0, 2.0}}}, 1000);
  j["height_m"] = {1.55, 1.95};
  j["postures"] = {"standing", "reaching", "crouching"};
  const auto zone = parse(j);
  const auto samples = core::detail::people_samples(zone, {}, kArea, "scene.json", 0);
  ASSERT_EQ(samples.size(), 1000u);
  EXPECT_EQ(samples.back().candidate, 999);  // none left S: the sample is unconditioned
  // Positions: 8 × 4 cells of 0.25 m.
  std::vector<double> cells(32, 0.0);
  std::vector<double> heights, yaws;
  std::vector<double> postures(3, 0.0);
  for (const auto& s : samples) {
    ASSERT_TRUE(s.feet.x() >= 1.0 && s.feet.x() < 3.0 && s.feet.y() >= 1.0 && s.feet.y() < 2.0);
    EXPECT_EQ(s.feet.z(), 0.0);
    const int cx = std::min(7, int((s.feet.x() - 1.0) / 0.25));
    const int cy = std::min(3, int((s.feet.y() - 1.0) / 0.25));
    cells[cx + 8 * cy] += 1;
    heights.push_back(s.stature);
    yaws.push_back(s.heading);
    postures[int(s.posture)] += 1;
  }
  EXPECT_GT(chi_square_p(chi_square(cells, std::vector<double>(32, 1000.0 / 32)), 31), kAlpha);
  EXPECT_GT(ks_uniform_p(heights, 1.55, 1.95), kAlpha);
  EXPECT_GT(ks_uniform_p(yaws, 0.0, 2 * core::kPi), kAlpha);
  EXPECT_GT(chi_square_p(chi_square(postures, std::vector<double>(3, 1000.0 / 3)), 2), kAlpha);
  // The tests can fail: a wrong distribution of the same values is refused.
  std::vector<double> squared;
  for (double h : heights) squared.push_back(1.55 + (h - 1.55) * (h - 1.55) / 0.4);
  EXPECT_LT(ks_uniform_p(squared, 1.55, 1.95), kAlpha);
  std::vector<double> skewed_cells = cells;
  for (int i = 0; i < 32; i += 8) skewed_cells[i] += 20, skewed_cells[i + 7] -= 20;
  EXPECT_LT(chi_square_p(chi_square(skewed_cells, std::vector<double>(32, 1000.0 / 32)), 31),
            kAlpha);
}

TEST(PeopleDistribution, PolygonPositionsAreUniformOverTheLShape) {
  // L-shape: [1, 3] × [1, 1.5] and [1, 2] × [1.5, 2], clockwise (turned to counter-clockwise).
  json poly = {{1, 1}, {1, 2}, {2, 2}, {2, 1.5}, {3, 1.5}, {3, 1}};
  const auto zone = parse(zone_json({{"polygon", poly}}, 1000));
  EXPECT_NEAR(zone.zone_area, 1.5, 1e-12);
  const auto samples = core::detail::people_samples(zone, {}, kArea, "scene.json", 0);
  std::map<int, double> cells;  // 0.25 m cells, index cx + 8 cy
  for (const auto& s : samples) {
    const int cx = int((s.feet.x() - 1.0) / 0.25), cy = int((s.feet.y() - 1.0) / 0.25);
    cells[cx + 8 * cy] += 1;
  }
  std::vector<double> observed, expected;
  for (int cy = 0; cy < 4; ++cy) {
    for (int cx = 0; cx < 8; ++cx) {
      const bool inside = cy < 2 || cx < 4;
      const double n = cells.count(cx + 8 * cy) ? cells[cx + 8 * cy] : 0.0;
      if (!inside) {
        EXPECT_EQ(n, 0.0) << "cell " << cx << ", " << cy << " lies outside the polygon";
        continue;
      }
      observed.push_back(n);
      expected.push_back(1000.0 / 24);
    }
  }
  ASSERT_EQ(observed.size(), 24u);
  EXPECT_GT(chi_square_p(chi_square(observed, expected), 23), kAlpha);
}

TEST(PeopleDistribution, WithAnObstacleAcceptedPositionsAreUniformOverTheFreePart) {
  // A large S so that only the obstacle rejects. Feet cannot stand on the obstacle (x ≥ 2);
  // no part of a person reaches 1 m from the feet, so at x < 1 every candidate is accepted and
  // the accepted positions there must be uniform.
  const Box3 big{Vec3(-2, -2, 0), Vec3(6, 5, 3)};
  const auto zone = parse(zone_json({{"min", {0.0, 0.0}}, {"max", {4.0, 3.0}}}, 1000), big);
  const SceneObject block =
      box_object("block", "/static_obstacles/0", Vec3(2.0, -0.5, 0.0), Vec3(4.5, 3.5, 1.0));
  const auto samples = core::detail::people_samples(zone, {&block}, big, "scene.json", 0);
  ASSERT_EQ(samples.size(), 1000u);
  std::vector<double> far(2 * 6, 0.0);  // cells of 0.5 m over x ∈ [0, 1), y ∈ [0, 3)
  for (const auto& s : samples) {
    EXPECT_LT(s.feet.x(), 2.0);
    if (s.feet.x() < 1.0) far[int(s.feet.x() / 0.5) + 2 * int(s.feet.y() / 0.5)] += 1;
  }
  double total = 0.0;
  for (double n : far) total += n;
  EXPECT_GT(total, 250.0);
  EXPECT_GT(chi_square_p(chi_square(far, std::vector<double>(12, total / 12)), 11), kAlpha);
}

// ---------------------------------------------------------------------------------------------
// Weights and the shared stream

TEST(PeopleWeights, EachStepsEventsSumToTheZonesWeightAndZonesAdd) {
  const auto a = parse(zone_json({{"min", {0.5, 0.5}}, {"max", {1.5, 1.5}}}, 3, 0.7));
  json jb = zone_json({{"min", {2.5, 1.5}}, {"max", {3.5, 2.5}}}, 5, 0.3);
  jb["name"] = "q";
  const auto b = parse(jb);
  const auto ea = core::detail::people_events(a, {}, kArea, "scene.json", 0);
  const auto eb = core::detail::people_events(b, {}, kArea, "scene.json", 0);
  ASSERT_EQ(ea.size(), 3u);
  ASSERT_EQ(eb.size(), 5u);
  double sa = 0.0, sb = 0.0;
  for (const auto& e : ea) {
    EXPECT_DOUBLE_EQ(e.weight, 0.7 / 3);
    sa += e.weight;
  }
  for (const auto& e : eb) {
    EXPECT_DOUBLE_EQ(e.weight, 0.3 / 5);
    sb += e.weight;
  }
  EXPECT_NEAR(sa, 0.7, 1e-15);
  EXPECT_NEAR(sa + sb, 1.0, 1e-15);
  EXPECT_EQ(ea[0].targets.size(), 13u);
  EXPECT_EQ(ea[0].targets[0].name, "p/0/head");
  EXPECT_EQ(eb[4].targets[12].name, "q/4/foot_right");
  EXPECT_EQ(eb[4].targets[12].entry, "/people/0");
}

TEST(PeopleStream, StepsWithoutDynamicObstaclesGetIdenticalPeople) {
  const auto zone = parse(zone_json({{"min", {0.5, 0.5}}, {"max", {3.5, 2.5}}}, 6));
  const SceneObject table =
      box_object("table", "/static_obstacles/0", Vec3(0.0, 0.0, 0.0), Vec3(1.2, 1.2, 0.8));
  const auto e0 = core::detail::people_events(zone, {&table}, kArea, "scene.json", 0);
  const auto e1 = core::detail::people_events(zone, {&table}, kArea, "scene.json", 1);
  ASSERT_EQ(e0.size(), e1.size());
  for (std::size_t l = 0; l < e0.size(); ++l) {
    for (std::size_t k = 0; k < e0[l].targets.size(); ++k) {
      EXPECT_EQ(e0[l].targets[k].name, e1[l].targets[k].name);
      EXPECT_EQ(e0[l].targets[k].mesh.vertices, e1[l].targets[k].mesh.vertices);
    }
  }
}

TEST(PeopleStream, ARobotElsewhereKeepsThePeopleItDoesNotMeet) {
  // Step 1 has a robot link in part of the zone: its people are the first 6 candidates of the
  // same stream that clear the link, so every person of step 1 is, mesh for mesh, the candidate
  // of the same index in a long unobstructed run, and the people before the first rejection are
  // those of the empty step.
  const auto zone = parse(zone_json({{"min", {0.5, 0.5}}, {"max", {3.5, 2.5}}}, 6));
  const SceneObject link = box_object("ur/link", "", Vec3(2.0, 0.0, 0.0), Vec3(4.0, 3.0, 2.0));
  const auto free_run = core::detail::people_samples(
      parse(zone_json({{"min", {0.5, 0.5}}, {"max", {3.5, 2.5}}}, 60)), {}, kArea, "scene.json", 0);
  const auto with_link = core::detail::people_samples(zone, {&link}, kArea, "scene.json", 1);
  ASSERT_EQ(with_link.size(), 6u);
  long long expected_next = 0;
  for (const auto& s : with_link) {
    const auto& f = free_run.at(static_cast<std::size_t>(s.candidate));
    EXPECT_EQ(f.candidate, s.candidate);
    EXPECT_EQ(f.feet, s.feet);
    EXPECT_EQ(f.stature, s.stature);
    // Every candidate skipped before this one meets the link (checked independently).
    for (long long c = expected_next; c < s.candidate; ++c) {
      const auto& r = free_run.at(static_cast<std::size_t>(c));
      bool meets = false;
      for (const auto& p :
           core::detail::person_parts(r.stature, r.posture, r.feet, r.heading, "p", ""))
        meets = meets || meets_box(p.mesh, link.bounds);
      EXPECT_TRUE(meets) << "candidate " << c << " was skipped without meeting the link";
    }
    expected_next = s.candidate + 1;
  }
  EXPECT_GT(with_link.back().candidate, 5);  // the link did reject someone
}

TEST(PeopleStream, TheStreamIsPortableMt19937_64WithTheDocumentedMapping) {
  // The first candidate, computed by hand from std::mt19937_64(7)'s first four outputs (the
  // engine's output is fixed by the C++ standard): x = 1 + 2u₀, y = 1 + u₁, yaw = 2πu₂,
  // stature = 1.55 + 0.4 u₃ with u = (r >> 11) · 2⁻⁵³.
  std::mt19937_64 engine(7);
  double u[5];
  for (double& v : u) v = static_cast<double>(engine() >> 11) * 0x1.0p-53;
  json j = zone_json({{"min", {1.0, 1.0}}, {"max", {3.0, 2.0}}}, 1);
  j["height_m"] = {1.55, 1.95};
  j["postures"] = {"standing", "reaching", "crouching"};
  const auto zone = parse(j);
  core::detail::CandidateStream stream(zone);
  const auto s = stream.next();
  EXPECT_EQ(s.feet.x(), 1.0 + 2.0 * u[0]);
  EXPECT_EQ(s.feet.y(), 1.0 + 1.0 * u[1]);
  EXPECT_EQ(s.heading, 2.0 * core::kPi * u[2]);
  EXPECT_EQ(s.stature, 1.55 + (1.95 - 1.55) * u[3]);
  EXPECT_EQ(int(s.posture), int(3 * u[4]));
  // And the standard's check value: the 10000th output of a default-seeded engine.
  std::mt19937_64 check;
  check.discard(9999);
  EXPECT_EQ(check(), 9981545732273789042ULL);
}

// ---------------------------------------------------------------------------------------------
// Input errors

TEST(PeopleInput, DefaultsAreDocumented) {
  const auto z = core::detail::parse_people_zone(
      core::JsonNode(
          json{{"zone", {{"min", {0.5, 0.5}}, {"max", {1.5, 1.5}}}}, {"count", 2}, {"weight", 1}},
          "scene.json", "/people/3"),
      kArea, 3);
  EXPECT_EQ(z.name, "people3");
  EXPECT_EQ(z.entry, "/people/3");
  EXPECT_EQ(z.floor_z, 0.0);
  EXPECT_EQ(z.height_lo, 1.535);
  EXPECT_EQ(z.height_hi, 1.855);
  ASSERT_EQ(z.postures.size(), 1u);
  EXPECT_EQ(z.postures[0], Posture::standing);
  EXPECT_EQ(z.seed, 0u);
}

TEST(PeopleInput, EveryBadEntryIsRejectedWithItsReason) {
  const json ok = zone_json({{"min", {0.5, 0.5}}, {"max", {1.5, 1.5}}}, 4);
  auto with = [&](const std::string& key, const json& value) {
    json j = ok;
    j[key] = value;
    return j;
  };
  auto without = [&](const std::string& key) {
    json j = ok;
    j.erase(key);
    return j;
  };
  expect_error(with("nmae", "x"), "/people/0/nmae", "unknown field \"nmae\"");
  expect_error(without("zone"), "/people/0", "missing required field \"zone\"");
  expect_error(without("count"), "/people/0", "missing required field \"count\"");
  expect_error(without("weight"), "/people/0", "missing required field \"weight\"");
  expect_error(with("name", ""), "/people/0/name", "name must not be empty");
  expect_error(with("zone", {{"min", {1.5, 0.5}}, {"max", {1.5, 1.5}}}), "/people/0/zone",
               "zone is degenerate");
  expect_error(with("zone", {{"min", {0.5, 0.5}}, {"max", {1.5, 1.5}}, {"polygon", {}}}),
               "/people/0/zone", "not both");
  expect_error(with("zone", {{"min", {0.5, 0.5}}}), "/people/0/zone", "missing required field");
  expect_error(with("zone", {{"min", {0.5, 0.5}}, {"max", {4.5, 1.5}}}), "/people/0/zone",
               "zone leaves the area S: its point [4.5, 0.5]");
  expect_error(with("zone", {{"polygon", {{0.5, 0.5}, {1.5, 0.5}}}}), "/people/0/zone/polygon",
               "at least 3 points");
  expect_error(with("zone", {{"polygon", {{0.5, 0.5}, {1.5, 0.5}, {2.5, 0.5}}}}),
               "/people/0/zone/polygon", "degenerate: it encloses no area");
  expect_error(with("zone", {{"polygon", {{0.5, 0.5}, {2.5, 1.5}, {2.5, 0.5}, {0.5, 1.0}}}}),
               "/people/0/zone/polygon", "not simple");
  expect_error(with("zone", {{"polygon", {{0.5, 0.5}, {1.5, 0.5}, {1.5}}}}),
               "/people/0/zone/polygon/2", "expected [x, y]");
  expect_error(with("zone", {{"min", {0.5, 0.5}}, {"max", {0.625, 0.625}}}), "/people/0/zone",
               "zone is smaller than a person's footprint: it covers 0.015625 m², less than "
               "the 0.05587 m² that both feet of a 1.535 m person cover");
  expect_error(with("height_m", {1.9, 1.6}), "/people/0/height_m", "height range is invalid");
  expect_error(with("height_m", {1600, 1900}), "/people/0/height_m/0", "out of range [0.5, 2.5]");
  expect_error(with("height_m", {1.6}), "/people/0/height_m", "expected [lo, hi]");
  expect_error(with("height_m", {1.6, 1.9}), "/people/0/height_m",
               "a standing person of 1.9 m on the floor at z = 0 m reaches z = 1.9 m, above the "
               "top of the area S (z = 1.8 m)",
               Box3{Vec3(0, 0, 0), Vec3(4, 3, 1.8)});
  expect_error(with("floor_z", 2.0), "/people/0",
               "reaches z = 3.855 m, above the top of the area S");
  expect_error(with("floor_z", -0.5), "/people/0/floor_z", "out of range [0, 3]");
  expect_error(with("postures", {"standing", "sitting"}), "/people/0/postures/1",
               "unknown posture \"sitting\"");
  expect_error(with("postures", {"reaching", "reaching"}), "/people/0/postures/1", "listed twice");
  expect_error(with("postures", json::array()), "/people/0/postures", "at least one posture");
  expect_error(with("count", 0), "/people/0/count", "out of range [1, 1000]");
  expect_error(with("count", 1001), "/people/0/count", "out of range [1, 1000]");
  expect_error(with("count", 2.5), "/people/0/count", "expected an integer");
  expect_error(with("weight", -0.1), "/people/0/weight", "weight must not be negative");
  expect_error(with("seed", -1), "/people/0/seed", "seed must not be negative");
  expect_error(with("seed", 1.5), "/people/0/seed", "expected an integer");
  // A seed takes the full 64-bit range.
  EXPECT_EQ(parse(with("seed", 18446744073709551615ULL)).seed, 18446744073709551615ULL);
}

}  // namespace
}  // namespace camplace::testing
