// Trilinear hexahedral elements on the unit voxel, the units and notation of src/properties/.
//
// Units: lengths in voxels (h = 1), the solid's Young's modulus E_s = 1 and conductivity
// k_s = 1, so stiffnesses come out normalised by E_s and conductivities by k_s.
// Notation (Voigt): strain (e11, e22, e33, 2 e23, 2 e13, 2 e12), stress
// (s11, s22, s33, s23, s13, s12), C maps the first to the second. Axes 1, 2, 3 = x, y, z.
// Corner a of the voxel is offset (a & 1, a >> 1 & 1, a >> 2 & 1) (grid/kuhn.h's kCubeCorner);
// element dofs are ordered node-major: dof D a + c is component c of corner a.
#pragma once

#include <array>

namespace cmcsurf::properties {

using Voigt6 = std::array<double, 6>;
using Matrix6 = std::array<Voigt6, 6>;
using Vector3 = std::array<double, 3>;
using Matrix3 = std::array<Vector3, 3>;

// Lame constants of the isotropic solid with E = 1 and Poisson ratio nu.
struct Lame {
  double lambda;
  double mu;
};
Lame lame_of(double poisson_ratio);

// Voigt stiffness of the isotropic solid (E = 1).
Matrix6 isotropic_stiffness(double poisson_ratio);

// Element matrices, exact (2x2x2 Gauss): conductivity 8x8 (k = 1), elasticity 24x24 (E = 1).
using ElementMatrix8 = std::array<std::array<double, 8>, 8>;
using ElementMatrix24 = std::array<std::array<double, 24>, 24>;
ElementMatrix8 conductivity_element();
ElementMatrix24 elasticity_element(double poisson_ratio);

// Mean over the voxel of d N_a / d x_d: +-1/4 (the sign of corner a's offset along d).
inline double mean_shape_gradient(int a, int d) { return (a >> d & 1) ? 0.25 : -0.25; }

// Displacement gradient of the macroscopic Voigt strain: u_i = sum_j G_ij x_j (symmetric).
Matrix3 strain_tensor(const Voigt6& strain_voigt);

}  // namespace cmcsurf::properties
