// Labelling (SPEC §3, §5): the unfiltered models of all states for one camera configuration —
// per voxel and camera the label κ for up to 64 states at once (judge.cpp), with the FOV tests
// (fov.cpp) and the cameras' tables (camera_setup.cpp) — and the labels of one camera.
//
// The fast labeller gives the labels of the plain per-voxel tests (Möller–Trumbore on the ray to
// the voxel centre; the separating-axis test of a triangle's cone against the voxel box; the FOV
// test on the centre or the 8 corners) and only skips tests that cannot change a label: image-
// plane bins (docs/design/labelling.md L1), back-face culling (L3), block clearing (L4), row
// intervals and early FOV decisions (L5), voxels an occupying object reaches into (L6), objects
// shared between states (L7), bit masks over 64 states; center mode's first hit breaks ties by
// triangle index (L8); a conservative free label is sound by L2. Refinement (refine.cpp) labels
// octree cells with these same tests: judge_conservative() and box_in_fov() take the cell's size.
#include <algorithm>
#include <cmath>
#include <limits>

#include "impl.hpp"

namespace camplace::voxel {

using core::Vec3;
using detail::CameraSetup;
using detail::Scratch;
using detail::StateMask;
using detail::Verdict;

void VoxelEvaluator::Impl::raw_models(const std::vector<CameraSetup>& cameras, int k_begin,
                                      int k_end, std::vector<std::vector<StateMask>>& masks) const {
  const int nx = grid.n[0], ny = grid.n[1];
  const int state_count = static_cast<int>(states.size());
  const std::size_t n_cam = cameras.size();
  Scratch scratch;
  scratch.stamp.assign(triangles.size(), 0);
  // Per row (j, k) of the slice and camera: row_interval's lo, hi, in_lo, in_hi, computed on
  // first use in conservative mode (lo = −1 until then: row_interval's lo is ≥ 0), where blocks
  // leave many rows without a test, up front in center mode.
  std::vector<std::array<int, 4>> rows(static_cast<std::size_t>(ny) * (k_end - k_begin) * n_cam,
                                       {-1, 0, 0, 0});
  for (int k = k_begin; k < k_end && !conservative; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (std::size_t c = 0; c < n_cam; ++c) {
        auto& r = rows[((k - k_begin) * ny + j) * n_cam + c];
        row_interval(cameras[c], j, k, r[0], r[1], r[2], r[3]);
      }
    }
  }
  // Per voxel of the slice: the camera that last freed a state of it, in an earlier chunk (or
  // kNone); a camera that sees a voxel free in some states tends to in the others too.
  constexpr std::uint8_t kNone = 0xff;
  CAMPLACE_ASSERT(n_cam < kNone);
  const int slice_first = nx * ny * k_begin;
  std::vector<std::uint8_t> freed_by(static_cast<std::size_t>(nx) * ny * (k_end - k_begin), kNone);
  for (int chunk = 0; chunk * detail::kChunk < state_count; ++chunk) {
    const int first = chunk * detail::kChunk;
    const int count = std::min(detail::kChunk, state_count - first);
    const StateMask all = count == 64 ? ~StateMask(0) : (StateMask(1) << count) - 1;
    const StateMask* removed = chunk_removed[chunk].data();
    const StateMask* reached = conservative ? chunk_reached[chunk].data() : nullptr;
    const std::vector<StateMask> seeing = seeing_states(cameras, chunk);
    StateMask* out = masks[chunk].data();
    std::size_t hint = 0, block_hint = 0;
    // Inlined into visit's loops (GCC and Clang; an outlined call per voxel costs ~6%).
    auto label = [&](int i, int j, int k, StateMask clear) __attribute__((always_inline)) {
      auto* row = &rows[((k - k_begin) * ny + j) * n_cam];
      const int v = i + nx * (j + ny * k);
      StateMask pending = all & ~clear & ~removed[v];  // not removed, not yet seen free
      // Conservative mode: the states where an occupying object reaches into the voxel stay in
      // M untested; no camera would see it free there (docs/design/labelling.md L6).
      const StateMask kept = reached ? pending & reached[v] : 0;
      pending &= ~kept;
      if (pending) {
        const Vec3 center(box_center[0][i], box_center[1][j], box_center[2][k]);
        // Cameras from the one that last freed this voxel in an earlier chunk on, else from the
        // one that last freed a voxel: neighbours tend to be seen by the same camera (the order
        // does not change the result).
        std::uint8_t& last = freed_by[v - slice_first];
        const std::size_t first_cam = last != kNone ? last : hint;
        for (std::size_t step = 0; step < n_cam && pending; ++step) {
          const std::size_t c =
              first_cam + step < n_cam ? first_cam + step : first_cam + step - n_cam;
          const StateMask interest = pending & seeing[c];
          if (!interest) continue;
          auto& r = row[c];
          if (r[0] < 0) row_interval(cameras[c], j, k, r[0], r[1], r[2], r[3]);
          if (i < r[0] || i > r[1]) continue;
          const CameraSetup& cam = cameras[c];
          const Vec3 w = center - cam.c;
          double d = -1.0;  // |w|, computed when needed
          if (i < r[2] || i > r[3]) {
            d = w.norm();
            if (!in_fov(cam, i, j, k, w, d)) continue;
          }
          const Verdict verdict =
              conservative
                  ? judge_conservative(cam, w, d, cell_sizes[0], interest, chunk, scratch, true)
                  : judge_center(cam, w, d, interest, chunk, scratch, true);
          const StateMask freed = interest & ~(verdict.occupied | verdict.blocked);
          if (freed) {
            hint = c;
            last = static_cast<std::uint8_t>(c);
          }
          pending &= ~freed;
        }
      }
      pending |= kept;
      CAMPLACE_ASSERT((pending & ~all) == 0);  // states of this chunk only
      out[v] = pending;
    };
    // Conservative mode: the states where some camera sees a whole block free (block_clear,
    // every camera from the one that last cleared a block on) need no test per voxel; blocks of
    // 4³ voxels, then the 2³ blocks of those that the cameras did not clear for every state;
    // then voxel by voxel.
    constexpr int kBlock = 4;
    auto visit = [&](int i0, int i1, int j0, int j1, int k0, int k1, int size, StateMask clear,
                     auto& self) -> void {
      if (conservative && (i1 - i0) * (j1 - j0) * (k1 - k0) > 1) {
        const Vec3 lo(box_min[0][i0], box_min[1][j0], box_min[2][k0]);
        const Vec3 hi(box_max[0][i1 - 1], box_max[1][j1 - 1], box_max[2][k1 - 1]);
        // Every camera, from the last one to clear a block on, until every state is cleared:
        // states one camera leaves (a triangle of theirs may decide a voxel) another may clear.
        // Which cameras are tried changes no label: block_clear holds for any camera.
        // States where an occupying object reaches into a voxel of the block: never free there
        // (chunk_reached), so block_clear cannot clear them; it need not try.
        StateMask held = 0;
        for (int k = k0; k < k1; ++k) {
          for (int j = j0; j < j1; ++j) {
            for (int i = i0; i < i1; ++i) held |= reached[i + nx * (j + ny * k)];
          }
        }
        for (std::size_t step = 0; step < n_cam && (clear | held) != all; ++step) {
          const std::size_t c = (block_hint + step) % n_cam;
          const StateMask open = seeing[c] & ~clear & ~held;
          const StateMask cleared =
              open ? block_clear(cameras[c], lo, hi, open, chunk, scratch) : 0;
          if (cleared) {
            clear |= cleared;
            block_hint = c;
          }
        }
      }
      if (conservative && size > 2 && clear != all) {
        const int half = size / 2;
        for (int k = k0; k < k1; k += half) {
          for (int j = j0; j < j1; j += half) {
            for (int i = i0; i < i1; i += half) {
              self(i, std::min(i + half, i1), j, std::min(j + half, j1), k, std::min(k + half, k1),
                   half, clear, self);
            }
          }
        }
        return;
      }
      for (int k = k0; k < k1; ++k) {
        for (int j = j0; j < j1; ++j) {
          for (int i = i0; i < i1; ++i) label(i, j, k, clear);
        }
      }
    };
    for (int k0 = k_begin; k0 < k_end; k0 += kBlock) {
      for (int j0 = 0; j0 < ny; j0 += kBlock) {
        for (int i0 = 0; i0 < nx; i0 += kBlock) {
          visit(i0, std::min(i0 + kBlock, nx), j0, std::min(j0 + kBlock, ny), k0,
                std::min(k0 + kBlock, k_end), kBlock, 0, visit);
        }
      }
    }
  }
}

