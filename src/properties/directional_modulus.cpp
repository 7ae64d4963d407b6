#include "properties/directional_modulus.h"

#include <cmath>
#include <stdexcept>

#include "properties/cell_properties.h"

namespace cmcsurf::properties {

namespace {

// q(x) = v(x) S v(x), v = (x^2, y^2, z^2, yz, xz, xy): homogeneous of degree 4, 1 / E on the
// unit sphere.
double quartic(const Matrix6& s, const Vector3& x) {
  const Voigt6 v{x[0] * x[0], x[1] * x[1], x[2] * x[2], x[1] * x[2], x[0] * x[2], x[0] * x[1]};
  double q = 0.0;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) q += v[i] * s[i][j] * v[j];
  return q;
}

// The surface r = E(d) d is q(x) = |x|^3 (|x| = E(x/|x|) and q(x) = |x|^4 / E); its normal is
// the gradient of q(x) - |x|^3, here by central differences (smooth, degree 4).
Vector3 surface_normal(const Matrix6& s, const Vector3& x) {
  const double r = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]), h = 1e-5 * r;
  auto f = [&](Vector3 y) {
    const double ry = std::sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
    return quartic(s, y) - ry * ry * ry;
  };
  Vector3 g{};
  for (int a = 0; a < 3; ++a) {
    Vector3 p = x, m = x;
    p[a] += h;
    m[a] -= h;
    g[a] = f(p) - f(m);
  }
  // f grows outwards where |x|^3 dominates: the outward normal is -grad f.
  double len = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  if (!(len > 0.0)) return {x[0] / r, x[1] / r, x[2] / r};
  Vector3 n{-g[0] / len, -g[1] / len, -g[2] / len};
  if (n[0] * x[0] + n[1] * x[1] + n[2] * x[2] < 0.0) n = {-n[0], -n[1], -n[2]};
  return n;
}

}  // namespace

DirectionalSurface directional_youngs_surface(const Matrix6& s, int divisions) {
  if (divisions < 2 || divisions % 2 != 0)
    throw std::invalid_argument("directional_youngs_surface: divisions must be even and >= 2");
  DirectionalSurface out;
  const int m = divisions;
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {-1.0, 1.0}) {
      const auto base = std::uint32_t(out.directions.size());
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      for (int j = 0; j <= m; ++j)
        for (int i = 0; i <= m; ++i) {
          Vector3 c{};
          c[axis] = sign;
          c[u] = -1.0 + 2.0 * i / m;
          c[w] = -1.0 + 2.0 * j / m;
          const double l = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
          const Vector3 d{c[0] / l, c[1] / l, c[2] / l};
          const double e = directional_youngs_modulus(s, d);
          out.directions.push_back(d);
          out.modulus.push_back(e);
          out.normals.push_back(surface_normal(s, {e * d[0], e * d[1], e * d[2]}));
        }
      // (u, w, axis) is right-handed, so u x w points along +axis: flip the order for -axis.
      for (int j = 0; j < m; ++j)
        for (int i = 0; i < m; ++i) {
          const std::uint32_t a = base + std::uint32_t(j * (m + 1) + i), b = a + 1,
                              c = a + std::uint32_t(m + 1), d = c + 1;
          if (sign > 0) {
            out.triangles.push_back({a, b, d});
            out.triangles.push_back({a, d, c});
          } else {
            out.triangles.push_back({a, d, b});
            out.triangles.push_back({a, c, d});
          }
        }
    }
  return out;
}

}  // namespace cmcsurf::properties
