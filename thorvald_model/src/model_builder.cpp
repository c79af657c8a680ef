#include "thorvald_model/model_builder.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "module_dimensions.h"

namespace thorvald_model {

using thorvald_base::ConfigError;
using thorvald_base::DriveConfig;
using thorvald_base::PassiveWheelConfig;
using thorvald_base::RobotConfig;

namespace {

constexpr double kPi = 3.14159265358979323846;
const Eigen::Vector3d kAlongY(kPi / 2.0, 0.0, 0.0);  ///< rpy turning a cylinder's z axis onto y

Eigen::Matrix3d rotationFromRpy(const Eigen::Vector3d& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

/// Adds a shape to a link and its mass (volume x density) to the link's mass properties.
void addPart(Link& link, const Shape& shape, double density) {
  MassProperties body;
  if (shape.kind == Shape::Kind::kBox) {
    body = solidBox(shape.size_m, density * shape.size_m.prod());
  } else {
    body =
        solidCylinder(shape.radius_m, shape.length_m, density * kPi * shape.radius_m * shape.radius_m * shape.length_m);
  }
  link.shapes.push_back(shape);
  link.inertial = combine({link.inertial, placed(body, shape.xyz_m, rotationFromRpy(shape.rpy_rad))});
}

Shape box(const Eigen::Vector3d& size, const Eigen::Vector3d& xyz, const std::string& material) {
  Shape s;
  s.kind = Shape::Kind::kBox;
  s.size_m = size;
  s.xyz_m = xyz;
  s.material = material;
  return s;
}

Shape cylinder(double radius, double length, const Eigen::Vector3d& xyz, const Eigen::Vector3d& rpy,
               const std::string& material) {
  Shape s;
  s.kind = Shape::Kind::kCylinder;
  s.radius_m = radius;
  s.length_m = length;
  s.xyz_m = xyz;
  s.rpy_rad = rpy;
  s.material = material;
  return s;
}

/// A hollow tube between two points: drawn as a cylinder, weighed as a tube.
void addTube(Link& link, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d d = b - a;
  const double length = d.norm();
  if (length < 1e-6) return;
  const Eigen::Vector3d rpy(0.0, std::atan2(std::hypot(d.x(), d.y()), d.z()), std::atan2(d.y(), d.x()));
  Shape s = cylinder(dims::kTubeOuterRadius, length, 0.5 * (a + b), rpy, "aluminium");
  const double area =
      kPi * (dims::kTubeOuterRadius * dims::kTubeOuterRadius - dims::kTubeInnerRadius * dims::kTubeInnerRadius);
  const MassProperties body =
      tube(dims::kTubeOuterRadius, dims::kTubeInnerRadius, length, dims::kAluminiumDensity * area * length);
  link.shapes.push_back(s);
  link.inertial = combine({link.inertial, placed(body, s.xyz_m, rotationFromRpy(rpy))});
}

Joint joint(const std::string& name, const std::string& type, const std::string& parent, const std::string& child,
            const Eigen::Vector3d& xyz, const Eigen::Vector3d& axis = Eigen::Vector3d::UnitZ()) {
  Joint j;
  j.name = name;
  j.type = type;
  j.parent = parent;
  j.child = child;
  j.xyz_m = xyz;
  j.axis = axis;
  return j;
}

/// Height of the steering joint (bottom of the steering module) above the ground [m].
double mountHeight(const DriveConfig& d) { return d.r_wheel + dims::kLegLength; }

/// Which side of the wheel the leg and drive module sit on (+1: +y of the leg frame), from `leg_mesh`.
double legSide(const DriveConfig& d) { return (d.leg_mesh / 2) % 2 == 0 ? 1.0 : -1.0; }

class Builder {
 public:
  Builder(const RobotConfig& config, const ModelOptions& options) : config_(config), options_(options) {}

  UrdfTree build() {
    tree_.robot_name = options_.robot_name;
    if (options_.floating_base) {
      // MuJoCo's URDF reader takes a link named exactly `world` as its world body: never prefixed.
      tree_.links.push_back(Link{"world", {}, {}});
      tree_.joints.push_back(joint(name("world_to_base_link"), "floating", "world", name("base_link"), {0, 0, 0}));
    }
    tree_.links.push_back(Link{name("base_link"), {}, {}});
    for (const auto& d : config_.drives) addDrive(d);
    for (const auto& b : config_.batteries) addBattery(b);
    for (const auto& p : config_.pipes) addPipe(p);
    for (const auto& c : config_.corners) addCorner(c);
    for (const auto& b : config_.beams) addBeam(b);
    const auto casters = sortedByName(config_.casters);
    for (size_t i = 0; i < casters.size(); ++i) addCaster(casters[i], static_cast<int>(i));
    const auto passive = sortedByName(config_.passive_wheels);
    for (size_t i = 0; i < passive.size(); ++i) addPassiveWheel(passive[i], static_cast<int>(i));
    return tree_;
  }

 private:
  std::string name(const std::string& n) const { return prefixed(options_.tf_prefix, n); }

  void fail(const std::string& where, const std::string& what) const { throw ConfigError(config_.source, where, what); }

  void checkPositive(double value, const std::string& where, const std::string& what) const {
    if (!(value > 0.0) || !std::isfinite(value)) fail(where, "is " + std::to_string(value) + ", expected " + what);
  }

  void addLinkWithJoint(Link link, Joint j) {
    tree_.links.push_back(std::move(link));
    tree_.joints.push_back(std::move(j));
  }

  void addDrive(const DriveConfig& d) {
    const std::string i = std::to_string(d.index);
    const std::string where = "motor_drives.drive" + i;
    checkPositive(d.r_wheel, where + ".r_wheel", "a wheel radius > 0 [m]");
    checkPositive(d.w_wheel, where + ".w_wheel", "a wheel width > 0 [m]");
    if (d.leg_mesh < 0 || d.leg_mesh > 9)
      fail(where + ".leg_mesh", "is " + std::to_string(d.leg_mesh) + ", expected 0-9");
    const double z_mount = mountHeight(d);
    const double side = legSide(d);
    const double drive_y = side * (0.5 * d.w_wheel + 0.5 * dims::kDriveLength);
    const double leg_y = side * (0.5 * d.w_wheel + dims::kDriveLength + 0.5 * dims::kLegY);

    // The leg: a vertical section beside the wheel, an arm to the steering axis, the drive module at the hub.
    Link leg{name("leg_link" + i), {}, {}};
    addPart(leg, box({dims::kLegX, dims::kLegY, dims::kLegLength}, {0, leg_y, -0.5 * dims::kLegLength}, "grey"),
            dims::kLegDensity);
    addPart(leg,
            box({dims::kLegX, std::abs(leg_y) + 0.5 * dims::kLegY, dims::kLegArmZ},
                {0, 0.5 * (leg_y + side * 0.5 * dims::kLegY), -0.5 * dims::kLegArmZ}, "grey"),
            dims::kLegDensity);
    addPart(leg, cylinder(dims::kDriveRadius, dims::kDriveLength, {0, drive_y, -dims::kLegLength}, kAlongY, "orange"),
            dims::kDriveDensity);

    if (d.steered()) {
      Link module{name("steering_module_link" + i), {}, {}};
      addPart(module,
              box({dims::kSteeringBoxX, dims::kSteeringBoxY, dims::kSteeringBoxZ}, {0, 0, 0.5 * dims::kSteeringBoxZ},
                  "orange"),
              dims::kSteeringDensity);
      addLinkWithJoint(module, joint(name("steering_module" + i + "_joint"), "fixed", name("base_link"), module.name,
                                     {d.x, d.y, z_mount}));
      Joint steering = joint(name("steering" + i), "revolute", name("base_link"), leg.name, {d.x, d.y, z_mount});
      checkPositive(d.str_lim, where + ".str_lim", "a steering limit > 0 [rad]");
      steering.lower_rad = -d.str_lim;
      steering.upper_rad = d.str_lim;
      steering.effort = 200.0;
      steering.velocity = std::max(d.str_sim_v, 0.1);
      addLinkWithJoint(leg, steering);
    } else {
      addPart(
          leg,
          box({dims::kFixedMountX, dims::kFixedMountY, dims::kFixedMountZ}, {0, 0, 0.5 * dims::kFixedMountZ}, "grey"),
          dims::kFixedMountDensity);
      addLinkWithJoint(leg,
                       joint(name("leg" + i + "_joint"), "fixed", name("base_link"), leg.name, {d.x, d.y, z_mount}));
    }

    Link wheel{name("wheel_link" + i), {}, {}};
    addPart(wheel, cylinder(d.r_wheel, d.w_wheel, {0, 0, 0}, kAlongY, "black"), dims::kWheelDensity);
    Joint w = joint(name("wheel" + i), "continuous", leg.name, wheel.name, {0, 0, d.r_wheel - z_mount},
                    Eigen::Vector3d::UnitY());
    w.effort = 300.0;
    w.velocity = 50.0;
    addLinkWithJoint(wheel, w);
  }

  void addBattery(const thorvald_base::BatteryConfig& b) {
    const std::string where = "batteries." + b.name;
    if (b.z - 0.5 * dims::kBatteryZ < -1e-9) {
      fail(where + ".z", "is " + std::to_string(b.z) + ": the enclosure (" + std::to_string(dims::kBatteryZ) +
                             " m tall, z at its centre) would reach below the ground; expected z >= " +
                             std::to_string(0.5 * dims::kBatteryZ));
    }
    Link link{name("battery_" + b.name), {}, {}};
    const bool full = b.type != 0 && b.with_battery;
    addPart(link, box({dims::kBatteryX, dims::kBatteryY, dims::kBatteryZ}, {0, 0, 0}, "orange"),
            full ? dims::kBatteryFullDensity : dims::kBatteryEmptyDensity);
    Joint j = joint(name("battery_" + b.name + "_joint"), "fixed", name("base_link"), link.name, {b.x, b.y, b.z});
    j.rpy_rad.z() = b.yaw;
    addLinkWithJoint(link, j);
  }

  void addPipe(const thorvald_base::PipeConfig& p) {
    const std::string where = "pipes." + p.name;
    // docs/robot_file.md: height 0 (the default) puts the tube at ground height, as the field robots' files do.
    if (!(p.height >= 0.0)) {
      fail(where + ".height", "is " + std::to_string(p.height) + ", expected the upper tube's height >= 0 [m]");
    }
    if (p.space < 0.0 || (p.space > 0.0 && p.space > p.height - dims::kTubeOuterRadius + 1e-9)) {
      fail(where + ".space", "is " + std::to_string(p.space) + ", expected 0 (one tube) up to height - " +
                                 std::to_string(dims::kTubeOuterRadius) + " (lower tube above the ground)");
    }
    if (std::hypot(p.x2 - p.x1, p.y2 - p.y1) < 1e-3) fail(where + ".x2", "the pipe's two ends coincide");
    Link link{name("pipe_" + p.name), {}, {}};
    addTube(link, {p.x1, p.y1, 0}, {p.x2, p.y2, 0});
    if (p.space > 0.0) addTube(link, {p.x1, p.y1, -p.space}, {p.x2, p.y2, -p.space});
    addLinkWithJoint(link,
                     joint(name("pipe_" + p.name + "_joint"), "fixed", name("base_link"), link.name, {0, 0, p.height}));
  }

  void addCorner(const thorvald_base::CornerConfig& c) {
    const std::string where = "corners." + c.name;
    if (c.z - 0.5 * dims::kCornerSize < -1e-9) {
      fail(where + ".z", "is " + std::to_string(c.z) + ", expected the corner's centre height >= " +
                             std::to_string(0.5 * dims::kCornerSize) + " [m]");
    }
    Link link{name("corner_" + c.name), {}, {}};
    const double s = dims::kCornerSize;
    addPart(link, box({s, s, s}, {0, 0, 0}, "grey"), dims::kCornerDensity);
    if (c.space > 0.0) addTube(link, {0, 0, 0}, {0, 0, -std::min(c.space, c.z - dims::kTubeOuterRadius)});
    addLinkWithJoint(
        link, joint(name("corner_" + c.name + "_joint"), "fixed", name("base_link"), link.name, {c.x, c.y, c.z}));
  }

  void addBeam(const thorvald_base::BeamConfig& b) {
    const DriveConfig* ends[2] = {findDrive(b.start, "beams." + b.name + ".start"),
                                  findDrive(b.end, "beams." + b.name + ".end")};
    const double z =
        std::max(mountHeight(*ends[0]), mountHeight(*ends[1])) + dims::kSteeringBoxZ + dims::kTubeOuterRadius;
    Link link{name("beam_" + b.name), {}, {}};
    addTube(link, {ends[0]->x, ends[0]->y, 0}, {ends[1]->x, ends[1]->y, 0});
    if (link.shapes.empty()) fail("beams." + b.name + ".end", "joins a drive to itself");
    addLinkWithJoint(link, joint(name("beam_" + b.name + "_joint"), "fixed", name("base_link"), link.name, {0, 0, z}));
  }

  const DriveConfig* findDrive(const std::string& drive_name, const std::string& where) const {
    for (const auto& d : config_.drives)
      if ("drive" + std::to_string(d.index) == drive_name) return &d;
    fail(where,
         "names '" + drive_name + "', expected one of drive0..drive" + std::to_string(config_.drives.size() - 1));
    return nullptr;
  }

  static std::vector<PassiveWheelConfig> sortedByName(std::vector<PassiveWheelConfig> wheels) {
    std::sort(wheels.begin(), wheels.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
    return wheels;
  }

  /// A fork (two plates and a top plate) from the mount at `top` [m] above the axle down to the axle.
  void addFork(Link& link, const PassiveWheelConfig& w, double height, double axle_x) {
    const double y = 0.5 * w.w_wheel + dims::kForkClearance;
    for (double s : {-1.0, 1.0}) {
      addPart(link, box({dims::kForkX, 0.01, height}, {0.5 * axle_x, s * y, -0.5 * height}, "grey"),
              dims::kForkDensity);
    }
    addPart(link,
            box({std::max(dims::kForkX, std::abs(axle_x) + dims::kForkX), 2 * y + 0.01, 0.01},
                {0.5 * axle_x, 0, -0.005}, "grey"),
            dims::kForkDensity);
  }

  double forkHeight(const PassiveWheelConfig& w, const std::string& where) {
    checkPositive(w.r_wheel, where + ".r_wheel", "a wheel radius > 0 [m]");
    checkPositive(w.w_wheel, where + ".w_wheel", "a wheel width > 0 [m]");
    const double height = w.z_top - w.r_wheel;
    if (height >= dims::kMinForkHeight) return height;
    tree_.warnings.push_back(where + ".z_top " + std::to_string(w.z_top) + " leaves no room for the fork above a " +
                             std::to_string(w.r_wheel) + " m wheel: mount drawn at " +
                             std::to_string(w.r_wheel + dims::kMinForkHeight) + " m");
    return dims::kMinForkHeight;
  }

  void addCaster(const PassiveWheelConfig& c, int index) {
    const std::string i = std::to_string(index);
    const double height = forkHeight(c, "casters." + c.name);
    Link swivel{name("caster_swivel_link" + i), {}, {}};
    addFork(swivel, c, height, -c.offset);
    Joint s = joint(name("caster" + i + "_swivel"), "continuous", name("base_link"), swivel.name,
                    {c.x, c.y, c.r_wheel + height});
    s.effort = 10.0;
    s.velocity = 20.0;
    addLinkWithJoint(swivel, s);
    addWheel(name("caster_wheel_link" + i), name("caster" + i + "_wheel"), swivel.name, c, {-c.offset, 0, -height});
  }

  void addPassiveWheel(const PassiveWheelConfig& p, int index) {
    const std::string i = std::to_string(index);
    const double height = forkHeight(p, "passive_wheels." + p.name);
    Link mount{name("passive_wheel_mount_link" + i), {}, {}};
    addFork(mount, p, height, 0.0);
    addLinkWithJoint(mount, joint(name("passive_wheel_mount" + i + "_joint"), "fixed", name("base_link"), mount.name,
                                  {p.x, p.y, p.r_wheel + height}));
    addWheel(name("passive_wheel_link" + i), name("passive_wheel" + i), mount.name, p, {0, 0, -height});
  }

  void addWheel(const std::string& link_name, const std::string& joint_name, const std::string& parent,
                const PassiveWheelConfig& w, const Eigen::Vector3d& xyz) {
    Link wheel{link_name, {}, {}};
    addPart(wheel, cylinder(w.r_wheel, w.w_wheel, {0, 0, 0}, kAlongY, "black"), dims::kCasterWheelDensity);
    Joint j = joint(joint_name, "continuous", parent, link_name, xyz, Eigen::Vector3d::UnitY());
    j.effort = 10.0;
    j.velocity = 100.0;
    addLinkWithJoint(wheel, j);
  }

  const RobotConfig& config_;
  const ModelOptions& options_;
  UrdfTree tree_;
};

}  // namespace

std::string prefixed(const std::string& tf_prefix, const std::string& name) {
  return tf_prefix.empty() ? name : tf_prefix + "/" + name;
}

UrdfTree buildModel(const RobotConfig& config, const ModelOptions& options) {
  if (config.drives.empty()) throw ConfigError(config.source, "motor_drives", "no drives: expected drive0 at least");
  return Builder(config, options).build();
}

std::vector<std::string> baseDriverJointNames(const RobotConfig& config, const std::string& tf_prefix) {
  std::vector<std::string> names;
  for (const auto& d : config.drives)
    if (d.steered()) names.push_back(prefixed(tf_prefix, "steering" + std::to_string(d.index)));
  for (const auto& d : config.drives) names.push_back(prefixed(tf_prefix, "wheel" + std::to_string(d.index)));
  return names;
}

std::vector<std::string> passiveJointNames(const RobotConfig& config, const std::string& tf_prefix) {
  std::vector<std::string> names;
  for (size_t i = 0; i < config.casters.size(); ++i) {
    names.push_back(prefixed(tf_prefix, "caster" + std::to_string(i) + "_swivel"));
    names.push_back(prefixed(tf_prefix, "caster" + std::to_string(i) + "_wheel"));
  }
  for (size_t i = 0; i < config.passive_wheels.size(); ++i)
    names.push_back(prefixed(tf_prefix, "passive_wheel" + std::to_string(i)));
  return names;
}

std::vector<std::string> movableJointNames(const std::string& urdf_xml) {
  tinyxml2::XMLDocument doc;
  if (doc.Parse(urdf_xml.c_str(), urdf_xml.size()) != tinyxml2::XML_SUCCESS)
    throw std::runtime_error(std::string("robot_description is not XML: ") + doc.ErrorStr());
  const tinyxml2::XMLElement* robot = doc.FirstChildElement("robot");
  if (!robot) throw std::runtime_error("robot_description has no <robot> element");
  std::vector<std::string> names;
  for (const auto* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const char* name = j->Attribute("name");
    const char* type = j->Attribute("type");
    if (!name || !type) continue;
    const std::string t = type;
    if (t == "revolute" || t == "continuous" || t == "prismatic") names.emplace_back(name);
  }
  return names;
}

std::vector<std::string> unpublishedJointNames(const RobotConfig& config, const std::string& tf_prefix,
                                               const std::string& urdf_xml) {
  std::vector<std::string> names = passiveJointNames(config, tf_prefix);
  if (urdf_xml.empty()) return names;
  std::vector<std::string> known = baseDriverJointNames(config, tf_prefix);
  known.insert(known.end(), names.begin(), names.end());
  for (const auto& j : movableJointNames(urdf_xml)) {
    if (std::find(known.begin(), known.end(), j) != known.end()) continue;
    names.push_back(j);
    known.push_back(j);
  }
  return names;
}

}  // namespace thorvald_model
