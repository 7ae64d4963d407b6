// The directional Young's modulus E(d) = 1 / (d_i d_j d_k d_l S_ijkl) of an effective
// stiffness as a closed surface r(d) = E(d) d for the picture (docs/properties.md): the sphere
// as a subdivided cube, so the axes <100> (face centres) and the body diagonals <111> (cube
// corners), where a cubic tensor has its extremes, are vertices.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "properties/voxel_element.h"

namespace cmcsurf::properties {

struct DirectionalSurface {
  std::vector<Vector3> directions;  // unit directions d
  std::vector<double> modulus;      // E(d), / E_s like the compliance's inverse
  std::vector<Vector3> normals;     // unit outward normals of r(d) = E(d) d
  std::vector<std::array<std::uint32_t, 3>> triangles;  // counter-clockwise seen from outside
};

// `divisions` (>= 2, even) per cube edge: 6 divisions^2 quads, (divisions + 1)^2 vertices per
// face (the faces' edges are repeated, so each face shades on its own normals).
DirectionalSurface directional_youngs_surface(const Matrix6& compliance_voigt, int divisions);

}  // namespace cmcsurf::properties
