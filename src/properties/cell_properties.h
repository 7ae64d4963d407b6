// Properties of a periodic unit cell of composite voxels: the effective
// stiffness and its engineering constants, the conductivities of the solid and of the pore
// space, Hashin-Shtrikman upper bounds beside them, and percolation along the axes.
// Units and notation: voxel_element.h (Voigt 11 22 33 23 13 12; C / E_s; k / k_s; the pore
// space's conductivity / the fluid's).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "properties/homogenize.h"
#include "properties/stokes_flow.h"

namespace cmcsurf::properties {

// Engineering constants of a Voigt stiffness (any symmetry; axes x, y, z).
struct ElasticConstants {
  Matrix6 compliance_voigt{};   // S = C^-1
  Vector3 youngs_modulus{};     // E_x, E_y, E_z = 1 / S_ii
  Vector3 shear_modulus{};      // G_yz, G_xz, G_xy = 1 / S_44, 1 / S_55, 1 / S_66
  Matrix3 poisson_ratio{};      // nu_ij = -S_ji / S_ii: strain along j per strain along i
  double bulk_modulus = 0.0;    // (1/9) sum_{i,j <= 3} C_ij: hydrostatic strain (= Reuss if cubic)
  double shear_modulus_mean = 0.0;   // Voigt mean: (sum C_ii - sum C_ij + 3 sum C_44..66) / 15
  double youngs_modulus_mean = 0.0;  // 9 K G / (3 K + G) of the two above
  double zener_ratio = 0.0;          // 2 C44 / (C11 - C12)
  double youngs_modulus_min = 0.0, youngs_modulus_max = 0.0;  // E(d) over unit directions d
  Vector3 direction_min{}, direction_max{};
  bool invertible = false;  // false: C singular (a solid that does not percolate); E, G, nu = 0
};
ElasticConstants elastic_constants(const Matrix6& stiffness_voigt);
// E(d) = 1 / (d d : S : d d) for a unit direction d.
double directional_youngs_modulus(const Matrix6& compliance_voigt, const Vector3& d);

// Hashin-Shtrikman upper bounds of an isotropic two-phase composite of the solid (fraction
// f, E = 1, Poisson ratio nu, k = 1) and void (zero stiffness and conductivity). The bulk and
// shear bounds also bound the Voigt means of any anisotropic cell (trace bounds), the
// conductivity bound the mean of its diagonal.
struct HashinShtrikman {
  double bulk_modulus, shear_modulus, youngs_modulus, conductivity;
};
HashinShtrikman hashin_shtrikman_upper(double solid_fraction, double poisson_ratio);

// Axes x, y, z along which a cluster of voxels with s > 0 and s >= void_below (26-connected:
// voxels sharing a node are coupled by the elements) wraps around the periodic cell.
std::array<bool, 3> percolating_axes(int n, const std::vector<double>& s,
                                     double void_below = 0.0);

struct CellPropertiesOptions {
  double poisson_ratio = 0.3;  // of the solid
  SolverOptions solver;
  bool elasticity = true;
  bool conductivity = true;  // solid and pore space
  bool flow = false;         // Stokes flow through the pore space (stokes_flow.h)
  FlowOptions flow_solver;
};

struct CellProperties {
  int n = 0;
  double relative_density = 0.0;  // mean solid fraction
  double porosity = 0.0;
  double poisson_ratio_solid = 0.0;
  ElasticHomogenization elastic;
  ElasticConstants constants;
  ConductivityHomogenization solid_conduction, pore_conduction;
  Vector3 formation_factor{};   // 1 / k_pore,ii (infinity where the pore does not conduct)
  Vector3 tortuosity_pore{};    // porosity x formation factor
  HashinShtrikman bound_solid{};     // at the relative density
  double bound_conductivity_pore = 0.0;  // 2 phi / (3 - phi), phi = porosity
  // Fraction of the bound reached: bulk, Voigt shear and Young's means; mean diagonal k.
  double bulk_fraction_of_bound = 0.0, shear_fraction_of_bound = 0.0,
         youngs_fraction_of_bound = 0.0, conductivity_solid_fraction_of_bound = 0.0,
         conductivity_pore_fraction_of_bound = 0.0;
  std::array<bool, 3> solid_percolates{}, pore_percolates{};
  // With flow: permeability (voxel^2) and the rest of FlowResult, the wall shear stress of
  // the flow along x, y, z (solver units, stokes_flow.h; empty for an axis without flow) and
  // along z alone (wall_shear, the earlier key), the specific surface (voxel^-1) and the
  // Kozeny-Carman constant c = porosity^3 / (k S^2), k the mean diagonal (0 without flow).
  FlowResult flow;
  std::array<WallShearStats, 3> wall_shear_axes{};
  WallShearStats wall_shear;
  double specific_surface = 0.0;
  double kozeny_carman_constant = 0.0;
  std::vector<std::string> warnings;  // non-percolating axes, load cases not converged
  double seconds = 0.0;
};

CellProperties compute_cell_properties(int n, const std::vector<double>& solid_fraction,
                                       const CellPropertiesOptions& o = {});

// Grid check: the same cell on n and n/2 (restrict_solid_fraction) and Richardson's limit
// of a value under an error ~ h^order: fine + (fine - coarse) / (2^order - 1). The order is
// assumed, 2: observed 2.3-2.8 on gyroids from 32^3, 64^3, 128^3 (docs/properties.md), so
// the assumed one under-corrects a little; the error estimate is |fine - limit|.
inline constexpr double kGridCheckOrder = 2.0;
double richardson_limit(double fine, double coarse, double order = kGridCheckOrder);
struct GridCheck {
  CellProperties fine, coarse;
};
GridCheck grid_check(int n, const std::vector<double>& solid_fraction,
                     const CellPropertiesOptions& o = {});

}  // namespace cmcsurf::properties
