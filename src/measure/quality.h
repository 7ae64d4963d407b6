// How far a surface is from constant mean curvature, and how far the nodal approximation at the
// same volume fraction is from the CMC surface: distributions of the local mean curvature on
// the surface (measure/sharp_surface.h) and their common histogram (docs/families.md).
#pragma once

#include <cstddef>
#include <vector>

#include "measure/sharp_surface.h"
#include "parallel/decomposition.h"

namespace cmcsurf {

struct CurvatureDistribution {
  double mean = 0.0;    // sum(w H) / sum(w)
  double std = 0.0;     // sqrt(sum(w (H - mean)^2) / sum(w))
  double weight = 0.0;  // sum(w): the area
  std::size_t samples = 0;
};
// d: the processes whose samples together make the surface (each passes its own; every process
// gets the same result), or null for samples of a whole grid.
CurvatureDistribution summarize(const std::vector<CurvatureSample>& samples,
                                const Decomposition* d = nullptr);

// Weighted histogram of H over [lo, hi) in `bins` equal bins; values outside go to the end bins.
// Returns the weight fraction per bin (sums to 1 unless there are no samples).
std::vector<double> curvature_histogram(const std::vector<CurvatureSample>& samples, double lo,
                                        double hi, int bins, const Decomposition* d = nullptr);

inline constexpr int kHistogramBins = 48;

// The area-weighted distribution of the local H (or, gaussian, of K) on one surface, binned on
// that surface's own range, mean +- 4 std of the quantity (values outside go to the end bins),
// so that a relaxed surface's narrow H distribution spreads over the bins instead of falling
// into the few that the nodal surface's wide one leaves it.
struct OwnRangeHistogram {
  std::vector<double> edges;     // bins + 1
  std::vector<double> fraction;  // of the area per bin
  double mean = 0.0, std = 0.0;
};
OwnRangeHistogram own_range_histogram(const std::vector<CurvatureSample>& samples,
                                      bool gaussian, int bins, const Decomposition* d = nullptr);

// CMC quality of a relaxed surface and of the nodal surface at the same volume fraction, both
// measured by the sharp estimators.
struct CmcQuality {
  CurvatureDistribution relaxed;
  bool has_nodal = false;
  double nodal_level = 0.0;            // c of {F + 1/2 > c} (surfaces/nodal_level.h)
  double nodal_volume_fraction = 0.0;  // sharp
  double nodal_area = 0.0;             // sharp
  double nodal_mean_curvature = 0.0;   // sharp surface average
  CurvatureDistribution nodal;
  // Appendix B's estimators on the nodal surface's tanh-profile phase field at the run's epsilon.
  double nodal_area_diffuse = 0.0;
  double nodal_mean_curvature_diffuse = 0.0;
  // Histogram: bin edges (bins + 1) over mean +- 4 std of both distributions, and the area
  // fraction of each distribution per bin.
  std::vector<double> edges;
  std::vector<double> relaxed_hist, nodal_hist;
  // The relaxed surface's H and K each on its own range (curvature_distribution.csv).
  OwnRangeHistogram relaxed_h_own, relaxed_k_own;
  double seconds = 0.0;  // wall time of the whole comparison (pipeline/sweep.h)
};

// Fills the distributions and the histogram of a CmcQuality from the local samples of the
// relaxed surface and, if given, of the nodal surface (has_nodal is set then).
void fill_distributions(CmcQuality& q, const std::vector<CurvatureSample>& relaxed,
                        const std::vector<CurvatureSample>* nodal,
                        const Decomposition* d = nullptr);

}  // namespace cmcsurf
