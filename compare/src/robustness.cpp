#include "camplace/compare/robustness.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>
#include <set>

#include "camplace/compare/evaluation_json.hpp"
#include "camplace/core/err.hpp"
#include "camplace/core/error.hpp"
#include "camplace/core/files.hpp"
#include "camplace/optimize/encoding.hpp"
#include "camplace/voxel/evaluator.hpp"
#include "format.hpp"

namespace camplace::compare {
namespace {

/// Rounding of camera files (angles stored in degrees, positions as shortest decimals): the
/// slack of the tolerance check.
constexpr double kSlack = 1e-9;

/// One camera's perturbation: position offset dp (m), the tilt (a, b) of the viewing direction
/// (radians along the planned camera's right and up vectors; the direction turns by
/// |(a, b)|), and the roll offset r (radians).
struct Offset {
  core::Vec3 dp = core::Vec3::Zero();
  double a = 0.0, b = 0.0, r = 0.0;
  bool zero() const { return dp.isZero(0.0) && a == 0.0 && b == 0.0 && r == 0.0; }
};
using Offsets = std::vector<Offset>;

/// Angle between two unit directions (radians), accurate for small angles too.
double angle_between(const core::Vec3& u, const core::Vec3& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

/// The planned camera's right and up vectors without roll: a basis of the plane ⟂ d.
std::pair<core::Vec3, core::Vec3> tangent_basis(const core::CameraSetting& c) {
  core::CameraSetting level = c;
  level.roll = 0.0;
  const core::Vec3 d = core::view_direction(c);
  const core::Vec3 up = core::up_vector(level);
  return {d.cross(up).normalized(), up};
}

core::CameraSetting apply(const core::CameraSetting& c, const Offset& o) {
  core::CameraSetting out = c;
  out.position = c.position + o.dp;
  const double phi = std::hypot(o.a, o.b);
  if (phi > 0.0) {
    const core::Vec3 d0 = core::view_direction(c);
    const auto [e1, e2] = tangent_basis(c);
    const core::Vec3 d =
        (std::cos(phi) * d0 + std::sin(phi) * (o.a * e1 + o.b * e2) / phi).normalized();
    out.yaw = std::atan2(d.y(), d.x());
    out.pitch = std::asin(std::clamp(d.z(), -1.0, 1.0));
  }
  out.roll = c.roll + o.r;
  return out;
}

/// The nearest-rank percentile q ∈ (0, 1] of the values (0 for none).
double percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(values.size())));
  return values[std::clamp<std::size_t>(rank, 1, values.size()) - 1];
}

class Analyser {
 public:
  Analyser(const core::Scene& scene, const core::CameraConfig& planned,
           const RobustnessOptions& options)
      : scene_(scene),
        planned_(planned),
        options_(options),
        encoding_(scene),
        evaluator_(scene, voxel_options(options)),
        started_(std::chrono::steady_clock::now()) {
    for (const core::CameraModel& m : scene.cameras.models) has_roll_.push_back(m.has_roll());
  }

