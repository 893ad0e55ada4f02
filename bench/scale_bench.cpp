// How the voxel pipeline scales, one factor at a time, from the paper's scene
// (data/paper_basic.json, cameras data/paper_basic_corners.json, 16×12×12 voxels):
//  - robot:      each time step's robot (its critical objects, which are also its dynamic
//                obstacles) replaced by one closed ellipsoid mesh of N triangles inscribed in
//                their bounding box (tests/support/scene_builder: ellipsoid_mesh), N = 1k, 3k,
//                10k, 30k, 100k (up to --max-triangles); and series "robot+person": each
//                event's people too replaced by one ellipsoid of N triangles (as in person);
//  - person:     the same for each event's targets (one ellipsoid per event in the bounding box
//                of its targets), with the scene cut to 1 state (time step 0, event 0) and with
//                the scene's 6 states;
//  - states:     2, 8, 32, 128 time steps × 3 events = 6, 24, 96, 384 states (up to
//                --max-states); "distinct": time step h ≥ 2 repeats step h mod 2 with its robot
//                moved by its own offset, and each of its events' people by theirs (< 6 cm,
//                horizontal, all different), so every added state has objects of its own (the
//                paper's 2 time steps share their events' people); "identical": the paper's 2
//                steps repeated unmoved, so Err is the paper's times H/2 (the voxel pipeline
//                shares equal objects between states);
//  - cameras:    2, 6, 12, 24 cameras: the first 2 of the corners configuration, all 6, and 6 or
//                18 more on the ceiling's edge (z = 2.9 m) looking at (2, 1.5, 0.9);
//  - resolution: 16×12×12, 36×27×27, 64×48×48 voxels.
// For each point and mode (conservative, center) one child process (fork) builds the evaluator
// and evaluates the configuration: set-up (wall-clock seconds of the VoxelEvaluator
// constructor), warm evaluation (CPU ms of evaluate() with threads = 1, median and minimum of
// --repeat evaluations after one warm-up) and peak RSS growth (the child's VmHWM at the end less
// its VmRSS before the set-up, so each peak is the point's own). With Embree 3 found at build
// time, center mode also times the yardstick: all triangles of the scene (every object of every
// state once) in one Embree BVH (single-threaded device), and one first-hit ray
// (rtcIntersect1, from the camera through the voxel centre, unbounded) per camera and voxel
// centre inside that camera's FOV (core::Fov), CPU ms, median of --repeat after one warm-up;
// only the time is compared (camplace finds the first hit per state, Embree over the union).
// The exact true distances of the states (core::true_squared_distance, part of the set-up) are
// timed apart once per point (dtrue_s). Tables per family, then log-log slopes (growth
// exponents) between consecutive points, over the top decade and over the whole range; --csv
// writes every row; --help explains every column.
//   build/release/bench/scale_bench [--family F[,F...]] [--max-triangles N] [--max-states N]
//                                   [--voxels NXxNYxNZ]
//                                   [--mode conservative|center|both] [--repeat R] [--csv FILE]
// Without options: every family, N ≤ 10k triangles, up to 384 states, both modes, 5 repeats
// (about a minute on 2 loaded cores). --max-triangles 100000 takes several minutes and, in the
// person family's center mode with 6 states, about 3.3 GB of RSS.
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "camplace/core/camera.hpp"
#include "camplace/core/distance.hpp"
#include "camplace/core/scene.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "paper_basic.hpp"
#include "scene_builder.hpp"

#ifdef CAMPLACE_WITH_EMBREE
#include <embree3/rtcore.h>
#endif

