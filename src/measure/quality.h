// How far a surface is from constant mean curvature, and how far a nodal scaffold is from the
// relaxed CMC surface: the distribution of local mean curvature, the iso-surface area, and the
// nodal surface at a prescribed volume fraction (docs/families.md).
#pragma once

#include <string>
#include <vector>

#include "grid/field.h"

namespace cmcsurf {

// Local mean curvature H = -kappa/2 at one cell, kappa of Appendix B, and its area weight
// w = |grad_d phi|^2 (fourth-order gradient, the integrand of the area estimator).
struct CurvatureSample {
  double h = 0.0;
  double w = 0.0;
};

// Samples at the cells with |phi - 1/2| < band (band >= 0.5 keeps every cell, and then the
// weighted mean equals mean_curvature(phi) of Appendix B). Needs ghost >= 2; refreshes the halo.
std::vector<CurvatureSample> local_mean_curvature(Field& phi, double band);

struct CurvatureDistribution {
  double mean = 0.0;  // sum(w H) / sum(w)
  double std = 0.0;   // sqrt(sum(w (H - mean)^2) / sum(w))
  double weight = 0.0;
  std::size_t cells = 0;
};
CurvatureDistribution summarize(const std::vector<CurvatureSample>& samples);

// Area of the iso-surface phi = level by marching tetrahedra: each cube between eight cell
// centres (periodic wrap) is cut into six tetrahedra around its main diagonal, phi is linear on
// each, and the areas of the planar pieces are summed. Needs ghost >= 1; refreshes the halo.
double iso_area(Field& phi, double level = 0.5);

// The nodal surface {F = c} of a nodal formula (Eqs. 7-9 with their +0.5, or expr:) as a phase
// field with the equilibrium profile phi = q(d / (2 sqrt2 eps)), q(t) = (1 + tanh t)/2, and
// d = (F - c)/|grad F| the first-order signed distance (grad F by central differences of the
// formula). The level c is the one at which a fraction alpha of the cells has F > c (hence
// phi > 1/2), the volume_fraction() of the field. Ghost 2.
struct NodalPhaseField {
  Field phi;
  double level = 0.0;  // c
};
NodalPhaseField nodal_phase_field(const std::string& surface, double alpha, int n, double epsilon);

// Weighted histogram of H over [lo, hi) in `bins` equal bins; values outside go to the end bins.
// Returns the weight fraction per bin (sums to 1 unless there are no samples).
std::vector<double> curvature_histogram(const std::vector<CurvatureSample>& samples, double lo,
                                        double hi, int bins);

// Cells with |phi - 1/2| < kQualityBand enter the curvature distributions of a run.
inline constexpr double kQualityBand = 0.3;
inline constexpr int kHistogramBins = 48;

// CMC quality of a relaxed field and of the nodal surface at the same volume fraction.
struct CmcQuality {
  CurvatureDistribution relaxed;
  double area_iso = 0.0;  // iso_area(relaxed phi)
  bool has_nodal = false;
  double nodal_level = 0.0;
  double nodal_area = 0.0;  // diffuse-interface area (Appendix B) at the run's epsilon
  double nodal_area_tanh = 0.0;  // the same of the sampled tanh profile, before any relaxation
  int nodal_relax_steps = 0;     // steps taken before nodal_area was measured
  double nodal_area_iso = 0.0;
  double nodal_mean_curvature = 0.0;  // Appendix B surface average
  CurvatureDistribution nodal;
  double nodal_volume_fraction = 0.0;
  // Histogram: bin edges (bins + 1) and weight fractions of each distribution.
  std::vector<double> edges;
  std::vector<double> relaxed_hist, nodal_hist;
};

// Fills a CmcQuality from the final field of a run (ghost >= 2) and, when the surface has a
// nodal formula, the nodal phase field at the same volume fraction (else nullptr). Both are
// measured with the same estimators at the same epsilon. The pipeline's measure_cmc_quality
// (pipeline/sweep.h) builds and briefly relaxes the nodal field first.
CmcQuality compare_with_nodal(Field& relaxed, Field* nodal, double nodal_level, double epsilon);

}  // namespace cmcsurf