  RobustnessResult run() {
    RobustnessResult result;
    result.tolerance = tolerance();
    result.err_lower_bound = evaluator_.err_lower_bound();
    result.nominal_voxel_err = voxel_err(planned_);
    if (exact_samples() || options_.exact_checks > 0) {
      result.nominal_exact_err = exact_err(planned_);
    }
    result.nominal_err = exact_samples() ? *result.nominal_exact_err : result.nominal_voxel_err;

    // Seeded random perturbations of every camera at once.
    std::mt19937_64 rng(options_.seed);
    for (int k = 0; k < options_.samples && !stopped(); ++k) {
      Offsets offsets(planned_.size());
      for (std::size_t i = 0; i < planned_.size(); ++i) offsets[i] = random_offset(rng, i);
      Perturbed p = evaluate(offsets, "sample " + std::to_string(k + 1), exact_samples());
      result.samples.push_back(std::move(p));
      progress("samples", k + 1, options_.samples);
    }
    std::vector<double> errs;
    for (const Perturbed& p : result.samples) errs.push_back(p.err);
    result.p95_err = percentile(errs, 0.95);
    result.median_err = percentile(errs, 0.5);

    std::vector<const Perturbed*> candidates;
    for (const Perturbed& p : result.samples) candidates.push_back(&p);

    // The worst-case search over all cameras, from the samples worst by the voxel Err (up to
    // kStarts of them, worst first, sharing the budget): the voxel Err is piecewise constant,
    // so one ascent often ends on its first plateau.
    if (options_.search_evaluations > 0 && !result.samples.empty() && !stopped()) {
      constexpr std::size_t kStarts = 5;
      std::vector<std::size_t> order(result.samples.size());
      for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
      std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return result.samples[a].voxel_err > result.samples[b].voxel_err;
      });
      std::vector<bool> all(planned_.size(), true);
      int remaining = options_.search_evaluations;
      for (std::size_t k = 0; k < std::min(kStarts, order.size()) && remaining > 0 && !stopped();
           ++k) {
        int used = 0;
        Perturbed found = search(sample_offsets_[order[k]], result.samples[order[k]], all,
                                 remaining, "search (all cameras)", &used);
        remaining -= used;
        if (!result.searched || found.voxel_err > result.searched->voxel_err) {
          result.searched = std::move(found);
        }
      }
      candidates.push_back(&*result.searched);
    }

    // One camera at a time: its own samples and search, the others as planned.
    std::vector<Perturbed> per_camera_worst;
    per_camera_worst.reserve(planned_.size());
    const int n = static_cast<int>(planned_.size());
    const int camera_samples = std::max(10, options_.samples / std::max(n, 1));
    const int camera_budget = options_.search_evaluations / std::max(n, 1);
    for (int j = 0; j < n && !stopped(); ++j) {
      std::mt19937_64 camera_rng(options_.seed + 1000003ULL * static_cast<unsigned>(j + 1));
      const int before = voxel_evaluations_;
      std::optional<Perturbed> worst;
      Offsets worst_offsets;
      for (int k = 0; k < camera_samples && !stopped(); ++k) {
        Offsets offsets(planned_.size());
        offsets[j] = random_offset(camera_rng, j);
        Perturbed p = evaluate(offsets, "camera " + std::to_string(j) + " sample", false);
        if (!worst || p.voxel_err > worst->voxel_err) {
          worst = std::move(p);
          worst_offsets = last_offsets_;
        }
      }
      if (!worst) break;
      if (camera_budget > 0 && !stopped()) {
        std::vector<bool> only(planned_.size(), false);
        only[j] = true;
        int used = 0;
        Perturbed searched = search(worst_offsets, *worst, only, camera_budget,
                                    "search (camera " + std::to_string(j) + ")", &used);
        if (searched.voxel_err > worst->voxel_err) worst = std::move(searched);
      }
      worst->origin = "worst with camera " + std::to_string(j) + " alone (" + worst->origin + ")";
      result.per_camera.push_back({j, worst->voxel_err, voxel_evaluations_ - before});
      per_camera_worst.push_back(std::move(*worst));
      progress("per camera", j + 1, n);
    }
    for (const Perturbed& p : per_camera_worst) candidates.push_back(&p);

    // Exact check of the worst distinct configurations.
    std::vector<const Perturbed*> order = candidates;
    std::stable_sort(order.begin(), order.end(), [&](const Perturbed* a, const Perturbed* b) {
      return exact_samples() ? rank_err(*a) > rank_err(*b) : a->voxel_err > b->voxel_err;
    });
    std::set<std::string> seen;
    const int checks = exact_samples() ? static_cast<int>(order.size()) : options_.exact_checks;
    for (const Perturbed* p : order) {
      if (static_cast<int>(result.exact_checked.size()) >= checks || stopped()) break;
      if (!seen.insert(p->cameras_json).second) continue;
      Perturbed checked = *p;
      if (!checked.exact_err) checked.exact_err = exact_err(checked.cameras);
      if (exact_samples()) checked.err = *checked.exact_err;
      result.exact_checked.push_back(std::move(checked));
      progress("exact check", static_cast<int>(result.exact_checked.size()), checks);
    }
    std::stable_sort(result.exact_checked.begin(), result.exact_checked.end(),
                     [](const Perturbed& a, const Perturbed& b) { return a.err > b.err; });

    // The worst by the samples' pipeline.
    if (exact_samples()) {
      if (!result.exact_checked.empty()) result.worst = result.exact_checked.front();
    } else {
      const Perturbed* worst = nullptr;
      for (const Perturbed* p : candidates) {
        if (worst == nullptr || p->voxel_err > worst->voxel_err) worst = p;
      }
      if (worst != nullptr) {
        result.worst = *worst;
        for (const Perturbed& c : result.exact_checked) {
          if (c.cameras_json == worst->cameras_json) result.worst.exact_err = c.exact_err;
        }
      }
    }
    result.samples.shrink_to_fit();
    result.voxel_evaluations = voxel_evaluations_;
    result.exact_evaluations = exact_evaluations_;
    result.interrupted = stopped();
    result.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
    return result;
  }

 private:
  static voxel::VoxelOptions voxel_options(const RobustnessOptions& o) {
    voxel::VoxelOptions v;
    v.mode = o.mode;
    v.resolution = o.resolution;
    v.refine = o.refine;
    v.threads = std::max(o.threads, 1);
    return v;
  }

  bool exact_samples() const { return options_.pipeline == core::Pipeline::exact; }
  bool stopped() const { return options_.interrupt != nullptr && options_.interrupt->load(); }
  double rank_err(const Perturbed& p) const { return p.exact_err ? *p.exact_err : p.voxel_err; }

  void progress(const std::string& stage, int done, int total) const {
    if (options_.on_progress) options_.on_progress(stage, done, total);
  }

  /// (½ voxel diagonal)² at the evaluator's resolution (SPEC §4).
  double tolerance() const {
    return core::default_tolerance(evaluator_.grid().area, evaluator_.grid().n);
  }

  double voxel_err(const core::CameraConfig& config) {
    ++voxel_evaluations_;
    return evaluator_.evaluate(config).err;
  }

  double exact_err(const core::CameraConfig& config) {
    ++exact_evaluations_;
    EvaluationOptions o;
    o.pipeline = core::Pipeline::exact;
    o.threads = std::max(options_.threads, 1);
    return evaluate_json(scene_, config, o).result.at("err").get<double>();
  }

  Offset random_offset(std::mt19937_64& rng, std::size_t camera) const {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::normal_distribution<double> normal(0.0, 1.0);
    Offset o;
    // Position: uniform in the ball of radius position_tol.
    core::Vec3 direction(normal(rng), normal(rng), normal(rng));
    const double radius = options_.position_tol * std::cbrt(unit(rng));
    if (direction.norm() > 0.0 && radius > 0.0) o.dp = radius * direction.normalized();
    // Direction: uniform on the spherical cap of half angle angle_tol about the planned one.
    const double cos_phi = 1.0 - unit(rng) * (1.0 - std::cos(options_.angle_tol));
    const double phi = std::acos(std::clamp(cos_phi, -1.0, 1.0));
    const double beta = 2.0 * core::kPi * unit(rng);
    if (phi > 0.0) {
      o.a = phi * std::cos(beta);
      o.b = phi * std::sin(beta);
    }
    const double roll = options_.angle_tol * (2.0 * unit(rng) - 1.0);
    if (has_roll_[camera]) o.r = roll;
    return o;
  }

  /// Offsets shrunk onto the tolerance balls.
  Offset project(Offset o) const {
    const double moved = o.dp.norm();
    if (moved > options_.position_tol) {
      o.dp *= moved > 0.0 ? options_.position_tol / moved : 0.0;
    }
    const double phi = std::hypot(o.a, o.b);
    if (phi > options_.angle_tol) {
      o.a *= options_.angle_tol / phi;
      o.b *= options_.angle_tol / phi;
    }
    o.r = std::clamp(o.r, -options_.angle_tol, options_.angle_tol);
    return o;
  }

  /// The valid configuration of `offsets` (as the optimizer decodes its own: clamped into the
  /// domain, onto the mount, out of keep-out boxes), as a camera file re-reads it; shrunk toward
  /// the planned configuration until every camera lies within the tolerances. Sets
  /// last_offsets_ to the offsets used.
  Perturbed make_valid(const Offsets& offsets) {
    Offsets scaled = offsets;
    for (int attempt = 0; attempt <= 40; ++attempt) {
      core::CameraConfig raw = planned_;
      bool any = false;
      for (std::size_t i = 0; i < raw.size(); ++i) {
        if (scaled[i].zero()) continue;
        raw[i] = apply(planned_[i], scaled[i]);
        any = true;
      }
      core::CameraConfig config = raw;
      if (any) {
        const core::CameraConfig decoded = encoding_.decode(encoding_.encode(raw));
        for (std::size_t i = 0; i < raw.size(); ++i) {
          if (!scaled[i].zero()) config[i] = decoded[i];
        }
      }
      Perturbed p;
      p.cameras_json = core::camera_config_json(config, 2, &scene_);
      p.cameras = core::camera_config_from_json(nlohmann::json::parse(p.cameras_json),
                                                "perturbed cameras", &scene_);
      if (attempt == 40 ||
          within_tolerance(planned_, p.cameras, options_.position_tol, options_.angle_tol)) {
        CAMPLACE_ASSERT(attempt < 40 || !any);
        for (std::size_t i = 0; i < planned_.size(); ++i) {
          p.moved_m.push_back((p.cameras[i].position - planned_[i].position).norm());
          p.turned.push_back(
              angle_between(core::view_direction(planned_[i]), core::view_direction(p.cameras[i])));
          p.rolled.push_back(std::abs(p.cameras[i].roll - planned_[i].roll));
        }
        last_offsets_ = scaled;
        return p;
      }
      // The repair moved a camera beyond the tolerances: halve every offset (the last
      // attempt, all offsets ~1e-12 of the tolerances, is the planned configuration).
      for (Offset& o : scaled) {
        o.dp *= 0.5;
        o.a *= 0.5;
        o.b *= 0.5;
        o.r *= 0.5;
      }
      if (attempt == 39) scaled.assign(scaled.size(), Offset{});
    }
    CAMPLACE_ASSERT(false && "unreachable");
    return {};
  }

  Perturbed evaluate(const Offsets& offsets, const std::string& origin, bool exact) {
    Perturbed p = make_valid(offsets);
    p.origin = origin;
    p.voxel_err = voxel_err(p.cameras);
    if (exact) p.exact_err = exact_err(p.cameras);
    p.err = exact ? *p.exact_err : p.voxel_err;
    if (origin.rfind("sample ", 0) == 0) sample_offsets_.push_back(last_offsets_);
    return p;
  }

  /// Coordinate ascent on the voxel Err over the offsets of the cameras in `which`: each
  /// coordinate (dx, dy, dz, tilt a, tilt b, roll) in turn moves by ± a step (the tolerance,
  /// then half, then a quarter of it), projected onto the tolerance balls; a move is kept when
  /// the Err strictly increases; sweeps repeat while one does, within `budget` evaluations
  /// (those used in `evaluations`).
  Perturbed search(Offsets current, Perturbed best, const std::vector<bool>& which, int budget,
                   const std::string& origin, int* evaluations) {
    int used = 0;
    const double p_tol = options_.position_tol, a_tol = options_.angle_tol;
    for (const double fraction : {1.0, 0.5, 0.25}) {
      bool improved = true;
      while (improved && used < budget && !stopped()) {
        improved = false;
        for (std::size_t i = 0; i < current.size() && used < budget && !stopped(); ++i) {
          if (!which[i]) continue;
          for (int c = 0; c < 6 && used < budget && !stopped(); ++c) {
            const double step = (c < 3 ? p_tol : a_tol) * fraction;
            if (step <= 0.0 || (c == 5 && !has_roll_[i])) continue;
            for (const double sign : {1.0, -1.0}) {
              Offsets trial = current;
              Offset& o = trial[i];
              if (c < 3) {
                o.dp[c] += sign * step;
              } else if (c == 3) {
                o.a += sign * step;
              } else if (c == 4) {
                o.b += sign * step;
              } else {
                o.r += sign * step;
              }
              o = project(o);
              const Offset& was = current[i];
              if ((o.dp - was.dp).isZero(0.0) && o.a == was.a && o.b == was.b && o.r == was.r)
                continue;
              ++used;
              Perturbed p = evaluate(trial, origin, false);
              progress("search", used, budget);
              if (p.voxel_err > best.voxel_err) {
                best = std::move(p);
                current = last_offsets_;
                improved = true;
                break;
              }
              if (used >= budget) break;
            }
          }
        }
      }
    }
    best.origin = origin;
    *evaluations = used;
    return best;
  }

  const core::Scene& scene_;
  const core::CameraConfig& planned_;
  const RobustnessOptions& options_;
  optimize::Encoding encoding_;
  voxel::VoxelEvaluator evaluator_;
  std::vector<bool> has_roll_;
  std::vector<Offsets> sample_offsets_;  ///< the offsets of each random sample, in order
  Offsets last_offsets_;                 ///< of the last make_valid()
  int voxel_evaluations_ = 0, exact_evaluations_ = 0;
  std::chrono::steady_clock::time_point started_;
};

}  // namespace

