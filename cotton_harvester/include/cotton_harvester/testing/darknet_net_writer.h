#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace cotton_harvester {
namespace perception {

/// One [section] of a Darknet .cfg file (after [net]).
struct DarknetSection {
  std::string type;                                          ///< convolutional, maxpool, route, upsample, yolo
  std::vector<std::pair<std::string, std::string>> options;  ///< key=value lines in order
};

/// Parameters of one convolutional layer in .weights order. With batch normalisation scales, rolling means and
/// rolling variances hold one value per filter; without it they are empty. weights: filters x in x k x k.
struct ConvolutionWeights {
  std::vector<float> biases;
  std::vector<float> scales;
  std::vector<float> rolling_means;
  std::vector<float> rolling_variances;
  std::vector<float> weights;
};

/// A Darknet network: its [net] block, its sections and the weights of its convolutional sections in order.
struct DarknetNet {
  int width = 416;   ///< input width [px]
  int height = 416;  ///< input height [px]
  int channels = 3;
  std::vector<DarknetSection> sections;
  std::vector<ConvolutionWeights> convolutions;  ///< one per convolutional section, in file order
};

/// The .cfg text of the network.
std::string cfgText(const DarknetNet& net);

/// Writes the .cfg and the .weights file (version 0.2.0 header with a 64-bit "seen" counter, then per
/// convolution: biases, [scales, rolling means, rolling variances], weights; all float32).
/// Throws std::runtime_error naming the file on an I/O error, std::invalid_argument when the number of weight
/// blocks does not match the convolutional sections.
void writeDarknetFiles(const DarknetNet& net, const std::string& cfg_path, const std::string& weights_path);

/// A network with the layer layout of tiny YOLOv3 (13 convolutions, 6 max-pools, two yolo heads at strides 32
/// and 16 with the standard six anchors) for `classes` classes, with random weights drawn from `seed`. It has
/// the size and cost of the paper's detector; its detections mean nothing (used for timing and loading).
DarknetNet tinyYoloV3Layout(int input_width, int input_height, int classes, std::uint32_t seed);

}  // namespace perception
}  // namespace cotton_harvester