namespace {

using namespace camplace;
using core::Box3;
using core::Vec3;

const char* const kHelp = R"(scale_bench: how the voxel evaluator scales, one factor at a time,
from data/paper_basic.json with the corners configuration (16x12x12 voxels).

Options:
  --family F[,F...]  robot, person, states, cameras, resolution or all (default all):
                     robot       each time step's robot replaced by an ellipsoid mesh of N
                                 triangles (1k, 3k, 10k, 30k, 100k up to --max-triangles),
                                 and (series robot+person) its people too;
                     person      each event's people replaced by an ellipsoid of N triangles,
                                 on the scene cut to 1 state and on its 6 states;
                     states      6, 24, 96, 384 states (up to --max-states), each with its own
                                 object positions ("distinct") or repeated ("identical");
                     cameras     2, 6, 12, 24 cameras;
                     resolution  16x12x12, 36x27x27, 64x48x48 voxels.
  --max-triangles N  largest N of the robot and person families (default 10000)
  --max-states N     largest state count of the states family (default 384)
  --voxels NXxNYxNZ  the resolution of every family but resolution (default 16x12x12)
  --mode M           conservative, center or both (default both)
  --repeat R         evaluations timed per point after one warm-up (default 5)
  --csv FILE         also write every row as CSV
  --help             this text

Columns (one child process per point and mode):
  N            the factor: triangles per robot / per event's people, states, cameras or voxels
  tri          triangles of the scene (static, dynamic and target objects, each once)
  dtrue_s      wall-clock seconds of the exact true distances of all states
               (core::true_squared_distance, which the set-up computes too; first mode only)
  setup_s      wall-clock seconds of building the VoxelEvaluator
  eval_ms      CPU ms of one warm evaluate() (threads = 1), median of R; min_ms the fastest
               (the CSV also has the labelling stage's wall ms from evaluate()'s Timing,
               median, which under load may exceed the CPU time)
  rss_MiB      peak RSS growth of the child: VmHWM at the end less VmRSS before the set-up
               (the CSV also has it at the end of the set-up)
  Err          the configuration's Err (m^2), for orientation
  embree_bms   center mode, when built with Embree 3: wall ms of building one BVH over all
               triangles of the scene (one thread; after a warm-up build)
  rays         one per camera and voxel centre inside its FOV (core::Fov)
  embree_ms    CPU ms of casting them all with rtcIntersect1, median of R (unbounded rays
               through the centres, made before the clock starts): a yardstick, the first hit
               over all states' triangles at once, where camplace needs the first hit per state
               (compare times only)
Exponents: log-log slopes d ln(value) / d ln(N) of eval_ms, setup_s, rss_MiB and embree_ms
between consecutive points, over the top decade (the first point with N >= N_top/10 to the
top) and over the whole range; n/a where a value is not positive.
)";

// ---------------------------------------------------------------------------------------------
// Options

struct Options {
  std::set<std::string> families;
  int max_triangles = 10000;
  int max_states = 384;
  std::vector<voxel::LabelMode> modes{voxel::LabelMode::conservative, voxel::LabelMode::center};
  int repeat = 5;
  std::string csv;
  std::array<int, 3> voxels{16, 12, 12};  ///< every family's resolution but `resolution`'s
};

const std::vector<std::string> kFamilies{"robot", "person", "states", "cameras", "resolution"};

int parse_int(const std::string& text, const std::string& what, int lo) {
  std::size_t used = 0;
  int value = 0;
  try {
    value = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || value < lo) {
    throw std::invalid_argument(what + ": expected an integer >= " + std::to_string(lo) +
                                ", got \"" + text + "\"");
  }
  return value;
}

Options parse_options(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--help" || arg == "-h") {
      std::fputs(kHelp, stdout);
      std::exit(0);
    } else if (arg == "--family") {
      std::stringstream list(value());
      for (std::string f; std::getline(list, f, ',');) {
        if (f == "all") {
          o.families.insert(kFamilies.begin(), kFamilies.end());
        } else if (std::find(kFamilies.begin(), kFamilies.end(), f) != kFamilies.end()) {
          o.families.insert(f);
        } else {
          throw std::invalid_argument("--family: unknown family \"" + f + "\"");
        }
      }
    } else if (arg == "--max-triangles") {
      o.max_triangles = parse_int(value(), arg, 1000);
    } else if (arg == "--voxels") {
      const std::string v = value();
      char x1 = 0, x2 = 0;
      std::istringstream in(v);
      if (!(in >> o.voxels[0] >> x1 >> o.voxels[1] >> x2 >> o.voxels[2]) || x1 != 'x' ||
          x2 != 'x' || !in.eof() || *std::min_element(o.voxels.begin(), o.voxels.end()) < 1) {
        throw std::invalid_argument("--voxels: expected NXxNYxNZ with positive counts, got \"" + v +
                                    "\"");
      }
    } else if (arg == "--max-states") {
      o.max_states = parse_int(value(), arg, 6);
    } else if (arg == "--repeat") {
      o.repeat = parse_int(value(), arg, 1);
    } else if (arg == "--mode") {
      const std::string m = value();
      if (m == "conservative") {
        o.modes = {voxel::LabelMode::conservative};
      } else if (m == "center") {
        o.modes = {voxel::LabelMode::center};
      } else if (m != "both") {
        throw std::invalid_argument("--mode: expected conservative, center or both");
      }
    } else if (arg == "--csv") {
      o.csv = value();
    } else {
      throw std::invalid_argument("unknown argument \"" + arg + "\" (see --help)");
    }
  }
  if (o.families.empty()) o.families.insert(kFamilies.begin(), kFamilies.end());
  return o;
}

