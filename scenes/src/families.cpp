// The scene families of the paper's examinations (SPEC §9 table), each applied to a base scene:
// the paper's basic setup (data/paper_basic.json; data/README.md says where its numbers come
// from) or any other scene.
//
// Properties every scene generated from the basic setup keeps (they make the plausibility
// filter of SPEC §4 valid, see data/README.md "Why the person is made of two tall parts"):
// - every dynamic obstacle's top is below 1 m, every target is at least 1.45 m tall;
// - min_volume / min_height are the smallest target's volume and z-extent, rounded down to
//   6 decimals, so no component holding a whole target part is ever discarded;
// - no target meets an obstacle of its own state, nothing leaves S, every time step has
//   critical objects and its event weights sum to 1.
#include "families.hpp"

#include <cmath>
#include <random>
#include <utility>

#include "camplace/core/error.hpp"
#include "camplace/core/geometry.hpp"
#include "shapes.hpp"

namespace camplace::scenes::detail {

namespace {

using core::Box3;
using core::SceneObject;
using core::Vec3;

const std::vector<SceneFamily> kFamilies = {
    {"resolution", true, 0, 5, false, "voxels (16+4i)x(12+3i)x(12+3i)",
     "the base's voxels times (4+i)/4 along each axis, rounded"},
    {"static_facets", true, 0, 5, false, "8+60i static facets at 2 objects (4+30i each)",
     "each static tetrahedron of the base with 4+30i facets (same volume)"},
    {"static_objects", true, 0, 3, false,
     "2+i static tetrahedra, 8+4i facets (the paper's \"6+4i facets at 2+i objects\" is "
     "impossible for closed polyhedra)",
     "the base's static obstacles and i of the paper's 3 extra pieces of furniture, their floor "
     "plan stretched from the paper's 4x3 m to the base's area"},
    {"dynamic_facets", true, 0, 5, false,
     "24+60i dynamic facets at 3 objects per time step, 2 time steps (4+10i each)",
     "each dynamic tetrahedron of the base with 4+10i facets (same volume)"},
    {"dynamic_objects", true, 0, 3, true,
     "2+i dynamic objects with 24+4i facets in total, 1 time step, placed randomly",
     "the base's first time step, its dynamic obstacles replaced by 2+i random ones (24+4i "
     "facets, 0.5-0.95 m tall)"},
    {"dynamic_steps", true, 1, 5, false,
     "i time steps with 2i dynamic tetrahedra (8i facets), 3 events per step",
     "not on another base: it moves the paper's robot arm"},
    {"unmodelled_facets", true, 0, 5, false,
     "24+60i target facets at 2 objects per event, 3 events (4+10i each)",
     "each target tetrahedron of the base with 4+10i facets (same volume)"},
    {"unmodelled_objects", true, 0, 3, true,
     "2+i target objects with 24+4i facets in total, 1 event, placed randomly",
     "one event of 2+i random targets (24+4i facets, 1.5-1.9 m tall) in every time step of "
     "the base"},
    {"unmodelled_events", true, 1, 5, false,
     "i events with 2i target tetrahedra (8i facets), 3 time steps",
     "the base's first i events of every time step (i up to the base's fewest), weights scaled "
     "to the step's sum"},
    {"cameras", true, 3, 9, false, "i cameras", "i cameras, with the base's shared domain"},
    {"domain_ceiling", false, 0, 0, false, "cameras on the ceiling only (domain preset ceiling)",
     ""},
    {"domain_upper_fourth", false, 0, 0, false,
     "cameras in the upper fourth of S's height only (domain preset upper_fourth)", ""},
};

/// `objects` with `facets` facets each (finer()); every one must be a tetrahedron (4 vertices,
/// 4 facets, as the loader makes of a "tetrahedron" entry: base triangle, then apex).
std::vector<SceneObject> finer_objects(const SceneFamily& family, const BaseScene& base,
                                       const std::vector<SceneObject>& objects, int facets,
                                       const std::string& what) {
  std::vector<SceneObject> out;
  for (const SceneObject& o : objects) {
    if (o.mesh.vertices.size() != 4 || o.mesh.triangles.size() != 4) {
      not_applicable(family, base,
                     what + " \"" + o.name + "\" has " + std::to_string(o.mesh.triangles.size()) +
                         " facets; only tetrahedra are made finer");
    }
    NamedTetra t{o.name,
                 {o.mesh.vertices[0], o.mesh.vertices[1], o.mesh.vertices[2], o.mesh.vertices[3]}};
    out.push_back(finer(t, facets));
  }
  return out;
}

/// Same names and vertices (a step's critical objects left at their default, SPEC §2).
bool same_objects(const std::vector<SceneObject>& a, const std::vector<SceneObject>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].name != b[i].name || a[i].mesh.vertices != b[i].mesh.vertices) return false;
  }
  return true;
}

