// The parametric person model (docs/people.md): body parts from segment-length ratios, a seeded
// candidate stream per zone, and rejection of candidates that leave S or meet an obstacle.
#include "people.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "camplace/core/error.hpp"
#include "camplace/core/table_text.hpp"
#include "mesh_checks.hpp"
#include "scene_format.hpp"
#include "scene_limits.hpp"

namespace camplace::core::detail {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point2 = Kernel::Point_2;

// Vertical landmarks as fractions of the stature H: Drillis & Contini (1966), as tabulated in
// D. A. Winter, Biomechanics and Motor Control of Human Movement, Fig. 4.1 (docs/people.md).
constexpr double kTop = 1.000;        // vertex (top of the head)
constexpr double kChin = 0.870;       // chin
constexpr double kShoulder = 0.818;   // shoulder (acromion)
constexpr double kElbow = 0.630;      // elbow
constexpr double kFingertip = 0.377;  // tip of the middle finger, arm hanging
constexpr double kHip = 0.530;        // hip (greater trochanter)
constexpr double kKnee = 0.285;       // knee
constexpr double kAnkle = 0.039;      // ankle
// Widths from the same figure.
constexpr double kShoulderWidth = 0.259;
constexpr double kHipWidth = 0.191;
constexpr double kFootLength = 0.152;
constexpr double kFootWidth = 0.055;
// Thicknesses the figure does not give: the model's own choices (docs/people.md).
constexpr double kTorsoDepth = 0.130;
constexpr double kNeckWidth = 0.070;
constexpr double kHeadLength = 0.110;   // front to back (ellipse axis of the octagon)
constexpr double kHeadBreadth = 0.090;  // side to side
constexpr double kUpperArmWidth = 0.055;
constexpr double kForearmWidth = 0.045;
constexpr double kThighWidth = 0.090;
constexpr double kShankWidth = 0.060;
constexpr double kHeelBehind = 0.040;  // the foot reaches this far behind the ankle
// Crouching: shank tilted forward, thigh backward (from the vertical), torso leaning forward.
constexpr double kCrouchShankDeg = 40.0;
constexpr double kCrouchThighDeg = 70.0;
constexpr double kCrouchLeanDeg = 30.0;

constexpr double kSlack = 1e-9;  // zone vs S's x-y extent (as the loader's S slack)
constexpr double kMinStature = 0.5, kMaxStature = 2.5;
constexpr double kDefaultHeightLo = 1.535, kDefaultHeightHi = 1.855;  // DIN 33402-2:2005

std::string fmt(double v) { return format_number(v); }

bool boxes_meet(const Box3& a, const Box3& b) {
  return (a.min.array() <= b.max.array()).all() && (b.min.array() <= a.max.array()).all();
}

/// The box [−w/2, w/2] × [−d/2, d/2] × [0, length] in the frame (side, a × side, axis) at p.
TriangleMesh segment_box(const Vec3& p, const Vec3& q, const Vec3& side_hint, double width,
                         double depth) {
  const Vec3 axis = (q - p).normalized();
  const double length = (q - p).norm();
  const Vec3 side = (side_hint - side_hint.dot(axis) * axis).normalized();
  Eigen::Matrix3d r;
  r.col(0) = side;
  r.col(1) = axis.cross(side);
  r.col(2) = axis;  // det r = +1, so box_mesh's outward orientation is kept
  TriangleMesh m = box_mesh(Vec3(-width / 2, -depth / 2, 0), Vec3(width / 2, depth / 2, length));
  for (Vec3& v : m.vertices) v = p + r * v;
  return m;
}

/// The octagonal prism over the ellipse with semi-axes a (x), b (y), from z0 to z1; vertices at
/// 22.5° + k·45°.
TriangleMesh octagonal_prism(double a, double b, double z0, double z1) {
  TriangleMesh m;
  for (int level = 0; level < 2; ++level) {
    for (int k = 0; k < 8; ++k) {
      const double t = (22.5 + 45.0 * k) * kDegree;
      m.vertices.emplace_back(a * std::cos(t), b * std::sin(t), level ? z1 : z0);
    }
  }
  for (int k = 1; k + 1 < 8; ++k) {
    m.triangles.push_back({8, 8 + k, 8 + k + 1});  // top, counter-clockwise from above
    m.triangles.push_back({0, k + 1, k});          // bottom
  }
  for (int k = 0; k < 8; ++k) {
    const int n = (k + 1) % 8;
    m.triangles.push_back({k, n, 8 + n});
    m.triangles.push_back({k, 8 + n, 8 + k});
  }
  return m;
}

Eigen::Vector2d vec2(const JsonNode& node) {
  if (node.array_size() != 2) node.fail("expected [x, y] (2 numbers)");
  return Eigen::Vector2d(node.at(std::size_t{0}).number(), node.at(std::size_t{1}).number());
}

std::string fmt2(const Eigen::Vector2d& p) { return "[" + fmt(p.x()) + ", " + fmt(p.y()) + "]"; }

std::vector<Point2> cgal_points(const std::vector<Eigen::Vector2d>& polygon) {
  std::vector<Point2> points;
  for (const auto& p : polygon) points.emplace_back(p.x(), p.y());
  return points;
}

double signed_area(const std::vector<Eigen::Vector2d>& p) {
  double twice = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto& a = p[i];
    const auto& b = p[(i + 1) % p.size()];
    twice += (a.x() - p[0].x()) * (b.y() - p[0].y()) - (b.x() - p[0].x()) * (a.y() - p[0].y());
  }
  return twice / 2.0;
}

