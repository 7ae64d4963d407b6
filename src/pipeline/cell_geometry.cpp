#include "pipeline/cell_geometry.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "common/wall_clock.h"

namespace cmcsurf {

Field profile_distance(const Field& psi, double epsilon) {
  Field d = Field::like(psi, psi.ghost());
  const double w = 2.0 * std::sqrt(2.0) * epsilon;
  for_each_cell(psi, [&](int i, int j, int k) { d(i, j, k) = w * psi(i, j, k); });
  d.exchange_halo();
  return d;
}

CellGeometry measure_cell_geometry(const Field& psi, const SurfaceIntegrals& s,
                                   const std::vector<double>& distances, double lipid_length_nm,
                                   double lipid_fraction) {
  const auto t0 = WallClock::now();
  CellGeometry g;
  g.integrals = s;
  g.channels = channel_radius(psi);
  const double h = 1.0 / psi.n();
  double reach = distances.empty() ? 0.0 : *std::max_element(distances.begin(), distances.end());
  std::optional<LipidLattice> lipid;
  if (lipid_length_nm > 0.0) {
    LipidLattice l;
    l.ratio_measured = l.lattice_nm_measured = std::numeric_limits<double>::quiet_NaN();
    l.length_nm = lipid_length_nm;
    l.fraction = lipid_fraction;
    l.ratio_formula = lipid_length_ratio(lipid_fraction, s.area, s.euler_characteristic);
    l.lattice_nm_formula = lipid_length_nm / l.ratio_formula;
    // Newton's steps for the measured bilayer start at the formula's x and stay below twice
    // it (no formula solution: none measured either).
    if (std::isfinite(l.ratio_formula)) reach = std::max(reach, 2.0 * l.ratio_formula);
    lipid = l;
  }
  if (reach > 0.0) {
    // The distance is exact within its band: a few cells beyond the farthest level asked for.
    const double band = std::min(0.5, reach + 3.0 * h);
    const Field d = surface_distance(psi, band);
    g.parallel = parallel_surfaces(d, s, distances);
    if (lipid && std::isfinite(lipid->ratio_formula)) {
      lipid->ratio_measured = measured_lipid_length_ratio(
          d, lipid->fraction, lipid->ratio_formula, std::min(band - 2.0 * h, reach));
      lipid->lattice_nm_measured = lipid->length_nm / lipid->ratio_measured;
    }
  }
  g.lipid = lipid;
  g.seconds = seconds_since(t0);
  return g;
}

}  // namespace cmcsurf
