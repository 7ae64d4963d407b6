// Topology of a phase field's phases: which member of a family a run found. Near a topology
// change (the P family's channels pinch off towards spheres near alpha = 1/4 and 3/4) two runs
// can end on different members with the same volume fraction; their areas differ by a few
// percent, their Euler characteristics by whole numbers.
#pragma once

#include <cstdint>

#include "grid/field.h"

namespace cmcsurf {

// Euler characteristic chi = V - E + F - C of phase 1, {phi > level}, taken as the union of its
// closed voxels (the cubes around the cell centres) in the periodic unit cell (a 3-torus): every
// lattice vertex, edge and face that touches a phase-1 voxel counts once. A ball counts 1, a
// solid torus or a slab 0; the P surface's phase at alpha = 1/2 -2, so that a surface between
// two connected phases has genus 1 - chi per unit cell (P 3, G 5, D 9). Phase 1 is taken
// 26-connected (voxels touching at an edge or a corner join), as its closed voxels are.
// Reads one ghost layer below each axis (halo current); works on a decomposed block, summed
// over the processes.
std::int64_t euler_characteristic(const Field& phi, double level = 0.5);
// Plain twin: whole grid, periodic index wrap (no halo), serial.
std::int64_t euler_characteristic_ref(const Field& phi, double level = 0.5);

// The same of phase 2, {phi < level}, also as closed, 26-connected voxels. Where the surface
// between the phases is resolved (no voxels touching only at an edge or a corner across it)
// both phases are handlebodies bounded by the same surface, so chi(phase 2) = chi(phase 1) and
// the surface's chi = chi(phase 1) + chi(phase 2) (chi(boundary of M) = 2 chi(M)).
std::int64_t euler_characteristic_phase2(const Field& phi, double level = 0.5);
std::int64_t euler_characteristic_phase2_ref(const Field& phi, double level = 0.5);

// Connected components on the 3-torus of phase 1 ({phi > level}) and phase 2 ({phi < level}),
// each 26-connected as in euler_characteristic, and the number of (phase 1 component, phase 2
// component) pairs that share a voxel face: the surface's components when no pair of
// components meets along two separate sheets (two parallel planes count once; their genus, 1,
// is the same either way). Whole grid only (a decomposed run gathers it first).
struct PhaseComponents {
  std::int64_t phase1 = 0;
  std::int64_t phase2 = 0;
  std::int64_t interfaces = 0;
};
PhaseComponents phase_components(const Field& phi, double level = 0.5);
// Plain twin: one union-find in cell order, the pairs in a hash set, serial.
PhaseComponents phase_components_ref(const Field& phi, double level = 0.5);

}  // namespace cmcsurf
