// Small-angle scattering of a phase field's structure (docs/science.md, "Scattering"):
// structure factors F_hkl of a density model by FFT, reflection classes of the cubic point
// group m-3m, the cubic space groups their absences allow, the powder pattern I(q) and the
// indexing of measured peaks.
//
// Conventions: F_hkl = integral over the unit cell of rho(x) exp(-2 pi i (h, k, l) . x) dx, so
// F_000 is the mean density (the volume fraction for the step density); I_hkl = |F_hkl|^2;
// q_hkl = 2 pi sqrt(s) / a with s = h^2 + k^2 + l^2 and a the lattice parameter.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <complex>
#include <optional>
#include <string>
#include <vector>

#include "grid/field.h"

namespace cmcsurf {

enum class DensityModel {
  kStep,     // 1 where phi > 1/2, 0 elsewhere: exact voxel fractions (sub-voxel surface)
  kBilayer,  // 1 within a half-thickness L of the phi = 1/2 surface, 0 elsewhere
  kProfile,  // phi itself, sampled at the cell centres
};

struct DensityParams {
  DensityModel model = DensityModel::kStep;
  double half_thickness = 0.0;  // bilayer: L in unit-cell units
};

// Density samples on the N^3 grid, x fastest: sample (i, j, k) sits at ((i, j, k) + shift) / N
// and is either the density there (point) or its average over the cube of side 1/N centred
// there (voxel_average), which the transform divides out (sinc per axis).
struct DensityGrid {
  int n = 0;
  std::vector<double> values;
  double shift = 0.5;
  bool voxel_average = false;
  double interface_width = 0.0;  // bilayer: w of phi = (1 + tanh(d / w)) / 2, from the field
};

// Parses "step", "profile" or "bilayer:L" (0 < L < 0.25); throws std::invalid_argument
// with the accepted forms.
DensityParams parse_density_model(const std::string& text);
std::string density_model_name(const DensityParams& p);

// The density of a whole-grid phase field. step: for each dual cell (the cube between cell
// centres i..i+1), the exact fraction where the piecewise-linear (Kuhn) interpolant of
// psi = (phi - 1/2) - h^2 (Lap + mean diagonal second difference) / 24 is positive, averaged
// over the Kuhn splits along all 4 body diagonals (so the rule keeps the m-3m symmetry of the
// grid). bilayer: the same fractions of {d > -L} minus {d > L}, d = w atanh(2 phi - 1) the
// distance of the tanh profile, w estimated from the field. profile: phi at the centres.
DensityGrid density_from_phase_field(const Field& phi, const DensityParams& p);

// F_hkl of a density grid for |h|, |k|, |l| <= n/2 - 1, from one r2c FFT (FFTW), with the
// samples' offset and, for voxel averages, the box's transform divided out.
class StructureFactors {
 public:
  explicit StructureFactors(const DensityGrid& rho);
  int n() const { return n_; }
  int max_index() const { return n_ / 2 - 1; }
  std::complex<double> operator()(int h, int k, int l) const;

