#include "measure/quality.h"

#include <gtest/gtest.h>

#include <cmath>

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

TEST(Quality, HistogramIsAFractionOfArea) {
  const std::vector<CurvatureSample> s = {{-1.0, 1.0}, {0.1, 2.0}, {0.2, 1.0}, {9.0, 4.0}};
  const std::vector<double> h = curvature_histogram(s, -0.5, 0.5, 4);
  ASSERT_EQ(h.size(), 4u);
  EXPECT_DOUBLE_EQ(h[0], 1.0 / 8.0);  // -1 clipped into the first bin
  EXPECT_DOUBLE_EQ(h[2], 3.0 / 8.0);
  EXPECT_DOUBLE_EQ(h[3], 4.0 / 8.0);  // 9 clipped into the last bin
  EXPECT_THROW(curvature_histogram(s, 1.0, 1.0, 4), std::invalid_argument);
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
