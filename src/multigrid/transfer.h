// Grid transfers between a level of size 2n and its coarse level of size n (Appendix A), on
// whole grids or on blocks (the coarse block covers the fine block's cells in pairs). Both read
// and write interiors only: the caller exchanges the written field's halo before reading its
// ghosts.
#pragma once

#include "grid/field.h"

namespace cmcsurf {

// Cell-average restriction I_l^{l-1}: coarse = mean of the 8 fine children.
void restrict_average(const Field& fine, Field& coarse);
void restrict_average_ref(const Field& fine, Field& coarse);

// Coarse-grid correction with piecewise-constant interpolation I_{l-1}^l (steps 6-8):
// fine += coarse - coarse_before, each coarse value copied to its 8 children.
void add_interpolated_correction(const Field& coarse, const Field& coarse_before, Field& fine);
void add_interpolated_correction_ref(const Field& coarse, const Field& coarse_before,
                                     Field& fine);

}  // namespace cmcsurf
