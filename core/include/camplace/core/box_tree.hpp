#pragma once
/// A bounding-volume hierarchy over axis-aligned boxes, for searches by distance (the exact true
/// distance's triangle pairs, the voxel set-up's distances to the critical solids).
#include <algorithm>
#include <cstddef>
#include <vector>

#include "camplace/core/geometry.hpp"

namespace camplace::core {

/// A node of build_box_tree()'s hierarchy. A node with count > 0 is a leaf holding the items
/// [first, first + count) (in their reordered sequence), otherwise its children are the nodes
/// `first` and `first + 1`. Its box is the union of its items' boxes (min/max of the input
/// coordinates: no rounding), so a distance to it bounds every one of theirs from below.
struct BoxTreeNode {
  Box3 box;
  std::size_t first = 0;
  std::size_t count = 0;
};

/// The hierarchy over `items` (reordered; box_of(item) gives an item's box), node 0 the root,
/// top down: split at the median of the box centres along the widest axis of their range,
/// leaves of at most `leaf_size` items. Empty when there are no items.
template <class Item, class BoxOf>
std::vector<BoxTreeNode> build_box_tree(std::vector<Item>& items, const BoxOf& box_of,
                                        std::size_t leaf_size) {
  std::vector<BoxTreeNode> nodes;
  if (items.empty()) return nodes;
  struct Task {
    std::size_t node, first, last;
  };
  nodes.emplace_back();
  std::vector<Task> tasks{{0, 0, items.size()}};
  while (!tasks.empty()) {
    const Task task = tasks.back();
    tasks.pop_back();
    const auto begin = items.begin() + static_cast<std::ptrdiff_t>(task.first);
    const auto end = items.begin() + static_cast<std::ptrdiff_t>(task.last);
    Box3 box = box_of(*begin);
    Box3 centres{box.center(), box.center()};
    for (auto it = begin; it != end; ++it) {
      const Box3& b = box_of(*it);
      box.min = box.min.cwiseMin(b.min);
      box.max = box.max.cwiseMax(b.max);
      centres.min = centres.min.cwiseMin(b.center());
      centres.max = centres.max.cwiseMax(b.center());
    }
    nodes[task.node].box = box;
    const std::size_t count = task.last - task.first;
    if (count <= leaf_size) {
      nodes[task.node].first = task.first;
      nodes[task.node].count = count;
      continue;
    }
    int axis = 0;
    const Vec3 extent = centres.max - centres.min;
    if (extent[1] > extent[axis]) axis = 1;
    if (extent[2] > extent[axis]) axis = 2;
    const std::size_t mid = task.first + count / 2;
    std::nth_element(begin, items.begin() + static_cast<std::ptrdiff_t>(mid), end,
                     [&](const Item& x, const Item& y) {
                       const Box3 &bx = box_of(x), &by = box_of(y);
                       return bx.min[axis] + bx.max[axis] < by.min[axis] + by.max[axis];
                     });
    const std::size_t left = nodes.size();
    nodes[task.node].first = left;
    nodes.emplace_back();
    nodes.emplace_back();
    tasks.push_back({left, task.first, mid});
    tasks.push_back({left + 1, mid, task.last});
  }
  return nodes;
}

}  // namespace camplace::core
