// The benchmarks' statistics: the nearest-rank percentile convention, mean, rms, max, and no samples.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "thorvald_common/bench_statistics.h"

namespace tc = thorvald_common;

TEST(BenchStatistics, PercentileIsTheSampleAtTheRoundedRank) {
  const std::vector<double> v = {5.0, 1.0, 4.0, 2.0, 3.0};  // unsorted on purpose
  EXPECT_DOUBLE_EQ(tc::percentile(v, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(tc::percentile(v, 0.5), 3.0);  // index 2
  EXPECT_DOUBLE_EQ(tc::percentile(v, 1.0), 5.0);
  EXPECT_DOUBLE_EQ(tc::percentile(v, 0.625), 4.0);  // 0.625 * 4 = 2.5: halves round up, index 3
  EXPECT_DOUBLE_EQ(tc::percentile(v, 0.6), 3.0);    // 2.4 -> index 2
  EXPECT_DOUBLE_EQ(tc::percentile(v, 2.0), 5.0);    // clamped
  EXPECT_DOUBLE_EQ(tc::percentile(v, -1.0), 1.0);
  EXPECT_DOUBLE_EQ(v[0], 5.0);  // the caller's order is untouched
}

TEST(BenchStatistics, PercentileOfOneHundredSamples) {
  std::vector<double> v;
  for (int i = 1; i <= 100; ++i) v.push_back(i);
  EXPECT_DOUBLE_EQ(tc::percentile(v, 0.95), 95.0);  // 0.95 * 99 = 94.05 -> index 94
  EXPECT_DOUBLE_EQ(tc::percentile(v, 0.99), 99.0);  // 98.01 -> index 98
  EXPECT_DOUBLE_EQ(tc::percentile(v, 0.5), 51.0);   // 49.5 -> index 50
}

TEST(BenchStatistics, MeanRmsMax) {
  const std::vector<double> v = {3.0, -4.0};
  EXPECT_DOUBLE_EQ(tc::mean(v), -0.5);
  EXPECT_DOUBLE_EQ(tc::rms(v), std::sqrt(12.5));
  EXPECT_DOUBLE_EQ(tc::max(v), 3.0);
}

TEST(BenchStatistics, NoSamplesGiveZero) {
  const std::vector<double> none;
  EXPECT_EQ(tc::percentile(none, 0.5), 0.0);
  EXPECT_EQ(tc::mean(none), 0.0);
  EXPECT_EQ(tc::rms(none), 0.0);
  EXPECT_EQ(tc::max(none), 0.0);
}
