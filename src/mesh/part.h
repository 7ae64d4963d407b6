// A printed part in a box of any size (docs/scaffolds.md): a periodic unit-cell field sampled
// on the nodes of the box, the solid {a > level} capped on the box faces, its connected
// components (fragments cut off by the box removed), the pore space's percolation between
// opposite faces, and the mesh. Node m of axis c sits at (m + 1/2) spacing[c] in output
// units; the caps lie on the box faces 0 and size[c], half-way between the outermost nodes and
// the pads beyond them (mesh/marching_tets.h).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "grid/field.h"
#include "mesh/tri_mesh.h"

namespace cmcsurf {

struct PartLattice {
  std::array<int, 3> nodes{0, 0, 0};
  Vec3 spacing{0, 0, 0};  // output units
  Vec3 size{0, 0, 0};     // the box, output units: nodes * spacing
  std::vector<float> a;   // x fastest; the solid is {a > level}
  // A user's shape (--shape): the solid is also cut to {clip > 0} and joined with the skin
  // {skin > 0}; empty: none. Set by the caller in a's units.
  std::vector<float> clip, skin;
  Vec3 origin{0, 0, 0};         // of the box, output units (the mesh is placed there)
  double reference_volume = 0;  // porosity is relative to this; 0: the box
  // Nodes left out of the solid (fragments; empty: none), set by clean_part.
  std::vector<std::uint8_t> removed;
  // > 0 in the solid at `level`: max(min(a - level, clip), skin).
  double value(std::size_t id, double level) const {
    double v = double(a[id]) - level;
    if (!clip.empty()) v = std::min(v, double(clip[id]));
    if (!skin.empty()) v = std::max(v, double(skin[id]));
    return v;
  }
  double porosity_volume() const { return reference_volume > 0 ? reference_volume : box_volume(); }
  std::size_t index(int i, int j, int k) const {
    return (std::size_t(k) * nodes[1] + j) * nodes[0] + i;
  }
  std::size_t count() const { return std::size_t(nodes[0]) * nodes[1] * nodes[2]; }
  double box_volume() const { return size[0] * size[1] * size[2]; }
};

// Samples g (cell-centred on a periodic unit cell of grid n, any ghost width) on a box of
// `size` output units with unit cells of edge `cell_size`: refine * ceil(size / h) nodes per
// axis (h = cell_size / n), spacing size / nodes, periodic trilinear interpolation (the cell
// values themselves where size is a whole number of h and refine is 1), a = transform(g).
// Throws std::invalid_argument on a size or cell size out of range.
PartLattice sample_part(const Field& g, const Vec3& size, double cell_size,
                        const std::function<double(double)>& transform, int refine = 1);
// The same on the nodes `lat` already has (its nodes and spacing), with unit cells of edge
// cell_size: a lattice of one cell size sampled at another's nodes (a graded cell size).
void fill_part(PartLattice& lat, const Field& g, double cell_size,
               const std::function<double(double)>& transform);

// Connected components of the solid and of the pore space. Both are found on the nodes along
// the edges of the Kuhn tetrahedra (14 neighbours): within a tetrahedron the part of a linear
// function above (or below) the level is convex, so these are exactly the components of the
// piecewise-linear solid the mesh bounds, and of its complement in the box.
struct PartTopology {
  std::size_t solid_components = 0;  // before removal
  std::size_t fragments = 0;         // all but the largest
  bool fragments_removed = false;
  std::vector<double> fragment_volumes;  // output units^3, from their own meshes, largest first
  double fragment_volume = 0.0;          // their sum
  std::size_t pore_components = 0;
  std::array<bool, 3> pore_percolates{false, false, false};  // x, y, z
  std::size_t closed_pores = 0;     // pore components that touch no box face
  double closed_pore_volume = 0.0;  // output units^3, their nodes times the node cell
  double seconds = 0.0;
  bool percolates() const { return pore_percolates[0] && pore_percolates[1] && pore_percolates[2]; }
};

// Finds the components at `level`; unless keep_fragments, marks every node of all but the
// largest solid component as removed (the mesh leaves them out). Recomputes `removed`.
PartTopology clean_part(PartLattice& lat, double level, bool keep_fragments);

// The closed, capped, outward-oriented mesh of {a > level} without the removed nodes.
TriMesh mesh_part(const PartLattice& lat, double level);

nlohmann::json part_topology_json(const PartTopology& t, const std::string& units);

// Removing fragments moved the porosity by more than its tolerance: the solid is in pieces
// (a member of another topology, such as separate balls), not a lattice with slivers cut off.
struct FragmentRemovalError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Throws FragmentRemovalError when the removed fragments hold more than `tol` of `volume`
// (the box's or the shape's; the porosity moves by their share).
void check_fragment_share(const PartTopology& t, double volume, double tol,
                          const std::string& units);

}  // namespace cmcsurf
