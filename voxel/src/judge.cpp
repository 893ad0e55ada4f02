// The label κ of SPEC §3 of one voxel or refined cell for one camera, for up to 64 states at
// once: center mode (the ray through the centre, judge_center) and conservative mode (every
// point of the box, judge_conservative, with the cone test); block_clear proves whole blocks
// free (docs/design/labelling.md L2, L4, L8).
#include <algorithm>
#include <cmath>
#include <limits>

#include "camplace/core/geometry.hpp"
#include "image_plane.hpp"
#include "impl.hpp"

namespace camplace::voxel {

using core::Vec3;
using detail::bin_of;
using detail::bin_range;
using detail::BinRange;
using detail::box_projection;
using detail::CameraSetup;
using detail::kMargin;
using detail::kTouch;
using detail::Scratch;
using detail::StateMask;
using detail::TriangleCone;
using detail::Verdict;
namespace {

/// The candidate slots of judge_conservative() in order, until `done`: those of the slot groups
/// of the bundles in the bins under the box's projection that `open_bundle` does not rule out as
/// a whole (each bundle once), of the groups that `open` does not rule out as a whole (`project`
/// projects a group), then the slots everywhere. `test(s)`: true when the verdict changed.
/// `group_test(group, s)`: test(s) for a slot s of `group` (whose slots share its object).
template <class Test, class GroupTest, class OpenBundle, class Open, class Project, class Done>
void judge_candidates(const CameraSetup& cam, const detail::ChunkCandidates& cand, double vx0,
                      double vx1, double vy0, double vy1, double z_lo, Scratch& scratch, Test& test,
                      GroupTest& group_test, const OpenBundle& open_bundle, const Open& open,
                      const Project& project, const Done& done) {
  auto slots = [&](int g) __attribute__((always_inline)) {
    project(g);
    const detail::SlotGroup& group = cam.groups[g];
    for (int s = group.first; s < group.last; ++s) {
      if (group_test(group, s) && done()) return true;
    }
    return false;
  };
  // A bundle that open_bundle did not rule out.
  auto bundle = [&](int b) {
    const detail::SlotBundle& members = cand.bundles[b];
    // A bundle of one group has that group's bounds: open's tests are made.
    if (members.last - members.first == 1) return slots(cand.bundle_groups[members.first]);
    for (int n = members.first; n < members.last; ++n) {
      const int g = cand.bundle_groups[n];
      if (open(g) && slots(g)) return true;
    }
    return false;
  };
  // Bundle b, unless open_bundle rules it out as a whole (inlined into the bins' loops: most
  // bundles a box visits are, and an outlined call each cost ~10% of an evaluation on fine meshes,
  // bench/scale_bench, robot family of 10k triangles, perf).
  auto visit = [&](int b) __attribute__((always_inline)) {
    return open_bundle(cand.bundles[b]) && bundle(b);
  };
  auto everywhere = [&] {
    for (int s : cand.everywhere) {
      if (test(s) && done()) return;
    }
  };
  if (z_lo > 0.0 && detail::outside_bins(cam.coarse, vx0, vx1, vy0, vy1)) return everywhere();
  if (z_lo > 0.0 && vx1 - vx0 <= 2.0 * cam.widen[0] && vy1 - vy0 <= 2.0 * cam.widen[1]) {
    // A group whose rectangle overlaps the voxel's has its widened rectangle around the voxel
    // rectangle's centre: one wide bin holds every candidate, once.
    const int b = bin_of(cam.wide, 0.5 * (vy0 + vy1), 1) * cam.wide.n[0] +
                  bin_of(cam.wide, 0.5 * (vx0 + vx1), 0);
    for (int n = cand.wide.start[b]; n < cand.wide.start[b + 1]; ++n) {
      if (visit(cand.wide.items[n])) return;
    }
    return everywhere();
  }
  // The bins under the box's projection (all of them when it is not wholly in front); their
  // lists repeat bundles.
  const BinRange bins = z_lo > 0.0 ? detail::bins_under(cam.coarse, vx0, vx1, vy0, vy1)
                                   : BinRange{0, cam.coarse.n[0] - 1, 0, cam.coarse.n[1] - 1};
  ++scratch.visit;
  for (int by = bins.y0; by <= bins.y1; ++by) {
    for (int bx = bins.x0; bx <= bins.x1; ++bx) {
      const int b = by * cam.coarse.n[0] + bx;
      for (int n = cand.coarse.start[b]; n < cand.coarse.start[b + 1]; ++n) {
        const int u = cand.coarse.items[n];
        if (scratch.stamp[u] == scratch.visit) continue;
        scratch.stamp[u] = scratch.visit;
        if (visit(u)) return;
      }
    }
  }
  everywhere();
}

}  // namespace

// (Defined before its callers, so that it is inlined: one per box.)
inline VoxelEvaluator::Impl::ConeBox VoxelEvaluator::Impl::cone_box(const Vec3& w,
                                                                    const detail::CellSize& size) {
  const double norm = w.norm();
  return {w, &size, kTouch * (norm + size.half.sum()), kMargin * norm};
}

/// Center mode: the ray from the camera through the voxel centre at w (d = |w|, or < 0 when not
/// yet known), in the camera's FOV, for the states in `interest`: the states where the voxel is
/// occupied (the first hit along the whole ray is occupying; at equal distance a non-occupying
/// hit first, docs/design/labelling.md L8) and those where it is otherwise not free (a hit in
/// (0, d]). With `free_only` the split between the two is not kept (the model needs no more).
Verdict VoxelEvaluator::Impl::judge_center(const CameraSetup& cam, const Vec3& w, double d,
                                           StateMask interest, int chunk, Scratch& scratch,
                                           bool free_only) const {
  Verdict out;
  const StateMask* object_states = chunk_object_states[chunk].data();
  const detail::ChunkCandidates& cand = cam.chunks[chunk];
  const double x = w.dot(cam.ex), y = w.dot(cam.ey), z = w.dot(cam.axis);
  BinRange bins{0, cam.coarse.n[0] - 1, 0, cam.coarse.n[1] - 1};
  double px = 0.0, py = 0.0;  // the centre's projection
  bool projected = z > 0.0;
  bool binned = true;  // binned slots may hold the centre
  if (projected) {
    px = x / z;
    py = y / z;
    binned = !detail::outside_bins(cam.coarse, px, px, py, py);
    const int bx = bin_of(cam.coarse, px, 0), by = bin_of(cam.coarse, py, 1);
    bins = {bx, bx, by, by};
  }
  // The ray's direction, once a triangle gets to the ray test.
  Vec3 u;
  bool ray_ready = false;
  scratch.hits.clear();
  auto ready = [&] {
    if (!ray_ready) {
      if (d < 0.0) d = w.norm();
      u = w / d;
      ray_ready = true;
    }
  };
  // The ray test of slot s (states m of its object).
  auto ray = [&](int t, int o, StateMask m) {
    const auto& tri = triangles[t];
    const double hit = core::ray_triangle_hit(cam.c, u, tri[0], tri[1], tri[2]);
    if (!(hit > 0.0)) return;
    scratch.hits.push_back({hit, objects[o].occupying ? 1 : 0, t});
    if (hit <= d) out.blocked |= m;
  };
  // The states a hit of object o can still change: with free_only, a state with a hit in
  // (0, d] is not free whatever else the ray meets, so the hits of an object whose states of
  // interest are all blocked change neither the model nor another state's first hit (each hit
  // claims only its own object's states).
  auto open_states = [&](int o) {
    return object_states[o] & interest & (free_only ? ~out.blocked : ~StateMask(0));
  };
  // With free_only, done once every state of interest is blocked.
  auto all_blocked = [&] { return free_only && !(interest & ~out.blocked); };
  auto test = [&](int s) {
    const int o = cam.slot_object[s];
    const StateMask m = open_states(o);
    if (!m) return;
    if (projected) {
      const auto& r = cam.rect[s];  // padded: a ray through the triangle projects inside
      if (px < r[0] || px > r[1] || py < r[2] || py > r[3]) return;
      const detail::EdgeLines& lines = cam.lines[s];
      if (lines.valid) {
        for (const auto& l : lines.line) {
          if (l[0] * px + l[1] * py + l[2] < 0.0) return;
        }
      }
    }
    ready();
    ray(cam.slot_triangle[s], o, m);
  };
  // A group not projected yet, ray by ray: each triangle whose ball the ray's line passes near
  // (within a margin far above the rounding of the distance) gets the ray test. The projection's
  // tests only rule out triangles the ray misses (docs/design/labelling.md L10 e).
  auto direct = [&](const detail::SlotGroup& group) {
    const int o = group.object;
    const StateMask m = open_states(o);
    if (!m) return;
    ready();
    for (int s = group.first; s < group.last; ++s) {
      const int t = group_triangle(cam, group, s);
      const detail::Ball& ball = triangle_balls[t];
      const Vec3 v = ball.center - cam.c;
      const double reach = ball.radius + 1e-7 * (v.norm() + ball.radius);
      if (v.dot(u) < -reach || v.cross(u).squaredNorm() > reach * reach) continue;
      ray(t, o, m);
    }
  };
  // Slot group g of a bundle that passed (its rectangle, its object's states): true when every
  // state of interest is blocked (free_only: nothing left to find).
  auto visit_group = [&](int g) __attribute__((always_inline)) {
    const detail::SlotGroup& group = cam.groups[g];
    // Its object's states (test's first test, the same for each of its slots), then its
    // rectangle, which holds each of its slots' (test's second test).
    if (!open_states(group.object)) return false;
    if (projected) {
      const auto& r = group.rect;
      if (px < r[0] || px > r[1] || py < r[2] || py > r[3]) return false;
    }
    if (cam.direct_rays > 0 &&
        cam.group_state[g].load(std::memory_order_acquire) != detail::kConeReady &&
        cam.group_rays[g].fetch_add(1, std::memory_order_relaxed) < cam.direct_rays) {
      direct(group);
      return all_blocked();
    }
    ensure_projected(cam, g);
    for (int s = group.first; s < group.last; ++s) test(s);
    return all_blocked();
  };
  if (binned) {
    // The bins list bundles of slot groups (copies of one mesh in consecutive time steps, as in
    // conservative mode): the union of their rectangles and of their objects' states holds each
    // group's, so a bundle that fails these tests has no group that passes them.
    const bool bundled = !cand.bundles.empty();
    const bool single = bins.x0 == bins.x1 && bins.y0 == bins.y1;
    if (!single) ++scratch.visit;
    for (int by = bins.y0; by <= bins.y1; ++by) {
      for (int bx = bins.x0; bx <= bins.x1; ++bx) {
        const int b = by * cam.coarse.n[0] + bx;
        for (int n = cand.coarse.start[b]; n < cand.coarse.start[b + 1]; ++n) {
          const int u = cand.coarse.items[n];
          if (!single) {
            if (scratch.stamp[u] == scratch.visit) continue;
            scratch.stamp[u] = scratch.visit;
          }
          // Groups, when the chunk has no bundles (few time steps).
          if (!bundled) {
            if (visit_group(u)) return out;
            continue;
          }
          const detail::SlotBundle& bundle = cand.bundles[u];
          // A bundle of one group has that group's bounds: visit_group's tests are made.
          if (bundle.last - bundle.first == 1) {
            if (visit_group(cand.bundle_groups[bundle.first])) return out;
            continue;
          }
          if (!(bundle.states & interest & (free_only ? ~out.blocked : ~StateMask(0)))) continue;
          if (projected) {
            const auto& r = bundle.rect;
            if (px < r[0] || px > r[1] || py < r[2] || py > r[3]) continue;
          }
          for (int k = bundle.first; k < bundle.last; ++k) {
            if (visit_group(cand.bundle_groups[k])) return out;
          }
        }
      }
    }
  }
  for (int s : cand.everywhere) test(s);
  if (scratch.hits.empty()) return out;
  if (free_only && !(interest & ~out.blocked)) return out;
  // First hit per state: by distance; at equal distance non-occupying first, then by triangle
  // index (the previous labeller's order: a state's objects ascending, occluding ones before
  // occupying ones, their triangles in order; L8).
  std::sort(scratch.hits.begin(), scratch.hits.end(), [](const auto& a, const auto& b) {
    return a.t < b.t || (a.t == b.t && (a.occupying < b.occupying ||
                                        (a.occupying == b.occupying && a.triangle < b.triangle)));
  });
  StateMask claimed = 0;
  for (const Scratch::Hit& h : scratch.hits) {
    const int o = triangle_object[h.triangle];
    const StateMask m = object_states[o] & interest & ~claimed;
    if (objects[o].occupying) out.occupied |= m;
    claimed |= m;
    if (claimed == interest) break;
  }
  return out;
}

/// Conservative mode: the box of size `size` (the voxel's, cell_sizes[0], or a refined cell's;
/// the camera's box extents scale with size.factor) with centre at w from the camera (d = |w|, or
/// < 0 when not yet known), in the camera's FOV, for the states in `interest`: the states where
/// it is occupied and those where it is otherwise not free; free only when every point of the
/// box is (L2). With `free_only` the split is not kept. `witnesses` (optional, refinement): see
/// detail::Witnesses; the verdict does not depend on the order of the tests.
Verdict VoxelEvaluator::Impl::judge_conservative(const CameraSetup& cam, const Vec3& w, double d,
                                                 const detail::CellSize& size, StateMask interest,
                                                 int chunk, Scratch& scratch, bool free_only,
                                                 detail::Witnesses* witnesses) const {
  Verdict out;
  const StateMask* object_states = chunk_object_states[chunk].data();
  const detail::ChunkCandidates& cand = cam.chunks[chunk];
  const double x = w.dot(cam.ex), y = w.dot(cam.ey), z = w.dot(cam.axis);
  // Conservative: free for every point p of the box B when (SPEC §5) no object triangle meets
  // a segment [c, p] (its cone misses B, or it lies wholly beyond B), and no triangle of an
  // occupying object lies on any ray through B (its cone misses B).
  const double inf = std::numeric_limits<double>::infinity();
  double vx0 = -inf, vx1 = inf, vy0 = -inf, vy1 = inf;  // the box's projection lies inside
  const double box_x = cam.box_x * size.factor, box_y = cam.box_y * size.factor;
  const double box_z = cam.box_z * size.factor;
  const double z_lo = z - box_z;
  if (z_lo > 0.0) {
    // (The triangles' rectangles are padded, this one need not be.)
    const auto r = box_projection(x, y, z, box_x, box_y, box_z);
    vx0 = r[0];
    vx1 = r[1];
    vy0 = r[2];
    vy1 = r[3];
  }
  // The box's outline in the image, once a triangle whose rectangle meets the box's has no cone
  // yet (none when the box is not wholly in front): a triangle in front of the camera whose
  // rectangle lies clearly outside it has a cone that misses the box clearly (cone_test's
  // Cone::miss, L10); groups are tested against it once it is known.
  detail::BoxOutline outline;
  bool outlined = z_lo <= 0.0;
  auto outside = [&](const std::array<double, 4>& r) {
    if (!outlined) {
      detail::box_outline(cam, w, size.half, outline);
      outlined = true;
    }
    return detail::outside_outline(outline, r);
  };
  // Needed only once a triangle gets to the cone test.
  Vec3 wc;            // the previous labeller's dir · dist
  ConeBox box;        // the box at wc as cone_test sees it
  double far = -1.0;  // the box's farthest distance, once an occluding triangle needs it
  bool exact_ready = false;
  // The states of object o still open for a test of its triangles: states already decided need
  // no more tests (occupied wins over undetectable).
  auto open_states = [&](int o, bool occupying) {
    const StateMask m = object_states[o] & interest;
    return m & ((free_only || !occupying) ? ~(out.occupied | out.blocked) : ~out.occupied);
  };
  // Whether slots within these bounds may hold a triangle that changes `out`: a rectangle that
  // meets the box's, open states among `states` (those of the slots' objects), and if blocking,
  // not wholly beyond the box (test's tests, on bounds that hold each slot's).
  auto open_bounds = [&](const std::array<double, 4>& r, StateMask states, bool occupying,
                         double near) {
    if (r[0] > vx1 || r[1] < vx0 || r[2] > vy1 || r[3] < vy0) return false;
    const StateMask decided = (free_only || !occupying) ? out.occupied | out.blocked : out.occupied;
    if (!(states & interest & ~decided)) return false;
    if (!occupying) {
      if (far < 0.0) far = (w.cwiseAbs() + size.half).norm();
      if (!(near < far)) return false;
    }
    return !(outlined && outside(r));
  };
  // A bundle of slot groups: its bounds hold each of its groups' (the outline's test is monotone
  // in the rectangle).
  auto open_bundle = [&](const detail::SlotBundle& bundle) {
    return open_bounds(bundle.rect, bundle.states, bundle.occupying, bundle.near);
  };
  auto open = [&](int g) {
    const detail::SlotGroup& group = cam.groups[g];
    return open_bounds(group.rect, object_states[group.object], objects[group.object].occupying,
                       group.near);
  };
  auto project = [&](int g) { ensure_projected(cam, g); };
  // True when `out` changed: slot s of object o (whose role is `occupying`). Inlined into
  // judge_candidates' loops (GCC and Clang): 5% of an evaluation at 36×27×27.
  auto test_of = [&](int s, int o, bool occupying) __attribute__((always_inline)) {
    const StateMask m = open_states(o, occupying);
    if (!m) return false;
    // (The edge lines of the projection would repeat the cone-plane test of cone_test.)
    const auto& r = cam.rect[s];
    if (r[0] > vx1 || r[1] < vx0 || r[2] > vy1 || r[3] < vy0) return false;
    if (!occupying && far < 0.0) far = (w.cwiseAbs() + size.half).norm();
    if (!cone_ready(cam, s)) {
      // Before a cone is made: clearly outside the box's outline, or wholly beyond the box.
      if (outside(r)) return false;
      if (!occupying &&
          detail::nearest_in_ball(triangle_balls[cam.slot_triangle[s]], cam.c) >= far) {
        return false;
      }
    }
    const TriangleCone& tc = cone_of(cam, s);
    if (!exact_ready) {
      if (d < 0.0) d = w.norm();
      wc = (w / d) * d;
      box = cone_box(wc, size);
      exact_ready = true;
    }
    if (!occupying && tc.near_distance >= far) return false;
    const Cone cone = cone_test(tc, box);
    if (cone == Cone::near_miss && cam.culled[o]) {
      // A culled object touching the voxel within rounding: its back faces decide as they
      // did without culling (the front face through the touching point may have been
      // rounded apart). Back faces are no slots: each one's cone is made here, and tested once.
      const detail::ObjectInfo& info = objects[o];
      for (int b = info.first_triangle; b < info.first_triangle + info.triangle_count; ++b) {
        if (!detail::back_face(triangles[b], cam.c)) continue;
        detail::TriangleCone back;
        make_cone(b, cam.c, back);
        if (!occupying && back.near_distance >= far) continue;
        if (cone_test(back, box) == Cone::meet) {
          (occupying ? out.occupied : out.blocked) |= m;
          return true;
        }
      }
    }
    if (cone != Cone::meet) return false;
    (occupying ? out.occupied : out.blocked) |= m;
    if (witnesses) {
      // The cone holds the box: the box's lowest point along each inward plane normal is
      // inside by the margin. A smaller box inside is met too; a blocking triangle nearer than
      // the box's nearest point (|w| − radius) is nearer than every sub-box's `far`.
      const double margin = kMargin * (d + size.radius);
      bool holds = occupying || tc.near_distance < (d - size.radius) * (1.0 - 1e-9) - 1e-12;
      for (int i = 0; i < 3 && holds; ++i) {
        holds = tc.normal[i].dot(wc) - tc.normal[i].cwiseAbs().dot(size.half) > margin;
      }
      if (holds) witnesses->sure |= m;
    }
    return true;
  };
  auto test = [&](int s) __attribute__((always_inline)) {
    const int o = cam.slot_object[s];
    return test_of(s, o, objects[o].occupying);
  };
  // A group's slots are of its object (its role read once per group, not per slot).
  auto group_test = [&](const detail::SlotGroup& group, int s) __attribute__((always_inline)) {
    return test_of(s, group.object, objects[group.object].occupying);
  };
  // With free_only, done as soon as every state of interest is decided.
  auto done = [&] { return free_only && !(interest & ~(out.occupied | out.blocked)); };
  if (witnesses) {
    int* witness = witnesses->triangles;
    // A repeated test finds the states it decides decided: it changes nothing.
    const auto plain = test;
    auto test = [&, plain](int s) {
      if (!plain(s)) return false;
      // Most recent first, each slot once.
      int at = 0;
      while (at < detail::kWitnesses - 1 && witness[at] != s) ++at;
      for (; at > 0; --at) witness[at] = witness[at - 1];
      witness[0] = s;
      return true;
    };
    int first[detail::kWitnesses];
    std::copy(witness, witness + detail::kWitnesses, first);
    for (int s : first) {
      if (s >= 0 && test(s) && done()) return out;
    }
    auto group_witness = [&](const detail::SlotGroup&, int s) { return test(s); };
    judge_candidates(cam, cand, vx0, vx1, vy0, vy1, z_lo, scratch, test, group_witness, open_bundle,
                     open, project, done);
    return out;
  }
  judge_candidates(cam, cand, vx0, vx1, vy0, vy1, z_lo, scratch, test, group_test, open_bundle,
                   open, project, done);
  return out;
}

/// Whether the triangle's infinite cone and the voxel box (centre at w from the camera) meet,
/// by the separating-axis theorem for two convex polyhedra: the cone's 3 planes, the box's 3
/// face normals and the 9 cross products of cone edges and box edges. Exact up to rounding;
/// touching counts as meeting (Cone::meet). Cone::near_miss: separated, but by less than
/// 1e-12 of the scale (|w| + Σh) on every separating axis — a touching configuration where
/// rounding decided; back-face culling then tests the object's back faces too (see
/// judge_conservative()).
VoxelEvaluator::Impl::Cone VoxelEvaluator::Impl::cone_test(const TriangleCone& tc,
                                                           const ConeBox& box) const {
  const Vec3& w = box.w;
  const detail::CellSize& size = *box.size;
  const Vec3& h = size.half;  // the box's half extents (a voxel's or a refined cell's)
  const double scale = box.scale;
  bool near_miss = false;
  // Cone planes first: cheapest and most often decisive.
  double s[3];
  for (int i = 0; i < 3; ++i) {
    s[i] = tc.normal[i].dot(w);
    const double gap = s[i] + tc.normal[i].cwiseAbs().dot(h);
    if (gap < -scale) return Cone::miss;
    near_miss = near_miss || gap < 0.0;
  }
  // The box centre clearly inside the cone: they meet (no axis can separate them).
  const double inside = box.inside;
  if (s[0] > inside && s[1] > inside && s[2] > inside) return Cone::meet;
  // Else the box corner deepest across the planes the centre is outside of: clearly inside
  // the cone, they meet too.
  Vec3 toward = Vec3::Zero();
  for (int i = 0; i < 3; ++i) {
    if (!(s[i] > inside)) toward += tc.normal[i];
  }
  const Vec3 corner = w + Vec3(toward.x() >= 0 ? h.x() : -h.x(), toward.y() >= 0 ? h.y() : -h.y(),
                               toward.z() >= 0 ? h.z() : -h.z());
  if (tc.normal[0].dot(corner) > inside && tc.normal[1].dot(corner) > inside &&
      tc.normal[2].dot(corner) > inside) {
    return Cone::meet;
  }
  // Axis L: the cone projects to [0, ∞) (relative to the camera; L is turned so, when its
  // edges all project to one side, else it was dropped); the box to L·w ± Σ|L_i|·h_i, with the
  // base voxel's h_i times the cell's factor (a power of two: exact).
  for (int a = 0; a < tc.axis_count; ++a) {
    const Vec3& axis = tc.axes[a];
    const double mid = axis.dot(w);
    const double radius = axis.cwiseAbs().dot(half_step) * size.factor;
    const double gap = -(mid + radius);  // > 0: apart
    if (gap > 0.0) {
      if (gap > scale * axis.norm()) return Cone::miss;
      near_miss = true;
    }
  }
  return near_miss ? Cone::near_miss : Cone::meet;
}

/// Conservative mode: the states of `open` where every voxel of the block [lo, hi] is free for
/// this camera, as judge_conservative() would label each of them: each test it or box_in_fov()
/// makes per voxel, made on the whole block with a larger margin (docs/design/labelling.md L4).
StateMask VoxelEvaluator::Impl::block_clear(const CameraSetup& cam, const Vec3& lo, const Vec3& hi,
                                            StateMask open, int chunk, Scratch& scratch) const {
  const StateMask* object_states = chunk_object_states[chunk].data();
  const detail::ChunkCandidates& cand = cam.chunks[chunk];
  const Vec3 center = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  const Vec3 w = center - cam.c;
  const double d = w.norm(), r = half.norm();
  if (!(d > r * (1.0 + 1e-9))) return 0;
  const Vec3 to_centres =
      (lo + half_step - cam.c).cwiseMax(cam.c - (hi - half_step)).cwiseMax(Vec3::Zero());
  const double clear_of_balls = voxel_radius * (1.0 + 1e-9);
  if (!(to_centres.squaredNorm() > clear_of_balls * clear_of_balls)) return 0;
  const double tol = kMargin * (d + r);
  const double z = w.dot(cam.axis);
  if (cam.range && !(z + r < *cam.range - tol)) return 0;
  if (cam.near > 0.0 && !(z - r > cam.near + tol)) return 0;
  if (!(z - r > tol)) return 0;  // wholly in front (also for the projection below)
  if (cam.pyramid) {
    for (const Vec3& n : cam.normals) {
      if (!(n.dot(w) > r + tol)) return 0;
    }
  } else if (!ball_in_cone(cam, w, z, r + tol)) {
    return 0;
  }
  const double x = w.dot(cam.ex), y = w.dot(cam.ey);
  const double box_x = cam.abs_ex.dot(half), box_y = cam.abs_ey.dot(half);
  const double box_z = cam.abs_axis.dot(half);
  if (!(z - box_z > 0.0)) return 0;
  const auto proj = box_projection(x, y, z, box_x, box_y, box_z);
  double vx0 = proj[0], vx1 = proj[1], vy0 = proj[2], vy1 = proj[3];
  // Padded against rounding (a voxel's projection is computed from other numbers).
  const double px = kMargin * (1.0 + std::max(std::abs(vx0), std::abs(vx1)));
  const double py = kMargin * (1.0 + std::max(std::abs(vy0), std::abs(vy1)));
  vx0 -= px;
  vx1 += px;
  vy0 -= py;
  vy1 += py;
  const double far = (w.cwiseAbs() + half).norm() * (1.0 + 1e-12);
  const double scale = 2.0 * kTouch * (d + half.sum());
  // True when slot s may decide some voxel of the block.
  // The block's outline in the image (once a triangle whose rectangle meets the block's has no
  // cone yet): a triangle whose rectangle lies clearly outside it decides no voxel of the block
  // (L10); groups are tested against it once it is known.
  detail::BoxOutline outline;
  bool outlined = false;
  auto outside = [&](const std::array<double, 4>& rect) {
    if (!outlined) {
      detail::box_outline(cam, w, half, outline);
      outlined = true;
    }
    return detail::outside_outline(outline, rect);
  };
  // (occupying: the role of the slot's object.)
  auto decides = [&](int s, bool occupying) {
    const auto& rect = cam.rect[s];
    if (rect[0] > vx1 || rect[1] < vx0 || rect[2] > vy1 || rect[3] < vy0) return false;
    if (!cone_ready(cam, s)) {
      // Before a cone is made: clearly outside the block's outline, or wholly beyond the block.
      if (outside(rect)) return false;
      if (!occupying &&
          detail::nearest_in_ball(triangle_balls[cam.slot_triangle[s]], cam.c) >= far) {
        return false;
      }
    }
    const TriangleCone& tc = cone_of(cam, s);
    if (!occupying && tc.near_distance >= far) return false;
    for (int i = 0; i < 3; ++i) {
      if (tc.normal[i].dot(w) + tc.normal[i].cwiseAbs().dot(half) < -scale) return false;
    }
    for (int a = 0; a < tc.axis_count; ++a) {
      const Vec3& axis = tc.axes[a];
      const double gap = -(axis.dot(w) + axis.cwiseAbs().dot(half));
      if (gap > 0.0 && gap > scale * axis.norm()) return false;
    }
    return true;
  };
  StateMask clear = open;
  // True when no state is left.
  auto pass = [&](int s) {
    const int o = cam.slot_object[s];
    const StateMask m = object_states[o] & clear;
    if (!m) return false;
    if (decides(s, objects[o].occupying)) clear &= ~m;
    return !clear;
  };
  for (int s : cand.everywhere) {
    if (pass(s)) return 0;
  }
  if (detail::outside_bins(cam.coarse, vx0, vx1, vy0, vy1)) return clear;
  auto may_decide = [&](const std::array<double, 4>& rect, StateMask states, bool occupying,
                        double near) {
    if (rect[0] > vx1 || rect[1] < vx0 || rect[2] > vy1 || rect[3] < vy0) return false;
    if (!(states & clear)) return false;
    if (!occupying && near >= far) return false;
    return !(outlined && outside(rect));
  };
  // The coarse bins' lists repeat bundles: a slot that did not decide the block once does not
  // the next time (decides depends on the slot and the block only), and one that did has no
  // state left in `clear`; so each bundle is visited once.
  ++scratch.visit;
  const BinRange bins = bin_range(cam.coarse, vx0, vx1, vy0, vy1);
  for (int by = bins.y0; by <= bins.y1; ++by) {
    for (int bx = bins.x0; bx <= bins.x1; ++bx) {
      const int b = by * cam.coarse.n[0] + bx;
      for (int n = cand.coarse.start[b]; n < cand.coarse.start[b + 1]; ++n) {
        const int u = cand.coarse.items[n];
        if (scratch.stamp[u] == scratch.visit) continue;
        scratch.stamp[u] = scratch.visit;
        // decides' first tests on bounds that hold each slot's: the rectangle holds each slot's,
        // `near` is at most each triangle's near_distance. First on the bundle's bounds, which
        // hold each of its groups'; a bundle of one group has that group's.
        const detail::SlotBundle& bundle = cand.bundles[u];
        if (!may_decide(bundle.rect, bundle.states, bundle.occupying, bundle.near)) continue;
        const bool single = bundle.last - bundle.first == 1;
        // Once a copy of a bundle of several may decide the block, the later copies whose
        // group's bounds may too have their states left out of the result untested: copies
        // moved a little mostly decide alike, and fewer states cleared only leaves more voxels
        // to judge one by one (L4 step 4).
        bool decided = false;
        for (int k = bundle.first; k < bundle.last; ++k) {
          const int g = cand.bundle_groups[k];
          const detail::SlotGroup& group = cam.groups[g];
          if (!single && !may_decide(group.rect, object_states[group.object],
                                     objects[group.object].occupying, group.near))
            continue;
          if (decided) {
            clear &= ~object_states[group.object];
            if (!clear) return 0;
            continue;
          }
          ensure_projected(cam, g);
          // The group's slots are of its object.
          const bool occupying = objects[group.object].occupying;
          for (int s = group.first; s < group.last; ++s) {
            const StateMask m = object_states[group.object] & clear;
            if (!m || !decides(s, occupying)) continue;
            clear &= ~m;
            if (!clear) return 0;
            decided = !single;
            if (decided) break;
          }
        }
      }
    }
  }
  return clear;
}

}  // namespace camplace::voxel
