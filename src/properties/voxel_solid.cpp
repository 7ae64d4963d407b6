#include "properties/voxel_solid.h"

#include <algorithm>
#include <functional>
#include <stdexcept>

#include <fmt/format.h>

#include "measure/sharp_volume.h"
#include "surfaces/nodal_level.h"

namespace cmcsurf {

namespace {

constexpr double kPorosityTol = 1e-7;  // the sheet's thickness or band is solved to this

// The voxel fractions of {g > level} and their mean.
VoxelSolid fractions_above(const Field& g, double level) {
  VoxelSolid v;
  v.fraction = Field(g.n(), 1);
  dual_cell_fractions(g, level, v.fraction);
  v.fraction.exchange_halo();
  double sum = 0.0;
  for_each_cell(v.fraction, [&](int i, int j, int k) { sum += v.fraction(i, j, k); });
  v.solid_fraction = sum / v.fraction.global_cells();
  v.porosity = 1.0 - v.solid_fraction;
  return v;
}

// The x in [lo, hi] where solid(x) (increasing) leaves `porosity`, by bisection.
double solve_for_porosity(const std::function<double(double)>& solid, double lo, double hi,
                          double porosity) {
  const double target = 1.0 - porosity;
  for (int it = 0; it < 200 && hi - lo > 1e-14 * std::max(1.0, std::abs(hi)); ++it) {
    const double mid = 0.5 * (lo + hi);
    const double s = solid(mid);
    if (std::abs(s - target) <= kPorosityTol) return mid;
    (s < target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// A wall |d| < T/2 around the zero level of the signed distance d: as the level set
// T/2 - |d| > 0, i.e. -|d| > -T/2.
VoxelSolid sheet_from_distance(const Field& d, const SolidSpec& spec) {
  Field minus_abs = Field::like(d, 1);
  for_each_cell(d, [&](int i, int j, int k) { minus_abs(i, j, k) = -std::abs(d(i, j, k)); });
  minus_abs.exchange_halo();
  double thickness = spec.thickness;
  if (std::isfinite(spec.porosity)) {
    const double widest = 1.0;  // unit cells: far beyond any cell's thickest wall
    thickness = solve_for_porosity(
        [&](double t) { return fractions_above(minus_abs, -0.5 * t).solid_fraction; }, 0.0,
        widest, spec.porosity);
  }
  VoxelSolid v = fractions_above(minus_abs, -0.5 * thickness);
  v.thickness = thickness;
  return v;
}

void check_spec(const SolidSpec& spec) {
  if (spec.kind != SolidKind::kNetwork && spec.kind != SolidKind::kSheet)
    throw std::invalid_argument("--solid: accepted: network, sheet");
  if (spec.kind != SolidKind::kSheet) return;
  if (std::isfinite(spec.porosity)) {
    if (!(spec.porosity > 0.0 && spec.porosity < 1.0))
      throw std::invalid_argument(
          fmt::format("--porosity: got {}; accepted: 0 < P < 1", spec.porosity));
  } else if (!(spec.thickness > 0.0 && spec.thickness < 0.5)) {
    throw std::invalid_argument(fmt::format(
        "--thickness: got {}; accepted: 0 < T < 0.5 unit cells (or give --porosity)",
        spec.thickness));
  }
}

}  // namespace

VoxelSolid cmc_voxel_solid(const Field& phi, const SolidSpec& spec) {
  check_spec(spec);
  require_ghost(phi, 2, "cmc_voxel_solid");
  if (!phi.whole()) throw std::invalid_argument("cmc_voxel_solid: a whole grid only");
  if (spec.kind == SolidKind::kNetwork) {
    // The bias-corrected level set of the sharp volume fraction, so that the mean is the
    // run's reported volume fraction.
    Field psi = Field::like(phi, 1);
    curvature_corrected(phi, psi);
    VoxelSolid v = fractions_above(psi, 0.5);
    if (spec.other_phase) {
      for_each_cell(v.fraction, [&](int i, int j, int k) {
        v.fraction(i, j, k) = 1.0 - v.fraction(i, j, k);
      });
      v.fraction.exchange_halo();
      std::swap(v.solid_fraction, v.porosity);
    }
    return v;
  }
  const double band = std::isfinite(spec.porosity) ? 0.5 : 0.5 * spec.thickness + 3.0 * phi.h();
  return sheet_from_distance(signed_distance(phi, band), spec);
}

VoxelSolid nodal_voxel_solid(const std::string& surface, int n, const SolidSpec& spec,
                             double porosity, NodalSheet sheet) {
  if (!(porosity > 0.0 && porosity < 1.0))
    throw std::invalid_argument(fmt::format("porosity: got {}; accepted: 0 < P < 1", porosity));
  if (spec.kind == SolidKind::kNetwork) {
    // Phase 1 of the nodal level set is {F > c}: the solid, or the pores of phase 2's solid.
    const double alpha = spec.other_phase ? porosity : 1.0 - porosity;
    NodalLevelSet nodal = nodal_level_set(surface, alpha, n);
    Field psi = Field::like(nodal.f, 1);
    curvature_corrected(nodal.f, psi);
    VoxelSolid v = fractions_above(psi, nodal.level);
    if (spec.other_phase) {
      for_each_cell(v.fraction, [&](int i, int j, int k) {
        v.fraction(i, j, k) = 1.0 - v.fraction(i, j, k);
      });
      v.fraction.exchange_halo();
      std::swap(v.solid_fraction, v.porosity);
    }
    v.level = nodal.level - 0.5;  // F = f - 1/2
    return v;
  }
  SolidSpec s = spec;
  s.porosity = porosity;
  NodalLevelSet zero = nodal_level_set(surface, 0.5, n);  // f = F + 1/2, any level
  if (sheet == NodalSheet::kOffset) {
    VoxelSolid v = sheet_from_distance(signed_distance(zero.f, 0.5, 0.5), s);
    v.level = 0.0;
    return v;
  }
  // The band |F| < c: the level set -|F| > -c.
  Field minus_abs = Field::like(zero.f, 1);
  double widest = 0.0;
  for_each_cell(zero.f, [&](int i, int j, int k) {
    minus_abs(i, j, k) = -std::abs(zero.f(i, j, k) - 0.5);
    widest = std::max(widest, -minus_abs(i, j, k));
  });
  minus_abs.exchange_halo();
  const double c = solve_for_porosity(
      [&](double level) { return fractions_above(minus_abs, -level).solid_fraction; }, 0.0,
      widest, porosity);
  VoxelSolid v = fractions_above(minus_abs, -c);
  v.level = c;
  return v;
}

}  // namespace cmcsurf