// ---------------------------------------------------------------------------------------------
// Scene families

using bench::corners;
using bench::paper_scene;

/// One point of a family: the scene and configuration to measure.
struct Point {
  std::string family;
  std::string series;
  std::string label;  ///< N as printed ("1k", "16x12x12")
  double n = 0.0;     ///< the factor's value
  core::Scene scene;
  core::CameraConfig config;
  std::array<int, 3> resolution{16, 12, 12};
};

Box3 objects_bounds(const std::vector<core::SceneObject>& objects) {
  Box3 b{objects.front().bounds.min, objects.front().bounds.max};
  for (const auto& o : objects) {
    b.min = b.min.cwiseMin(o.bounds.min);
    b.max = b.max.cwiseMax(o.bounds.max);
  }
  return b;
}

void translate(core::SceneObject& o, const Vec3& offset) {
  for (Vec3& v : o.mesh.vertices) v += offset;
  o.bounds.min += offset;
  o.bounds.max += offset;
}

/// The k-th point (k ≥ 1) of a Vogel spiral of radius 8 cm: all different, horizontal.
Vec3 offset(int k) {
  constexpr int kMax = 1024;
  const double golden = core::kPi * (3.0 - std::sqrt(5.0));
  const double r = 0.08 * std::sqrt(static_cast<double>(k) / kMax);
  return Vec3(r * std::cos(k * golden), r * std::sin(k * golden), 0.0);
}

std::string count_label(int n) {
  if (n >= 1000 && n % 1000 == 0) return std::to_string(n / 1000) + "k";
  return std::to_string(n);
}

const std::vector<int> kTriangleCounts{1000, 3000, 10000, 30000, 100000};

core::Scene robot_scene(int triangles) {
  core::Scene s = paper_scene();
  for (core::TimeStep& step : s.time_steps) {
    const core::SceneObject robot =
        testing::ellipsoid_object("robot", objects_bounds(step.critical), triangles);
    step.dynamic_obstacles = {robot};
    step.critical = {robot};
  }
  return s;
}

core::Scene person_scene(int triangles, bool one_state) {
  core::Scene s = paper_scene();
  if (one_state) {
    s.time_steps.resize(1);
    s.time_steps[0].events.resize(1);
  }
  for (core::TimeStep& step : s.time_steps) {
    for (core::Event& event : step.events) {
      event.targets = {
          testing::ellipsoid_object("person", objects_bounds(event.targets), triangles)};
    }
  }
  return s;
}

/// robot_scene with each event's people one ellipsoid of the same triangle count: a cell of fine
/// meshes on both sides (the set-up's exact true distances pair every robot triangle with every
/// person triangle that may hold the minimum).
core::Scene robot_and_person_scene(int triangles) {
  core::Scene s = robot_scene(triangles);
  for (core::TimeStep& step : s.time_steps) {
    for (core::Event& event : step.events) {
      event.targets = {
          testing::ellipsoid_object("person", objects_bounds(event.targets), triangles)};
    }
  }
  return s;
}

