#include "properties/voxel_element.h"

#include <cmath>

namespace cmcsurf::properties {

namespace {

// d N_a / d x_d at the point xi of the unit voxel.
double shape_gradient(int a, int d, const Vector3& xi) {
  double g = 1.0;
  for (int e = 0; e < 3; ++e) {
    const bool up = a >> e & 1;
    if (e == d)
      g *= up ? 1.0 : -1.0;
    else
      g *= up ? xi[e] : 1.0 - xi[e];
  }
  return g;
}

// The 2x2x2 Gauss points (weight 1/8 each).
template <class F>
void for_each_gauss_point(F f) {
  const double lo = 0.5 - 0.5 / std::sqrt(3.0), hi = 0.5 + 0.5 / std::sqrt(3.0);
  for (int q = 0; q < 8; ++q)
    f(Vector3{q & 1 ? hi : lo, q >> 1 & 1 ? hi : lo, q >> 2 & 1 ? hi : lo});
}

}  // namespace

Lame lame_of(double nu) {
  return {nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), 1.0 / (2.0 * (1.0 + nu))};
}

Matrix6 isotropic_stiffness(double nu) {
  const Lame l = lame_of(nu);
  Matrix6 c{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) c[i][j] = l.lambda;
    c[i][i] = l.lambda + 2.0 * l.mu;
    c[i + 3][i + 3] = l.mu;
  }
  return c;
}

ElementMatrix8 conductivity_element() {
  ElementMatrix8 k{};
  for_each_gauss_point([&](const Vector3& xi) {
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b)
        for (int d = 0; d < 3; ++d)
          k[a][b] += 0.125 * shape_gradient(a, d, xi) * shape_gradient(b, d, xi);
  });
  return k;
}

// Test corner a component i, trial corner b component k:
// lambda dN_a/dx_i dN_b/dx_k + mu (delta_ik gradN_a . gradN_b + dN_a/dx_k dN_b/dx_i).
ElementMatrix24 elasticity_element(double nu) {
  const Lame l = lame_of(nu);
  ElementMatrix24 k{};
  for_each_gauss_point([&](const Vector3& xi) {
    double g[8][3];
    for (int a = 0; a < 8; ++a)
      for (int d = 0; d < 3; ++d) g[a][d] = shape_gradient(a, d, xi);
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b) {
        const double dot = g[a][0] * g[b][0] + g[a][1] * g[b][1] + g[a][2] * g[b][2];
        for (int i = 0; i < 3; ++i)
          for (int c = 0; c < 3; ++c)
            k[3 * a + i][3 * b + c] +=
                0.125 * (l.lambda * g[a][i] * g[b][c] +
                         l.mu * ((i == c ? dot : 0.0) + g[a][c] * g[b][i]));
      }
  });
  return k;
}

Matrix3 strain_tensor(const Voigt6& e) {
  return {Vector3{e[0], 0.5 * e[5], 0.5 * e[4]}, Vector3{0.5 * e[5], e[1], 0.5 * e[3]},
          Vector3{0.5 * e[4], 0.5 * e[3], e[2]}};
}

}  // namespace cmcsurf::properties
