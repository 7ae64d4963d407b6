// interface_measures (measure/components.h) from what the final measures already know of the
// whole surface, so that a surface of one piece is labelled and measured once.
#pragma once

#include <cstdint>
#include <vector>

#include "grid/field.h"
#include "measure/components.h"
#include "measure/sharp_surface.h"
#include "measure/topology.h"

namespace cmcsurf {

// What the final measures found of the whole surface phi = 1/2 before interface_measures: the
// counts of phase_components(phi), the level_set_surface of tanh_profile_inverse(phi), both
// phases' Euler characteristics and sharp_volume_fraction(phi).
struct WholeSurfaceMeasures {
  PhaseComponents counts;
  LevelSetSurface surface;
  std::int64_t euler_phase1 = 0;
  std::int64_t euler_phase2 = 0;
  double volume_fraction = 0.0;
};
// interface_measures(phi) from them: the counts are not labelled again, and where the labelled
// phase is one component its boundary is the whole surface, so its entry is `whole` (the same
// values; the enclosed volume the same sum in another order, equal to round-off) and no field is
// labelled, copied or measured again.
std::vector<InterfaceMeasures> interface_measures(const Field& phi,
                                                  const WholeSurfaceMeasures& whole);

}  // namespace cmcsurf