bool same_domain(const core::CameraDomain& d, const core::CameraDomain& d0) {
  return d.x.lo == d0.x.lo && d.x.hi == d0.x.hi && d.y.lo == d0.y.lo && d.y.hi == d0.y.hi &&
         d.z.lo == d0.z.lo && d.z.hi == d0.z.hi && d.yaw.lo == d0.yaw.lo && d.yaw.hi == d0.yaw.hi &&
         d.pitch.lo == d0.pitch.lo && d.pitch.hi == d0.pitch.hi && d.roll.lo == d0.roll.lo &&
         d.roll.hi == d0.roll.hi;
}

/// The basic setup's events of its first time step at places 0..2, then the extra persons at
/// places 3 and 4, weighted by event_weights(events).
std::vector<core::Event> paper_events(const std::vector<core::Event>& basic, int events) {
  const std::vector<double> weights = event_weights(events);
  std::vector<core::Event> out;
  for (int l = 0; l < events; ++l) {
    out.push_back(
        {weights[l], l < static_cast<int>(basic.size()) ? basic[l].targets : extra_person(l)});
  }
  return out;
}

}  // namespace

const std::vector<SceneFamily>& families() { return kFamilies; }

void not_applicable(const SceneFamily& family, const BaseScene& base, const std::string& reason) {
  throw core::OptionError("base", "family " + family.name +
                                      " cannot be applied to the base scene " + base.label + ": " +
                                      reason);
}

