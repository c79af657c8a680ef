#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include <unistd.h>

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "cotton_harvester/perception/darknet_boll_detector.h"
#include "cotton_harvester/testing/darknet_net_writer.h"

using namespace cotton_harvester::perception;
namespace fs = std::filesystem;

namespace {

double sigmoid(double x) { return 1.0 / (1.0 + std::exp(-x)); }

/// A network whose answer is known in closed form. Input 128x128; a 1x1 convolution turns RGB into grey
/// g in [0, 1]; five 2x2 max-pools give a 4x4 grid of 32-pixel cells holding the brightest grey of each cell;
/// a 1x1 convolution gives per anchor: x, y, w, h logits 0 (cell centre, anchor size), objectness logit
/// 20 g - 18 (anchor 0) or 20 g - 19 (anchor 1), class logit 1. Anchors 32x32 and 48x48 px.
DarknetNet knownNet() {
  DarknetNet net;
  net.width = net.height = 128;
  net.sections.push_back(
      {"convolutional", {{"filters", "1"}, {"size", "1"}, {"stride", "1"}, {"activation", "linear"}}});
  ConvolutionWeights grey;
  grey.biases = {0.0f};
  grey.weights = {1.0f / 3, 1.0f / 3, 1.0f / 3};
  net.convolutions.push_back(grey);
  for (int i = 0; i < 5; ++i) net.sections.push_back({"maxpool", {{"size", "2"}, {"stride", "2"}}});
  net.sections.push_back(
      {"convolutional", {{"filters", "12"}, {"size", "1"}, {"stride", "1"}, {"activation", "linear"}}});
  ConvolutionWeights head;
  head.biases.assign(12, 0.0f);
  head.weights.assign(12, 0.0f);  // 12 filters x 1 input x 1 x 1
  for (int anchor = 0; anchor < 2; ++anchor) {
    head.weights[anchor * 6 + 4] = 20.0f;
    head.biases[anchor * 6 + 4] = anchor == 0 ? -18.0f : -19.0f;
    head.biases[anchor * 6 + 5] = 1.0f;
  }
  net.convolutions.push_back(head);
  net.sections.push_back({"yolo", {{"mask", "0,1"}, {"anchors", "32,32, 48,48"}, {"classes", "1"}, {"num", "2"}}});
  return net;
}

class DarknetBollDetectorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("cotton_harvester_darknet_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    params_.cfg_path = (dir_ / "known.cfg").string();
    params_.weights_path = (dir_ / "known.weights").string();
    params_.input_width = params_.input_height = 128;
    writeDarknetFiles(knownNet(), params_.cfg_path, params_.weights_path);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  DarknetParams params_;
};

/// Black image with white 40x40 squares centred in the given 64-px cells (row, column) of a 256x256 image.
cv::Mat squares(const std::vector<cv::Point>& cells) {
  cv::Mat image(256, 256, CV_8UC3, cv::Scalar(0, 0, 0));
  for (const cv::Point& cell : cells)
    cv::rectangle(image, cv::Rect(cell.x * 64 + 12, cell.y * 64 + 12, 40, 40), cv::Scalar(255, 255, 255), cv::FILLED);
  return image;
}

}  // namespace

TEST_F(DarknetBollDetectorTest, LoadsAndDecodesTheGeneratedNetwork) {
  DarknetBollDetector detector(params_);
  const auto bolls = detector.detect(squares({{1, 1}, {3, 2}}), cv::Mat());
  ASSERT_EQ(bolls.size(), 2u);
  // Image 256 -> input 128: one cell is 64 image px; anchor 0 (32 input px) is 64 image px wide.
  const double expected_confidence = sigmoid(20.0 - 18.0) * sigmoid(1.0);  // objectness x class probability
  std::set<std::pair<int, int>> centres;
  for (const BollDetection& b : bolls) {
    centres.insert({static_cast<int>(std::lround(b.centroid.x)), static_cast<int>(std::lround(b.centroid.y))});
    EXPECT_NEAR(b.box.width, 64.0, 0.5);
    EXPECT_NEAR(b.box.height, 64.0, 0.5);
    EXPECT_NEAR(b.confidence, expected_confidence, 1e-3);
  }
  EXPECT_EQ(centres, (std::set<std::pair<int, int>>{{96, 96}, {224, 160}}));
  // The raw output holds a row per cell and anchor: 4 x 4 x 2, 5 + 1 columns.
  ASSERT_EQ(detector.lastOutputs().size(), 1u);
  EXPECT_EQ(detector.lastOutputs()[0].rows, 32);
  EXPECT_EQ(detector.lastOutputs()[0].cols, 6);
}

