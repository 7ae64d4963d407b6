#include "mesh/parallel_surfaces.h"

#include <cmath>
#include <limits>
#include <numbers>

#include "mesh/scaffold.h"
#include "mesh/tri_mesh.h"

namespace cmcsurf {

Field surface_distance(const Field& psi, double band) {
  return signed_distance(psi, band, 0.0);
}

namespace {
double gauss_bonnet(const SurfaceIntegrals& s) {
  return 2.0 * std::numbers::pi * double(s.euler_characteristic);
}
}  // namespace

double steiner_area(const SurfaceIntegrals& s, double l) {
  return s.area + 2.0 * s.total_mean_curvature * l + gauss_bonnet(s) * l * l;
}

double steiner_volume(const SurfaceIntegrals& s, double l) {
  const double v = s.area * l + s.total_mean_curvature * l * l + gauss_bonnet(s) * l * l * l / 3.0;
  return std::abs(v);
}

double level_area(const Field& d, double t) { return mesh_area(periodic_surface_mesh(d, t)); }

double layer_volume(const Field& d, double a, double b) {
  // 4-point Gauss-Legendre: exact for Steiner's quadratic A(t).
  constexpr double kNode[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                               0.8611363115940526};
  constexpr double kWeight[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                 0.3478548451374538};
  const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
  double v = 0.0;
  for (int q = 0; q < 4; ++q) v += kWeight[q] * level_area(d, mid + half * kNode[q]);
  return std::abs(half * v);
}

ParallelSurfaces parallel_surfaces(const Field& d, const SurfaceIntegrals& s,
                                   const std::vector<double>& distances) {
  ParallelSurfaces out;
  for (double l : distances) {
    ParallelSurface one;
    one.distance = l;
    one.area = level_area(d, l);
    one.volume = layer_volume(d, 0.0, l);
    one.area_steiner = steiner_area(s, -l);
    one.volume_steiner = steiner_volume(s, -l);
    out.phase1.push_back(one);
    one.area = level_area(d, -l);
    one.volume = layer_volume(d, -l, 0.0);
    one.area_steiner = steiner_area(s, l);
    one.volume_steiner = steiner_volume(s, l);
    out.phase2.push_back(one);
  }
  return out;
}

double lipid_fraction(double x, double sigma, std::int64_t chi) {
  return 2.0 * sigma * x + 4.0 * std::numbers::pi / 3.0 * double(chi) * x * x * x;
}

double lipid_length_ratio(double phi_L, double sigma, std::int64_t chi) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (!(phi_L > 0.0) || !(sigma > 0.0)) return nan;
  // Where d(phi_L)/dx = 2 sigma + 4 pi chi x^2 vanishes (chi < 0); no bound otherwise.
  double hi = chi < 0 ? std::sqrt(sigma / (2.0 * std::numbers::pi * double(-chi))) : 0.0;
  if (chi >= 0) {
    hi = phi_L / (2.0 * sigma);  // lipid_fraction(hi) >= phi_L
  } else if (lipid_fraction(hi, sigma, chi) < phi_L) {
    return nan;
  }
  double lo = 0.0;
  for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (lipid_fraction(mid, sigma, chi) < phi_L ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double bilayer_fraction(const Field& d, double x) {
  return layer_volume(d, -x, 0.0) + layer_volume(d, 0.0, x);
}

double measured_lipid_length_ratio(const Field& d, double phi_L, double x_start, double x_max) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (!(phi_L > 0.0) || !(x_start > 0.0 && x_start < x_max)) return nan;
  // Newton on V(x) = phi_L with V'(x) = A(x) + A(-x), the two parallel surfaces' areas.
  double x = x_start;
  for (int it = 0; it < 20; ++it) {
    const double slope = level_area(d, x) + level_area(d, -x);
    if (!(slope > 0.0)) return nan;
    const double step = (bilayer_fraction(d, x) - phi_L) / slope;
    x -= step;
    if (!(x > 0.0 && x < x_max)) return nan;
    if (std::abs(step) < 1e-12 * x) return x;
  }
  return nan;
}

}  // namespace cmcsurf
