// The part's mesh size in a printer's terms (docs/scaffolds.md, "Mesh size"): a default chordal
// tolerance in millimetres whatever the output unit, and a voxel size (--resolution) turned
// into the member's grid.
#pragma once

#include <cstddef>
#include <string>

namespace cmcsurf {

// The default decimation tolerance: 10 um, a tenth of a typical FDM layer and about an SLA
// printer's pixel; below what any of them prints.
constexpr double kDefaultChordalToleranceMm = 0.01;

// The decimation error of a part is measured on at most this many samples per side (every
// k-th beyond): all of them took 60 s of the 5.6M-triangle cylinder's decimation.
constexpr std::size_t kPartErrorSamples = 1'000'000;

// Millimetres per output unit (um, mm, cm, m, in); throws std::invalid_argument otherwise.
double mesh_unit_mm(const std::string& unit);

// The smallest grid the solver accepts (m 2^k, m in {1, 3, 5, 7}, >= 8) whose spacing
// cell_size / N is at most `resolution` (both in one unit). Throws std::invalid_argument when
// that grid would exceed max_grid.
int grid_for_resolution(double cell_size, double resolution, int max_grid);

}  // namespace cmcsurf