std::vector<StateMask> VoxelEvaluator::Impl::seeing_states(const std::vector<CameraSetup>& cameras,
                                                           int chunk) const {
  // A camera inside an object of a state sees nothing in that state (SPEC §3.3).
  const int first = chunk * detail::kChunk;
  const int count = std::min(detail::kChunk, static_cast<int>(states.size()) - first);
  std::vector<StateMask> seeing(cameras.size(), 0);
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    for (int s = 0; s < count; ++s) {
      bool blind = false;
      for (int o : states[first + s].objects) blind = blind || cameras[c].inside_object[o];
      if (!blind) seeing[c] |= StateMask(1) << s;
    }
  }
  return seeing;
}

void VoxelEvaluator::Impl::all_raw_models(const core::CameraConfig& config,
                                          std::vector<detail::Rows>& models,
                                          std::vector<CameraSetup>* cameras_out) const {
  core::check_configuration(scene, config);
  std::vector<CameraSetup> local;
  std::vector<CameraSetup>& cameras = cameras_out ? *cameras_out : local;
  cameras.resize(config.size());  // each one's memory reused
  for (std::size_t i = 0; i < config.size(); ++i) {
    camera_setup(config[i], scene.cameras.models[i], cameras[i]);
  }
  // Per chunk and voxel: the states where it is in M (raw_models writes every voxel); per
  // calling thread, reused.
  thread_local std::vector<std::vector<StateMask>> masks;
  const int chunks = static_cast<int>(chunk_object_states.size());
  masks.resize(chunks);
  for (auto& m : masks) m.resize(grid.count());
  // Slices of a few z-layers each, shared out among the threads (results do not depend on it).
  const int nz = grid.n[2];
  const int slices = options.threads <= 1 ? 1 : std::min(nz, 4 * options.threads);
  std::vector<std::vector<StateMask>>& shared = masks;  // (the workers see this thread's)
  detail::parallel_for(slices, options.threads, [&](int s) {
    raw_models(cameras, nz * s / slices, nz * (s + 1) / slices, shared);
  });
  // Each state's rows from its chunk's masks.
  models.resize(states.size());
  detail::parallel_for(chunks, options.threads, [&](int chunk) {
    const int first = chunk * detail::kChunk;
    const int count = std::min(detail::kChunk, static_cast<int>(states.size()) - first);
    detail::Rows* out[detail::kChunk];
    for (int s = 0; s < count; ++s) out[s] = &models[first + s];
    detail::rows_from_masks(shared[chunk].data(), count, grid, out);
  });
}

std::vector<Label> VoxelEvaluator::Impl::labels(const CameraSetup& cam, int state) const {
  const int nx = grid.n[0], ny = grid.n[1], nz = grid.n[2];
  std::vector<Label> out(grid.count(), Label::undetectable);
  for (int o : states.at(state).objects) {
    if (cam.inside_object[o]) return out;  // blind (SPEC §3.3)
  }
  const int chunk = state / detail::kChunk;
  const StateMask interest = StateMask(1) << (state % detail::kChunk);
  Scratch scratch;
  scratch.stamp.assign(triangles.size(), 0);
  int v = 0;
  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i, ++v) {
        const Vec3 center(box_center[0][i], box_center[1][j], box_center[2][k]);
        const Vec3 w = center - cam.c;
        const double d = w.norm();
        if (!in_fov(cam, i, j, k, w, d)) continue;
        const Verdict verdict =
            conservative
                ? judge_conservative(cam, w, d, cell_sizes[0], interest, chunk, scratch, false)
                : judge_center(cam, w, d, interest, chunk, scratch, false);
        out[v] = verdict.occupied  ? Label::occupied
                 : verdict.blocked ? Label::undetectable
                                   : Label::free;
      }
    }
  }
  return out;
}

}  // namespace camplace::voxel
