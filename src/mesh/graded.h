// Graded porosity (paper Fig. 2): the volume fraction ramps linearly along one axis across the
// tiles. Each sample blends the two CMC family members whose volume fractions bracket the
// local target, with weights linear in the target, so the field (and its 1/2 level set) stays
// continuous across tile faces and the mesh stays closed. See docs/meshing.md.
#pragma once

#include <array>
#include <vector>

#include <nlohmann/json.hpp>

#include "grid/field.h"
#include "mesh/scaffold.h"

namespace cmcsurf {

struct GradedMember {
  double volume_fraction = 0.0;  // of phase 1, as measured on the member's field
  Field phi;                     // same N for all members
};

struct GradedRamp {
  int axis = 2;                // 0 x, 1 y, 2 z
  double from_fraction = 0.3;  // at the low end of the axis (phase 1)
  double to_fraction = 0.6;    // at the high end
};

// Linear ramp of the target volume fraction at position s (unit cells) in [0, tiles[axis]].
double graded_target(const GradedRamp& ramp, const std::array<int, 3>& tiles, double s);

// Sampler over the tiled cells. members: sorted by volume fraction, at least two, whole grids
// of one N, with the ramp's end values inside their range widened by fraction_tol on each
// side (throws std::invalid_argument otherwise); an end value in that margin is held at the
// end member. fraction_tol is the volume constraint's tolerance the members were computed to
// (RunParams::volume_tol): members run for 0.3 and 0.6 measure e.g. 0.30006 and 0.59999, and
// their targets 0.3 and 0.6 are then accepted as ramp ends. The sampler owns the members
// (pass them with std::move to avoid a copy), so it stays valid after the caller's vector is
// gone or changed.
TiledSampler graded_sampler(std::vector<GradedMember> members, const GradedRamp& ramp,
                            const std::array<int, 3>& tiles, double fraction_tol = 0.0);

// Per tile: the target at the tile's centre, the fraction of the tile's cells where the
// blended field exceeds 1/2 (achieved), and the tile index.
nlohmann::json graded_cell_report(const TiledSampler& f, int n, const GradedRamp& ramp,
                                  const std::array<int, 3>& tiles);

}  // namespace cmcsurf
