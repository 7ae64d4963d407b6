// Edge lengths within the bounds asked for, on a periodic tetrahedral mesh after the flat cut
// (mesh/periodic_cut.h): edges shorter than size_min are collapsed, edges longer than size_max
// split at their midpoints. Done on the torus, where a vertex on a cell face is one vertex for
// both faces of the box, so both faces change identically and stay mirrored node for node.
// See docs/volume_mesh.md.
#pragma once

#include <cstddef>

#include "mesh/tet_mesh.h"

namespace cmcsurf {

// Unit cells. 0: that bound is not enforced.
struct EdgeSizeBounds {
  double size_min = 0.0;
  double size_max = 0.0;
  // A collapse on the solid's surface must leave the new surface within this of the removed
  // vertex (which lay on the surface).
  double facet_distance = 0.0;
};

struct EdgeSizing {
  std::size_t below_min_before = 0, below_min_after = 0;  // edges
  std::size_t above_max_before = 0, above_max_after = 0;
  std::size_t collapsed = 0;  // edges collapsed (one vertex and its shell of tets removed each)
  std::size_t split = 0;      // edges split at their midpoints
  // Collapses refused, by the first reason found: a vertex that must stay (on a cell face its
  // partner is not on, on the surface with the edge inside), the topology (the mesh or the
  // surface would stop being a manifold), a tet that would turn inverted or worse than it was,
  // an edge that would grow past size_max, the surface moving by over facet_distance.
  std::size_t refused_fixed = 0, refused_topology = 0, refused_quality = 0,
              refused_length = 0, refused_surface = 0;
  std::size_t split_refused = 0;  // a half or a new edge below size_min, or a worse tet
};

// The smallest dihedral angle a collapse or split may leave, when the tets it replaces were
// better than that (else: no worse than they were), degrees.
inline constexpr double kSizingFloorDeg = 10.0;

// Collapses edges shorter than b.size_min (shortest first, either end into the other) and
// then splits edges longer than b.size_max (longest first), a few passes each. A vertex on a
// cell face collapses only into one on the same faces, a surface vertex only along a surface
// edge; the link condition keeps the mesh and its surface manifold; tets stay positive.
// Unused vertices are removed (indices renumbered in order).
EdgeSizing enforce_edge_sizes(PeriodicTets& t, const EdgeSizeBounds& b);

// The edges of the torus mesh shorter than lo and longer than hi (unit cells; 0: not counted).
std::pair<std::size_t, std::size_t> count_edges_outside(const PeriodicTets& t, double lo,
                                                        double hi);

}  // namespace cmcsurf