bool within_tolerance(const core::CameraConfig& planned, const core::CameraConfig& perturbed,
                      double position_tol, double angle_tol) {
  if (planned.size() != perturbed.size()) return false;
  for (std::size_t i = 0; i < planned.size(); ++i) {
    const double moved = (perturbed[i].position - planned[i].position).norm();
    const double turned =
        angle_between(core::view_direction(planned[i]), core::view_direction(perturbed[i]));
    const double rolled = std::abs(perturbed[i].roll - planned[i].roll);
    if (moved > position_tol * (1.0 + kSlack) + kSlack || turned > angle_tol + kSlack ||
        rolled > angle_tol + kSlack) {
      return false;
    }
  }
  return true;
}

RobustnessResult analyse_robustness(const core::Scene& scene, const core::CameraConfig& planned,
                                    const RobustnessOptions& options) {
  if (planned.size() != static_cast<std::size_t>(scene.cameras.count)) {
    throw core::InputError("cameras", "",
                           "holds " + std::to_string(planned.size()) +
                               " cameras but the scene has " + std::to_string(scene.cameras.count));
  }
  if (!(options.position_tol >= 0.0) || !std::isfinite(options.position_tol)) {
    throw core::OptionError("position-tol", "must be a finite number >= 0 (m)");
  }
  if (!(options.angle_tol >= 0.0) || !(options.angle_tol <= core::kPi)) {
    throw core::OptionError("angle-tol", "must be a finite number in [0, 180] (degrees)");
  }
  if (options.samples < 1) throw core::OptionError("samples", "must be at least 1");
  Analyser analyser(scene, planned, options);
  return analyser.run();
}

}  // namespace camplace::compare

