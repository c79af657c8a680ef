#pragma once

#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

#include <Eigen/Core>
#include <sensor_msgs/PointCloud2.h>

namespace thorvald_base {

/// Reads x, y, z of an organised sensor_msgs/PointCloud2 (a depth camera's cloud: one point per pixel, row-major)
/// by pixel, without copying it. `reset()` checks the message once: x, y and z present as single little-endian
/// FLOAT32 fields inside point_step, rows long enough, data as long as height x row_step, width and height bounded.
/// Pixels where the sensor saw nothing read NaN, as the message has them. The view borrows the message's buffer: keep
/// the message alive while reading.
class OrganisedCloudView {
 public:
  /// Largest width and height accepted [pixels]: bounds what a malformed header can make a reader walk.
  static constexpr std::uint32_t kMaxSide = 16384;

  /// Checks `msg` and views it; false with what is wrong in *error (the view is then empty). A cloud with no points
  /// (width or height 0) is valid and empty.
  bool reset(const sensor_msgs::PointCloud2& msg, std::string* error) {
    *this = OrganisedCloudView();
    const char* names[3] = {"x", "y", "z"};
    std::uint32_t offsets[3] = {0, 0, 0};
    bool found[3] = {false, false, false};
    for (const sensor_msgs::PointField& field : msg.fields)
      for (int i = 0; i < 3; ++i) {
        if (field.name != names[i]) continue;
        if (field.datatype != sensor_msgs::PointField::FLOAT32 || field.count != 1)
          return fail(error, std::string("field '") + names[i] + "' is not a single FLOAT32");
        offsets[i] = field.offset;
        found[i] = true;
      }
    for (int i = 0; i < 3; ++i) {
      if (!found[i]) return fail(error, std::string("no field '") + names[i] + "'");
      if (std::uint64_t{offsets[i]} + 4 > msg.point_step) return fail(error, "field offset beyond point_step");
    }
    if (msg.is_bigendian) return fail(error, "big-endian clouds are not supported");
    if (msg.width > kMaxSide || msg.height > kMaxSide)
      return fail(error, "cloud of " + std::to_string(msg.width) + " x " + std::to_string(msg.height) +
                             " points is larger than " + std::to_string(kMaxSide) + " on a side");
    if (std::uint64_t{msg.row_step} < std::uint64_t{msg.width} * msg.point_step ||
        msg.data.size() < std::uint64_t{msg.row_step} * msg.height)
      return fail(error, "data shorter than height x row_step (or row_step < width x point_step)");
    data_ = msg.data.data();
    width_ = static_cast<int>(msg.width);
    height_ = static_cast<int>(msg.height);
    row_step_ = msg.row_step;
    point_step_ = msg.point_step;
    for (int i = 0; i < 3; ++i) offset_[i] = offsets[i];
    return true;
  }

  int width() const { return width_; }    ///< [pixels] (columns)
  int height() const { return height_; }  ///< [pixels] (rows)
  bool empty() const { return width_ == 0 || height_ == 0; }

  /// x, y, z of the pixel in column u, row v [m] (NaN where the sensor saw nothing); u, v must be inside.
  Eigen::Vector3f at(int u, int v) const {
    const std::uint8_t* p = data_ + static_cast<std::size_t>(v) * row_step_ + static_cast<std::size_t>(u) * point_step_;
    Eigen::Vector3f out;
    for (int i = 0; i < 3; ++i) std::memcpy(&out[i], p + offset_[i], sizeof(float));
    return out;
  }
  /// The pixel's point, or false if (u, v) lies outside the cloud or the point is not finite.
  bool finitePoint(int u, int v, Eigen::Vector3f* point) const {
    if (u < 0 || v < 0 || u >= width_ || v >= height_) return false;
    *point = at(u, v);
    return point->allFinite();
  }

  /// The layout, for readers that walk the buffer themselves.
  const std::uint8_t* data() const { return data_; }
  std::size_t rowStep() const { return row_step_; }             ///< [bytes]
  std::size_t pointStep() const { return point_step_; }         ///< [bytes]
  std::size_t offset(int axis) const { return offset_[axis]; }  ///< [bytes] of x (0), y (1), z (2) in a point

 private:
  bool fail(std::string* error, const std::string& what) {
    *this = OrganisedCloudView();
    *error = what;
    return false;
  }

  const std::uint8_t* data_ = nullptr;
  int width_ = 0, height_ = 0;
  std::size_t row_step_ = 0, point_step_ = 0;
  std::size_t offset_[3] = {0, 4, 8};
};

}  // namespace thorvald_base
