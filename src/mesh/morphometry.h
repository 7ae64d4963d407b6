// The numbers a scaffold is judged by (docs/scaffolds.md): local thickness of each phase on the
// periodic unit cell, as bone morphometry's "local thickness" (Hildebrand & Ruegsegger 1997):
// at each voxel of a phase, the diameter of the largest ball inside the phase that contains
// it. Written here: an exact squared Euclidean distance transform (Felzenszwalb & Huttenlocher's
// separable lower envelope of parabolas, periodic), then, largest radius first, the opening of
// the phase by a ball of that radius as one more transform (the distance to the centres deep
// enough for it): a voxel's thickness is the first radius whose opening holds it.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include <nlohmann/json.hpp>

#include "grid/field.h"

namespace cmcsurf {

// Exact squared distance (in voxels^2) from each voxel to the nearest voxel where !inside, on
// the n^3 periodic grid (x fastest); 0 outside. A phase without any outside voxel gets a huge
// value.
std::vector<double> periodic_edt2(const std::vector<std::uint8_t>& inside, int n);

// Local thickness in voxels at every voxel of the phase (0 outside): the largest 2 r - 1 over
// the balls of radius r <= sqrt(edt2(c)) around the phase's voxels c that contain it
// (|x - c| < r), r from the distances that occur, in steps of at least 1/8 voxel. The "- 1"
// counts the voxel centres a ball spans, so that a slab m voxels thick gets m (m odd).
std::vector<double> local_thickness(const std::vector<std::uint8_t>& inside, int n);

// The same on a box of dims[0] x dims[1] x dims[2] voxels (x fastest), not periodic: beyond
// the box is outside the phase when `outside_beyond` (a wall ends where the box cuts it), else
// it is neither (a pore goes on past the box's faces, into the room around the part).
// radius_step: ball radii closer than this (voxels) are merged to the larger, so diameters
// read at most 2 radius_step short (local_thickness: 1/8; fewer transforms for coarser).
std::vector<double> box_edt2(const std::vector<std::uint8_t>& inside,
                             const std::array<int, 3>& dims, bool outside_beyond);
std::vector<double> box_local_thickness(const std::vector<std::uint8_t>& inside,
                                        const std::array<int, 3>& dims, bool outside_beyond,
                                        double radius_step = 0.125);

struct ThicknessStats {
  double mean = 0.0, std = 0.0, min = 0.0, max = 0.0;
  // Percentiles over the phase's voxels (volume-weighted): p5 is the thinnest wall a designer
  // can trust, min moves with the grid (one voxel at a corner can read thin).
  double p5 = 0.0, p50 = 0.0, p95 = 0.0;
  double fraction = 0.0;  // of the cell's voxels in the phase
  std::vector<double> histogram_edges, histogram;  // fraction of the phase's voxels per bin
};
// Over the voxels of the phase, scaled by `voxel` (output units per voxel).
ThicknessStats thickness_stats(const std::vector<double>& thickness,
                               const std::vector<std::uint8_t>& inside, double voxel,
                               int bins = 20);
nlohmann::json thickness_json(const ThicknessStats& s, const std::string& units);

// The throat of a phase along each axis: the diameter (in voxels, 2 r - 1 as local_thickness
// counts it) of the largest ball that passes through the periodic cell along x, y, z, i.e. the
// largest r such that the centres at distance >= r from outside the phase connect (through
// face neighbours) to their own copy one period along the axis; the bottleneck of the
// distance map. 0 along an axis where the phase does not percolate.
std::array<double, 3> throat_diameter(const std::vector<std::uint8_t>& inside, int n);

// The throat of a phase in a box along each axis: the diameter (voxels, as above) of the
// largest ball that passes from one face of the box to the opposite one inside the phase
// (centres at distance >= r from the phase's outside, the box's faces not counting as outside,
// connected through face neighbours); 0 along an axis where the phase does not cross the box.
std::array<double, 3> box_throat_diameter(const std::vector<std::uint8_t>& inside,
                                          const std::array<int, 3>& dims);

}  // namespace cmcsurf
