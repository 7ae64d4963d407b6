// `cmcsurf scaffold`'s numerics (docs/scaffolds.md): from a computed CMC member and design
// targets (porosity, solid kind, cell size, box) to a clean part: sampled on the box, the
// sheet's wall thickness solved for the porosity, fragments removed, the pore space checked to
// percolate, optionally decimated, and measured (porosity, specific surface, local thickness
// of wall and pore). Everything is computed here; the caller only writes.
#pragma once

#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "grid/field.h"
#include "mesh/decimate.h"
#include "mesh/graded.h"
#include "mesh/part.h"
#include "mesh/scaffold.h"

namespace cmcsurf {

struct ScaffoldDesign {
  double porosity = 0.7;                   // target: 1 - solid volume / box volume
  SolidKind solid = SolidKind::kNetwork;   // network or sheet
  double cell_size = 2.0;                  // output units
  Vec3 size{10.0, 10.0, 10.0};             // the box, output units
  std::string units = "mm";
  bool keep_fragments = false;
  double porosity_tol = 1e-4;  // the sheet's thickness (or a network's level) is solved to this
  DecimateParams decimate;     // no budget and no tolerance: no decimation
  double min_feature = 0.0;    // warn when the thinnest wall or pore is below (0: no check)
  bool morphometry = true;
};

// The member the design needs: a network's solid is phase 1 at volume fraction 1 - porosity;
// a sheet is the wall around the alpha = 1/2 surface.
double member_volume_fraction(const ScaffoldDesign& d);

// The pore space does not connect some pair of opposite box faces.
struct ClosedCellError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct ScaffoldPart {
  TriMesh mesh;
  nlohmann::json report;   // every number, with the time of each stage
  std::vector<std::string> warnings;
};

// A user's part to fill instead of the box (--shape): a closed mesh in output units, and the
// thickness of a dense skin inside its surface (0: none). The lattice covers its bounding box
// with a margin, is cut to the shape (capped on its surface) and the porosity target holds
// over the shape's volume. Without a skin every pore must reach the outside.
struct ShapeFill {
  TriMesh mesh;
  double skin = 0.0;
};

// phi: the member's field (whole grid, ghost >= 1); shape: fill it instead of d.size's box.
// Throws std::invalid_argument on a design out of range and ClosedCellError on a closed-cell
// part (nothing to write). progress: the decimation's, when there is one.
ScaffoldPart design_scaffold(const Field& phi, const ScaffoldDesign& d,
                             const ShapeFill* shape = nullptr,
                             const DecimateProgress& progress = {});

// The wall thickness, pore size and throat of the design's unit cell (design_scaffold's
// `morphometry` keys, in d.units at d.cell_size) without building the part: a network is phase
// 1 of phi, a sheet the wall of d.porosity's Steiner thickness (the part's solved one differs
// by the box's trimming). Sizes scale with d.cell_size: what --pore-size solves with.
nlohmann::json design_cell_morphometry(const Field& phi, const ScaffoldDesign& d);

// A graded part (the paper's Fig. 2): the porosity ramps linearly from `from` at the low
// end of the axis to `to` at the high end.
struct PorosityRamp {
  double from = 0.8, to = 0.6;
  int axis = 2;               // 0 x, 1 y, 2 z
  double fraction_tol = 1e-4;  // ends accepted this far outside the members' range
  // In a shape, by depth instead of along the axis: `from` at the shape's surface (the inner
  // face of its skin), `to` at `depth` below it and deeper, linear in between.
  bool by_surface = false;
  double depth = 0.0;  // output units
};

// members: network members (phase 1 solid) sorted by increasing volume fraction, one grid,
// spanning 1 - from and 1 - to; each node layer along the axis blends the two that bracket
// its target. d.porosity is ignored (the ramp's mean is the overall target); the report adds
// `graded` (the profile per cell along the axis) and per-member morphometry. Throws
// std::invalid_argument on a ramp outside the members or a sheet, ClosedCellError as above.
// shape: fill it instead of d.size's box (a graded fill: the ramp runs along its bounding
// box's axis, the mean porosity is the ramp's weighted by the shape's section per layer; with
// ramp.by_surface by the depth below its surface, the mean over the shape's nodes).
ScaffoldPart design_graded_scaffold(const std::vector<GradedMember>& members,
                                    const ScaffoldDesign& d, const PorosityRamp& ramp,
                                    const DecimateProgress& progress = {},
                                    const ShapeFill* shape = nullptr);

// A graded sheet: the wall thickness ramps along the axis so that the porosity goes linearly
// from ramp.from to ramp.to (each node layer's wall from Steiner's formula at its porosity, all
// shifted by the part's level solve to meet the mean porosity). phi: the balanced member. The
// report adds `graded` (the profile per cell), `sheet.thickness_from` and `_to`, and the end
// cells' morphometry in `morphometry.members`. Throws as design_graded_scaffold. shape: fill it
// (along its bounding box's axis or, with ramp.by_surface, by depth), as design_graded_scaffold.
ScaffoldPart design_graded_sheet(const Field& phi, const ScaffoldDesign& d,
                                 const PorosityRamp& ramp, const DecimateProgress& progress = {},
                                 const ShapeFill* shape = nullptr);

// A graded cell size (a network): the member at cell size `from` at the low end of the axis and
// at `to` at the high end, the two lattices (sampled on the finer one's nodes) blended with a
// smoothstep weight over the middle `transition` of the part's length. Both are one member at
// d.porosity, so the porosity holds along the axis; a ramp of the period itself would shear
// the cells instead. d.cell_size is ignored. The report adds `graded_cell_size` (the ends,
// the transition, the porosity per slab of the finer cell) and the two cells' morphometry in
// `morphometry.members`. Throws std::invalid_argument on a sheet or a ramp out of range,
// ClosedCellError as design_scaffold.
struct CellSizeRamp {
  double from = 2.0, to = 1.0;  // output units
  int axis = 2;
  double transition = 1.0 / 3.0;  // of the part's length along the axis, centred
};
ScaffoldPart design_graded_cell_scaffold(const Field& phi, const ScaffoldDesign& d,
                                         const CellSizeRamp& ramp,
                                         const DecimateProgress& progress = {});

}  // namespace cmcsurf