double body_top(double stature, Posture posture) {
  double top = 0.0;
  for (const SceneObject& part : person_parts(stature, posture, Vec3::Zero(), 0.0, "", ""))
    top = std::max(top, part.bounds.max.z());
  return top;
}

}  // namespace

const char* posture_name(Posture posture) {
  switch (posture) {
    case Posture::standing:
      return "standing";
    case Posture::reaching:
      return "reaching";
    case Posture::crouching:
      return "crouching";
  }
  return "standing";
}

const std::vector<std::string>& person_part_names() {
  static const std::vector<std::string> names = {
      "head",         "neck",          "torso",      "upper_arm_left", "upper_arm_right",
      "forearm_left", "forearm_right", "thigh_left", "thigh_right",    "shank_left",
      "shank_right",  "foot_left",     "foot_right"};
  return names;
}

double footprint_area(double stature) {
  // Both feet: x from −kHeelBehind to kFootLength − kHeelBehind, y across the outer edges.
  const double leg_y = kHipWidth / 2 - kThighWidth / 2;
  return (kFootLength * stature) * (2 * (leg_y + kFootWidth / 2) * stature);
}

std::vector<SceneObject> person_parts(double stature, Posture posture, const Vec3& feet,
                                      double heading, const std::string& prefix,
                                      const std::string& entry) {
  const double h = stature;
  const Vec3 x = Vec3::UnitX(), y = Vec3::UnitY(), z = Vec3::UnitZ();
  const double leg_y = (kHipWidth / 2 - kThighWidth / 2) * h;
  // Legs in the body frame (feet at the origin, facing +x, left = +y).
  std::array<Vec3, 2> hip_joint, knee, ankle;
  for (int side = 0; side < 2; ++side) {
    const double sy = side == 0 ? leg_y : -leg_y;
    ankle[side] = Vec3(0, sy, kAnkle * h);
    if (posture == Posture::crouching) {
      const double s = kCrouchShankDeg * kDegree, t = kCrouchThighDeg * kDegree;
      knee[side] = ankle[side] + (kKnee - kAnkle) * h * Vec3(std::sin(s), 0, std::cos(s));
      hip_joint[side] = knee[side] + (kHip - kKnee) * h * Vec3(-std::sin(t), 0, std::cos(t));
    } else {
      knee[side] = Vec3(0, sy, kKnee * h);
      hip_joint[side] = Vec3(0, sy, kHip * h);
    }
  }
  // The upper body (torso, neck, head, shoulders) moves rigidly: crouching turns it forward
  // about the hip axis and lowers it onto the bent legs.
  const Vec3 hip_standing(0, 0, kHip * h);
  const Vec3 hip_now(hip_joint[0].x(), 0, hip_joint[0].z());
  const Eigen::Matrix3d lean =
      posture == Posture::crouching
          ? Eigen::AngleAxisd(kCrouchLeanDeg * kDegree, y).toRotationMatrix()
          : Eigen::Matrix3d::Identity();
  auto upper = [&](const Vec3& p) -> Vec3 { return hip_now + lean * (p - hip_standing); };

  std::vector<TriangleMesh> meshes;
  // Head: octagonal prism from chin to vertex.
  TriangleMesh head =
      octagonal_prism(kHeadLength / 2 * h, kHeadBreadth / 2 * h, kChin * h, kTop * h);
  for (Vec3& v : head.vertices) v = upper(v);
  meshes.push_back(head);
  // Neck: box from shoulder level to the chin.
  TriangleMesh neck = box_mesh(Vec3(-kNeckWidth / 2 * h, -kNeckWidth / 2 * h, kShoulder * h),
                               Vec3(kNeckWidth / 2 * h, kNeckWidth / 2 * h, kChin * h));
  for (Vec3& v : neck.vertices) v = upper(v);
  meshes.push_back(neck);
  // Torso: hip width at the hips, shoulder width at the shoulders (box_mesh's corner order).
  TriangleMesh torso = box_mesh(Vec3::Zero(), Vec3::Ones());
  for (int i = 0; i < 8; ++i) {
    const bool top = i & 4;
    const double half_w = (top ? kShoulderWidth : kHipWidth) / 2 * h;
    torso.vertices[i] = upper(Vec3((i & 1 ? 0.5 : -0.5) * kTorsoDepth * h,
                                   (i & 2 ? half_w : -half_w), (top ? kShoulder : kHip) * h));
  }
  meshes.push_back(torso);
  // Arms: from the shoulder joints (acromion), hanging, or forward at shoulder height.
  std::array<Vec3, 2> shoulder, elbow, fingertip;
  for (int side = 0; side < 2; ++side) {
    const double sy = (side == 0 ? 1 : -1) * kShoulderWidth / 2 * h;
    shoulder[side] = upper(Vec3(0, sy, kShoulder * h));
    const Vec3 dir = posture == Posture::reaching ? x : Vec3(-z);
    elbow[side] = shoulder[side] + (kShoulder - kElbow) * h * dir;
    fingertip[side] = elbow[side] + (kElbow - kFingertip) * h * dir;
  }
  for (int side = 0; side < 2; ++side) {
    meshes.push_back(
        segment_box(shoulder[side], elbow[side], y, kUpperArmWidth * h, kUpperArmWidth * h));
  }
  for (int side = 0; side < 2; ++side) {
    meshes.push_back(
        segment_box(elbow[side], fingertip[side], y, kForearmWidth * h, kForearmWidth * h));
  }
  for (int side = 0; side < 2; ++side) {
    meshes.push_back(segment_box(hip_joint[side], knee[side], y, kThighWidth * h, kThighWidth * h));
  }
  for (int side = 0; side < 2; ++side) {
    meshes.push_back(segment_box(knee[side], ankle[side], y, kShankWidth * h, kShankWidth * h));
  }
  for (int side = 0; side < 2; ++side) {
    const double sy = ankle[side].y();
    meshes.push_back(
        box_mesh(Vec3(-kHeelBehind * h, sy - kFootWidth / 2 * h, 0),
                 Vec3((kFootLength - kHeelBehind) * h, sy + kFootWidth / 2 * h, kAnkle * h)));
  }
  // Body frame to world: yaw about z, then the feet's position.
  const Eigen::Matrix3d yaw = Eigen::AngleAxisd(heading, z).toRotationMatrix();
  std::vector<SceneObject> parts;
  const auto& names = person_part_names();
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    SceneObject part;
    part.name = prefix.empty() ? names[i] : prefix + "/" + names[i];
    part.entry = entry;
    part.mesh = std::move(meshes[i]);
    for (Vec3& v : part.mesh.vertices) v = feet + yaw * v;
    part.bounds = bounding_box(part.mesh);
    parts.push_back(std::move(part));
  }
  return parts;
}

