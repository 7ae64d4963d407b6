// A user's part to fill (`scaffold --shape part.stl`, docs/scaffolds.md): a closed triangle
// mesh in output units, and its signed distance on a part lattice's nodes by OpenVDB's
// mesh-to-level-set (Debian libopenvdb-dev): < 0 inside, exact within a narrow band, +-band
// beyond it with the inside found by OpenVDB's flood fill.
#pragma once

#include <filesystem>
#include <vector>

#include "mesh/part.h"
#include "mesh/tri_mesh.h"

namespace cmcsurf {

// Binary or ASCII STL, vertices welded where they coincide exactly. Throws
// std::runtime_error naming the file when it cannot be read or holds no triangle.
TriMesh read_stl(const std::filesystem::path& path);

// Whether the bounding boxes of two of the mesh's shells (components by shared vertices)
// overlap: the triangles' signed volumes may then count a region twice.
bool shells_may_overlap(const TriMesh& shape);

// Signed distance (output units) from each node of lat to the shape, clamped to +-band. The
// shape is the union of its shells: overlapping closed shells count once.
std::vector<float> shape_distance(const TriMesh& shape, const PartLattice& lat, double band);

}  // namespace cmcsurf
