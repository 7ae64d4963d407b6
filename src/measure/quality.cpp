#include "measure/quality.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "parallel/first_exception.h"

namespace cmcsurf {

CurvatureDistribution summarize(const std::vector<CurvatureSample>& samples,
                                const Decomposition* d) {
  CurvatureDistribution out;
  double sums[3] = {0.0, 0.0, double(samples.size())};  // sw, swh, count
  for (const CurvatureSample& s : samples) {
    sums[0] += s.w;
    sums[1] += s.w * s.h;
  }
  if (d) d->sum(sums, 3);
  const double sw = sums[0];
  out.weight = sw;
  out.samples = std::size_t(sums[2]);
  if (sw <= 0.0) return out;
  out.mean = sums[1] / sw;
  double var = 0.0;  // two passes: no cancellation when the spread is small
  for (const CurvatureSample& s : samples) var += s.w * (s.h - out.mean) * (s.h - out.mean);
  if (d) var = d->sum(var);
  out.std = std::sqrt(var / sw);
  return out;
}

namespace {

double value_of(const CurvatureSample& s, bool gaussian) { return gaussian ? s.k : s.h; }

std::vector<double> histogram_of(const std::vector<CurvatureSample>& samples, bool gaussian,
                                 double lo, double hi, int bins, const Decomposition* d) {
  if (bins < 1 || !(hi > lo)) throw std::invalid_argument("curvature_histogram: bad range");
  std::vector<double> hist(bins, 0.0);
  double total = 0.0;
  for (const CurvatureSample& s : samples) {
    const double v = value_of(s, gaussian);
    const int b = std::clamp(int(std::floor((v - lo) / (hi - lo) * bins)), 0, bins - 1);
    hist[b] += s.w;
    total += s.w;
  }
  if (d) {
    d->sum(hist.data(), bins);
    total = d->sum(total);
  }
  if (total > 0.0)
    for (double& v : hist) v /= total;
  return hist;
}

}  // namespace

std::vector<double> curvature_histogram(const std::vector<CurvatureSample>& samples, double lo,
                                        double hi, int bins, const Decomposition* d) {
  return histogram_of(samples, false, lo, hi, bins, d);
}

OwnRangeHistogram own_range_histogram(const std::vector<CurvatureSample>& samples,
                                      bool gaussian, int bins, const Decomposition* d) {
  OwnRangeHistogram out;
  double sums[2] = {0.0, 0.0};  // sw, sw v
  for (const CurvatureSample& s : samples) {
    sums[0] += s.w;
    sums[1] += s.w * value_of(s, gaussian);
  }
  if (d) d->sum(sums, 2);
  if (sums[0] > 0.0) {
    out.mean = sums[1] / sums[0];
    double var = 0.0;  // two passes, as in summarize
    for (const CurvatureSample& s : samples) {
      const double e = value_of(s, gaussian) - out.mean;
      var += s.w * e * e;
    }
    if (d) var = d->sum(var);
    out.std = std::sqrt(var / sums[0]);
  }
  double lo = out.mean - 4.0 * out.std, hi = out.mean + 4.0 * out.std;
  // A constant quantity (a ball's H) or no samples: a range of its own scale around it.
  const double floor = 1e-6 * (1.0 + std::abs(out.mean));
  if (!(hi - lo > floor)) {
    lo = out.mean - floor;
    hi = out.mean + floor;
  }
  out.edges.resize(bins + 1);
  for (int b = 0; b <= bins; ++b) out.edges[b] = lo + (hi - lo) * b / bins;
  out.fraction = histogram_of(samples, gaussian, lo, hi, bins, d);
  return out;
}

void fill_distributions(CmcQuality& q, const std::vector<CurvatureSample>& relaxed,
                        const std::vector<CurvatureSample>* nodal, const Decomposition* d) {
  // Each distribution and histogram is a serial pass in sample order (the sums' order is the
  // result's bits); the independent ones run side by side, on a whole grid (a decomposed one
  // reduces over the processes, in one order on every process: one at a time).
  const bool side_by_side = d == nullptr && omp_get_max_threads() > 1;
  FirstException errors;
#pragma omp parallel for schedule(static, 1) num_threads(2) if (side_by_side && nodal)
  for (int task = 0; task < 2; ++task)
    errors.run([&] {
      if (task == 0) q.relaxed = summarize(relaxed, d);
      if (task == 1 && nodal) q.nodal = summarize(*nodal, d);
    });
  errors.rethrow();
  q.has_nodal = nodal != nullptr;
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
#pragma omp parallel for schedule(dynamic, 1) if (side_by_side)
  for (int task = 0; task < 4; ++task)
    errors.run([&] {
      if (task == 0) q.relaxed_hist = curvature_histogram(relaxed, lo, hi, kHistogramBins, d);
      if (task == 1 && nodal)
        q.nodal_hist = curvature_histogram(*nodal, lo, hi, kHistogramBins, d);
      if (task == 2) q.relaxed_h_own = own_range_histogram(relaxed, false, kHistogramBins, d);
      if (task == 3) q.relaxed_k_own = own_range_histogram(relaxed, true, kHistogramBins, d);
    });
  errors.rethrow();
}

}  // namespace cmcsurf