core::Scene states_scene(int time_steps, bool distinct) {
  const core::Scene& paper = paper_scene();
  core::Scene s = paper;
  s.time_steps.clear();
  for (int h = 0; h < time_steps; ++h) {
    core::TimeStep step = paper.time_steps[h % paper.time_steps.size()];
    step.t = h;
    if (distinct && h >= static_cast<int>(paper.time_steps.size())) {
      for (auto& o : step.dynamic_obstacles) translate(o, offset(4 * h));
      for (auto& o : step.critical) translate(o, offset(4 * h));
      for (std::size_t l = 0; l < step.events.size(); ++l) {
        for (auto& o : step.events[l].targets) translate(o, offset(4 * h + 1 + l));
      }
    }
    s.time_steps.push_back(std::move(step));
  }
  return s;
}

/// The corners configuration's first n cameras, or all 6 and n − 6 more spread along the
/// ceiling's edge (z = 2.9 m), each looking at (2, 1.5, 0.9).
core::CameraConfig camera_config(int n) {
  core::CameraConfig config(corners().begin(), corners().begin() + std::min<int>(n, 6));
  const Box3& area = paper_scene().area;
  const Vec3 size = area.size();
  const double perimeter = 2.0 * (size.x() + size.y());
  const Vec3 aim(2.0, 1.5, 0.9);
  for (int k = 0, extra = n - 6; k < extra; ++k) {
    double d = perimeter * (k + 0.5) / extra;
    Vec3 p = area.min;
    if (d < size.x()) {
      p.x() += d;
    } else if ((d -= size.x()) < size.y()) {
      p += Vec3(size.x(), d, 0);
    } else if ((d -= size.y()) < size.x()) {
      p += Vec3(size.x() - d, size.y(), 0);
    } else {
      p.y() += size.y() - (d - size.x());
    }
    p.z() = 2.9;
    const Vec3 v = aim - p;
    core::CameraSetting c;
    c.position = p;
    c.yaw = std::atan2(v.y(), v.x());
    c.pitch = std::atan2(v.z(), std::hypot(v.x(), v.y()));
    config.push_back(c);
  }
  return config;
}

/// --voxels: the resolution of every point but the resolution family's.
std::array<int, 3> g_voxels{16, 12, 12};

Point make_point(const std::string& family, const std::string& series, const std::string& label,
                 double n, core::Scene scene) {
  Point p;
  p.family = family;
  p.series = series;
  p.label = label;
  p.n = n;
  p.scene = std::move(scene);
  p.config = corners();
  p.resolution = g_voxels;
  return p;
}

std::vector<Point> family_points(const std::string& family, const Options& o) {
  std::vector<Point> points;
  if (family == "robot") {
    // The robot alone, then the robot and the people both of N triangles.
    for (const bool people : {false, true}) {
      for (int t : kTriangleCounts) {
        if (t > o.max_triangles) continue;
        points.push_back(make_point(family, people ? "robot+person" : "6 states", count_label(t), t,
                                    people ? robot_and_person_scene(t) : robot_scene(t)));
      }
    }
  } else if (family == "person") {
    for (const bool one : {true, false}) {
      for (int t : kTriangleCounts) {
        if (t > o.max_triangles) continue;
        points.push_back(make_point(family, one ? "1 state" : "6 states", count_label(t), t,
                                    person_scene(t, one)));
      }
    }
  } else if (family == "states") {
    for (const bool distinct : {true, false}) {
      for (int steps : {2, 8, 32, 128}) {
        if (3 * steps > o.max_states) continue;
        points.push_back(make_point(family, distinct ? "distinct" : "identical",
                                    std::to_string(3 * steps), 3 * steps,
                                    states_scene(steps, distinct)));
      }
    }
  } else if (family == "cameras") {
    for (int n : {2, 6, 12, 24}) {
      core::Scene s = paper_scene();
      s.cameras.resize(n);
      Point p = make_point(family, "corners+ring", std::to_string(n), n, std::move(s));
      p.config = camera_config(n);
      points.push_back(std::move(p));
    }
  } else if (family == "resolution") {
    for (const std::array<int, 3> r :
         {std::array<int, 3>{16, 12, 12}, {36, 27, 27}, {64, 48, 48}}) {
      Point p =
          make_point(family, "grid",
                     std::to_string(r[0]) + "x" + std::to_string(r[1]) + "x" + std::to_string(r[2]),
                     static_cast<double>(r[0]) * r[1] * r[2], paper_scene());
      p.resolution = r;
      points.push_back(std::move(p));
    }
  }
  return points;
}

