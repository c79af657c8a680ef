#pragma once

#include <Eigen/Core>
#include <sstream>
#include <string>

namespace thorvald_sim {

/// Writes static MJCF geoms (world bodies' children) one line each. Positions [m], colours "r g b a".
class GeomWriter {
 public:
  GeomWriter() { out_.precision(9); }
  /// Horizontal plane at `pos`, `half_size` [m] each way.
  void plane(const std::string& name, const Eigen::Vector3d& pos, double half_size, const char* rgba);
  /// Plane through `pos` tilted by `pitch_rad` about y.
  void tiltedPlane(const std::string& name, const Eigen::Vector3d& pos, double half_size, double pitch_rad,
                   const char* rgba);
  void box(const std::string& name, const Eigen::Vector3d& pos, const Eigen::Vector3d& half, const char* rgba);
  void capsule(const std::string& name, const Eigen::Vector3d& from, const Eigen::Vector3d& to, double radius,
               const char* rgba);
  /// Cylinder along the segment `from`-`to` (flat ends there).
  void cylinderBetween(const std::string& name, const Eigen::Vector3d& from, const Eigen::Vector3d& to, double radius,
                       const char* rgba);
  /// Upright cylinder centred at `pos`.
  void cylinder(const std::string& name, const Eigen::Vector3d& pos, double radius, double half_height,
                const char* rgba);
  void sphere(const std::string& name, const Eigen::Vector3d& pos, double radius, const char* rgba);
  /// Ellipsoid with semi-axes `half`, turned by `yaw_rad` about z.
  void ellipsoid(const std::string& name, const Eigen::Vector3d& pos, const Eigen::Vector3d& half, double yaw_rad,
                 const char* rgba);
  /// A capsule from `from` to `to` split into pieces of at most `piece_m` named `<name>_s<k>` (k from the start):
  /// short geoms keep ray-cast culling effective (a long geom's bounding sphere covers everything).
  void capsulePieces(const std::string& name, const Eigen::Vector3d& from, const Eigen::Vector3d& to, double radius,
                     const char* rgba, double piece_m);
  /// A box split along x and y into pieces of at most `piece_m`, named `<name>_s<k>`.
  void boxPieces(const std::string& name, const Eigen::Vector3d& pos, const Eigen::Vector3d& half, const char* rgba,
                 double piece_m);
  std::string str() const { return out_.str(); }

 private:
  std::ostringstream out_;
  void head(const std::string& name, const char* type);
  void vec(const char* attr, const Eigen::Vector3d& v);
};

}  // namespace thorvald_sim
