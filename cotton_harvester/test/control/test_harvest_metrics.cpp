#include <gtest/gtest.h>

#include <unistd.h>

#include <fstream>
#include <sstream>

#include "cotton_harvester/control/harvest_metrics.h"

using namespace cotton_harvester::control;

// Table 2, first experiment: 18 bolls, 17 detected, 16 reached, 15 picked, 214 s, 2.4 m
// -> OV 1.12 cm/s, PR 0.07 bolls/s, CT 14.27 s, ASR 83.33 %, DP 94.44 %, MRR 88.89 %.
TEST(HarvestMetrics, ReproducesTableTwoRowOne) {
  HarvestCounts counts;
  counts.bolls_present = 18;
  counts.detected = 17;
  counts.reached = 16;
  counts.picked = 15;
  counts.time_s = 214.0;
  counts.distance_m = 2.4;
  const HarvestMetrics m = computeMetrics(counts);
  EXPECT_NEAR(m.operation_velocity_cm_s, 1.12, 0.005);
  EXPECT_NEAR(m.production_rate_bolls_s, 0.07, 0.005);
  ASSERT_TRUE(m.cycle_time_s);
  EXPECT_NEAR(*m.cycle_time_s, 14.27, 0.005);
  EXPECT_NEAR(*m.action_success_pct, 83.33, 0.005);
  EXPECT_NEAR(*m.detection_performance_pct, 94.44, 0.005);
  EXPECT_NEAR(*m.reaching_ratio_pct, 88.89, 0.005);
}

// Table 3, first field test: 84 bolls, 83 detected, 79 reached, 67 picked, 2700 s -> CT 40.30, ASR 79.76,
// DP 98.81, MRR 94.05, PR 0.02.
TEST(HarvestMetrics, ReproducesTableThreeRowOne) {
  HarvestCounts counts;
  counts.bolls_present = 84;
  counts.detected = 83;
  counts.reached = 79;
  counts.picked = 67;
  counts.time_s = 2700.0;
  counts.distance_m = 5.3;
  const HarvestMetrics m = computeMetrics(counts);
  EXPECT_NEAR(*m.cycle_time_s, 40.30, 0.005);
  EXPECT_NEAR(*m.action_success_pct, 79.76, 0.005);
  EXPECT_NEAR(*m.detection_performance_pct, 98.81, 0.005);
  EXPECT_NEAR(*m.reaching_ratio_pct, 94.05, 0.005);
  EXPECT_NEAR(m.production_rate_bolls_s, 0.02, 0.005);
  EXPECT_NEAR(m.operation_velocity_cm_s, 0.196, 0.001);  // the table rounds to 0.20
}

TEST(HarvestMetrics, UnknownTruthAndEmptyRuns) {
  HarvestCounts counts;  // nothing happened
  HarvestMetrics m = computeMetrics(counts);
  EXPECT_FALSE(m.cycle_time_s);
  EXPECT_FALSE(m.action_success_pct);
  EXPECT_DOUBLE_EQ(m.operation_velocity_cm_s, 0.0);
  counts.detected = 10;  // truth unknown: ratios against the bolls detected
  counts.picked = 5;
  counts.reached = 8;
  counts.time_s = 100.0;
  m = computeMetrics(counts);
  EXPECT_DOUBLE_EQ(*m.action_success_pct, 50.0);
  EXPECT_DOUBLE_EQ(*m.detection_performance_pct, 100.0);
  EXPECT_DOUBLE_EQ(*m.reaching_ratio_pct, 80.0);
}

TEST(HarvestMetrics, CsvHeaderOnceThenRows) {
  const std::string path = "/tmp/cotton_metrics_test_" + std::to_string(::getpid()) + ".csv";
  ::unlink(path.c_str());
  HarvestCounts counts;
  counts.bolls_present = 18;
  counts.detected = 18;
  counts.reached = 17;
  counts.picked = 16;
  counts.time_s = 343.0;
  counts.distance_m = 2.4;
  std::string error;
  ASSERT_TRUE(appendCsv(path, "run1", counts, computeMetrics(counts), &error)) << error;
  ASSERT_TRUE(appendCsv(path, "run2", counts, computeMetrics(counts), &error)) << error;
  std::ifstream in(path);
  std::string header, row1, row2, extra;
  std::getline(in, header);
  std::getline(in, row1);
  std::getline(in, row2);
  EXPECT_FALSE(std::getline(in, extra));
  EXPECT_EQ(header, csvHeader());
  // Table 2 row 2: CT 343/16 = 21.4375 (the paper prints 21.43), ASR 88.89, DP 100.00, MRR 94.44.
  EXPECT_EQ(row1, "run1,18,18,17,16,0,0,343.00,2.400,0.70,0.0466,21.44,88.89,100.00,94.44");
  EXPECT_EQ(row2.substr(0, 5), "run2,");
  ::unlink(path.c_str());
  EXPECT_FALSE(appendCsv("/nonexistent/dir/m.csv", "x", counts, computeMetrics(counts), &error));
  EXPECT_NE(error.find("/nonexistent/dir/m.csv"), std::string::npos);
}
