// Periodic tetrahedral meshes of the network or sheet solid of a CMC field, for a user's own
// finite-element code: the options as a user gives them (checked here, for the command line and
// Python alike), the mesh (mesh/periodic_mesher.h, unfolded by mesh/tet_mesh.h) and its report.
// See docs/volume_mesh.md.
#pragma once

#include <array>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "grid/field.h"
#include "mesh/periodic_cut.h"
#include "mesh/periodic_mesher.h"
#include "mesh/scaffold.h"
#include "mesh/tet_mesh.h"
#include "mesh/tet_sizing.h"
#include "mesh/tet_smooth.h"

namespace cmcsurf {

// The options as given (`cmcsurf volume-mesh`, cmcsurf.volume_mesh); NaN (thickness: 0): not
// given.
struct VolumeMeshOptions {
  std::string solid = "network";  // network | sheet
  double porosity = NAN;          // sheet: the wall thickness that leaves this porosity
  double thickness = 0.0;         // sheet: wall thickness, output units
  std::string tile = "1x1x1";
  double cell_size = 1.0;
  std::string units = "mm";
  double size = NAN;              // the longest edge; default kDefaultVolumeMeshSize cells
  double size_min = NAN, size_max = NAN;
  double facet_distance = NAN;    // default: kDefaultFacetDistanceShare of the longest edge
  // flat: the box cut by its planes; fundamental: each tet whole where its centroid falls
  // (jagged cut faces, but CGAL's tets untouched: better angles, fewer tets).
  std::string cut = "flat";
};

// The default longest edge, unit cells, and facet distance, a fraction of the longest edge: a
// 64^3 gyroid network cell in ~6 s, volume within 0.25 % (docs/volume_mesh.md).
inline constexpr double kDefaultVolumeMeshSize = 0.08;
inline constexpr double kDefaultFacetDistanceShare = 1.0 / 40;
// A one-sided face vertex (mesh/periodic_cut.h) moves off the face by at most this share of
// the facet distance, so the surface stays within about 1.25 times it there.
inline constexpr double kOneSidedLiftFacetShare = 0.25;
// Tiles per axis: each tile copies the cell's tets (memory and file size grow with the count).
inline constexpr int kMaxVolumeMeshTiles = 8;

struct VolumeMeshParams {
  SolidKind solid = SolidKind::kNetwork;
  double porosity = NAN;     // sheet, when given
  double thickness = 0.0;    // sheet: unit cells (from --thickness / cell_size) when given
  std::array<int, 3> tiles{1, 1, 1};
  double cell_size = 1.0;
  std::string units = "mm";
  double size_min = 0.0;     // unit cells; 0: none (flat cut: short edges collapsed)
  double size_max = kDefaultVolumeMeshSize;  // unit cells
  double facet_distance = kDefaultVolumeMeshSize * kDefaultFacetDistanceShare;  // unit cells
  // The cut faces: flat (the torus mesh split at the cell faces, vertices within cut_snap of
  // their shortest edge snapped onto them first) or, when false, the unsplit fundamental
  // domain.
  bool flat_faces = true;
  double cut_snap = kDefaultCellFaceSnap;
  // After the flat cut: the vertices of tets under this smallest dihedral angle are smoothed
  // (mesh/tet_smooth.h); 0: not.
  double sliver_target_deg = kSliverTargetDeg;
};

// Checks every option against the field's grid n; throws OptionError (model/run_options.h)
// naming the option and the accepted range.
VolumeMeshParams volume_mesh_params(const VolumeMeshOptions& o, int n);

struct VolumeMesh {
  TetMesh mesh;                // output units
  nlohmann::json report;       // FILE.json's keys (docs/volume_mesh.md)
  double solid_fraction = 0;   // of the field's solid (the voxel fractions' mean)
  double thickness = 0;        // sheet: the wall thickness meshed, unit cells
};

// phi: whole grid, ghost >= 2. Throws std::runtime_error when the mesher is unavailable.
VolumeMesh build_volume_mesh(const Field& phi, const VolumeMeshParams& p);

// The level-set field g and level whose Kuhn interpolant's {g > level} is the solid: the
// curvature-corrected phi at 1/2 (network) or -|d| at -T/2 (sheet), the functions
// properties/voxel_solid.h integrates. thickness: the sheet's, unit cells.
struct SolidLevelSet {
  Field g;
  double level = 0.5;
};
SolidLevelSet solid_level_set(const Field& phi, SolidKind solid, double thickness);

// The mean voxel fraction of {g_h > level} (measure/sharp_volume.h).
double solid_fraction_above(const Field& g, double level);

// The sheet whose voxel solid leaves `porosity`, to kSheetPorosityTol: the thickness that
// cmc_voxel_solid's bisection finds, from a distance field whose band only just holds the wall
// (estimated from the surface's area, widened if the wall is thicker) and a regula falsi
// solve; the wide band and ~25 bisection steps there took most of a sheet's time.
inline constexpr double kSheetPorosityTol = 1e-7;
struct SheetForPorosity {
  SolidLevelSet level_set;     // -|d| at -T/2
  double thickness = 0.0;      // T, unit cells
  double solid_fraction = 0.0;
  double band = 0.0;           // of the last distance field, unit cells
  int distance_fields = 0;     // computed (1 unless the first band was too narrow)
  int evaluations = 0;         // of the solid fraction
};
SheetForPorosity sheet_for_porosity(const Field& phi, double porosity);

}  // namespace cmcsurf
