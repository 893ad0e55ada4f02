// Does a voxel model hold the exact model? (SPEC §8)
//
// A voxel outside the voxel model holds exact-model points when a boundary triangle of the exact
// model reaches into its interior, or else (no boundary inside it) when its centre lies in the
// model. Locating a point in a Nef polyhedron costs about a millisecond, and a fine grid with
// refinement has millions of centres, so the fast path locates few: two centres joined by a
// segment that no boundary triangle meets lie on the same side of the boundary (a closed
// polyhedral set's boundary separates its interior from its exterior). The grid's segments
// between neighbouring centres that some triangle meets are marked; the centres joined by the
// others form connected sets, and one located centre answers for its whole set.
#include "model_containment.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <utility>

#include "camplace/core/geometry.hpp"

namespace camplace::compare::detail {

namespace {

using core::Box3;
using core::Vec3;

// Faces of the exact model lying on a voxel's boundary are not "inside" it; a segment's box is
// widened by the same amount, far above the separating-axis test's rounding (~1e-15 m).
constexpr double kBoundarySlack = 1e-9;
// The cells a triangle may meet are found by clipping it to slabs widened by this margin, far
// above the clipping's rounding for coordinates up to kilometres; the exact test follows.
constexpr double kClipMargin = 1e-6;

/// The closed range of cell indices along `axis` whose extent, widened by `margin`, meets
/// [lo, hi]; empty (first > second) when none does.
std::pair<int, int> cell_range(const voxel::Grid& grid, int axis, double lo, double hi,
                               double margin) {
  const double origin = grid.area.min[axis], step = grid.step[axis];
  const double n = grid.n[axis];
  const double a = std::clamp(std::floor((lo - margin - origin) / step), -1.0, n);
  const double b = std::clamp(std::floor((hi + margin - origin) / step), -1.0, n);
  return {std::max(static_cast<int>(a), 0), std::min(static_cast<int>(b), grid.n[axis] - 1)};
}

/// A convex polygon: a triangle clipped by up to four axis-aligned planes.
struct Polygon {
  std::array<Vec3, 8> v;
  int n = 0;
};

/// The part of `p` with coordinate `axis` ≥ `bound` (`keep_above`) or ≤ `bound`.
Polygon clip(const Polygon& p, int axis, double bound, bool keep_above) {
  Polygon out;
  auto inside = [&](const Vec3& q) { return keep_above ? q[axis] >= bound : q[axis] <= bound; };
  for (int i = 0; i < p.n; ++i) {
    const Vec3& a = p.v[i];
    const Vec3& b = p.v[(i + 1) % p.n];
    const bool in_a = inside(a), in_b = inside(b);
    if (in_a) out.v[out.n++] = a;
    if (in_a != in_b) {
      const double t = (bound - a[axis]) / (b[axis] - a[axis]);
      Vec3 q = a + t * (b - a);
      q[axis] = bound;
      out.v[out.n++] = q;
    }
  }
  return out;
}

Polygon clip_to_slab(const Polygon& p, int axis, double lo, double hi) {
  return clip(clip(p, axis, lo, true), axis, hi, false);
}

std::pair<double, double> extent(const Polygon& p, int axis) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int i = 0; i < p.n; ++i) {
    lo = std::min(lo, p.v[i][axis]);
    hi = std::max(hi, p.v[i][axis]);
  }
  return {lo, hi};
}

