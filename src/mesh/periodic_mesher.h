// The periodic tetrahedral mesher: CGAL's Periodic_3_mesh_3 (Debian libcgal-dev 5.5) on the
// Kuhn piecewise-linear interpolant of a level-set field, the same interpolant whose volume
// measure/sharp_volume.h and the properties' voxel fractions integrate. The only translation
// unit that includes CGAL (its headers take minutes to compile); without CGAL at configure
// time it builds a stub that says so.
#pragma once

#include <string>
#include <vector>

#include "grid/field.h"
#include "mesh/tet_mesh.h"

namespace cmcsurf {

// CGAL's criteria, unit-cell units (the torus is [0, 1)^3).
struct PeriodicMeshCriteria {
  double cell_radius = 0.04;      // a tet's circumradius at most (its edges: 2x that)
  double facet_size = 0.04;       // a surface facet's Delaunay ball radius at most
  double facet_distance = 0.002;  // facet circumcentre to the surface at most
  double facet_angle = 25.0;      // surface facets' smallest angle at least (degrees; <= 30)
  double radius_edge = 2.0;       // a tet's circumradius / shortest edge at most
  // CGAL's sliver perturber and exuder. repeatable: no wall-clock limit (CGAL's default stops
  // them after as long as the refinement took, so a busier machine got fewer of their steps and
  // runs differed by a few tets); they stop once no tet's smallest dihedral angle is below their
  // bound (degrees) or no step improves one. 10: measured on the 64^3 gyroid, 4-8 s a cell
  // like the time-limited default (bound 0, as far as they get: 4x that); the flat cut's
  // smoothing (mesh/tet_smooth.h) then takes the smallest angle above 5 degrees.
  bool repeatable = true;
  bool perturb = true;
  double perturb_bound_deg = 10.0;
  double exude_bound_deg = 10.0;
};

// Whether this build has the mesher (CGAL found at configure time), and its name and version.
bool periodic_mesher_available();
std::string periodic_mesher_name();

// Tetrahedra of {g_h > level} on the unit torus, g_h the Kuhn interpolant of the cell-centred
// values of g (whole grid, any ghost width). Throws std::runtime_error when the mesher is not
// available or the solid is empty.
PeriodicTets mesh_periodic_solid(const Field& g, double level, const PeriodicMeshCriteria& c);

// The Kuhn interpolant of g at unit-cell point p (any p: periodic), from the n^3 values of g
// (x fastest); the function the mesher sees. For tests.
double kuhn_interpolate(const std::vector<double>& g, int n, const Vec3& p);

}  // namespace cmcsurf