namespace camplace::compare {
namespace {

nlohmann::ordered_json perturbed_json(const Perturbed& p) {
  nlohmann::ordered_json j;
  j["origin"] = p.origin;
  j["err"] = p.err;
  j["voxel_err"] = p.voxel_err;
  j["exact_err"] = p.exact_err ? nlohmann::ordered_json(*p.exact_err) : nullptr;
  nlohmann::ordered_json deviations = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < p.moved_m.size(); ++i) {
    deviations.push_back({{"camera", i},
                          {"moved_m", p.moved_m[i]},
                          {"turned_deg", p.turned[i] / core::kDegree},
                          {"rolled_deg", p.rolled[i] / core::kDegree}});
  }
  j["deviations"] = deviations;
  j["cameras"] = nlohmann::ordered_json::parse(p.cameras_json).at("cameras");
  return j;
}

double max_of(const std::vector<double>& v) {
  return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
}

/// The camera whose tolerance alone raises the Err most (-1: none analysed).
int most_sensitive(const RobustnessResult& r) {
  int best = -1;
  for (std::size_t j = 0; j < r.per_camera.size(); ++j) {
    if (best < 0 || r.per_camera[j].worst_voxel_err > r.per_camera[best].worst_voxel_err) {
      best = static_cast<int>(j);
    }
  }
  return best;
}

}  // namespace