/// Calls visit(i, j, k) for every cell whose closed box, widened by kClipMargin, the triangle
/// (a, b, c) may meet (a superset of those it meets), by clipping it to z slabs, then y rows.
template <class Visit>
void for_each_cell_near(const voxel::Grid& grid, const Vec3& a, const Vec3& b, const Vec3& c,
                        Visit&& visit) {
  Polygon triangle;
  triangle.v[0] = a;
  triangle.v[1] = b;
  triangle.v[2] = c;
  triangle.n = 3;
  auto slab = [&](int axis, int index) {
    const double lo = grid.area.min[axis] + index * grid.step[axis];
    return std::pair<double, double>{lo - kClipMargin, lo + grid.step[axis] + kClipMargin};
  };
  const auto [zlo, zhi] = extent(triangle, 2);
  const auto [k0, k1] = cell_range(grid, 2, zlo, zhi, kClipMargin);
  for (int k = k0; k <= k1; ++k) {
    const auto [slab_lo, slab_hi] = slab(2, k);
    const Polygon in_z = clip_to_slab(triangle, 2, slab_lo, slab_hi);
    if (in_z.n == 0) continue;
    const auto [ylo, yhi] = extent(in_z, 1);
    const auto [j0, j1] = cell_range(grid, 1, ylo, yhi, kClipMargin);
    for (int j = j0; j <= j1; ++j) {
      const auto [row_lo, row_hi] = slab(1, j);
      const Polygon in_row = clip_to_slab(in_z, 1, row_lo, row_hi);
      if (in_row.n == 0) continue;
      const auto [xlo, xhi] = extent(in_row, 0);
      const auto [i0, i1] = cell_range(grid, 0, xlo, xhi, kClipMargin);
      for (int i = i0; i <= i1; ++i) visit(i, j, k);
    }
  }
}

/// The closed box around the segment between two centres, widened by kBoundarySlack.
Box3 segment_box(const Vec3& p, const Vec3& q) {
  return {p.cwiseMin(q) - Vec3::Constant(kBoundarySlack),
          p.cwiseMax(q) + Vec3::Constant(kBoundarySlack)};
}

Box3 shrunk_box(const voxel::Grid& grid, long v) {
  Box3 box = grid.voxel_box(static_cast<int>(v));
  box.min += Vec3::Constant(kBoundarySlack);
  box.max -= Vec3::Constant(kBoundarySlack);
  return box;
}

/// The reference: every voxel of a boundary triangle's bounding box is tested, and every centre
/// in the model's bounding box located.
int count_by_locating_every_centre(const exact::ExactModel& model, const voxel::Grid& grid,
                                   const std::vector<std::uint8_t>& voxel_model) {
  std::vector<std::uint8_t> violated(voxel_model.size(), 0);
  const core::TriangleMesh boundary = model.boundary_mesh();
  auto index_range = [&](double lo, double hi, int axis) {
    return cell_range(grid, axis, lo, hi, 0.0);
  };
  for (const auto& t : boundary.triangles) {
    const Vec3 &a = boundary.vertices[t[0]], &b = boundary.vertices[t[1]],
               &c = boundary.vertices[t[2]];
    const Vec3 lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
    const auto [i0, i1] = index_range(lo.x(), hi.x(), 0);
    const auto [j0, j1] = index_range(lo.y(), hi.y(), 1);
    const auto [k0, k1] = index_range(lo.z(), hi.z(), 2);
    for (int k = k0; k <= k1; ++k) {
      for (int j = j0; j <= j1; ++j) {
        for (int i = i0; i <= i1; ++i) {
          const long v = i + static_cast<long>(grid.n[0]) * (j + static_cast<long>(grid.n[1]) * k);
          if (voxel_model[v] || violated[v]) continue;
          if (core::triangle_box_overlap(a, b, c, shrunk_box(grid, v))) violated[v] = 1;
        }
      }
    }
  }
  const Box3 bounds = core::bounding_box(boundary);
  const auto [i0, i1] = index_range(bounds.min.x(), bounds.max.x(), 0);
  const auto [j0, j1] = index_range(bounds.min.y(), bounds.max.y(), 1);
  const auto [k0, k1] = index_range(bounds.min.z(), bounds.max.z(), 2);
  for (int k = k0; k <= k1; ++k) {
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        const long v = i + static_cast<long>(grid.n[0]) * (j + static_cast<long>(grid.n[1]) * k);
        if (voxel_model[v] || violated[v]) continue;
        const Vec3 centre = grid.voxel_center(static_cast<int>(v));
        if (bounds.contains(centre) && model.contains(centre)) violated[v] = 1;
      }
    }
  }
  return static_cast<int>(std::count(violated.begin(), violated.end(), 1));
}

