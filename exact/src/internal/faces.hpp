#pragma once
// A scene object's faces in exact coordinates, without any Nef polyhedron: shared by the Nef
// translation unit (exact_pipeline.cpp, through solids.hpp) and the image-plane one
// (outline.cpp).
#include <CGAL/Bbox_3.h>

#include <array>
#include <vector>

#include "camplace/core/geometry.hpp"
#include "camplace/core/internal/exact_kernel.hpp"

namespace camplace::exact::internal {

using core::internal::FT;
using core::internal::Kernel;
using core::internal::Point;
using core::internal::to_point;
using core::internal::to_vector;
using core::internal::Vector;
using Plane = Kernel::Plane_3;
using Triangle = Kernel::Triangle_3;

/// One scene object (a closed outward triangle mesh) in exact coordinates.
struct Faces {
  std::vector<Point> points;
  std::vector<std::array<int, 3>> triangles;
  std::vector<Plane> planes;  ///< supporting planes, positive side = outside
  bool convex = true;
  CGAL::Bbox_3 bbox;

  explicit Faces(const core::TriangleMesh& mesh) {
    points.reserve(mesh.vertices.size());
    for (const auto& v : mesh.vertices) points.push_back(to_point(v));
    triangles = mesh.triangles;
    for (const auto& t : triangles) planes.emplace_back(points[t[0]], points[t[1]], points[t[2]]);
    // Convex when every vertex lies on the closed inner side of every face plane.
    for (const auto& plane : planes) {
      for (const auto& p : points) {
        if (plane.oriented_side(p) == CGAL::ON_POSITIVE_SIDE) {
          convex = false;
          break;
        }
      }
      if (!convex) break;
    }
    bbox = CGAL::bbox_3(points.begin(), points.end());
  }

  Triangle triangle(int i) const {
    const auto& t = triangles[i];
    return Triangle(points[t[0]], points[t[1]], points[t[2]]);
  }

  /// The faces whose outer side holds `eye` strictly (those it sees from the front).
  std::vector<int> front_faces(const Point& eye) const {
    std::vector<int> out;
    for (int i = 0; i < int(planes.size()); ++i)
      if (planes[i].oriented_side(eye) == CGAL::ON_POSITIVE_SIDE) out.push_back(i);
    return out;
  }
};

}  // namespace camplace::exact::internal
