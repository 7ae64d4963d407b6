// Union-find forests over indices (parent[i] == i at a root): the components of meshes and
// lattices.
#pragma once

#include <vector>

namespace cmcsurf {

// The root of x's tree, halving the path on the way (each node passed points to its
// grandparent).
template <class Index>
Index find_root(std::vector<Index>& parent, Index x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

}  // namespace cmcsurf