/// Union–find over the voxels (path halving, union by index).
struct ConnectedSets {
  std::vector<int> parent;
  explicit ConnectedSets(long count) : parent(static_cast<std::size_t>(count)) {
    std::iota(parent.begin(), parent.end(), 0);
  }
  int find(int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  }
  void join(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

int count_by_connected_sets(const exact::ExactModel& model, const voxel::Grid& grid,
                            const std::vector<std::uint8_t>& voxel_model) {
  const long count = grid.count();
  const std::array<long, 3> stride{1, grid.n[0], static_cast<long>(grid.n[0]) * grid.n[1]};
  std::vector<std::uint8_t> violated(voxel_model.size(), 0);
  // Bit `axis` of blocked[v]: a boundary triangle meets the segment from v's centre to the
  // centre of its neighbour v + e_axis.
  std::vector<std::uint8_t> blocked(voxel_model.size(), 0);
  const core::TriangleMesh boundary = model.boundary_mesh();
  for (const auto& t : boundary.triangles) {
    const Vec3 &a = boundary.vertices[t[0]], &b = boundary.vertices[t[1]],
               &c = boundary.vertices[t[2]];
    for_each_cell_near(grid, a, b, c, [&](int i, int j, int k) {
      const std::array<int, 3> at{i, j, k};
      const long v = i + stride[1] * j + stride[2] * k;
      if (!voxel_model[v] && !violated[v] &&
          core::triangle_box_overlap(a, b, c, shrunk_box(grid, v))) {
        violated[v] = 1;
      }
      // A segment between two centres lies in the two closed voxels: a triangle meeting it
      // meets one of them (widened by kBoundarySlack < kClipMargin), so it is tested from there.
      const Vec3 centre = grid.voxel_center(static_cast<int>(v));
      for (int axis = 0; axis < 3; ++axis) {
        const Vec3 step = grid.step[axis] * Vec3::Unit(axis);
        if (at[axis] + 1 < grid.n[axis] && !(blocked[v] >> axis & 1) &&
            core::triangle_box_overlap(a, b, c, segment_box(centre, centre + step))) {
          blocked[v] |= std::uint8_t(1u << axis);
        }
        const long before = v - stride[axis];
        if (at[axis] > 0 && !(blocked[before] >> axis & 1) &&
            core::triangle_box_overlap(a, b, c, segment_box(centre - step, centre))) {
          blocked[before] |= std::uint8_t(1u << axis);
        }
      }
    });
  }
  ConnectedSets sets(count);
  for (int k = 0; k < grid.n[2]; ++k) {
    for (int j = 0; j < grid.n[1]; ++j) {
      for (int i = 0; i < grid.n[0]; ++i) {
        const std::array<int, 3> at{i, j, k};
        const long v = i + stride[1] * j + stride[2] * k;
        for (int axis = 0; axis < 3; ++axis) {
          if (at[axis] + 1 < grid.n[axis] && !(blocked[v] >> axis & 1)) {
            sets.join(static_cast<int>(v), static_cast<int>(v + stride[axis]));
          }
        }
      }
    }
  }
  // Per set: 0 unknown, 1 outside, 2 inside. A centre outside the model's bounding box is
  // outside the model, and so is its whole set.
  enum : std::uint8_t { unknown = 0, outside = 1, inside = 2 };
  std::vector<std::uint8_t> side(static_cast<std::size_t>(count), unknown);
  const Box3 bounds = core::bounding_box(boundary);
  for (long v = 0; v < count; ++v) {
    if (!bounds.contains(grid.voxel_center(static_cast<int>(v)))) {
      side[sets.find(static_cast<int>(v))] = outside;
    }
  }
  for (long v = 0; v < count; ++v) {
    if (voxel_model[v] || violated[v]) continue;
    std::uint8_t& s = side[sets.find(static_cast<int>(v))];
    if (s == unknown) s = model.contains(grid.voxel_center(static_cast<int>(v))) ? inside : outside;
    if (s == inside) violated[v] = 1;
  }
  return static_cast<int>(std::count(violated.begin(), violated.end(), 1));
}

}  // namespace

int exact_outside_voxel_model(const exact::ExactModel& model, const voxel::Grid& grid,
                              const std::vector<std::uint8_t>& voxel_model,
                              CentreLocation location) {
  if (model.empty()) return 0;
  return location == CentreLocation::every_centre
             ? count_by_locating_every_centre(model, grid, voxel_model)
             : count_by_connected_sets(model, grid, voxel_model);
}

}  // namespace camplace::compare::detail
