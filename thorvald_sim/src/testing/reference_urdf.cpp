#include "thorvald_sim/testing/reference_urdf.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace thorvald_sim {

namespace {

void inertial(std::ostream& o, double m, double ix, double iy, double iz) {
  o << "<inertial><mass value=\"" << m << "\"/><inertia ixx=\"" << ix << "\" iyy=\"" << iy << "\" izz=\"" << iz
    << "\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>";
}

void wheelLink(std::ostream& o, const std::string& name, double r, double w, double m) {
  o << "<link name=\"" << name << "\">";
  inertial(o, m, m * (3 * r * r + w * w) / 12, m * r * r / 2, m * (3 * r * r + w * w) / 12);
  o << "<collision><origin rpy=\"1.5707963 0 0\"/><geometry><cylinder radius=\"" << r << "\" length=\"" << w
    << "\"/></geometry></collision></link>\n";
}

void joint(std::ostream& o, const std::string& name, const std::string& type, const std::string& parent,
           const std::string& child, double x, double y, double z, const char* axis) {
  o << "<joint name=\"" << name << "\" type=\"" << type << "\"><parent link=\"" << parent << "\"/><child link=\""
    << child << "\"/><origin xyz=\"" << x << " " << y << " " << z << "\"/><axis xyz=\"" << axis << "\"/>";
}

}  // namespace

std::string referenceUrdf(const thorvald_base::RobotConfig& robot, const std::string& tf_prefix, double body_mass_kg) {
  const std::string p = tf_prefix.empty() ? "" : tf_prefix + "/";
  std::ostringstream o;
  o.precision(9);
  double min_x = -0.5, max_x = 0.5, min_y = -0.5, max_y = 0.5, r_max = 0.1;
  for (const auto& d : robot.drives) {
    min_x = std::min(min_x, d.x), max_x = std::max(max_x, d.x);
    min_y = std::min(min_y, d.y), max_y = std::max(max_y, d.y);
    r_max = std::max(r_max, d.r_wheel);
  }
  o << "<?xml version=\"1.0\"?>\n<robot name=\"thorvald\">\n<link name=\"" << p << "base_link\"/>\n";
  // Frame: a box spanning the drives, above the wheels.
  const double lx = max_x - min_x, ly = max_y - min_y, z = 2 * r_max + 0.15;
  joint(o, p + "frame_joint", "fixed", p + "base_link", p + "frame", 0.5 * (min_x + max_x), 0.5 * (min_y + max_y), z,
        "0 0 1");
  o << "</joint>\n<link name=\"" << p << "frame\">";
  inertial(o, body_mass_kg, body_mass_kg * (ly * ly + 0.01) / 12, body_mass_kg * (lx * lx + 0.01) / 12,
           body_mass_kg * (lx * lx + ly * ly) / 12);
  o << "<collision><geometry><box size=\"" << lx << " " << ly << " 0.1\"/></geometry></collision></link>\n";
  for (const auto& d : robot.drives) {
    const std::string i = std::to_string(d.index);
    std::string wheel_parent = p + "base_link";
    double wx = d.x, wy = d.y;
    if (d.steered()) {
      joint(o, p + "steering" + i, "revolute", p + "base_link", p + "steering_link" + i, d.x, d.y, d.r_wheel, "0 0 1");
      o << "<limit lower=\"" << -d.str_lim << "\" upper=\"" << d.str_lim << "\" effort=\"500\" velocity=\"5\"/>"
        << "</joint>\n<link name=\"" << p << "steering_link" << i << "\">";
      inertial(o, 8.0, 0.2, 0.2, 0.1);
      o << "</link>\n";
      wheel_parent = p + "steering_link" + i;
      wx = wy = 0.0;
    }
    joint(o, p + "wheel" + i, "continuous", wheel_parent, p + "wheel_link" + i, wx, wy, d.steered() ? 0.0 : d.r_wheel,
          "0 1 0");
    o << "</joint>\n";
    wheelLink(o, p + "wheel_link" + i, d.r_wheel, d.w_wheel, 6.0);
  }
  auto passive = [&](const thorvald_base::PassiveWheelConfig& c, const std::string& name, bool swivel) {
    std::string parent = p + "base_link";
    double x = c.x, y = c.y;
    if (swivel) {
      joint(o, p + name + "_swivel", "continuous", parent, p + name + "_fork", c.x, c.y, c.r_wheel, "0 0 1");
      o << "</joint>\n<link name=\"" << p << name << "_fork\">";
      inertial(o, 1.0, 0.01, 0.01, 0.01);
      o << "</link>\n";
      parent = p + name + "_fork";
      x = -c.offset, y = 0.0;
    }
    joint(o, p + (swivel ? name + "_wheel" : name), "continuous", parent, p + name + "_wheel_link", x, y,
          swivel ? 0.0 : c.r_wheel, "0 1 0");
    o << "</joint>\n";
    wheelLink(o, p + name + "_wheel_link", c.r_wheel, c.w_wheel, 1.0);
  };
  for (size_t k = 0; k < robot.casters.size(); ++k) passive(robot.casters[k], "caster" + std::to_string(k), true);
  for (size_t k = 0; k < robot.passive_wheels.size(); ++k)
    passive(robot.passive_wheels[k], "passive_wheel" + std::to_string(k), false);
  o << "</robot>\n";
  return o.str();
}

}  // namespace thorvald_sim
