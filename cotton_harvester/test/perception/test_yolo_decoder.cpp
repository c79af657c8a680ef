#include <cmath>

#include <gtest/gtest.h>

#include "cotton_harvester/perception/yolo_decoder.h"

using namespace cotton_harvester::perception;

namespace {

/// One yolo-layer row: [cx, cy, w, h, objectness, class scores...].
cv::Mat rows(std::initializer_list<std::vector<float>> values) {
  cv::Mat m(0, static_cast<int>(values.begin()->size()), CV_32F);
  for (const std::vector<float>& row : values) m.push_back(cv::Mat(row).reshape(1, 1));
  return m;
}

}  // namespace

TEST(YoloDecoder, ScalesBoxesToTheImage) {
  const cv::Mat out = rows({{0.5f, 0.25f, 0.1f, 0.2f, 0.9f, 0.8f, 0.1f}});
  NetInputTransform t;
  t.scale_x = 1280;
  t.scale_y = 720;
  const auto bolls = decodeYoloOutputs({out}, t, {1280, 720}, YoloDecodeParams{});
  ASSERT_EQ(bolls.size(), 1u);
  EXPECT_NEAR(bolls[0].centroid.x, 640.0, 1e-3);
  EXPECT_NEAR(bolls[0].centroid.y, 180.0, 1e-3);
  EXPECT_NEAR(bolls[0].box.width, 128.0, 1e-3);
  EXPECT_NEAR(bolls[0].box.height, 144.0, 1e-3);
  EXPECT_NEAR(bolls[0].confidence, 0.8, 1e-6);
}

TEST(YoloDecoder, ThresholdClassAndNonMaximumSuppression) {
  // Two overlapping boxes of class 0 (IoU 0.75), one weak box, one box of class 1 only.
  const cv::Mat out = rows({{0.50f, 0.50f, 0.2f, 0.2f, 0.9f, 0.85f, 0.0f},
                            {0.52f, 0.51f, 0.2f, 0.2f, 0.9f, 0.70f, 0.0f},
                            {0.10f, 0.10f, 0.1f, 0.1f, 0.9f, 0.30f, 0.0f},
                            {0.80f, 0.80f, 0.1f, 0.1f, 0.9f, 0.00f, 0.95f}});
  NetInputTransform t;
  t.scale_x = t.scale_y = 100;
  YoloDecodeParams p;
  p.confidence_threshold = 0.5;
  p.nms_threshold = 0.4;
  auto bolls = decodeYoloOutputs({out}, t, {100, 100}, p);
  ASSERT_EQ(bolls.size(), 1u);
  EXPECT_NEAR(bolls[0].confidence, 0.85, 1e-6);
  EXPECT_NEAR(bolls[0].centroid.x, 50.0, 1e-3);

  p.nms_threshold = 0.9;  // overlap below 0.9: both kept
  EXPECT_EQ(decodeYoloOutputs({out}, t, {100, 100}, p).size(), 2u);

  p.class_id = -1;  // any class: the class-1 box counts too
  EXPECT_EQ(decodeYoloOutputs({out}, t, {100, 100}, p).size(), 3u);
  p.class_id = 5;  // no such class
  EXPECT_TRUE(decodeYoloOutputs({out}, t, {100, 100}, p).empty());
}

TEST(YoloDecoder, ClipsToTheImageAndSkipsBadRows) {
  const float nan = std::nanf("");
  const cv::Mat out = rows({{0.98f, 0.5f, 0.2f, 0.2f, 0.9f, 0.9f},
                            {nan, 0.5f, 0.2f, 0.2f, 0.9f, 0.9f},
                            {0.5f, 0.5f, 0.2f, 0.2f, 0.9f, nan},
                            {1.5f, 1.5f, 0.1f, 0.1f, 0.9f, 0.9f}});  // entirely outside
  NetInputTransform t;
  t.scale_x = t.scale_y = 100;
  const auto bolls = decodeYoloOutputs({out, cv::Mat(), cv::Mat(3, 3, CV_32F)}, t, {100, 100}, YoloDecodeParams{});
  ASSERT_EQ(bolls.size(), 1u);
  EXPECT_NEAR(bolls[0].box.x, 88.0, 1e-3);
  EXPECT_NEAR(bolls[0].box.width, 12.0, 1e-3);  // 88..100
  EXPECT_NEAR(bolls[0].centroid.x, 94.0, 1e-3);
}
