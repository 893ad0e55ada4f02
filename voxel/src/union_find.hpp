#pragma once
// Union–find over integer ids (path halving; the smaller id becomes the root), shared by the
// component filter on voxel runs and on refined cells (components.cpp).
#include <algorithm>
#include <vector>

namespace camplace::voxel::detail {

inline int find(std::vector<int>& parent, int a) {
  while (parent[a] != a) {
    parent[a] = parent[parent[a]];
    a = parent[a];
  }
  return a;
}

inline void unite(std::vector<int>& parent, int a, int b) {
  a = find(parent, a);
  b = find(parent, b);
  if (a != b) parent[std::max(a, b)] = std::min(a, b);
}

}  // namespace camplace::voxel::detail
