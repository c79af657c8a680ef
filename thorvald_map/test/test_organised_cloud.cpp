#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "thorvald_base/ros/organised_cloud.h"

using thorvald_base::OrganisedCloudView;

namespace {

sensor_msgs::PointField field(const std::string& name, std::uint32_t offset,
                              std::uint8_t type = sensor_msgs::PointField::FLOAT32) {
  sensor_msgs::PointField f;
  f.name = name;
  f.offset = offset;
  f.datatype = type;
  f.count = 1;
  return f;
}

// A width x height cloud with 16-byte points laid out z, pad, x, y (not the usual order), padded rows; point (u, v) is
// (u, v, u + 10 v), NaN at (1, 0).
sensor_msgs::PointCloud2 cloud(std::uint32_t width, std::uint32_t height) {
  sensor_msgs::PointCloud2 msg;
  msg.width = width;
  msg.height = height;
  msg.fields = {field("z", 0), field("x", 8), field("y", 12), field("rgb", 4, sensor_msgs::PointField::UINT32)};
  msg.point_step = 16;
  msg.row_step = width * 16 + 8;
  msg.data.assign(static_cast<std::size_t>(msg.row_step) * height, 0);
  for (std::uint32_t v = 0; v < height; ++v)
    for (std::uint32_t u = 0; u < width; ++u) {
      const float x = (u == 1 && v == 0) ? NAN : static_cast<float>(u), y = static_cast<float>(v), z = u + 10.0f * v;
      std::uint8_t* p = msg.data.data() + v * msg.row_step + u * msg.point_step;
      std::memcpy(p + 8, &x, 4);
      std::memcpy(p + 12, &y, 4);
      std::memcpy(p, &z, 4);
    }
  return msg;
}

TEST(OrganisedCloudView, ReadsPointsByPixelWithNaN) {
  const sensor_msgs::PointCloud2 msg = cloud(3, 2);
  OrganisedCloudView view;
  std::string error;
  ASSERT_TRUE(view.reset(msg, &error)) << error;
  EXPECT_EQ(view.width(), 3);
  EXPECT_EQ(view.height(), 2);
  EXPECT_FALSE(view.empty());
  EXPECT_EQ(view.at(2, 1), Eigen::Vector3f(2.0f, 1.0f, 12.0f));
  EXPECT_TRUE(std::isnan(view.at(1, 0).x()));
  Eigen::Vector3f p;
  EXPECT_FALSE(view.finitePoint(1, 0, &p));  // NaN
  EXPECT_FALSE(view.finitePoint(3, 0, &p));  // outside
  EXPECT_FALSE(view.finitePoint(0, -1, &p));
  ASSERT_TRUE(view.finitePoint(2, 0, &p));
  EXPECT_EQ(p, Eigen::Vector3f(2.0f, 0.0f, 2.0f));
  EXPECT_EQ(view.offset(0), 8u);
  EXPECT_EQ(view.rowStep(), 56u);
}

TEST(OrganisedCloudView, EmptyCloudIsValidAndEmpty) {
  OrganisedCloudView view;
  std::string error;
  ASSERT_TRUE(view.reset(cloud(0, 0), &error)) << error;
  EXPECT_TRUE(view.empty());
  ASSERT_TRUE(view.reset(cloud(4, 0), &error)) << error;
  EXPECT_TRUE(view.empty());
}

TEST(OrganisedCloudView, MalformedCloudsAreRefusedWithTheReason) {
  OrganisedCloudView view;
  std::string error;
  auto refused = [&](const sensor_msgs::PointCloud2& msg) {
    EXPECT_FALSE(view.reset(msg, &error));
    EXPECT_TRUE(view.empty());
    return error;
  };
  sensor_msgs::PointCloud2 msg = cloud(3, 2);
  msg.fields.erase(msg.fields.begin());  // no z
  EXPECT_EQ(refused(msg), "no field 'z'");
  msg = cloud(3, 2);
  msg.fields[1].datatype = sensor_msgs::PointField::FLOAT64;
  EXPECT_EQ(refused(msg), "field 'x' is not a single FLOAT32");
  msg = cloud(3, 2);
  msg.fields[2].count = 3;
  EXPECT_EQ(refused(msg), "field 'y' is not a single FLOAT32");
  msg = cloud(3, 2);
  msg.fields[2].offset = 14;
  EXPECT_EQ(refused(msg), "field offset beyond point_step");
  msg = cloud(3, 2);
  msg.data.pop_back();
  EXPECT_NE(refused(msg).find("data shorter"), std::string::npos) << error;
  msg = cloud(3, 2);
  msg.row_step = 40;
  EXPECT_NE(refused(msg).find("row_step < width x point_step"), std::string::npos) << error;
  msg = cloud(3, 2);
  msg.is_bigendian = true;
  EXPECT_NE(refused(msg).find("big-endian"), std::string::npos) << error;
  msg = cloud(3, 2);
  msg.height = 100000;  // a header claiming far more than the buffer holds, and more than any camera
  EXPECT_NE(refused(msg).find("larger than"), std::string::npos) << error;
  msg = cloud(3, 2);
  msg.width = 0x40000000;  // width x point_step overflows 32 bits
  msg.height = 1;
  EXPECT_FALSE(view.reset(msg, &error));
}

}  // namespace