std::string robustness_summary(const RobustnessOptions& options, const RobustnessResult& r) {
  const bool exact = options.pipeline == core::Pipeline::exact;
  const std::string pipeline = exact ? "exact pipeline" : "voxel pipeline";
  std::string s;
  s += "planned configuration: Err " + detail::num(r.nominal_err, 4) + " m² (" + pipeline + ")";
  if (!exact && r.nominal_exact_err)
    s += ", exact Err " + detail::num(*r.nominal_exact_err, 4) + " m²";
  s += "\n";
  s += std::to_string(r.samples.size()) + " random perturbations within " +
       detail::short_number(options.position_tol) + " m and " +
       detail::short_number(options.angle_tol / core::kDegree) + "° (seed " +
       std::to_string(options.seed) + "): median Err " + detail::num(r.median_err, 4) +
       " m², 95th percentile " + detail::num(r.p95_err, 4) + " m²\n";
  if (r.searched) {
    s += "worst-case search (coordinate ascent on the voxel Err, all cameras): voxel Err " +
         detail::num(r.searched->voxel_err, 4) + " m²\n";
  }
  s += "worst found: Err " + detail::num(r.worst.err, 4) + " m² (" + r.worst.origin + ")";
  if (!exact && r.worst.exact_err) s += ", exact Err " + detail::num(*r.worst.exact_err, 4) + " m²";
  s += "; largest deviation " + detail::num(max_of(r.worst.moved_m), 4) + " m, " +
       detail::num(max_of(r.worst.turned) / core::kDegree, 2) + "°\n";
  const int j = most_sensitive(r);
  if (j >= 0) {
    int ties = 0;
    for (const CameraSensitivity& c : r.per_camera) {
      ties += c.worst_voxel_err == r.per_camera[j].worst_voxel_err ? 1 : 0;
    }
    s += ties > 1 ? "no camera's tolerance matters more than the others' (" + std::to_string(ties) +
                        " share the largest worst voxel Err with one camera perturbed, " +
                        detail::num(r.per_camera[j].worst_voxel_err, 4) + " m²; per camera:"
                  : "camera whose tolerance matters most: " + std::to_string(j) +
                        " (worst voxel Err with it alone perturbed " +
                        detail::num(r.per_camera[j].worst_voxel_err, 4) + " m²; per camera:";
    for (const CameraSensitivity& c : r.per_camera) {
      s += " " + std::to_string(c.camera) + ": " + detail::num(c.worst_voxel_err, 4);
    }
    s += ")\n";
  }
  const double tol = r.tolerance;
  s += "tolerance " + detail::num(tol, 4) + " m²: planned " +
       (r.nominal_err <= tol ? "reaches it" : "misses it") + "; worst perturbed " +
       (r.worst.err <= tol ? "still reaches it" : "misses it") + " (" + pipeline + ")";
  if (!exact && r.err_lower_bound > tol) {
    s += "; the voxel lower bound " + detail::num(r.err_lower_bound, 4) +
         " m² lies above the tolerance, so no configuration reaches it by voxel Err in this mode "
         "and resolution";
  }
  s += "\n";
  if (!r.exact_checked.empty()) {
    double largest = 0.0;
    int reached = 0;
    for (const Perturbed& p : r.exact_checked) {
      largest = std::max(largest, *p.exact_err);
      reached += *p.exact_err <= tol ? 1 : 0;
    }
    s += "exact check of the " + std::to_string(r.exact_checked.size()) +
         " worst distinct configurations" + (exact ? "" : " by voxel Err") + ": " +
         std::to_string(reached) + " reach the tolerance, largest exact Err " +
         detail::num(largest, 4) + " m²\n";
  }
  if (r.interrupted) s += "interrupted: the figures cover the work done before the signal\n";
  return s;
}

