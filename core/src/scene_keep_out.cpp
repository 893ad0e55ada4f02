// Keep-out repair (SPEC §2): the nearest point of a camera domain outside the keep-out boxes.
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "camplace/core/scene.hpp"

namespace camplace::core {
namespace {

/// One piece of an axis cut by the boxes' faces: a cut value [c, c] or the open interval
/// between two cuts (closure [lo, hi]); `sample` lies inside it.
struct Piece {
  double lo, hi, sample, distance;  ///< distance: from the point's coordinate to [lo, hi]
};

/// The nearest point to p (inside the box domain [lo, hi]) outside every box's interior, or
/// none. The boxes' faces cut each axis into pieces on which every box's test is constant, so
/// the free part is a union of products of pieces (their closures are free: the free part is
/// closed). The pieces are visited in order of their distance to p per axis, each product
/// tested at its sample and pruned as soon as its distance cannot beat the best: typically a
/// few hundred tests for 32 boxes, where trying every pair and triple of the 6 + 6K planes
/// costs over a million.
std::optional<Vec3> nearest_free_in_box(const Vec3& lo, const Vec3& hi,
                                        const std::vector<KeepOut>& boxes, const Vec3& p) {
  std::array<std::vector<Piece>, 3> pieces;
  for (int a = 0; a < 3; ++a) {
    std::vector<double> cuts{lo[a], hi[a]};
    for (const KeepOut& k : boxes) {
      for (const double c : {k.box.min[a], k.box.max[a]}) {
        if (c > lo[a] && c < hi[a]) cuts.push_back(c);
      }
    }
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
    const auto add = [&](double l, double h, double sample) {
      const double d = p[a] < l ? l - p[a] : (p[a] > h ? p[a] - h : 0.0);
      pieces[a].push_back({l, h, sample, d});
    };
    for (std::size_t i = 0; i < cuts.size(); ++i) {
      add(cuts[i], cuts[i], cuts[i]);
      if (i + 1 < cuts.size()) add(cuts[i], cuts[i + 1], 0.5 * (cuts[i] + cuts[i + 1]));
    }
    std::stable_sort(pieces[a].begin(), pieces[a].end(),
                     [](const Piece& x, const Piece& y) { return x.distance < y.distance; });
  }
  const auto inside = [](const KeepOut& k, int a, double v) {
    return v > k.box.min[a] + kKeepOutSlack && v < k.box.max[a] - kKeepOutSlack;
  };
  const auto blocked = [&](const Vec3& q) {
    return std::any_of(boxes.begin(), boxes.end(), [&](const KeepOut& k) { return k.contains(q); });
  };
  std::optional<Vec3> best;
  double best_sq = std::numeric_limits<double>::infinity();
  const auto consider = [&](const Piece& x, const Piece& y, const Piece& z) {
    const Vec3 q(std::clamp(p.x(), x.lo, x.hi), std::clamp(p.y(), y.lo, y.hi),
                 std::clamp(p.z(), z.lo, z.hi));
    const double d = (q - p).squaredNorm();
    if (d < best_sq && !blocked(q)) {
      best_sq = d;
      best = q;
    }
  };
  std::vector<const KeepOut*> on_x, on_xy;
  for (const Piece& x : pieces[0]) {
    if (x.distance * x.distance >= best_sq) break;
    on_x.clear();
    for (const KeepOut& k : boxes) {
      if (inside(k, 0, x.sample)) on_x.push_back(&k);
    }
    for (const Piece& y : pieces[1]) {
      const double dxy = x.distance * x.distance + y.distance * y.distance;
      if (dxy >= best_sq) break;
      on_xy.clear();
      for (const KeepOut* k : on_x) {
        if (inside(*k, 1, y.sample)) on_xy.push_back(k);
      }
      for (const Piece& z : pieces[2]) {
        if (dxy + z.distance * z.distance >= best_sq) break;
        if (std::none_of(on_xy.begin(), on_xy.end(),
                         [&](const KeepOut* k) { return inside(*k, 2, z.sample); })) {
          consider(x, y, z);
          break;  // the pieces further along z are no nearer
        }
      }
    }
  }
  return best;
}

}  // namespace

std::optional<Vec3> keep_out_repair(const CameraDomain& domain,
                                    const std::vector<KeepOut>& keep_out, const Vec3& p) {
  const auto blocked = [&](const Vec3& q) {
    return std::any_of(keep_out.begin(), keep_out.end(),
                       [&](const KeepOut& k) { return k.contains(q); });
  };
  // The domain as origin + A·w with w in the box [lo, hi] (k = 3 for a box domain, k = 2 for
  // a mount's (s, t)).
  const bool on_mount = domain.mount.has_value();
  const int k = on_mount ? 2 : 3;
  Eigen::MatrixXd a(3, k);
  Eigen::VectorXd lo(k), hi(k), w0(k);
  Vec3 origin = Vec3::Zero();
  if (on_mount) {
    const Mount& m = *domain.mount;
    a << m.u, m.v;
    origin = m.corner;
    lo << 0.0, 0.0;
    hi << 1.0, 1.0;
    const auto [s, t] = m.coordinates(p);
    w0 << s, t;
  } else {
    a.setIdentity();
    lo << domain.x.lo, domain.y.lo, domain.z.lo;
    hi << domain.x.hi, domain.y.hi, domain.z.hi;
    w0 = p;
  }
  w0 = w0.cwiseMax(lo).cwiseMin(hi);
  const auto world = [&](const Eigen::VectorXd& w) -> Vec3 { return origin + a * w; };
  if (!blocked(world(w0))) return world(w0);
  if (!on_mount) return nearest_free_in_box(Vec3(lo), Vec3(hi), keep_out, world(w0));
  // On a mount: the free part of the domain is closed; its point nearest to w0 (in the world
  // metric G = AᵀA) is w0 projected onto the intersection of at most 2 of the planes that bound
  // the keep-out boxes and the domain. Try every such intersection and keep the nearest free one.
  std::vector<std::pair<Eigen::VectorXd, double>> planes;  // row·w = value
  for (int j = 0; j < k; ++j) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(k);
    e[j] = 1.0;
    planes.push_back({e, lo[j]});
    planes.push_back({e, hi[j]});
  }
  for (const KeepOut& box : keep_out) {
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::VectorXd row = a.row(axis).transpose();
      if (row.norm() == 0.0) continue;
      planes.push_back({row, box.box.min[axis] - origin[axis]});
      planes.push_back({row, box.box.max[axis] - origin[axis]});
    }
  }
  const Eigen::MatrixXd g = a.transpose() * a;
  const Eigen::MatrixXd g_inv = g.inverse();
  std::optional<Vec3> best;
  double best_distance = std::numeric_limits<double>::infinity();
  const auto consider = [&](const std::vector<int>& chosen) {
    const int m = static_cast<int>(chosen.size());
    Eigen::MatrixXd c(m, k);
    Eigen::VectorXd b(m);
    for (int r = 0; r < m; ++r) {
      c.row(r) = planes[chosen[r]].first.transpose();
      b[r] = planes[chosen[r]].second;
    }
    const Eigen::MatrixXd s = c * g_inv * c.transpose();
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(s);
    if (!lu.isInvertible()) return;
    Eigen::VectorXd w = w0 + g_inv * c.transpose() * lu.solve(b - c * w0);
    if (((w - lo).array() < -1e-9).any() || ((w - hi).array() > 1e-9).any()) return;
    w = w.cwiseMax(lo).cwiseMin(hi);
    const Vec3 q = world(w);
    if (blocked(q)) return;
    const double distance = (q - world(w0)).norm();
    if (distance < best_distance) {
      best_distance = distance;
      best = q;
    }
  };
  const int n = static_cast<int>(planes.size());
  for (int i = 0; i < n; ++i) {
    consider({i});
    for (int j = i + 1; j < n; ++j) {
      consider({i, j});
    }
  }
  return best;
}

}  // namespace camplace::core
