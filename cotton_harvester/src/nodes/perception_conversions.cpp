#include "perception_conversions.h"

#include <cstring>
#include <limits>

namespace cotton_harvester {

bool cloudToMat(const sensor_msgs::PointCloud2& cloud, cv::Mat* points, std::string* error) {
  if (cloud.height <= 1 || cloud.width == 0) {
    *error = "cloud is not organised (height " + std::to_string(cloud.height) + ")";
    return false;
  }
  int offsets[3] = {-1, -1, -1};
  const char* names[3] = {"x", "y", "z"};
  for (const sensor_msgs::PointField& field : cloud.fields) {
    for (int i = 0; i < 3; ++i) {
      if (field.name != names[i]) continue;
      if (field.datatype != sensor_msgs::PointField::FLOAT32 || field.count != 1) {
        *error = std::string("field '") + names[i] + "' is not a single float32";
        return false;
      }
      offsets[i] = static_cast<int>(field.offset);
    }
  }
  for (int i = 0; i < 3; ++i) {
    if (offsets[i] < 0) {
      *error = std::string("cloud has no '") + names[i] + "' field";
      return false;
    }
    if (offsets[i] + 4 > static_cast<int>(cloud.point_step)) {
      *error = "field offset beyond point_step";
      return false;
    }
  }
  if (cloud.row_step < cloud.width * cloud.point_step ||
      cloud.data.size() < static_cast<size_t>(cloud.row_step) * cloud.height) {
    *error = "cloud data shorter than height x row_step";
    return false;
  }
  if (cloud.is_bigendian) {
    *error = "big-endian clouds are not supported";
    return false;
  }
  points->create(static_cast<int>(cloud.height), static_cast<int>(cloud.width), CV_32FC3);
  for (uint32_t v = 0; v < cloud.height; ++v) {
    const uint8_t* row = cloud.data.data() + static_cast<size_t>(v) * cloud.row_step;
    cv::Vec3f* out = points->ptr<cv::Vec3f>(static_cast<int>(v));
    for (uint32_t u = 0; u < cloud.width; ++u) {
      const uint8_t* point = row + static_cast<size_t>(u) * cloud.point_step;
      for (int i = 0; i < 3; ++i) std::memcpy(&out[u][i], point + offsets[i], sizeof(float));
    }
  }
  return true;
}

BollArray toBollArray(const perception::FrameResult& result, const std_msgs::Header& header) {
  BollArray message;
  message.header = header;
  message.bolls.reserve(result.bolls.size());
  for (const perception::LocatedBoll& located : result.bolls) {
    Boll boll;
    boll.position.x = located.position.x;
    boll.position.y = located.position.y;
    boll.position.z = located.position.z;
    boll.confidence = static_cast<float>(located.detection.confidence);
    boll.reachable = located.reachable;
    boll.u = static_cast<int32_t>(std::lround(located.detection.centroid.x));
    boll.v = static_cast<int32_t>(std::lround(located.detection.centroid.y));
    message.bolls.push_back(boll);
  }
  message.nearest_reachable = result.nearest_reachable;
  return message;
}

visualization_msgs::MarkerArray toMarkers(const perception::FrameResult& result, const std_msgs::Header& header) {
  visualization_msgs::MarkerArray markers;
  visualization_msgs::Marker clear;
  clear.header = header;
  clear.action = visualization_msgs::Marker::DELETEALL;
  markers.markers.push_back(clear);
  for (size_t i = 0; i < result.bolls.size(); ++i) {
    const perception::LocatedBoll& boll = result.bolls[i];
    visualization_msgs::Marker m;
    m.header = header;
    m.ns = "bolls";
    m.id = static_cast<int>(i);
    m.type = visualization_msgs::Marker::SPHERE;
    m.action = visualization_msgs::Marker::ADD;
    m.pose.position.x = boll.position.x;
    m.pose.position.y = boll.position.y;
    m.pose.position.z = boll.position.z;
    m.pose.orientation.w = 1.0;
    m.scale.x = m.scale.y = m.scale.z = 0.07;
    const bool nearest = static_cast<int>(i) == result.nearest_reachable;
    m.color.a = 1.0f;
    m.color.r = nearest ? 0.1f : (boll.reachable ? 0.2f : 0.6f);
    m.color.g = nearest ? 0.3f : (boll.reachable ? 0.9f : 0.6f);
    m.color.b = nearest ? 1.0f : (boll.reachable ? 0.2f : 0.6f);
    markers.markers.push_back(m);
  }
  if (result.end_effector) {
    visualization_msgs::Marker m;
    m.header = header;
    m.ns = "end_effector";
    m.type = visualization_msgs::Marker::CUBE;
    m.action = visualization_msgs::Marker::ADD;
    m.pose.position.x = result.end_effector->position.x;
    m.pose.position.y = result.end_effector->position.y;
    m.pose.position.z = result.end_effector->position.z;
    m.pose.orientation.w = 1.0;
    m.scale.x = 0.12;
    m.scale.y = 0.10;
    m.scale.z = 0.05;
    m.color.a = 1.0f;
    m.color.r = 1.0f;
    m.color.g = 0.47f;
    markers.markers.push_back(m);
  }
  return markers;
}

}  // namespace cotton_harvester
