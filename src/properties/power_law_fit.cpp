#include "properties/power_law_fit.h"

#include <cmath>
#include <stdexcept>

namespace cmcsurf::properties {

PowerLawFit fit_power_law(const std::vector<double>& rho, const std::vector<double>& y) {
  if (rho.size() != y.size())
    throw std::invalid_argument("fit_power_law: rho and y differ in length");
  // Centred sums, so that close densities do not cancel catastrophically.
  std::vector<double> lx, ly;
  for (std::size_t i = 0; i < rho.size(); ++i)
    if (rho[i] > 0.0 && y[i] > 0.0 && std::isfinite(rho[i]) && std::isfinite(y[i])) {
      lx.push_back(std::log(rho[i]));
      ly.push_back(std::log(y[i]));
    }
  PowerLawFit f;
  f.points = int(lx.size());
  if (lx.size() < 2) return f;
  double mx = 0.0, my = 0.0;
  for (std::size_t i = 0; i < lx.size(); ++i) mx += lx[i], my += ly[i];
  mx /= double(lx.size());
  my /= double(lx.size());
  double sxx = 0.0, sxy = 0.0;
  for (std::size_t i = 0; i < lx.size(); ++i) {
    sxx += (lx[i] - mx) * (lx[i] - mx);
    sxy += (lx[i] - mx) * (ly[i] - my);
  }
  if (!(sxx > 1e-24)) return f;  // one density only: no slope
  f.exponent = sxy / sxx;
  f.coefficient = std::exp(my - f.exponent * mx);
  double r2 = 0.0;
  for (std::size_t i = 0; i < lx.size(); ++i) {
    const double r = ly[i] - (my + f.exponent * (lx[i] - mx));
    r2 += r * r;
  }
  f.rms_log_residual = std::sqrt(r2 / double(lx.size()));
  f.valid = true;
  return f;
}

}  // namespace cmcsurf::properties
