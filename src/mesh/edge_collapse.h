// Quadric-error edge collapses with a priority queue (Garland and Heckbert 1997): the fast
// path of decimate_solid (mesh/decimate.h). OpenMesh's decimater, kept there as
// decimate_solid_ref, took minutes on a 5.6M-triangle part; this one holds flat arrays and a
// lazily invalidated heap, and a large mesh is collapsed in slabs on the threads first and
// over the seams after (collapse_edges); collapse_edges_ref is the serial collapser as first
// written, frozen, which the tests compare with. A collapse is refused when it
// would break a closed manifold (the link condition, a vertex of valence 3 losing a
// triangle), flip a triangle's normal by more than max_normal_degrees, leave a zero-area
// triangle, or make a triangle more needle-like than max_aspect unless it improves on the
// worst one it replaces. Locked vertices never move.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "mesh/tri_mesh.h"

namespace cmcsurf {

struct CollapseParams {
  std::size_t target_triangles = 0;  // stop at or below this many (0: no budget)
  // Stop before the first collapse whose quadric error exceeds this distance: the root mean
  // square distance of the new vertex to the planes of the input triangles merged into it
  // (the surface between vertices may sag further: decimate_solid measures the result).
  double max_error = std::numeric_limits<double>::infinity();
  double max_normal_degrees = 60.0;
  double max_aspect = 20.0;  // longest edge / (2 sqrt(3) inradius): 1 for equilateral
  // Slabs of the first, parallel pass (collapse_edges): 0 sets them by the input's size
  // (kSlabTriangles each, kMaxSlabs at most), 1 is serial. Never by the thread count, so
  // that a part does not depend on it.
  int slabs = 0;
};

inline constexpr std::size_t kSlabTriangles = 250000;
inline constexpr std::size_t kMaxSlabs = 8;

// Called now and then with the triangles left.
using CollapseProgress = std::function<void(std::size_t triangles)>;

// m: a closed, consistently oriented, manifold mesh; locked: one flag per vertex (empty:
// none). Returns the collapsed mesh with unused vertices dropped.
TriMesh collapse_edges(const TriMesh& m, const std::vector<std::uint8_t>& locked,
                       const CollapseParams& p, const CollapseProgress& progress = {});
// The reference: serial, frozen (slabs ignored).
TriMesh collapse_edges_ref(const TriMesh& m, const std::vector<std::uint8_t>& locked,
                           const CollapseParams& p, const CollapseProgress& progress = {});

// The aspect measure of max_aspect for a triangle (infinity when it has no area).
double triangle_aspect(const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace cmcsurf