// ---------------------------------------------------------------------------------------------
// Measuring one point in a child process

/// What a child sends back (plain data through a pipe).
struct Result {
  int ok = 0;
  char error[200] = {};
  int triangles = 0, states = 0, cameras = 0, voxels = 0;
  double true_distance_s = -1.0;  ///< wall s of the states' exact true distances (-1: not run)
  double setup_rss_mib = 0.0;     ///< the peak RSS growth by the end of the set-up (CSV only)
  double labelling_ms = 0.0;      ///< the labelling stage's wall ms (Timing), median
  double setup_s = 0.0, eval_ms = 0.0, eval_min_ms = 0.0, rss_mib = 0.0, err = 0.0;
  int embree = 0;  ///< 1 when the Embree yardstick ran
  long long embree_rays = 0;
  long long embree_hits = 0;  ///< rays of the last cast that hit a triangle (CSV only)
  double embree_build_ms = 0.0, embree_ms = 0.0;
};

/// A field of /proc/self/status in KiB (VmRSS, VmHWM), or -1.
long status_kib(const char* field) {
  std::ifstream in("/proc/self/status");
  const std::string key = std::string(field) + ":";
  for (std::string line; std::getline(in, line);) {
    if (line.compare(0, key.size(), key) == 0) return std::atol(line.c_str() + key.size());
  }
  return -1;
}

double cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

double wall_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

/// Every object of the scene once: static obstacles, each step's dynamic obstacles and each
/// event's targets (critical objects are the dynamic obstacles here).
std::vector<const core::TriangleMesh*> scene_meshes(const core::Scene& s) {
  std::vector<const core::TriangleMesh*> out;
  for (const auto& o : s.static_obstacles) out.push_back(&o.mesh);
  for (const auto& step : s.time_steps) {
    for (const auto& o : step.dynamic_obstacles) out.push_back(&o.mesh);
    for (const auto& event : step.events) {
      for (const auto& o : event.targets) out.push_back(&o.mesh);
    }
  }
  return out;
}

#ifdef CAMPLACE_WITH_EMBREE
/// The yardstick: one BVH over every triangle of the scene, one first-hit ray per camera and
/// voxel centre inside its FOV; the rays are made before the clock starts.
void embree_yardstick(const Point& p, const voxel::Grid& grid, int repeat, Result& r) {
  RTCDevice device = rtcNewDevice("threads=1");
  auto build = [&] {
    RTCScene scene = rtcNewScene(device);
    for (const core::TriangleMesh* mesh : scene_meshes(p.scene)) {
      RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
      auto* vertices = static_cast<float*>(
          rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                  3 * sizeof(float), mesh->vertices.size()));
      for (std::size_t i = 0; i < mesh->vertices.size(); ++i) {
        for (int a = 0; a < 3; ++a) vertices[3 * i + a] = static_cast<float>(mesh->vertices[i][a]);
      }
      auto* indices = static_cast<unsigned*>(
          rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                  3 * sizeof(unsigned), mesh->triangles.size()));
      for (std::size_t i = 0; i < mesh->triangles.size(); ++i) {
        for (int a = 0; a < 3; ++a)
          indices[3 * i + a] = static_cast<unsigned>(mesh->triangles[i][a]);
      }
      rtcCommitGeometry(g);
      rtcAttachGeometry(scene, g);
      rtcReleaseGeometry(g);
    }
    rtcCommitScene(scene);
    return scene;
  };
  rtcReleaseScene(build());  // warm-up: the device's first build sets itself up
  const double t0 = wall_s();
  RTCScene scene = build();
  r.embree_build_ms = (wall_s() - t0) * 1e3;
  std::vector<std::array<float, 6>> rays;
  for (int c = 0; c < static_cast<int>(p.config.size()); ++c) {
    const core::Fov fov(p.config[c], p.scene.cameras.models[c]);
    const Vec3& o = p.config[c].position;
    for (int v = 0; v < grid.count(); ++v) {
      const Vec3 x = grid.voxel_center(v);
      if (!fov.contains(x)) continue;
      const Vec3 d = x - o;
      rays.push_back({static_cast<float>(o.x()), static_cast<float>(o.y()),
                      static_cast<float>(o.z()), static_cast<float>(d.x()),
                      static_cast<float>(d.y()), static_cast<float>(d.z())});
    }
  }
  r.embree_rays = static_cast<long long>(rays.size());
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  long long hits = 0;
  auto cast_all = [&] {
    for (const auto& ray : rays) {
      RTCRayHit rh;
      rh.ray.org_x = ray[0];
      rh.ray.org_y = ray[1];
      rh.ray.org_z = ray[2];
      rh.ray.dir_x = ray[3];
      rh.ray.dir_y = ray[4];
      rh.ray.dir_z = ray[5];
      rh.ray.tnear = 0.0f;
      rh.ray.tfar = std::numeric_limits<float>::infinity();
      rh.ray.time = 0.0f;
      rh.ray.mask = ~0u;
      rh.ray.id = 0;
      rh.ray.flags = 0;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene, &context, &rh);
      hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    }
  };
  cast_all();  // warm-up
  std::vector<double> times;
  for (int i = 0; i < repeat; ++i) {
    const double c0 = cpu_ms();
    cast_all();
    times.push_back(cpu_ms() - c0);
  }
  r.embree_ms = median(times);
  r.embree_hits = hits;  // used, so the casts cannot be dropped
  r.embree = 1;
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
}
#endif

