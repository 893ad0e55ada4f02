// Keep-out repair (SPEC §2): the nearest point of a camera domain outside the keep-out boxes.
#include <Eigen/LU>
#include <algorithm>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "camplace/core/scene.hpp"

namespace camplace::core {

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
  // The free part of the domain is closed; its point nearest to w0 (in the world metric
  // G = AᵀA) is w0 projected onto the intersection of at most k of the planes that bound the
  // keep-out boxes and the domain. Try every such intersection and keep the nearest free one.
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
      if (k == 3) {
        for (int l = j + 1; l < n; ++l) consider({i, j, l});
      }
    }
  }
  return best;
}

}  // namespace camplace::core