TEST_F(DarknetBollDetectorTest, NmsThresholdDecidesWhetherTheSecondAnchorSurvives) {
  // Anchor 1 scores sigmoid(1) x sigmoid(1) = 0.53 > 0.5; its 48 px box overlaps anchor 0's 32 px box with
  // IoU (32/48)^2 = 0.44.
  params_.decode.nms_threshold = 0.5;
  DarknetBollDetector loose(params_);
  const auto both = loose.detect(squares({{1, 1}}), cv::Mat());
  ASSERT_EQ(both.size(), 2u);
  params_.decode.nms_threshold = 0.4;
  DarknetBollDetector strict(params_);
  EXPECT_EQ(strict.detect(squares({{1, 1}}), cv::Mat()).size(), 1u);
  params_.decode.confidence_threshold = 0.7;  // above both scores
  DarknetBollDetector none(params_);
  EXPECT_TRUE(none.detect(squares({{1, 1}}), cv::Mat()).empty());
}

TEST_F(DarknetBollDetectorTest, NoInterpolationKeepsImagePixels) {
  params_.resize = InputResize::kNone;
  DarknetBollDetector detector(params_);
  cv::Mat image(100, 100, CV_8UC3, cv::Scalar(0, 0, 0));
  cv::rectangle(image, cv::Rect(40, 70, 16, 16), cv::Scalar(255, 255, 255), cv::FILLED);  // cell (row 2, col 1)
  const auto bolls = detector.detect(image, cv::Mat());
  ASSERT_EQ(bolls.size(), 1u);
  EXPECT_NEAR(bolls[0].centroid.x, 48.0, 0.5);
  EXPECT_NEAR(bolls[0].centroid.y, 80.0, 0.5);
  EXPECT_NEAR(bolls[0].box.width, 32.0, 0.5);
  // The same detection on the exclusion mask is dropped.
  cv::Mat exclude(image.size(), CV_8U, cv::Scalar(0));
  exclude(cv::Rect(40, 70, 16, 16)).setTo(255);
  EXPECT_TRUE(detector.detect(image, exclude).empty());
}

TEST_F(DarknetBollDetectorTest, MissingOrBrokenFilesAreReportedByName) {
  DarknetParams missing = params_;
  missing.weights_path = (dir_ / "absent.weights").string();
  try {
    DarknetBollDetector detector(missing);
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("absent.weights"), std::string::npos);
  }
  DarknetParams broken = params_;
  broken.cfg_path = (dir_ / "broken.cfg").string();
  std::ofstream(broken.cfg_path) << "[net]\nwidth=128\nheight=128\nchannels=3\n\n[convolutional]\nfilters=1\n"
                                    "size=1\nactivation=nonsense\n";
  EXPECT_THROW(DarknetBollDetector{broken}, std::runtime_error);
  DarknetParams bad_size = params_;
  bad_size.input_width = 100;
  EXPECT_THROW(DarknetBollDetector{bad_size}, std::invalid_argument);
}

TEST_F(DarknetBollDetectorTest, EmptyImageGivesNothing) {
  DarknetBollDetector detector(params_);
  EXPECT_TRUE(detector.detect(cv::Mat(), cv::Mat()).empty());
}

TEST(DarknetNetWriter, TinyYoloV3LayoutLoadsWithTwoHeads) {
  const fs::path dir = fs::temp_directory_path() / ("cotton_harvester_tiny_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  DarknetParams params;
  params.cfg_path = (dir / "tiny.cfg").string();
  params.weights_path = (dir / "tiny.weights").string();
  const DarknetNet net = tinyYoloV3Layout(416, 416, 1, 7);
  EXPECT_EQ(net.convolutions.size(), 13u);
  writeDarknetFiles(net, params.cfg_path, params.weights_path);
  // Tiny YOLOv3 with one class: 8,663,472 convolution weights, 4 x 3184 batch-norm values (biases, scales,
  // means, variances of the 11 normalised layers) and 2 x 18 head biases, as float32, after a 20-byte header.
  size_t floats = 0;
  for (const ConvolutionWeights& w : net.convolutions)
    floats +=
        w.biases.size() + w.scales.size() + w.rolling_means.size() + w.rolling_variances.size() + w.weights.size();
  EXPECT_EQ(floats, 8663472u + 4u * 3184u + 36u);
  EXPECT_EQ(fs::file_size(params.weights_path), 20 + 4 * floats);

  params.decode.confidence_threshold = 0.99;
  DarknetBollDetector detector(params);
  detector.detect(cv::Mat(720, 1280, CV_8UC3, cv::Scalar(90, 140, 60)), cv::Mat());
  std::multiset<int> rows;
  for (const cv::Mat& out : detector.lastOutputs()) {
    rows.insert(out.rows);
    EXPECT_EQ(out.cols, 6);
  }
  EXPECT_EQ(rows, (std::multiset<int>{13 * 13 * 3, 26 * 26 * 3}));
  fs::remove_all(dir);
}