Result measure(const Point& p, voxel::LabelMode mode, int repeat, bool time_true_distances) {
  Result r;
  r.states = static_cast<int>(core::states(p.scene).size());
  r.cameras = static_cast<int>(p.config.size());
  for (const core::TriangleMesh* m : scene_meshes(p.scene)) {
    r.triangles += static_cast<int>(m->triangles.size());
  }
  if (time_true_distances) {
    // The exact d(C, O_u) of every state, as the set-up computes them (once per point).
    const double d0 = wall_s();
    double sum = 0.0;
    for (const core::StateIndex& st : core::states(p.scene)) {
      sum += core::true_squared_distance(p.scene, st).value;
    }
    r.true_distance_s = wall_s() - d0;
    if (!(sum >= 0.0)) throw std::runtime_error("bad true distances");
  }
  // Reset the peak to the current RSS (Linux ≥ 4.0; a fresh child's peak is its RSS anyway),
  // so that the growth is the evaluator's.
  { std::ofstream("/proc/self/clear_refs") << "5"; }
  const long rss0 = status_kib("VmRSS");
  voxel::VoxelOptions options;
  options.mode = mode;
  options.resolution = p.resolution;
  options.threads = 1;
  const double t0 = wall_s();
  const voxel::VoxelEvaluator evaluator(p.scene, options);
  r.setup_s = wall_s() - t0;
  r.setup_rss_mib = (status_kib("VmHWM") - rss0) / 1024.0;
  r.voxels = evaluator.grid().count();
  r.err = evaluator.evaluate(p.config).err;  // warm-up
  std::vector<double> times, labelling;
  for (int i = 0; i < repeat; ++i) {
    const double c0 = cpu_ms();
    const core::Evaluation e = evaluator.evaluate(p.config);
    times.push_back(cpu_ms() - c0);
    labelling.push_back(e.timing.labelling_ms);
    if (e.err != r.err) throw std::runtime_error("evaluations differ");
  }
  r.eval_ms = median(times);
  r.labelling_ms = median(labelling);
  r.eval_min_ms = *std::min_element(times.begin(), times.end());
  r.rss_mib = (status_kib("VmHWM") - rss0) / 1024.0;
#ifdef CAMPLACE_WITH_EMBREE
  if (mode == voxel::LabelMode::center) embree_yardstick(p, evaluator.grid(), repeat, r);
#endif
  r.ok = 1;
  return r;
}

