#include "perception_conversions.h"

#include <cstring>
#include <limits>

#include <thorvald_base/ros/organised_cloud.h>

namespace cotton_harvester {

bool cloudToMat(const sensor_msgs::PointCloud2& cloud, cv::Mat* points, std::string* error) {
  if (cloud.height <= 1 || cloud.width == 0) {
    *error = "cloud is not organised (height " + std::to_string(cloud.height) + ")";
    return false;
  }
  thorvald_base::OrganisedCloudView view;
  if (!view.reset(cloud, error)) return false;
  points->create(view.height(), view.width(), CV_32FC3);
  for (int v = 0; v < view.height(); ++v) {
    cv::Vec3f* out = points->ptr<cv::Vec3f>(v);
    for (int u = 0; u < view.width(); ++u) {
      const Eigen::Vector3f p = view.at(u, v);
      out[u] = cv::Vec3f(p.x(), p.y(), p.z());
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
    boll.centre.x = located.centre.x;
    boll.centre.y = located.centre.y;
    boll.centre.z = located.centre.z;
    boll.radius = static_cast<float>(located.radius_m);
    boll.depth_source = located.depth_source == perception::BollDepthSource::kSurface  ? Boll::DEPTH_SURFACE
                        : located.depth_source == perception::BollDepthSource::kWindow ? Boll::DEPTH_WINDOW
                                                                                       : Boll::DEPTH_IMAGE_SIZE;
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