void write_robustness_report(const std::string& dir, const RobustnessOptions& options,
                             const RobustnessResult& r, const RobustnessReport& report) {
  namespace fs = std::filesystem;
  const fs::path out(dir);
  const bool exact = options.pipeline == core::Pipeline::exact;
  // The worst configuration as a camera file, exactly the text its Err was computed from.
  core::write_file_atomically((out / "worst-cameras.json").string(), r.worst.cameras_json + "\n");

  std::string csv = "sample,err,voxel_err,exact_err,max_moved_m,max_turned_deg,max_rolled_deg\n";
  for (std::size_t k = 0; k < r.samples.size(); ++k) {
    const Perturbed& p = r.samples[k];
    csv += std::to_string(k + 1) + "," + detail::full_number(p.err) + "," +
           detail::full_number(p.voxel_err) + "," +
           (p.exact_err ? detail::full_number(*p.exact_err) : "") + "," +
           detail::full_number(max_of(p.moved_m)) + "," +
           detail::full_number(max_of(p.turned) / core::kDegree) + "," +
           detail::full_number(max_of(p.rolled) / core::kDegree) + "\n";
  }
  core::write_file_atomically((out / "samples.csv").string(), csv);

  nlohmann::ordered_json j;
  j["format_version"] = 1;
  j["command"] = report.command;
  j["provenance"] = core::provenance_json(report.provenance);
  j["cameras_file"] = report.cameras_file;
  j["options"] = {{"position_tol_m", options.position_tol},
                  {"angle_tol_deg", options.angle_tol / core::kDegree},
                  {"samples", options.samples},
                  {"seed", options.seed},
                  {"pipeline", core::name_of(options.pipeline)},
                  {"mode", core::name_of(options.mode)},
                  {"resolution", options.resolution},
                  {"refine", options.refine},
                  {"search_evaluations", options.search_evaluations},
                  {"exact_checks", options.exact_checks}};
  j["tolerance"] = r.tolerance;
  j["err_lower_bound"] = r.err_lower_bound;
  j["planned"] = {{"err", r.nominal_err},
                  {"voxel_err", r.nominal_voxel_err},
                  {"exact_err", r.nominal_exact_err ? nlohmann::ordered_json(*r.nominal_exact_err)
                                                    : nlohmann::ordered_json()}};
  j["samples"] = r.samples.size();
  j["median_err"] = r.median_err;
  j["p95_err"] = r.p95_err;
  j["worst"] = perturbed_json(r.worst);
  j["searched"] = r.searched ? perturbed_json(*r.searched) : nlohmann::ordered_json();
  nlohmann::ordered_json per_camera = nlohmann::ordered_json::array();
  for (const CameraSensitivity& c : r.per_camera) {
    per_camera.push_back({{"camera", c.camera},
                          {"worst_voxel_err", c.worst_voxel_err},
                          {"evaluations", c.evaluations}});
  }
  j["per_camera"] = per_camera;
  // null when several cameras share the largest worst Err (none stands out).
  const int sensitive = most_sensitive(r);
  int ties = 0;
  for (const CameraSensitivity& c : r.per_camera) {
    ties += sensitive >= 0 && c.worst_voxel_err == r.per_camera[sensitive].worst_voxel_err;
  }
  j["most_sensitive_camera"] =
      sensitive >= 0 && ties == 1 ? nlohmann::ordered_json(sensitive) : nlohmann::ordered_json();
  nlohmann::ordered_json checked = nlohmann::ordered_json::array();
  for (const Perturbed& p : r.exact_checked) checked.push_back(perturbed_json(p));
  j["exact_checked"] = checked;
  j["tolerance_holds"] = {{"planned", r.nominal_err <= r.tolerance},
                          {"worst", r.worst.err <= r.tolerance}};
  j["voxel_evaluations"] = r.voxel_evaluations;
  j["exact_evaluations"] = r.exact_evaluations;
  j["seconds"] = r.seconds;
  j["interrupted"] = r.interrupted;
  core::write_file_atomically((out / "robustness.json").string(), j.dump(2) + "\n");

  const core::BuildInfo& b = report.provenance.build;
  std::string md = "# Robustness to mounting errors\n\n";
  md += "Made by `" + report.command + "` (camplace " + b.version + ", commit " + b.commit +
        "; scene " + report.provenance.scene_file + ", sha256 " +
        report.provenance.scene.combined.substr(0, 12) + "…; cameras " + report.cameras_file +
        "; " + report.provenance.host + ", " + report.provenance.started + ").\n\n";
  md += "Each camera is moved by at most " + detail::short_number(options.position_tol) +
        " m and its viewing direction turned by at most " +
        detail::short_number(options.angle_tol / core::kDegree) +
        "° (roll, where the model has one, by at most as much), then made valid as the optimizer "
        "makes its configurations (clamped into its domain, onto its mount, out of keep-out "
        "boxes). Err by the " +
        std::string(exact ? "exact" : "voxel") + " pipeline (" + core::name_of(options.mode) +
        " labelling" + (options.refine > 0 ? ", refine " + std::to_string(options.refine) : "") +
        "). The 95th percentile is the nearest-rank one of the random samples.\n\n```\n" +
        robustness_summary(options, r) + "```\n\n";
  md += "| camera | worst voxel Err with it alone perturbed [m²] | evaluations |\n|---|---|---|\n";
  for (const CameraSensitivity& c : r.per_camera) {
    md += "| " + std::to_string(c.camera) + " | " + detail::num(c.worst_voxel_err, 4) + " | " +
          std::to_string(c.evaluations) + " |\n";
  }
  if (!r.exact_checked.empty()) {
    md +=
        "\nExact check, worst first:\n\n| origin | voxel Err [m²] | exact Err [m²] "
        "|\n|---|---|---|\n";
    for (const Perturbed& p : r.exact_checked) {
      md += "| " + p.origin + " | " + detail::num(p.voxel_err, 4) + " | " +
            detail::num(*p.exact_err, 4) + " |\n";
    }
  }
  md +=
      "\nFiles: `worst-cameras.json` (the worst configuration found; `camplace evaluate SCENE "
      "--cameras worst-cameras.json" +
      std::string(exact ? " --pipeline exact" : "") +
      "` with the same mode and resolution gives its Err), `samples.csv` (one row per random "
      "sample), `robustness.json` (everything above). " +
      std::to_string(r.voxel_evaluations) + " voxel and " + std::to_string(r.exact_evaluations) +
      " exact evaluations, " + detail::num(r.seconds, 1) + " s.\n";
  core::write_file_atomically((out / "robustness.md").string(), md);
}

}  // namespace camplace::compare
