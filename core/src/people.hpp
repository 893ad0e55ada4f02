#pragma once
// The parametric person model (SPEC §2 "People"): a scene's "people" zones expand into weighted
// events whose targets are the body parts of sampled people (docs/people.md). Private to core.
#include <Eigen/Core>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "camplace/core/geometry.hpp"
#include "camplace/core/json_reader.hpp"
#include "camplace/core/scene.hpp"

namespace camplace::core::detail {

/// A body posture (docs/people.md, "The body").
enum class Posture { standing, reaching, crouching };

/// The posture's name in scene files ("standing", "reaching", "crouching").
const char* posture_name(Posture posture);

/// One parsed entry of the scene's top-level "people" array.
struct PeopleZone {
  std::string name;   ///< prefix of the target names `<name>/<k>/<part>`
  std::string file;   ///< the scene file (for messages)
  std::string entry;  ///< JSON pointer of the entry, e.g. "/people/0"
  /// The zone's outline in world x, y (metres), counter-clockwise, ≥ 3 points; a rectangle is
  /// its 4 corners.
  std::vector<Eigen::Vector2d> polygon;
  bool rectangle = false;  ///< true for {"min", "max"}: positions need no rejection
  Eigen::Vector2d lo = Eigen::Vector2d::Zero();  ///< bounding rectangle of the zone (m)
  Eigen::Vector2d hi = Eigen::Vector2d::Zero();
  double zone_area = 0.0;  ///< m²
  double floor_z = 0.0;    ///< z (m) of the floor the people stand on
  double height_lo = 0.0;  ///< stature range (m), sampled uniformly
  double height_hi = 0.0;
  std::vector<Posture> postures;  ///< sampled uniformly; no posture twice
  int count = 0;                  ///< people (events) per time step, 1–1000
  std::uint64_t seed = 0;         ///< seed of the zone's std::mt19937_64 stream
  double weight = 0.0;            ///< total weight per time step; each event gets weight / count
};

/// Parses entry `index` of "people" (node: the entry itself) against the area S. Throws
/// InputError naming the file, the entry and the reason for every rejection of docs/people.md.
PeopleZone parse_people_zone(const JsonNode& node, const Box3& area, int index);

/// One candidate of a zone's stream: where the person stands and how.
struct PersonSample {
  long long candidate = 0;   ///< index in the zone's stream (0-based): the `<k>` of its names
  Vec3 feet = Vec3::Zero();  ///< floor point midway between the ankles (m, world frame)
  double heading = 0.0;      ///< facing direction (cos, sin, 0) of this yaw (rad, [0, 2π))
  double stature = 0.0;      ///< m
  Posture posture = Posture::standing;
};

/// The zone's seeded candidate stream: std::mt19937_64(seed), each draw mapped to [0, 1) as
/// (x >> 11) · 2⁻⁵³; per candidate first the position (x then y, uniform in the bounding
/// rectangle, redrawn until inside a polygon zone), then yaw, stature, posture.
class CandidateStream {
 public:
  explicit CandidateStream(const PeopleZone& zone);
  PersonSample next();

 private:
  double uniform();
  PeopleZone zone_;
  std::mt19937_64 engine_;
  long long index_ = 0;
};

/// The first `zone.count` candidates of the zone's stream that lie in S and meet (touch or
/// overlap) none of `obstacles`. Throws InputError(scene_file, zone.entry, ...) naming
/// `time_step` and the obstacle (or S) that rejected the most candidates when fewer than
/// `count` fit after 200·count + 1000 candidates.
std::vector<PersonSample> people_samples(const PeopleZone& zone,
                                         const std::vector<const SceneObject*>& obstacles,
                                         const Box3& area, const std::string& scene_file,
                                         int time_step);

/// The zone's events at time step `time_step`: the first `count` candidates of the zone's
/// stream that lie in S and meet none of `obstacles`, each of weight zone.weight / count, its
/// targets the person's body parts (person_parts). Errors as people_samples.
std::vector<Event> people_events(const PeopleZone& zone,
                                 const std::vector<const SceneObject*>& obstacles, const Box3& area,
                                 const std::string& scene_file, int time_step);

/// One person's body parts: 13 closed, outward, convex meshes (boxes, a frustum-like torso and
/// an octagonal-prism head) named `<prefix>/<part>` with the given entry. stature in metres,
/// feet the floor point midway between the ankles (world frame), heading the yaw (rad) of the
/// direction the person faces. For "standing" the body spans z = feet.z .. feet.z + stature.
std::vector<SceneObject> person_parts(double stature, Posture posture, const Vec3& feet,
                                      double heading, const std::string& prefix,
                                      const std::string& entry);

/// The parts' names in the order person_parts returns them.
const std::vector<std::string>& person_part_names();

/// Area (m²) of the rectangle holding both feet of a standing person of this stature (m).
double footprint_area(double stature);

}  // namespace camplace::core::detail