PeopleZone parse_people_zone(const JsonNode& node, const Box3& area, int index) {
  node.only_keys({"name", "zone", "floor_z", "height_m", "postures", "count", "seed", "weight"});
  PeopleZone zone;
  zone.file = node.file();
  zone.entry = node.pointer();
  zone.name = "people" + std::to_string(index);
  if (node.has("name")) {
    const JsonNode n = node.at("name");
    zone.name = n.string();
    if (zone.name.empty()) n.fail("name must not be empty");
  }
  // Stature first: the zone's minimum size depends on the shortest person.
  zone.height_lo = kDefaultHeightLo;
  zone.height_hi = kDefaultHeightHi;
  if (node.has("height_m")) {
    const JsonNode hm = node.at("height_m");
    if (hm.array_size() != 2) hm.fail("expected [lo, hi] (2 numbers, metres)");
    zone.height_lo = hm.at(std::size_t{0}).number_in(kMinStature, kMaxStature);
    zone.height_hi = hm.at(std::size_t{1}).number_in(kMinStature, kMaxStature);
    if (zone.height_lo > zone.height_hi) {
      hm.fail("height range is invalid: lo " + fmt(zone.height_lo) + " exceeds hi " +
              fmt(zone.height_hi));
    }
  }
  zone.postures = {Posture::standing};
  if (node.has("postures")) {
    const JsonNode list = node.at("postures");
    if (list.array_size() == 0) list.fail("postures must list at least one posture");
    zone.postures.clear();
    for (std::size_t i = 0; i < list.array_size(); ++i) {
      const JsonNode p = list.at(i);
      const std::string s = p.string();
      Posture posture;
      if (s == "standing") {
        posture = Posture::standing;
      } else if (s == "reaching") {
        posture = Posture::reaching;
      } else if (s == "crouching") {
        posture = Posture::crouching;
      } else {
        p.fail("unknown posture \"" + s +
               "\" (expected \"standing\", \"reaching\" or \"crouching\")");
      }
      if (std::find(zone.postures.begin(), zone.postures.end(), posture) != zone.postures.end())
        p.fail("posture \"" + s + "\" is listed twice");
      zone.postures.push_back(posture);
    }
  }
  zone.floor_z = area.min.z();
  if (node.has("floor_z")) zone.floor_z = node.at("floor_z").number_in(area.min.z(), area.max.z());
  {
    double top = 0.0;
    Posture tallest = zone.postures[0];
    for (Posture p : zone.postures) {
      const double t = body_top(zone.height_hi, p);
      if (t > top) top = t, tallest = p;
    }
    if (zone.floor_z + top > area.max.z()) {
      const std::string where = node.has("height_m") ? "/height_m" : "";
      throw InputError(zone.file, zone.entry + where,
                       "a " + std::string(posture_name(tallest)) + " person of " +
                           fmt(zone.height_hi) + " m on the floor at z = " + fmt(zone.floor_z) +
                           " m reaches z = " + fmt(zone.floor_z + top) +
                           " m, above the top of the area S (z = " + fmt(area.max.z()) + " m)");
    }
  }
  // The zone.
  const JsonNode zn = node.at("zone");
  zn.only_keys({"min", "max", "polygon"});
  if (zn.has("polygon") == (zn.has("min") || zn.has("max"))) {
    zn.fail("a zone needs either \"min\" and \"max\" (a rectangle) or \"polygon\", not both");
  }
  if (zn.has("polygon")) {
    const JsonNode poly = zn.at("polygon");
    const std::size_t n = limited_size(poly, kMaxSmallList, "points of a polygon");
    if (n < 3) poly.fail("a polygon needs at least 3 points");
    for (std::size_t i = 0; i < n; ++i) zone.polygon.push_back(vec2(poly.at(i)));
    const double a = signed_area(zone.polygon);
    if (!(std::abs(a) > 1e-12)) poly.fail("polygon is degenerate: it encloses no area");
    const std::vector<Point2> pts = cgal_points(zone.polygon);
    if (!CGAL::is_simple_2(pts.begin(), pts.end(), Kernel())) {
      poly.fail("polygon is not simple: its edges intersect each other (or a point is repeated)");
    }
    if (a < 0) std::reverse(zone.polygon.begin(), zone.polygon.end());
    zone.zone_area = std::abs(a);
    // Positions are drawn from the bounding rectangle until one falls in the polygon: a sliver
    // that fills almost none of its rectangle would take unbounded draws.
    Eigen::Vector2d lo = zone.polygon.front(), hi = lo;
    for (const auto& q : zone.polygon) {
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
    const double rectangle = (hi.x() - lo.x()) * (hi.y() - lo.y());
    if (!(zone.zone_area >= 1e-3 * rectangle)) {
      poly.fail("polygon fills " + fmt(zone.zone_area) + " m² of its " + fmt(rectangle) +
                " m² bounding rectangle (less than 0.1%): positions are drawn from that "
                "rectangle, so split the zone into fuller polygons");
    }
  } else {
    const Eigen::Vector2d lo = vec2(zn.at("min")), hi = vec2(zn.at("max"));
    if (!(lo.x() < hi.x() && lo.y() < hi.y()))
      zn.fail("zone is degenerate: min must be below max on x and y");
    zone.rectangle = true;
    zone.polygon = {lo, {hi.x(), lo.y()}, hi, {lo.x(), hi.y()}};
    zone.zone_area = (hi.x() - lo.x()) * (hi.y() - lo.y());
  }
  zone.lo = zone.hi = zone.polygon[0];
  for (const auto& p : zone.polygon) {
    zone.lo = zone.lo.cwiseMin(p);
    zone.hi = zone.hi.cwiseMax(p);
    if (p.x() < area.min.x() - kSlack || p.x() > area.max.x() + kSlack ||
        p.y() < area.min.y() - kSlack || p.y() > area.max.y() + kSlack) {
      zn.fail("zone leaves the area S: its point " + fmt2(p) + " is not inside S's x-y extent [" +
              fmt(area.min.x()) + ", " + fmt(area.max.x()) + "] × [" + fmt(area.min.y()) + ", " +
              fmt(area.max.y()) + "]");
    }
  }
  const double footprint = footprint_area(zone.height_lo);
  if (zone.zone_area < footprint) {
    char rounded[32];  // 4 significant digits: the footprint is a model figure, not an input
    std::snprintf(rounded, sizeof rounded, "%.4g", footprint);
    zn.fail("zone is smaller than a person's footprint: it covers " + fmt(zone.zone_area) +
            " m², less than the " + rounded + " m² that both feet of a " + fmt(zone.height_lo) +
            " m person cover");
  }
  zone.count = node.at("count").integer_in(1, 1000);
  if (node.has("seed")) {
    const JsonNode s = node.at("seed");
    const nlohmann::json& v = s.value();
    if (!v.is_number_integer()) s.fail(std::string("expected an integer, found ") + v.type_name());
    if (v.is_number_unsigned()) {
      zone.seed = v.get<std::uint64_t>();
    } else {
      const long long signed_seed = v.get<long long>();
      if (signed_seed < 0) s.fail("seed must not be negative");
      zone.seed = static_cast<std::uint64_t>(signed_seed);
    }
  }
  const JsonNode w = node.at("weight");
  zone.weight = w.number();
  if (zone.weight < 0.0) w.fail("weight must not be negative");
  return zone;
}

CandidateStream::CandidateStream(const PeopleZone& zone) : zone_(zone), engine_(zone.seed) {}

double CandidateStream::uniform() {
  // 53 random bits → [0, 1): the same numbers from every standard library (std::mt19937_64's
  // output is fixed by the standard, std::uniform_real_distribution's mapping is not).
  return static_cast<double>(engine_() >> 11) * 0x1.0p-53;
}

PersonSample CandidateStream::next() {
  const PeopleZone& z = zone_;
  PersonSample s;
  s.candidate = index_++;
  std::vector<Point2> pts;
  if (!z.rectangle) pts = cgal_points(z.polygon);
  for (;;) {
    const double px = z.lo.x() + (z.hi.x() - z.lo.x()) * uniform();
    const double py = z.lo.y() + (z.hi.y() - z.lo.y()) * uniform();
    s.feet = Vec3(px, py, z.floor_z);
    if (z.rectangle || CGAL::bounded_side_2(pts.begin(), pts.end(), Point2(px, py), Kernel()) ==
                           CGAL::ON_BOUNDED_SIDE) {
      break;
    }
  }
  s.heading = 2.0 * kPi * uniform();
  s.stature = z.height_lo + (z.height_hi - z.height_lo) * uniform();
  const auto n = static_cast<double>(z.postures.size());
  const auto k = std::min(z.postures.size() - 1, static_cast<std::size_t>(n * uniform()));
  s.posture = z.postures[k];
  return s;
}

namespace {

/// The accepted samples and their parts.
std::vector<std::pair<PersonSample, std::vector<SceneObject>>> accepted_people(
    const PeopleZone& zone, const std::vector<const SceneObject*>& obstacles, const Box3& area,
    const std::string& scene_file, int time_step) {
  std::vector<std::pair<PersonSample, std::vector<SceneObject>>> out;
  const long long max_candidates = 200LL * zone.count + 1000;
  long long left_area = 0;
  std::vector<long long> blocked(obstacles.size(), 0);
  CandidateStream stream(zone);
  long long tried = 0;
  while (static_cast<int>(out.size()) < zone.count && tried < max_candidates) {
    ++tried;
    const PersonSample s = stream.next();
    const std::string prefix = zone.name + "/" + std::to_string(s.candidate);
    std::vector<SceneObject> parts =
        person_parts(s.stature, s.posture, s.feet, s.heading, prefix, zone.entry);
    Box3 body = parts[0].bounds;
    for (const SceneObject& p : parts) {
      body.min = body.min.cwiseMin(p.bounds.min);
      body.max = body.max.cwiseMax(p.bounds.max);
    }
    // Every part must lie in S (SPEC §2: targets lie in S), exactly, without the loader's slack.
    if ((body.min.array() < area.min.array()).any() ||
        (body.max.array() > area.max.array()).any()) {
      ++left_area;
      continue;
    }
    bool clear = true;
    for (std::size_t o = 0; o < obstacles.size() && clear; ++o) {
      const SceneObject& obstacle = *obstacles[o];
      if (!boxes_meet(body, obstacle.bounds)) continue;
      for (const SceneObject& p : parts) {
        if (boxes_meet(p.bounds, obstacle.bounds) && solids_intersect(p.mesh, obstacle.mesh)) {
          ++blocked[o];
          clear = false;
          break;
        }
      }
    }
    if (clear) out.emplace_back(s, std::move(parts));
  }
  if (static_cast<int>(out.size()) < zone.count) {
    std::string why;
    const auto worst = std::max_element(blocked.begin(), blocked.end());
    if (worst != blocked.end() && *worst >= left_area && *worst > 0) {
      const SceneObject& o = *obstacles[static_cast<std::size_t>(worst - blocked.begin())];
      why = "the zone is blocked by obstacle \"" + o.name + "\" (" + o.entry + "), which " +
            thousands(*worst) + " of them met";
    } else {
      why = "the people leave the area S (" + thousands(left_area) + " of them reached beyond it)";
    }
    throw InputError(scene_file, zone.entry,
                     "only " + std::to_string(out.size()) + " of " + std::to_string(zone.count) +
                         " people fit at time step " + std::to_string(time_step) + " after " +
                         thousands(tried) + " candidates: " + why);
  }
  return out;
}

}  // namespace

std::vector<PersonSample> people_samples(const PeopleZone& zone,
                                         const std::vector<const SceneObject*>& obstacles,
                                         const Box3& area, const std::string& scene_file,
                                         int time_step) {
  std::vector<PersonSample> out;
  for (auto& a : accepted_people(zone, obstacles, area, scene_file, time_step))
    out.push_back(a.first);
  return out;
}

std::vector<Event> people_events(const PeopleZone& zone,
                                 const std::vector<const SceneObject*>& obstacles, const Box3& area,
                                 const std::string& scene_file, int time_step) {
  std::vector<Event> events;
  for (auto& a : accepted_people(zone, obstacles, area, scene_file, time_step)) {
    Event e;
    e.weight = zone.weight / zone.count;
    e.targets = std::move(a.second);
    events.push_back(std::move(e));
  }
  return events;
}

}  // namespace camplace::core::detail
