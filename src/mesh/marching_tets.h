// Marching tetrahedra on a lattice of samples: each cube between eight nodes is cut into the
// six Kuhn tetrahedra that share its main diagonal (translation invariant, so neighbouring
// cubes split a shared face the same way and the surface is conforming). The iso-surface of
// the piecewise-linear interpolant is extracted with one vertex per crossed lattice edge,
// shared by every tetrahedron around that edge, so the mesh is indexed, manifold and, away
// from an open lattice boundary, closed. See docs/meshing.md.
#pragma once

#include <array>
#include <functional>

#include "mesh/tri_mesh.h"

namespace cmcsurf {

struct NodeLattice {
  std::array<int, 3> nodes{0, 0, 0};  // per axis
  // true: node n-1 connects back to node 0 on every axis (n cubes per axis) and the mesh is
  // returned with TriMesh::period set; false: n-1 cubes per axis.
  bool periodic = false;
  Vec3 origin{0, 0, 0};   // node (i, j, k) sits at origin + (i, j, k) * spacing
  Vec3 spacing{1, 1, 1};
  // false: every node is sampled. true: the outermost node layer on every side (not periodic
  // only) is a pad that counts as outside, and edges into it are cut at their midpoint, so a
  // solid closes itself with flat caps on the box half-way between the pad and the first node.
  bool pad_outside = false;
  // Fills the nodes[0] * nodes[1] values of node layer k (x fastest). Called once per layer
  // in increasing k (and once more for layer 0 when periodic).
  std::function<void(int k, double* values)> layer;
};

// Vertices are kept at least this fraction of an edge away from its nodes, so no triangle
// has zero area even where a sample equals the iso-value (which counts as outside).
constexpr double kMinEdgeFraction = 1e-3;

// The surface {value = iso}; inside = {value > iso}; triangles are counter-clockwise seen
// from outside (normals point towards lower values).
TriMesh extract_isosurface(const NodeLattice& lattice, double iso);

}  // namespace cmcsurf
