#pragma once
/// Plain geometric value types (metres, world frame, z up) and the double-precision primitives
/// the voxel pipeline and the tests build on.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <utility>
#include <vector>

namespace camplace::core {

using Vec3 = Eigen::Vector3d;

/// π, and one degree in radians (scene files give degrees, code uses radians: SPEC §1).
constexpr double kPi = 3.14159265358979323846;
constexpr double kDegree = kPi / 180.0;

/// Closed axis-aligned box [min, max] in metres.
struct Box3 {
  Vec3 min = Vec3::Zero();
  Vec3 max = Vec3::Zero();
  Vec3 center() const { return 0.5 * (min + max); }
  Vec3 size() const { return max - min; }
  double diagonal() const { return (max - min).norm(); }
  /// The 8 corners; corner i takes max along x when bit 0 of i is set, y bit 1, z bit 2.
  std::array<Vec3, 8> corners() const {
    std::array<Vec3, 8> out;
    for (int i = 0; i < 8; ++i) {
      out[i] = Vec3((i & 1) ? max.x() : min.x(), (i & 2) ? max.y() : min.y(),
                    (i & 4) ? max.z() : min.z());
    }
    return out;
  }
  bool contains(const Vec3& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
};

/// Closed triangle mesh: vertices in metres, triangles as vertex indices, outward orientation
/// (counter-clockwise seen from outside).
struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;
};

/// Axis-aligned bounding box of the mesh's vertices.
Box3 bounding_box(const TriangleMesh& mesh);
/// Signed enclosed volume (m³); positive for outward orientation.
double signed_volume(const TriangleMesh& mesh);
/// True when p lies inside the closed mesh (generalised winding number > 1/2). Points on the
/// surface may go either way.
bool inside_mesh(const TriangleMesh& mesh, const Vec3& p);

/// The point of triangle (a, b, c) nearest to p (m, world frame).
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

/// Squared distance from p to triangle (a, b, c): |p − closest_point_on_triangle(p, a, b, c)|².
double point_triangle_sq_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);
/// The closest points of segments [p0, p1] and [q0, q1] (first on [p0, p1]).
std::pair<Vec3, Vec3> closest_points_of_segments(const Vec3& p0, const Vec3& p1, const Vec3& q0,
                                                 const Vec3& q1);
/// Squared distance between segments [p0, p1] and [q0, q1].
double segment_segment_sq_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1);
/// Squared distance from p to the closed box.
double point_box_sq_distance(const Vec3& p, const Box3& box);
/// Squared distance between two closed boxes (0 when they meet): a lower bound of the squared
/// distance between anything inside them.
double box_box_sq_distance(const Box3& a, const Box3& b);
/// True when triangle (a, b, c) and the closed box share a point (separating-axis test).
bool triangle_box_overlap(const Vec3& a, const Vec3& b, const Vec3& c, const Box3& box);
/// Squared distance between triangle (a, b, c) and the closed box; 0 when they overlap.
double triangle_box_sq_distance(const Vec3& a, const Vec3& b, const Vec3& c, const Box3& box);
/// Ray parameter t > 0 where origin + t·dir meets triangle (a, b, c), or a negative value.
double ray_triangle_hit(const Vec3& origin, const Vec3& dir, const Vec3& a, const Vec3& b,
                        const Vec3& c);

/// Squared distance from p to the solid bounded by the mesh (0 inside).
double point_solid_sq_distance(const TriangleMesh& mesh, const Vec3& p);
/// Squared distance from the closed box to the solid bounded by the mesh (0 when they meet).
double box_solid_sq_distance(const TriangleMesh& mesh, const Box3& box);

}  // namespace camplace::core
