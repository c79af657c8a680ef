#include "cotton_harvester/testing/darknet_net_writer.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

namespace cotton_harvester {
namespace perception {
namespace {

/// Appends layers while tracking each layer's output channel count, so convolution weights get their size.
class LayoutBuilder {
 public:
  LayoutBuilder(DarknetNet& net, std::uint32_t seed) : net_(net), random_(seed) {}

  void convolution(int filters, int size, bool batch_normalize, const std::string& activation) {
    const int in = channels_.empty() ? net_.channels : channels_.back();
    DarknetSection section{"convolutional", {}};
    if (batch_normalize) section.options.emplace_back("batch_normalize", "1");
    section.options.emplace_back("filters", std::to_string(filters));
    section.options.emplace_back("size", std::to_string(size));
    section.options.emplace_back("stride", "1");
    section.options.emplace_back("pad", "1");
    section.options.emplace_back("activation", activation);
    net_.sections.push_back(section);

    ConvolutionWeights w;
    const double spread = std::sqrt(2.0 / (in * size * size));  // keeps activations in range layer after layer
    std::normal_distribution<float> weight(0.0f, static_cast<float>(spread));
    std::uniform_real_distribution<float> small(-0.1f, 0.1f);
    w.biases.resize(filters);
    for (float& b : w.biases) b = small(random_);
    if (batch_normalize) {
      w.scales.assign(filters, 1.0f);
      w.rolling_means.assign(filters, 0.0f);
      w.rolling_variances.assign(filters, 1.0f);
    }
    w.weights.resize(static_cast<size_t>(filters) * in * size * size);
    for (float& v : w.weights) v = weight(random_);
    net_.convolutions.push_back(std::move(w));
    channels_.push_back(filters);
  }

  void maxpool(int size, int stride) {
    net_.sections.push_back({"maxpool", {{"size", std::to_string(size)}, {"stride", std::to_string(stride)}}});
    channels_.push_back(channels_.back());
  }

  void route(const std::vector<int>& layers) {
    std::string text;
    int sum = 0;
    for (int layer : layers) {
      const int index = layer < 0 ? static_cast<int>(channels_.size()) + layer : layer;
      sum += channels_.at(index);
      text += (text.empty() ? "" : ",") + std::to_string(layer);
    }
    net_.sections.push_back({"route", {{"layers", text}}});
    channels_.push_back(sum);
  }

  void upsample() {
    net_.sections.push_back({"upsample", {{"stride", "2"}}});
    channels_.push_back(channels_.back());
  }

  void yolo(const std::string& mask, int classes) {
    net_.sections.push_back({"yolo",
                             {{"mask", mask},
                              {"anchors", "10,14, 23,27, 37,58, 81,82, 135,169, 344,319"},
                              {"classes", std::to_string(classes)},
                              {"num", "6"},
                              {"jitter", ".3"},
                              {"ignore_thresh", ".7"},
                              {"truth_thresh", "1"},
                              {"random", "1"}}});
    channels_.push_back(channels_.back());
  }

 private:
  DarknetNet& net_;
  std::mt19937 random_;
  std::vector<int> channels_;
};

void writeFloats(std::ofstream& out, const std::vector<float>& values) {
  out.write(reinterpret_cast<const char*>(values.data()), static_cast<std::streamsize>(values.size() * sizeof(float)));
}

}  // namespace

std::string cfgText(const DarknetNet& net) {
  std::ostringstream cfg;
  cfg << "[net]\nbatch=1\nsubdivisions=1\nwidth=" << net.width << "\nheight=" << net.height
      << "\nchannels=" << net.channels << "\n";
  for (const DarknetSection& section : net.sections) {
    cfg << "\n[" << section.type << "]\n";
    for (const auto& option : section.options) cfg << option.first << "=" << option.second << "\n";
  }
  return cfg.str();
}

void writeDarknetFiles(const DarknetNet& net, const std::string& cfg_path, const std::string& weights_path) {
  size_t convolutions = 0;
  for (const DarknetSection& section : net.sections) convolutions += section.type == "convolutional";
  if (convolutions != net.convolutions.size())
    throw std::invalid_argument("darknet net: " + std::to_string(convolutions) + " convolutional sections but " +
                                std::to_string(net.convolutions.size()) + " weight blocks");

  std::ofstream cfg(cfg_path);
  cfg << cfgText(net);
  if (!cfg) throw std::runtime_error("darknet net: cannot write '" + cfg_path + "'");

  std::ofstream weights(weights_path, std::ios::binary);
  const std::int32_t version[3] = {0, 2, 0};
  const std::uint64_t seen = 0;
  weights.write(reinterpret_cast<const char*>(version), sizeof(version));
  weights.write(reinterpret_cast<const char*>(&seen), sizeof(seen));
  for (const ConvolutionWeights& w : net.convolutions) {
    writeFloats(weights, w.biases);
    writeFloats(weights, w.scales);
    writeFloats(weights, w.rolling_means);
    writeFloats(weights, w.rolling_variances);
    writeFloats(weights, w.weights);
  }
  if (!weights) throw std::runtime_error("darknet net: cannot write '" + weights_path + "'");
}

DarknetNet tinyYoloV3Layout(int input_width, int input_height, int classes, std::uint32_t seed) {
  DarknetNet net;
  net.width = input_width;
  net.height = input_height;
  LayoutBuilder b(net, seed);
  const int head_filters = 3 * (5 + classes);
  b.convolution(16, 3, true, "leaky");  // 0
  b.maxpool(2, 2);
  b.convolution(32, 3, true, "leaky");  // 2
  b.maxpool(2, 2);
  b.convolution(64, 3, true, "leaky");  // 4
  b.maxpool(2, 2);
  b.convolution(128, 3, true, "leaky");  // 6
  b.maxpool(2, 2);
  b.convolution(256, 3, true, "leaky");  // 8: stride 16 features
  b.maxpool(2, 2);
  b.convolution(512, 3, true, "leaky");  // 10
  b.maxpool(2, 1);
  b.convolution(1024, 3, true, "leaky");  // 12
  b.convolution(256, 1, true, "leaky");   // 13
  b.convolution(512, 3, true, "leaky");   // 14
  b.convolution(head_filters, 1, false, "linear");
  b.yolo("3,4,5", classes);  // 16: stride 32 head
  b.route({-4});             // 17: back to layer 13
  b.convolution(128, 1, true, "leaky");
  b.upsample();
  b.route({-1, 8});
  b.convolution(256, 3, true, "leaky");
  b.convolution(head_filters, 1, false, "linear");
  b.yolo("0,1,2", classes);  // 23: stride 16 head
  return net;
}

}  // namespace perception
}  // namespace cotton_harvester
