// `cmcsurf scaffold --compare-nodal` (docs/scaffolds.md): the CMC part beside its nodal twin,
// the same design built from the nodal approximation (Eqs. 7-9) at the member's volume
// fraction, which is what scaffold tools threshold today: curvature spread, wall-thickness
// and pore-size spread, specific surface.
#pragma once

#include <nlohmann/json.hpp>

#include "grid/field.h"
#include "mesh/scaffold_part.h"
#include "pipeline/cmc.h"

namespace cmcsurf {

// phi: the member (computed with params); cmc: its part (design_scaffold(phi, d, shape)).
// Builds the twin's part (not written) with the same design and shape, and measures both
// surfaces' local mean curvature spread. Nodal surfaces only (throws std::invalid_argument
// for sphere, cube, noise).
nlohmann::json compare_with_nodal(const Field& phi, const RunParams& params,
                                  const ScaffoldDesign& d, const ScaffoldPart& cmc,
                                  const ShapeFill* shape = nullptr);

}  // namespace cmcsurf