 private:
  int n_ = 0;
  std::vector<std::complex<double>> half_;  // n x n x (n/2 + 1), FFTW's r2c layout
};

// One reflection class: the m-3m orbit of (h, k, l), represented by h >= k >= l >= 0.
struct Reflection {
  int h = 0, k = 0, l = 0;
  int s = 0;              // h^2 + k^2 + l^2
  int multiplicity = 0;   // members of the orbit
  double intensity = 0;   // mean |F|^2 over the members
  double amplitude = 0;   // |F| of the representative
  double phase = 0;       // arg F of the representative, radians in (-pi, pi]
  double spread = 0;      // (max - min) |F|^2 over the members / the strongest class's intensity
  bool present = true;    // intensity >= absent_tol * the strongest class's
};

// Every class with 0 < s <= smax (smax <= max_index^2), ordered by s then h, k, l.
std::vector<Reflection> reflection_classes(const StructureFactors& f, int smax,
                                           double absent_tol);

// The reflection conditions of a cubic space group of Laue class m-3m (International Tables
// A, general conditions).
struct SpaceGroup {
  int number;
  const char* symbol;
  int order;             // point-group order: 48 centrosymmetric, 24 otherwise
  const char* same_conditions;  // groups with identical conditions (not told apart here)
  char centring;         // 'P', 'I' or 'F'
  int c0kl;              // 0 none, 1 k+l=2n, 2 k,l=2n, 3 k+l=4n
  int chhl;              // 0 none, 1 l=2n, 2 h,l=2n, 3 h+l=2n, 4 2h+l=4n
  int ch00;              // 0 none, 1 h=2n, 2 h=4n
};
const std::vector<SpaceGroup>& cubic_space_groups();
const SpaceGroup& find_space_group(const std::string& symbol);  // throws when unknown
// Whether the group allows (h, k, l) (any signs and order).
bool space_group_allows(const SpaceGroup& g, int h, int k, int l);

struct SpaceGroupCandidate {
  const SpaceGroup* group;
  int forbidden = 0;  // classes in range it forbids (all observed absent when consistent)
};
struct SpaceGroupFit {
  // The density repeats with period 1/divisor of the unit cell when every present class's
  // indices share this factor (the D sheet in the nodal formula's cell: 2); the groups are
  // matched on that reduced cell, indices (h, k, l) / divisor, classes off it left out.
  int divisor = 1;
  const SpaceGroup* best = nullptr;  // most absences explained, then highest order
  std::vector<SpaceGroupCandidate> consistent;  // best first
  // Absent classes that the best group allows (accidentally weak), reduced indices.
  std::vector<std::array<int, 3>> accidental;
};
// Consistent: forbids no present class. Throws when none is (cannot happen: Pm-3m).
SpaceGroupFit detect_space_group(const std::vector<Reflection>& classes);

// The powder pattern on [0, q_max]: each present class adds multiplicity * |F|^2 times the
// Lorentz factor 1 / q_hkl^2 and the Debye-Waller factor exp(-sigma^2 q_hkl^2), spread into a
// peak of unit area and full width at half maximum `width` (Gaussian or Lorentzian).
struct PowderParams {
  double lattice = 1.0;        // a, nm
  double debye_waller = 0.0;   // sigma, nm
  double peak_width = 0.0;     // FWHM, 1/nm (0: 1% of the first present peak's q)
  bool lorentzian = false;
  int samples = 4000;
};
struct PowderPattern {
  std::vector<double> q, intensity;
  std::vector<double> peak_q;  // present classes' q_hkl
  std::vector<int> peak_s;
  double width = 0.0;          // the FWHM used
};
PowderPattern powder_pattern(const std::vector<Reflection>& classes, const PowderParams& p);

// Indexing of measured peak positions q_i (1/nm) with the s values a group allows (s <= smax):
// for each of the first allowed s for the first peak, assign every peak to the nearest allowed
// sqrt(s) (strictly increasing) and fit a by least squares, q_i = 2 pi sqrt(s_i) / a; the
// assignment with every relative residual <= tol and the smallest a wins (ties of a scaled
// lattice go to the smaller cell). Throws std::invalid_argument for fewer than 2 peaks and
// std::runtime_error naming the group when no assignment fits.
struct Indexing {
  std::string group;
  double lattice = 0.0;              // a, nm
  std::vector<int> s;                // per peak
  std::vector<double> q_fit;         // 2 pi sqrt(s_i) / a
  std::vector<double> residual;      // (q_i - q_fit_i) / q_i
  double rms_residual = 0.0;
};
Indexing index_peaks(const std::vector<double>& peaks, const SpaceGroup& g, int smax,
                     double tol = 0.01);

// The whole analysis that `cmcsurf scattering` writes (and a binding would return): density,
// transform, classes, space group, powder pattern and, with peaks, the indexing by the best
// group and by every consistent one (by_group: empty where none fits). Throws
// std::invalid_argument for a field without a phi = 1/2 surface, smax outside [0, (N/2-1)^2]
// (0: min(100, that)) or bad peaks; std::runtime_error when the best group indexes no
// assignment.
struct ScatteringParams {
  DensityParams density;
  int smax = 0;
  double absent_tol = 1e-6;
  PowderParams powder;
  std::vector<double> peaks;  // 1/nm; empty: no indexing
  double index_tol = 0.01;
};
struct ScatteringResult {
  int n = 0, smax = 0;
  double f000 = 0.0, interface_width = 0.0, symmetry_spread = 0.0;
  std::vector<Reflection> classes;
  SpaceGroupFit space_group;
  PowderPattern powder;
  bool indexed = false;
  Indexing indexing;  // lattice in the group's cell: times space_group.divisor for the box
  std::vector<std::pair<std::string, std::optional<Indexing>>> by_group;
  double density_seconds = 0, fft_seconds = 0, analysis_seconds = 0;
};
ScatteringResult scattering_analysis(const Field& phi, const ScatteringParams& p);

// scattering.json's keys (docs/science.md) of an analysis: what `cmcsurf scattering` writes
// and Python's cmcsurf.scattering returns (the command adds "source" and its load time).
nlohmann::json scattering_json(const ScatteringResult& r, const ScatteringParams& p);

}  // namespace cmcsurf