/// measure() in a child process, so that its peak RSS is the point's own.
Result measure_in_child(const Point& p, voxel::LabelMode mode, int repeat,
                        bool time_true_distances) {
  Result r;
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error("pipe failed");
  std::fflush(stdout);
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    close(fds[0]);
    Result out;
    try {
      out = measure(p, mode, repeat, time_true_distances);
    } catch (const std::exception& e) {
      std::snprintf(out.error, sizeof out.error, "%s", e.what());
    }
    const char* data = reinterpret_cast<const char*>(&out);
    std::size_t left = sizeof out;
    while (left > 0) {
      const ssize_t n = write(fds[1], data, left);
      if (n <= 0) break;
      data += n;
      left -= static_cast<std::size_t>(n);
    }
    _exit(0);
  }
  close(fds[1]);
  char* data = reinterpret_cast<char*>(&r);
  std::size_t got = 0;
  while (got < sizeof r) {
    const ssize_t n = read(fds[0], data + got, sizeof r - got);
    if (n <= 0) break;
    got += static_cast<std::size_t>(n);
  }
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (got != sizeof r) {
    r = Result{};
    std::snprintf(r.error, sizeof r.error, "child ended without a result (status %d)", status);
  }
  return r;
}

// ---------------------------------------------------------------------------------------------
// Report

const char* mode_name(voxel::LabelMode m) {
  return m == voxel::LabelMode::center ? "center" : "conservative";
}

struct Row {
  const Point* point;
  voxel::LabelMode mode;
  Result result;
};

const char* family_title(const std::string& family) {
  if (family == "robot") return "robot triangles";
  if (family == "person") return "person triangles";
  if (family == "states") return "states";
  if (family == "cameras") return "cameras";
  return "resolution";
}

void print_header() {
  std::printf("%-12s %-9s %-12s %8s %6s %5s %7s %8s %9s %9s %9s %8s %9s %10s %8s %9s\n", "series",
              "N", "mode", "tri", "states", "cams", "voxels", "dtrue_s", "setup_s", "eval_ms",
              "min_ms", "rss_MiB", "Err", "embree_bms", "rays", "embree_ms");
}

void print_row(const Row& row) {
  const Result& r = row.result;
  const Point& p = *row.point;
  if (!r.ok) {
    std::printf("%-12s %-9s %-12s failed: %s\n", p.series.c_str(), p.label.c_str(),
                mode_name(row.mode), r.error);
    return;
  }
  char dtrue[16] = "";
  if (r.true_distance_s >= 0.0) std::snprintf(dtrue, sizeof dtrue, "%.3f", r.true_distance_s);
  std::printf("%-12s %-9s %-12s %8d %6d %5d %7d %8s %9.3f %9.3f %9.3f %8.1f %9.4f",
              p.series.c_str(), p.label.c_str(), mode_name(row.mode), r.triangles, r.states,
              r.cameras, r.voxels, dtrue, r.setup_s, r.eval_ms, r.eval_min_ms, r.rss_mib, r.err);
  if (r.embree) {
    std::printf(" %10.3f %8lld %9.3f", r.embree_build_ms, r.embree_rays, r.embree_ms);
  }
  std::printf("\n");
  std::fflush(stdout);
}

/// The log-log slope of y between two rows, or NaN when a value is not positive.
double slope(double x0, double y0, double x1, double y1) {
  if (!(x0 > 0 && x1 > 0 && y0 > 0 && y1 > 0) || x0 == x1) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return std::log(y1 / y0) / std::log(x1 / x0);
}

std::string exponent_text(double e) {
  if (std::isnan(e)) return "  n/a";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%5.2f", e);
  return buf;
}

/// Exponents of one series and mode: consecutive pairs, the top decade, the whole range.
void print_exponents(const std::string& family, const std::vector<const Row*>& rows) {
  if (rows.size() < 2) return;
  const Row& top = *rows.back();
  std::vector<std::pair<std::size_t, std::size_t>> spans;
  for (std::size_t i = 0; i + 1 < rows.size(); ++i) spans.emplace_back(i, i + 1);
  std::size_t decade = 0;
  while (decade + 1 < rows.size() && rows[decade]->point->n < top.point->n / 10.0 * (1 - 1e-9)) {
    ++decade;
  }
  const std::size_t last = rows.size() - 1;
  if (decade + 1 < last) spans.emplace_back(decade, last);
  if (0 != decade && last > 1) spans.emplace_back(0, last);
  for (const auto& [i, j] : spans) {
    const Result& a = rows[i]->result;
    const Result& b = rows[j]->result;
    const double x0 = rows[i]->point->n, x1 = rows[j]->point->n;
    const char* what = j != i + 1 ? (i == decade ? " (top decade)" : " (whole range)") : "";
    std::printf("  %s %s %s->%s%s, %s: exponent eval %s, setup %s, rss %s", family_title(family),
                rows[i]->point->series.c_str(), rows[i]->point->label.c_str(),
                rows[j]->point->label.c_str(), what, mode_name(rows[i]->mode),
                exponent_text(slope(x0, a.eval_ms, x1, b.eval_ms)).c_str(),
                exponent_text(slope(x0, a.setup_s, x1, b.setup_s)).c_str(),
                exponent_text(slope(x0, a.rss_mib, x1, b.rss_mib)).c_str());
    if (a.embree && b.embree) {
      std::printf(", embree %s", exponent_text(slope(x0, a.embree_ms, x1, b.embree_ms)).c_str());
    }
    std::printf("\n");
  }
}

