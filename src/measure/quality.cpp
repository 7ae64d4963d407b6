#include "measure/quality.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace cmcsurf {

CurvatureDistribution summarize(const std::vector<CurvatureSample>& samples) {
  CurvatureDistribution d;
  double sw = 0.0, swh = 0.0;
  for (const CurvatureSample& s : samples) {
    sw += s.w;
    swh += s.w * s.h;
  }
  d.weight = sw;
  d.samples = samples.size();
  if (sw <= 0.0) return d;
  d.mean = swh / sw;
  double var = 0.0;  // two passes: no cancellation when the spread is small
  for (const CurvatureSample& s : samples) var += s.w * (s.h - d.mean) * (s.h - d.mean);
  d.std = std::sqrt(var / sw);
  return d;
}

std::vector<double> curvature_histogram(const std::vector<CurvatureSample>& samples, double lo,
                                        double hi, int bins) {
  if (bins < 1 || !(hi > lo)) throw std::invalid_argument("curvature_histogram: bad range");
  std::vector<double> hist(bins, 0.0);
  double total = 0.0;
  for (const CurvatureSample& s : samples) {
    const int b = std::clamp(int(std::floor((s.h - lo) / (hi - lo) * bins)), 0, bins - 1);
    hist[b] += s.w;
    total += s.w;
  }
  if (total > 0.0)
    for (double& v : hist) v /= total;
  return hist;
}

void fill_distributions(CmcQuality& q, const std::vector<CurvatureSample>& relaxed,
                        const std::vector<CurvatureSample>* nodal) {
  q.relaxed = summarize(relaxed);
  q.has_nodal = nodal != nullptr;
  if (nodal) q.nodal = summarize(*nodal);
  double lo = q.relaxed.mean - 4.0 * q.relaxed.std, hi = q.relaxed.mean + 4.0 * q.relaxed.std;
  if (nodal) {
    lo = std::min(lo, q.nodal.mean - 4.0 * q.nodal.std);
    hi = std::max(hi, q.nodal.mean + 4.0 * q.nodal.std);
  }
  if (!(hi - lo > 1e-9)) {
    lo -= 1.0;
    hi += 1.0;
  }
  q.edges.resize(kHistogramBins + 1);
  for (int b = 0; b <= kHistogramBins; ++b) q.edges[b] = lo + (hi - lo) * b / kHistogramBins;
  q.relaxed_hist = curvature_histogram(relaxed, lo, hi, kHistogramBins);
  if (nodal) q.nodal_hist = curvature_histogram(*nodal, lo, hi, kHistogramBins);
}

}  // namespace cmcsurf
