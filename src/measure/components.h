// The connected components of one phase, the part of the cell nearest to each, and the
// measures of each component's boundary: what --constrain components holds (a volume per
// network of a double structure) and report.json's `interfaces`.
#pragma once

#include <cstdint>
#include <vector>

#include "grid/field.h"

namespace cmcsurf {

// Components of phase 1 ({phi > level}) or phase 2 ({phi < level}) on the 3-torus,
// 26-connected as in measure/topology.h, and each cell's region: the component nearest to it in
// 26-neighbour steps (a breadth-first search from all components at once), so that the regions
// tile the cell and each holds its component whole. Whole grid only. Cells are indexed
// (k n + j) n + i.
struct ComponentLabels {
  int n = 0;
  int phase = 1;
  int count = 0;
  std::vector<std::int32_t> component;  // -1 outside the phase
  std::vector<std::int32_t> region;     // -1 only when the phase is empty
};
ComponentLabels label_components(const Field& phi, int phase = 1, double level = 0.5);

// phi with the labelled phase's other components mirrored (phi -> 1 - phi), so that its
// labelled phase is component c alone. No 2x2x2 block of cells holds two components (they
// would be 26-connected), so every dual cell that component c's surface cuts keeps its eight
// values, and the piecewise-linear surface there is unchanged; the other components' surfaces
// become touching points (psi -> -|psi|). Ghost 2, halo current.
Field component_field(const Field& phi, const ComponentLabels& labels, int c);

// The sharp volume (measure/sharp_volume.h) of each component, as fractions of the cell: the
// dual cells' fractions of the curvature-corrected interpolant, each dual cell given to the
// region of its corner with the largest phi (the component whose surface cuts it). They add up
// to sharp_volume_fraction(phi). For phase 2 labels, the volumes of phase 2's components.
// phi: whole grid, ghost >= 2, halo current.
std::vector<double> component_volumes(const Field& phi, const ComponentLabels& labels);

// The boundary of one component: its area, H (mean and spread, sign as in
// measure/sharp_surface.h: positive where phase 1 is convex), integral K dA, Euler
// characteristic (2 chi of the component, exact for its closed-voxel union) and the volume of
// the component (sharp, measure/sharp_volume.h).
struct InterfaceMeasures {
  int phase = 1;      // of the component it bounds
  int component = 0;  // its label
  double area = 0.0;
  double mean_curvature = 0.0;
  double mean_curvature_std = 0.0;
  double gaussian_curvature_integral = 0.0;
  std::int64_t euler_characteristic = 0;
  double enclosed_volume = 0.0;
};
// One entry per component of the phase with more components (phase 1 when both have one): the
// surface's connected pieces when every component of that phase touches one component of the
// other (two networks in a matrix, spheres in a matrix, one labyrinth of a bicontinuous pair).
// The surface is phi = 1/2. phi: whole grid, ghost >= 2, halo current.
std::vector<InterfaceMeasures> interface_measures(const Field& phi);

}  // namespace cmcsurf