GeneratedScene apply_family(const SceneFamily& family, int i, unsigned seed, const BaseScene& base,
                            bool paper) {
  GeneratedScene g;
  g.scene = base.scene;
  // The base's domains stay unless the family sets a preset; the paper's cameras go anywhere.
  g.domain = paper ? "room" : "";
  core::Scene& s = g.scene;
  const Box3& area = s.area;
  const std::string& f = family.name;
  std::mt19937 rng(seed);
  // Critical objects left at their default follow the dynamic obstacles they copy.
  std::vector<bool> default_critical;
  for (const core::TimeStep& step : s.time_steps) {
    default_critical.push_back(same_objects(step.critical, step.dynamic_obstacles));
  }
  // New targets: thresholds from the smallest target part, as for the paper's scenes; finer
  // targets of another base keep their volume and height, so the base's thresholds stay.
  bool new_targets = paper;
  if (f == "resolution") {
    // On the paper's 16x12x12 voxels: (16+4i)x(12+3i)x(12+3i), exactly.
    for (int a = 0; a < 3; ++a) {
      s.voxels[a] = static_cast<int>(std::lround(base.scene.voxels[a] * (4.0 + i) / 4.0));
    }
    const std::string problem = core::resolution_problem(s.voxels);
    if (!problem.empty()) not_applicable(family, base, problem);
  } else if (f == "static_facets") {
    if (s.static_obstacles.empty()) not_applicable(family, base, "it has no static obstacles");
    s.static_obstacles =
        finer_objects(family, base, s.static_obstacles, 4 + 30 * i, "static obstacle");
  } else if (f == "static_objects") {
    // The paper's extra furniture at the same place relative to the floor (x, y stretched from
    // the paper's S to the base's), at its own height above the base's floor. On the paper's S
    // the stretch and the rounding to micrometres give back the furniture's numbers.
    const Box3& from = paper_area();
    std::vector<NamedTetra> extra = extra_static();
    extra.resize(i);
    for (NamedTetra& t : extra) {
      for (Vec3& p : t.points) {
        p = rounded(Vec3(area.min.x() + (p.x() - from.min.x()) * area.size().x() / from.size().x(),
                         area.min.y() + (p.y() - from.min.y()) * area.size().y() / from.size().y(),
                         area.min.z() + p.z()));
      }
      s.static_obstacles.push_back(tetra_object(t));
    }
    if (paper) {
      g.note =
          " Note: SPEC §9 lists \"6+4i facets at 2+i objects\", impossible for closed "
          "polyhedra (each has at least 4 facets); this scene has 2+i tetrahedra, 8+4i facets.";
    }
  } else if (f == "dynamic_facets") {
    bool any = false;
    for (core::TimeStep& step : s.time_steps) {
      any = any || !step.dynamic_obstacles.empty();
      step.dynamic_obstacles =
          finer_objects(family, base, step.dynamic_obstacles, 4 + 10 * i, "dynamic obstacle");
    }
    if (!any) not_applicable(family, base, "it has no dynamic obstacles");
  } else if (f == "dynamic_objects") {
    s.time_steps.resize(1);
    default_critical.resize(1);
    // A base with explicit critical objects keeps them (they are what must be observed).
    std::vector<Box3> avoid = boxes_of(s.static_obstacles);
    for (const core::Event& e : s.time_steps[0].events) {
      const std::vector<Box3> b = boxes_of(e.targets);
      avoid.insert(avoid.end(), b.begin(), b.end());
    }
    // Robot-like links on the floor, tops in [0.5, 0.95] m (< 1 m, see the file comment).
    const PyramidShape shape{0.15, 0.3, 0.5, 0.95, 0.5, true};
    s.time_steps[0].dynamic_obstacles =
        place_randomly(rng, split_facets(24 + 4 * i, 2 + i), shape, "robot part", avoid, area);
    // On the paper's S the free floor is far larger than these objects need.
    CAMPLACE_ASSERT(!paper || !s.time_steps[0].dynamic_obstacles.empty());
    if (s.time_steps[0].dynamic_obstacles.empty()) {
      not_applicable(family, base,
                     "no room for " + std::to_string(2 + i) +
                         " objects 0.5-0.95 m tall and up to 0.6 m wide, 0.1 m clear of the "
                         "other objects and the walls (seed " +
                         std::to_string(seed) + ")");
    }
  } else if (f == "dynamic_steps") {
    if (!paper) {
      not_applicable(family, base,
                     "the family moves the paper's robot arm over i time steps; it applies to "
                     "the paper's basic setup only (no base)");
    }
    // i steps of a 2-link robot on the basic pedestal, the basic persons in each.
    const core::TimeStep first = s.time_steps.front();
    s.time_steps.clear();
    for (int h = 0; h < i; ++h) {
      core::TimeStep step;
      step.dynamic_obstacles = two_link_robot(first.dynamic_obstacles, h);
      step.events = first.events;
      s.time_steps.push_back(std::move(step));
    }
    default_critical.assign(s.time_steps.size(), true);
  } else if (f == "unmodelled_facets") {
    for (core::TimeStep& step : s.time_steps) {
      for (core::Event& e : step.events) {
        e.targets = finer_objects(family, base, e.targets, 4 + 10 * i, "target");
      }
    }
  } else if (f == "unmodelled_objects") {
    std::vector<Box3> avoid = boxes_of(s.static_obstacles);
    for (const core::TimeStep& step : s.time_steps) {
      const std::vector<Box3> b = boxes_of(step.dynamic_obstacles);
      avoid.insert(avoid.end(), b.begin(), b.end());
    }
    // Person-part-like pyramids 1.5–1.9 m tall (≥ 1.45 m, see the file comment), alternately
    // upright (like legs-head) and inverted (like shoulders-feet).
    const PyramidShape shape{0.15, 0.3, 1.5, 1.9, 0.3, false};
    const core::Event event{
        1.0, place_randomly(rng, split_facets(24 + 4 * i, 2 + i), shape, "target", avoid, area)};
    CAMPLACE_ASSERT(!paper || !event.targets.empty());
    if (event.targets.empty()) {
      not_applicable(family, base,
                     "no room for " + std::to_string(2 + i) +
                         " targets 1.5-1.9 m tall and up to 0.6 m wide, 0.1 m clear of the "
                         "obstacles and the walls (seed " +
                         std::to_string(seed) + ")");
    }
    for (core::TimeStep& step : s.time_steps) step.events = {event};
    new_targets = true;
  } else if (f == "unmodelled_events" && paper) {
    // 3 time steps (the basic robot's 2 poses and a third toward +x) with the basic persons and
    // up to 2 more, weighted by the SPEC §9 table's rule.
    const std::vector<core::Event> events = paper_events(s.time_steps.front().events, i);
    s.time_steps.push_back(s.time_steps.front());
    s.time_steps.back().dynamic_obstacles = robot_toward_x(s.time_steps.front().dynamic_obstacles);
    for (core::TimeStep& step : s.time_steps) step.events = events;
    default_critical.assign(s.time_steps.size(), true);
  } else if (f == "unmodelled_events") {
    for (std::size_t h = 0; h < s.time_steps.size(); ++h) {
      std::vector<core::Event>& events = s.time_steps[h].events;
      if (static_cast<int>(events.size()) < i) {
        not_applicable(family, base,
                       "i = " + std::to_string(i) + " needs " + std::to_string(i) +
                           " events in every time step, and its time step " + std::to_string(h) +
                           " has " + std::to_string(events.size()));
      }
      double all = 0.0, kept = 0.0;
      for (std::size_t l = 0; l < events.size(); ++l) {
        all += events[l].weight;
        if (static_cast<int>(l) < i) kept += events[l].weight;
      }
      if (!(kept > 0.0)) {
        not_applicable(family, base,
                       "the first " + std::to_string(i) + " events of time step " +
                           std::to_string(h) + " all have weight 0");
      }
      events.resize(i);
      for (core::Event& e : events) e.weight *= all / kept;
    }
  } else if (f == "cameras") {
    for (const core::CameraDomain& d : s.cameras.domains) {
      if (!same_domain(d, s.cameras.domains.front())) {
        not_applicable(family, base,
                       "its cameras have different domains (\"camera_domains\"); the family "
                       "needs one domain shared by every camera");
      }
    }
    if (!s.cameras.one_model()) {
      not_applicable(family, base,
                     "its cameras have different models (\"cameras.models\"); the family needs "
                     "one model shared by every camera");
    }
    s.cameras.resize(1);
    s.cameras.resize(i);
  } else if (f == "domain_ceiling") {
    g.domain = "ceiling";
  } else if (f == "domain_upper_fourth") {
    g.domain = "upper_fourth";
  }
  if (!g.domain.empty()) {
    const std::optional<core::CameraDomain> domain = core::domain_preset(area, g.domain);
    CAMPLACE_ASSERT(domain.has_value());
    s.cameras.domains.assign(s.cameras.count, *domain);
  }
  for (std::size_t h = 0; h < s.time_steps.size(); ++h) {
    // The paper's time steps are at t = 0, 1, ... (SPEC §2 default).
    if (paper) s.time_steps[h].t = static_cast<double>(h);
    if (default_critical[h]) s.time_steps[h].critical = s.time_steps[h].dynamic_obstacles;
  }
  if (new_targets) s.plausibility = smallest_target(s);
  s.file.clear();
  s.mesh_files.clear();
  return g;
}

}  // namespace camplace::scenes::detail
