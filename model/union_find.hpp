/// \file
/// Disjoint sets over 0 … n−1 (union–find with path halving): which bodies
/// the joints join into one group, for the joint-coordinate tree's Kruskal
/// pass (articulated_scene.cpp) and a model's free trees (import/free_tree_spin.cpp).
#pragma once

#include <numeric>
#include <vector>

namespace lieflow {

class UnionFind {
 public:
  explicit UnionFind(int n) : parent_(static_cast<std::size_t>(n)) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  /// The representative of i's set.
  int find(int i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }
  /// Joins the sets of a and b (b's representative becomes the joined set's).
  void join(int a, int b) { parent_[find(a)] = find(b); }

 private:
  std::vector<int> parent_;
};

}  // namespace lieflow
