// The surface of a periodic cell as one welded mesh on the 3-torus, for analysis: every vertex
// once, inside the cell [0, 1)^3, each triangle with the whole-period offset of each corner's
// image, so that the triangle is (v[a] + o_a, v[b] + o_b, v[c] + o_c) (o_a = 0). Closed, with
// V - E + F the surface's Euler characteristic. Per vertex: the unit normal and the mean and
// Gaussian curvature of the level sets of psi at the vertex, from psi's central differences
// (the sharp measures' H and K, measure/sharp_surface.h) interpolated trilinearly from the
// eight cell centres around it, as level_set_surface does at triangle centroids.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "grid/field.h"
#include "mesh/tri_mesh.h"

namespace cmcsurf {

struct PeriodicSurfaceMesh {
  std::vector<Vec3> vertices;  // in [0, 1)^3, cell units
  std::vector<std::array<std::uint32_t, 3>> triangles;  // counter-clockwise seen from phase 2
  std::vector<std::array<std::array<std::int32_t, 3>, 3>> offsets;  // per triangle, per corner
  std::vector<Vec3> normals;  // unit, pointing into phase 2 (psi < 0), as the triangles'
  std::vector<double> mean_curvature;      // H, > 0 where phase 1 is convex
  std::vector<double> gaussian_curvature;  // K
  // The mesh as a TriMesh on the torus (period 1): analyze_mesh gives V - E + F.
  TriMesh tri_mesh() const;
};

// The zero set of psi's piecewise-linear interpolant over the dual cells (the sharp surface of
// measure/sharp_surface.h; phase 1 = psi > 0). psi: whole grid, ghost >= 1, halo current.
PeriodicSurfaceMesh periodic_surface(const Field& psi);

}  // namespace cmcsurf
