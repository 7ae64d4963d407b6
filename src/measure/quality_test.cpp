#include "measure/quality.h"

#include <gtest/gtest.h>

#include <omp.h>

#include <cmath>
#include <cstring>

namespace cmcsurf {
namespace {

TEST(Quality, SummaryIsTheAreaWeightedMeanAndSpread) {
  const std::vector<CurvatureSample> s = {{1.0, 1.0}, {2.0, 3.0}};
  const CurvatureDistribution d = summarize(s);
  EXPECT_DOUBLE_EQ(d.mean, 1.75);
  EXPECT_DOUBLE_EQ(d.weight, 4.0);
  EXPECT_NEAR(d.std, std::sqrt((0.75 * 0.75 + 3 * 0.25 * 0.25) / 4.0), 1e-15);
  EXPECT_EQ(d.samples, 2u);
  EXPECT_EQ(summarize({}).weight, 0.0);
}

TEST(Quality, SpreadHasNoCancellationForANearlyConstantH) {
  std::vector<CurvatureSample> s;
  for (int i = 0; i < 1000; ++i) s.push_back({1e4 + (i % 2 ? 1e-6 : -1e-6), 1.0});
  EXPECT_NEAR(summarize(s).std, 1e-6, 1e-12);
}

// The distributions and histograms run side by side on two threads; each is still one pass in
// sample order, so one thread gives the same bits.
TEST(Quality, DistributionsAtOneAndTwoThreadsAreTheSameBits) {
  std::vector<CurvatureSample> relaxed, nodal;
  for (int i = 0; i < 5000; ++i) {
    relaxed.push_back({1.0 + 0.01 * std::sin(0.37 * i), 1e-3 * (1 + i % 7), 0.5 * std::cos(i)});
    nodal.push_back({1.0 + 0.3 * std::sin(0.11 * i), 1e-3 * (1 + i % 5), std::sin(0.5 * i)});
  }
  const int saved = omp_get_max_threads();
  CmcQuality q[2];
  for (int t = 0; t < 2; ++t) {
    omp_set_num_threads(t + 1);
    fill_distributions(q[t], relaxed, &nodal);
  }
  omp_set_num_threads(saved);
  const auto same = [](const std::vector<double>& a, const std::vector<double>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
  };
  EXPECT_EQ(std::memcmp(&q[0].relaxed, &q[1].relaxed, sizeof(CurvatureDistribution)), 0);
  EXPECT_EQ(std::memcmp(&q[0].nodal, &q[1].nodal, sizeof(CurvatureDistribution)), 0);
  EXPECT_TRUE(same(q[0].edges, q[1].edges));
  EXPECT_TRUE(same(q[0].relaxed_hist, q[1].relaxed_hist));
  EXPECT_TRUE(same(q[0].nodal_hist, q[1].nodal_hist));
  EXPECT_TRUE(same(q[0].relaxed_h_own.fraction, q[1].relaxed_h_own.fraction));
  EXPECT_TRUE(same(q[0].relaxed_k_own.fraction, q[1].relaxed_k_own.fraction));
  EXPECT_TRUE(same(q[0].relaxed_k_own.edges, q[1].relaxed_k_own.edges));
  EXPECT_GT(q[0].nodal.std, 10 * q[0].relaxed.std);  // two different distributions
}

TEST(Quality, HistogramIsAFractionOfArea) {
  const std::vector<CurvatureSample> s = {{-1.0, 1.0}, {0.1, 2.0}, {0.2, 1.0}, {9.0, 4.0}};
  const std::vector<double> h = curvature_histogram(s, -0.5, 0.5, 4);
  ASSERT_EQ(h.size(), 4u);
  EXPECT_DOUBLE_EQ(h[0], 1.0 / 8.0);  // -1 clipped into the first bin
  EXPECT_DOUBLE_EQ(h[2], 3.0 / 8.0);
  EXPECT_DOUBLE_EQ(h[3], 4.0 / 8.0);  // 9 clipped into the last bin
  EXPECT_THROW(curvature_histogram(s, 1.0, 1.0, 4), std::invalid_argument);
}

// A relaxed surface's narrow H (here 2 + 0.01 sin t: std 0.01/sqrt2, range +-1.41 std) on its own
// range mean +- 4 std: 35 % of the 48 bins carry it, against a few on a range it shares with
// a wide nodal distribution; K likewise on its own.
TEST(Quality, OwnRangeHistogramsSpreadANarrowDistribution) {
  std::vector<CurvatureSample> s;
  for (int i = 0; i < 4000; ++i) {
    const double t = 2 * 3.141592653589793 * (i + 0.5) / 4000;
    s.push_back({2.0 + 0.01 * std::sin(t), 1.0, -30.0 + 5.0 * std::cos(t)});
  }
  const OwnRangeHistogram h = own_range_histogram(s, false, kHistogramBins);
  EXPECT_NEAR(h.mean, 2.0, 1e-12);
  EXPECT_NEAR(h.std, 0.01 / std::sqrt(2.0), 1e-9);
  ASSERT_EQ(h.edges.size(), std::size_t(kHistogramBins + 1));
  EXPECT_NEAR(h.edges.front(), 2.0 - 4 * h.std, 1e-12);
  EXPECT_NEAR(h.edges.back(), 2.0 + 4 * h.std, 1e-12);
  int used = 0;
  double sum = 0.0;
  for (double f : h.fraction) {
    used += f > 0.0;
    sum += f;
  }
  EXPECT_NEAR(sum, 1.0, 1e-12);
  EXPECT_GE(used, 16);  // 48 x 2 x 1.41 / 8 = 17 bins, less one at each end
  const OwnRangeHistogram k = own_range_histogram(s, true, kHistogramBins);
  EXPECT_NEAR(k.mean, -30.0, 1e-9);
  EXPECT_NEAR(k.std, 5.0 / std::sqrt(2.0), 1e-9);
  // A constant H (a ball's) still gets a range and all of its area in one bin.
  const std::vector<CurvatureSample> ball = {{5.0, 1.0}, {5.0, 3.0}};
  const OwnRangeHistogram b = own_range_histogram(ball, false, 4);
  EXPECT_LT(b.edges.front(), 5.0);
  EXPECT_GT(b.edges.back(), 5.0);
  EXPECT_DOUBLE_EQ(b.fraction[2], 1.0);
}

TEST(Quality, DistributionsShareOneHistogramRange) {
  const std::vector<CurvatureSample> relaxed = {{1.0, 1.0}, {1.01, 1.0}};
  const std::vector<CurvatureSample> nodal = {{0.0, 1.0}, {3.0, 1.0}};
  CmcQuality q;
  fill_distributions(q, relaxed, &nodal);
  EXPECT_TRUE(q.has_nodal);
  ASSERT_EQ(q.edges.size(), std::size_t(kHistogramBins + 1));
  EXPECT_LE(q.edges.front(), q.nodal.mean - 4 * q.nodal.std + 1e-12);
  EXPECT_GE(q.edges.back(), q.nodal.mean + 4 * q.nodal.std - 1e-12);
  double total = 0.0;
  for (double v : q.relaxed_hist) total += v;
  EXPECT_NEAR(total, 1.0, 1e-12);
  CmcQuality alone;
  fill_distributions(alone, relaxed, nullptr);
  EXPECT_FALSE(alone.has_nodal);
  EXPECT_TRUE(alone.nodal_hist.empty());
}

}  // namespace
}  // namespace cmcsurf
