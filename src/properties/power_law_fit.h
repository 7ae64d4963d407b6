// Gibson-Ashby scaling of a lattice family: the least-squares line through (log rho, log y),
// y = C rho^n (E / E_s or k / k_s against the relative density rho).
#pragma once

#include <vector>

namespace cmcsurf::properties {

struct PowerLawFit {
  double coefficient = 0.0;  // C
  double exponent = 0.0;     // n
  double rms_log_residual = 0.0;  // root mean square of ln y - ln(C rho^n)
  int points = 0;            // the (rho, y) pairs used: both > 0 and finite
  bool valid = false;        // at least two distinct rho among them
};

PowerLawFit fit_power_law(const std::vector<double>& rho, const std::vector<double>& y);

}  // namespace cmcsurf::properties