void write_csv(const std::string& path, const std::vector<Row>& rows, int repeat) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  out << "family,series,n_label,n,mode,ok,triangles,states,cameras,voxels,true_distance_s,"
         "setup_s,eval_cpu_ms,eval_cpu_min_ms,labelling_wall_ms,repeat,setup_rss_growth_mib,rss_"
         "growth_mib,err,embree,"
         "embree_build_ms,embree_rays,"
         "embree_cpu_ms,embree_hits\n";
  out.precision(10);
  for (const Row& row : rows) {
    const Result& r = row.result;
    const Point& p = *row.point;
    out << p.family << ',' << p.series << ',' << p.label << ',' << p.n << ',' << mode_name(row.mode)
        << ',' << r.ok << ',' << r.triangles << ',' << r.states << ',' << r.cameras << ','
        << r.voxels << ',' << r.true_distance_s << ',' << r.setup_s << ',' << r.eval_ms << ','
        << r.eval_min_ms << ',' << r.labelling_ms << ',' << repeat << ',' << r.setup_rss_mib << ','
        << r.rss_mib << ',' << r.err << ',' << r.embree << ',' << r.embree_build_ms << ','
        << r.embree_rays << ',' << r.embree_ms << ',' << r.embree_hits << '\n';
  }
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse_options(argc, argv);
    g_voxels = o.voxels;
    const double t0 = wall_s();
#ifdef CAMPLACE_WITH_EMBREE
    std::printf("Embree: %d.%d.%d (yardstick in center mode)\n", RTC_VERSION_MAJOR,
                RTC_VERSION_MINOR, RTC_VERSION_PATCH);
#else
    std::printf("Embree: not installed\n");
#endif
    std::printf("repeat %d, pid %d; one child process per point and mode\n", o.repeat,
                static_cast<int>(getpid()));
    std::vector<std::vector<Point>> families;
    std::vector<Row> rows;
    for (const std::string& family : kFamilies) {
      if (!o.families.count(family)) continue;
      families.push_back(family_points(family, o));
    }
    // Rows point into `families`, which no longer grows.
    for (const auto& points : families) {
      if (points.empty()) continue;
      const std::string& family = points.front().family;
      std::printf("\n== %s ==\n", family_title(family));
      print_header();
      const std::size_t first = rows.size();
      for (const Point& p : points) {
        for (voxel::LabelMode mode : o.modes) {
          const bool first_mode = mode == o.modes.front();
          rows.push_back({&p, mode, measure_in_child(p, mode, o.repeat, first_mode)});
          print_row(rows.back());
        }
      }
      for (voxel::LabelMode mode : o.modes) {
        std::vector<std::string> series;
        for (const Point& p : points) {
          if (std::find(series.begin(), series.end(), p.series) == series.end()) {
            series.push_back(p.series);
          }
        }
        for (const std::string& s : series) {
          std::vector<const Row*> selected;
          for (std::size_t i = first; i < rows.size(); ++i) {
            if (rows[i].mode == mode && rows[i].point->series == s && rows[i].result.ok) {
              selected.push_back(&rows[i]);
            }
          }
          print_exponents(family, selected);
        }
      }
    }
    if (!o.csv.empty()) write_csv(o.csv, rows, o.repeat);
    std::printf("\ntotal %.1f s wall\n", wall_s() - t0);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "scale_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
