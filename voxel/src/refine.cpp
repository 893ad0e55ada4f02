// Adaptive refinement of the conservative voxel model (`refine` = L levels): kept base voxels
// near the critical objects are split into octree cells down to 1/2^L of the voxel's edge with
// the base labeller's own tests; M is the union of the finest cells and the whole voxels left
// unrefined. Why M stays between the exact and the unrefined model, why the shortcuts change
// nothing, which voxels must be refined and why cells tile exactly: docs/design/refinement.md
// R1–R4; the distance: docs/design/distance.md D2.
#include <algorithm>
#include <cmath>
#include <limits>

#include "camplace/core/geometry.hpp"
#include "impl.hpp"
#include "solid_distance.hpp"

namespace camplace::voxel {

using core::Box3;
using core::Vec3;
using detail::CameraSetup;
using detail::CellSet;
using detail::StateMask;

void VoxelEvaluator::Impl::refine_voxel(detail::RefineContext& ctx, const StateMask* step_states,
                                        int v, StateMask pending, StateMask* out) const {
  const std::vector<CameraSetup>& cameras = *ctx.cameras;
  const int cells = octree.cells;
  const int nx = grid.n[0], ny = grid.n[1];
  ctx.removal.clear();
  for (std::size_t h = 0; h < removal_index.size(); ++h) {
    const int table = removal_index[h][v];
    if (table >= 0 && (pending & step_states[h])) {
      ctx.removal.push_back({step_states[h], removal_tables[table].data()});
    }
  }
  ctx.inside.clear();
  for (const auto& [o, table] : inside_by_voxel[v]) {
    const StateMask mask = ctx.object_states[o];
    if (pending & mask) ctx.inside.push_back({mask, inside_tables[table].data()});
  }
  ctx.out = out;
  ctx.witness.assign((levels + 1) * cameras.size() * detail::kWitnesses, -1);
  ctx.sure.assign((levels + 1) * cameras.size(), 0);
  // The base voxel itself: states where it lies wholly inside an occupying object, or outside
  // every seeing camera's FOV, need no refinement; cameras whose FOV holds it.
  StateMask fixed = 0, open = pending;
  for (const auto& [mask, table] : ctx.inside) {
    if (table[0]) {
      fixed |= open & mask;
      open &= ~mask;
    }
  }
  std::uint64_t in_view = 0;
  if (open) {
    const Box3 box = node_box(v, 0, 0);
    const Vec3 center = 0.5 * (box.min + box.max);
    StateMask maybe_seen = 0;
    for (std::size_t c = 0; c < cameras.size(); ++c) {
      if (!(open & ctx.seeing[c])) continue;
      const Vec3 w = center - cameras[c].c;
      const double d = w.norm();
      if (ball_outside_fov(cameras[c], w, d, cell_sizes[0].radius)) continue;
      maybe_seen |= ctx.seeing[c];
      if (c < 64 && box_in_fov(cameras[c], box.min, box.max, cell_sizes[0].radius, w, d)) {
        in_view |= std::uint64_t(1) << c;
      }
    }
    fixed |= open & ~maybe_seen;
    open &= maybe_seen;
  }
  if (open) {
    const int i = v % nx, j = (v / nx) % ny, k = v / (nx * ny);
    refine_node(ctx, 0, 0, i, j, k, fixed, open, in_view);
  } else {
    for (int c = 0; c < cells; ++c) out[c] |= fixed;
  }
  // Obstacle interiors below cells filled without descending (the descent skipped the others
  // already; bits of the step's states set in an earlier call were cleared then).
  for (const auto& [mask, table] : ctx.removal) {
    for (int l = 1; l <= levels; ++l) {
      const int span = 1 << (3 * (levels - l));
      for (int m = 0; m < (1 << (3 * l)); ++m) {
        if (!table[octree.offset[l] + m]) continue;
        for (int c = m * span; c < (m + 1) * span; ++c) out[c] &= ~mask;
      }
    }
  }
}

void VoxelEvaluator::Impl::refined_states(const std::vector<CameraSetup>& cameras,
                                          const std::vector<detail::Rows>& rows,
                                          std::vector<CellSet>& leaves,
                                          std::vector<ComponentCount>& counts,
                                          std::vector<ModelDistance>& distances,
                                          core::Timing& timing) const {
  using detail::Clock;
  using detail::ms_since;
  const int state_count = static_cast<int>(states.size());
  const int cells = octree.cells;
  leaves.resize(state_count);
  counts.assign(state_count, {});
  distances.assign(state_count, {});
  // Per calling thread, reused; references, so that the worker threads below see this
  // thread's buffers (a thread_local named in a lambda would be each worker's own).
  thread_local std::vector<StateMask> mask_buffer, refined_buffer;
  thread_local std::vector<int> slot_buffer;
  std::vector<StateMask>& cell_masks = mask_buffer;  // per slot: its cells' states
  std::vector<StateMask>& refined = refined_buffer;  // per base voxel: states refined
  std::vector<int>& slot_of = slot_buffer;           // per base voxel: its slot, or −1
  // The chunk's models, one byte per voxel.
  thread_local std::vector<std::vector<std::uint8_t>> model_buffer;
  std::vector<std::vector<std::uint8_t>>& models = model_buffer;
  const double diagonal = grid.step.norm();
  for (int chunk = 0; chunk * detail::kChunk < state_count; ++chunk) {
    const int first = chunk * detail::kChunk;
    const int count = std::min(detail::kChunk, state_count - first);
    [[maybe_unused]] const StateMask chunk_all =
        count == detail::kChunk ? ~StateMask(0) : (StateMask(1) << count) - 1;
    const std::vector<StateMask> seeing = seeing_states(cameras, chunk);
    const StateMask* step_states = chunk_step_states[chunk].data();
    refined.assign(grid.count(), 0);
    slot_of.assign(grid.count(), -1);
    cell_masks.clear();
    int slot_count = 0;
    // The radius per state: kept base voxels nearer than it to C_h are refined. It starts at
    // the unrefined d(C_h, M) plus a voxel diagonal and grows until the nearest kept cell lies
    // within it, so that every voxel that could hold a nearer cell is refined.
    std::vector<double> radius(count, 0.0);
    std::vector<int> active;
    auto t0 = Clock::now();
    models.resize(count);
    for (int s = 0; s < count; ++s) {
      detail::bytes_from_rows(rows[first + s], grid, models[s]);
      const ModelDistance base = model_distance(rows[first + s], states[first + s].time_step);
      CellSet& set = leaves[first + s];
      set.voxels.clear();
      set.cells.clear();
      set.whole.clear();
      if (base.volume == 0.0) {
        distances[first + s] = base;  // empty: nothing to refine
        continue;
      }
      radius[s] = base.d_model + diagonal;
      active.push_back(s);
    }
    timing.distance_ms += ms_since(t0);
    std::vector<std::pair<int, StateMask>> work;  // (slot, states to refine)
    while (!active.empty()) {
      t0 = Clock::now();
      work.clear();
      for (int v = 0; v < grid.count(); ++v) {
        StateMask add = 0;
        for (int s : active) {
          const StateMask bit = StateMask(1) << s;
          if (!models[s][v] || (refined[v] & bit)) continue;
          const int h = states[first + s].time_step;
          const double r2 = radius[s] * radius[s];
          if (critical_lb_by_step[h][v] >= r2 || !(critical_sq(h, v) < r2)) continue;
          add |= bit;
        }
        if (!add) continue;
        if (slot_of[v] < 0) {
          slot_of[v] = slot_count++;
          cell_masks.resize(static_cast<std::size_t>(slot_count) * cells, 0);
        }
        CAMPLACE_ASSERT((add & ~chunk_all) == 0);  // states of this chunk only
        refined[v] |= add;
        work.push_back({v, add});
      }
      const int items = static_cast<int>(work.size());
      const int pieces =
          options.threads <= 1 ? std::min(items, 1) : std::min(items, 4 * options.threads);
      detail::parallel_for(pieces, options.threads, [&](int piece) {
        detail::Scratch scratch;
        scratch.stamp.assign(triangles.size(), 0);
        detail::RefineContext ctx;
        ctx.cameras = &cameras;
        ctx.seeing = seeing.data();
        ctx.chunk = chunk;
        ctx.object_states = chunk_object_states[chunk].data();
        ctx.scratch = &scratch;
        for (int n = items * piece / pieces; n < items * (piece + 1) / pieces; ++n) {
          const auto [v, add] = work[n];
          refine_voxel(ctx, step_states, v, add,
                       cell_masks.data() + static_cast<std::size_t>(slot_of[v]) * cells);
        }
      });
      timing.labelling_ms += ms_since(t0);
      // Per active state: the model (refined cells, the other kept voxels whole), its
      // components and filter, and d(C_h, M).
      t0 = Clock::now();
      const int n_active = static_cast<int>(active.size());
      detail::parallel_for(n_active, options.threads, [&](int a) {
        const int s = active[a];
        const StateMask bit = StateMask(1) << s;
        CellSet& set = leaves[first + s];
        set.voxels.clear();
        set.cells.clear();
        set.whole.clear();
        const std::vector<std::uint8_t>& model = models[s];
        for (int v = 0; v < grid.count(); ++v) {
          if (model[v]) set.voxels.push_back(v);
        }
        set.cells.resize(set.voxels.size() * cells, 1);
        set.whole.resize(set.voxels.size(), 1);
        for (std::size_t slot = 0; slot < set.voxels.size(); ++slot) {
          const int v = set.voxels[slot];
          if (!(refined[v] & bit)) continue;
          CAMPLACE_ASSERT(model[v] != 0);  // refined cells lie in the state's base voxels
          set.whole[slot] = 0;
          const std::size_t at = slot * cells;
          const StateMask* masks = cell_masks.data() + static_cast<std::size_t>(slot_of[v]) * cells;
          for (int c = 0; c < cells; ++c) set.cells[at + c] = (masks[c] & bit) != 0;
        }
        counts[first + s] = detail::filter_cells(set, octree, grid, scene.plausibility);
      });
      timing.clustering_ms += ms_since(t0);
      t0 = Clock::now();
      detail::parallel_for(n_active, options.threads, [&](int a) {
        const int s = active[a];
        distances[first + s] = model_distance(leaves[first + s], states[first + s].time_step);
      });
      timing.distance_ms += ms_since(t0);
      std::vector<int> next;
      for (int s : active) {
        const double d = distances[first + s].d_model;
        if (!(d > radius[s])) continue;
        radius[s] = d + diagonal;
        next.push_back(s);
      }
      active.swap(next);
    }
  }
}

void VoxelEvaluator::Impl::refine_node(detail::RefineContext& ctx, int level, int morton, long I,
                                       long J, long K, StateMask fixed, StateMask open,
                                       std::uint64_t in_view) const {
  const int child_level = level + 1;
  const detail::CellSize& size = cell_sizes[child_level];
  const Vec3 s = grid.step * size.factor;
  const std::vector<CameraSetup>& cameras = *ctx.cameras;
  const std::size_t n_cam = cameras.size();
  const int node = octree.offset[child_level];
  for (int q = 0; q < 8; ++q) {
    const long CI = 2 * I + (q & 1), CJ = 2 * J + ((q >> 1) & 1), CK = 2 * K + ((q >> 2) & 1);
    const int child = 8 * morton + q;
    StateMask f = fixed, o = open;
    for (const auto& [mask, table] : ctx.removal) {
      if (((f | o) & mask) && table[node + child]) {
        f &= ~mask;
        o &= ~mask;
      }
    }
    for (const auto& [mask, table] : ctx.inside) {
      if ((o & mask) && table[node + child]) {
        f |= o & mask;
        o &= ~mask;
      }
    }
    std::uint64_t child_in_view = 0;
    if (o) {
      const double x = static_cast<double>(CI), y = static_cast<double>(CJ),
                   z = static_cast<double>(CK);
      const Vec3 lo = grid.area.min + Vec3(x * s.x(), y * s.y(), z * s.z());
      const Vec3 hi = grid.area.min + Vec3((x + 1) * s.x(), (y + 1) * s.y(), (z + 1) * s.z());
      const Vec3 center = 0.5 * (lo + hi);
      // States some camera may still free in a cell below this one.
      StateMask open_below = 0;
      const StateMask* parent_sure = ctx.sure.data() + level * n_cam;
      StateMask* child_sure = ctx.sure.data() + child_level * n_cam;
      std::copy(parent_sure, parent_sure + n_cam, child_sure);
      const std::size_t first_cam = ctx.hint;
      for (std::size_t step = 0; step < n_cam && o; ++step) {
        const std::size_t c =
            first_cam + step < n_cam ? first_cam + step : first_cam + step - n_cam;
        // States the camera is known not to free anywhere in the parent need no test.
        const StateMask interest = o & ctx.seeing[c] & ~child_sure[c];
        if (!interest) continue;
        const CameraSetup& cam = cameras[c];
        const Vec3 w = center - cam.c;
        const double d = w.norm();
        // The parent's box in the FOV holds the child's (children tile their parent exactly).
        bool seen = c < 64 && ((in_view >> c) & 1);
        if (!seen) {
          if (ball_outside_fov(cam, w, d, size.radius)) {
            child_sure[c] = ~StateMask(0);  // no cell below is in this camera's FOV
            continue;
          }
          seen = box_in_fov(cam, lo, hi, size.radius, w, d);
        }
        if (!seen) {
          open_below |= interest;
          continue;
        }
        if (c < 64) child_in_view |= std::uint64_t(1) << c;
        int* witness = ctx.witness.data() + (child_level * n_cam + c) * detail::kWitnesses;
        const int* parent_witness = ctx.witness.data() + (level * n_cam + c) * detail::kWitnesses;
        std::copy(parent_witness, parent_witness + detail::kWitnesses, witness);
        // States where judge_conservative() would find the cell occupied because a triangle that
        // decided the parent holds it in its cone (and so every cell below): no test needed.
        StateMask held = 0;
        for (int n = 0; n < detail::kWitnesses && witness[n] >= 0; ++n) {
          held |= contained(cam, witness[n], w, d, size, interest & ~held, ctx.chunk);
        }
        child_sure[c] |= held;
        if (held == interest) continue;
        detail::Witnesses witnesses{witness};
        const detail::Verdict verdict = judge_conservative(
            cam, w, d, size, interest & ~held, ctx.chunk, *ctx.scratch, true, &witnesses);
        const StateMask freed = interest & ~held & ~(verdict.occupied | verdict.blocked);
        if (freed) ctx.hint = c;
        o &= ~freed;
        child_sure[c] |= witnesses.sure;
        open_below |= interest & ~freed & ~witnesses.sure;
      }
      // No camera can free any cell below in these states: all of them stay in M.
      f |= o & ~open_below;
      o &= open_below;
    }
    if (!(f | o)) continue;
    if (child_level == levels) {
      ctx.out[child] |= f | o;
    } else if (!o) {
      const int span = 1 << (3 * (levels - child_level));
      for (int c = child * span; c < (child + 1) * span; ++c) ctx.out[c] |= f;
    } else {
      refine_node(ctx, child_level, child, CI, CJ, CK, f, o, child_in_view);
    }
  }
}

StateMask VoxelEvaluator::Impl::contained(const CameraSetup& cam, int slot, const Vec3& w, double d,
                                          const detail::CellSize& size, StateMask interest,
                                          int chunk) const {
  const int o = cam.slot_object[slot];
  const StateMask states = interest & chunk_object_states[chunk][o];
  if (!objects[o].occupying || !states) return 0;
  const detail::TriangleCone& tc = cone_of(cam, slot);
  // judge_conservative()'s `sure` test (detail::Witnesses): the box's lowest point along each
  // inward plane normal is inside by the margin (then the cone test meets it: the centre is inside
  // too).
  const double margin = 1e-9 * (d + size.radius);
  for (int i = 0; i < 3; ++i) {
    if (!(tc.normal[i].dot(w) - tc.normal[i].cwiseAbs().dot(size.half) > margin)) return 0;
  }
  return states;
}

bool VoxelEvaluator::Impl::ball_outside_fov(const CameraSetup& cam, const Vec3& w, double d,
                                            double r) const {
  if (!(d > r * (1.0 + 1e-6) + 1e-9)) return false;  // the camera may be in the ball
  const double axial = w.dot(cam.axis);
  const double tol = 1e-9 * (d + r);
  if (cam.range && axial > *cam.range + r + tol) return true;
  if (cam.near > 0.0 && axial < cam.near - r - tol) return true;
  // The centre's angle θ off the axis exceeds the half angle α plus the ball's angular radius
  // β (sin β = r/d; α + β < π): cos θ < cos(α + β), with a margin.
  const double sin_b = r / d, cos_b = std::sqrt(1.0 - sin_b * sin_b);
  const double cos_limit = cam.cos_half * cos_b - cam.sin_half * sin_b;
  return axial < d * cos_limit - 1e-6 * d - tol;
}

}  // namespace camplace::voxel
