// The Kuhn split of a cube into six tetrahedra around its main diagonal, shared by every
// piecewise-linear (marching-tetrahedra) computation: the sharp volume fraction, the sharp
// surface measures and the surface mesh. The split is translation invariant, so the
// tetrahedra of neighbouring cubes meet face to face and the interpolant is continuous.
#pragma once

namespace cmcsurf {

// Corner c of a cube is offset (c & 1, c >> 1 & 1, c >> 2 & 1): index x + 2y + 4z.
inline constexpr int kCubeCorner[8][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0},
                                          {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};

// One tetrahedron per axis order (a, b, c): corner 0 -> +e_a -> +e_a + e_b -> corner 7. Within
// a tetrahedron the corners are listed in componentwise increasing order.
inline constexpr int kKuhnTets[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                                        {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

}  // namespace cmcsurf
