// The octree numbering of the cells below one base voxel (cells.hpp).
#include "cells.hpp"

namespace camplace::voxel::detail {

namespace {

int morton_of(const std::array<int, 3>& c, int levels) {
  int m = 0;
  for (int t = 0; t < levels; ++t) {
    for (int a = 0; a < 3; ++a) m |= ((c[a] >> t) & 1) << (3 * t + a);
  }
  return m;
}

}  // namespace

Octree make_octree(int levels) {
  Octree t;
  t.levels = levels;
  t.side = 1 << levels;
  t.cells = 1 << (3 * levels);
  t.coords.resize(t.cells);
  for (int m = 0; m < t.cells; ++m) {
    std::array<int, 3> c{0, 0, 0};
    for (int b = 0; b < levels; ++b) {
      for (int a = 0; a < 3; ++a) c[a] |= ((m >> (3 * b + a)) & 1) << b;
    }
    t.coords[m] = c;
  }
  for (int a = 0; a < 3; ++a) {
    t.next[a].resize(t.cells);
    t.crosses[a].resize(t.cells);
    for (int m = 0; m < t.cells; ++m) {
      std::array<int, 3> c = t.coords[m];
      ++c[a];
      t.crosses[a][m] = c[a] == t.side;
      if (c[a] == t.side) c[a] = 0;
      t.next[a][m] = morton_of(c, levels);
      if (t.coords[m][a] == 0) t.low_face[a].push_back(m);
    }
  }
  t.offset.assign(levels + 1, 0);
  int count = 1;
  for (int l = 1; l <= levels; ++l) {
    t.offset[l] = t.offset[l - 1] + count;
    count *= 8;
  }
  t.nodes = t.offset[levels] + count;
  return t;
}

}  // namespace camplace::voxel::detail
