#include "cotton_harvester_sim/rover_scene.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

namespace cotton_harvester {
namespace sim {

namespace {

constexpr double kDegToRad = M_PI / 180.0;
constexpr const char* kFrameColour = "0.22 0.22 0.24 1";
constexpr const char* kTyreColour = "0.08 0.08 0.08 1";
constexpr const char* kArmColour = "0.3 0.3 0.32 1";      // anodised, dark: never bright like a boll
constexpr const char* kEffectorColour = "1 0.45 0.05 1";  // the orange housing (§2.6)

bool positive(double v) { return v > 0.0 && std::isfinite(v); }

std::string vec3(double x, double y, double z) {
  std::ostringstream s;
  s.precision(9);
  s << x << " " << y << " " << z;
  return s.str();
}

/// Writes the scene part by part: the options and the row, the rear body, the front body, the arm, the actuators.
class SceneWriter {
 public:
  explicit SceneWriter(const RoverSimParams& params)
      : p_(params),
        g_(params.geometry),
        th_(params.row.slope_deg * kDegToRad),
        r_(g_.wheel_radius_m),
        wy_(0.5 * (g_.width_m - g_.wheel_width_m)),
        cam_z_(g_.camera_height_m - r_),
        rail_y_(wy_ - 0.5 * g_.wheel_width_m - 0.08) {
    x_.precision(9);
  }

  std::string write(const std::string& worldbody) {
    options(worldbody);
    rearBody();
    frontBody();
    arm();
    actuators();
    return x_.str();
  }

 private:
  void options(const std::string& worldbody) {
    const int slices = p_.realism == thorvald_sim::Realism::kDatasheet ? thorvald_sim::kDatasheetRowRenderSlices : 32;
    x_ << "<mujoco model=\"cotton_rover_row\">\n"
       << "<compiler angle=\"radian\" autolimits=\"true\"/>\n"
       << "<option timestep=\"" << p_.timestep_s << "\" integrator=\"Euler\"/>\n"
       << "<visual><global offwidth=\"" << std::max(1280, p_.camera_width) << "\" offheight=\""
       << std::max(720, p_.camera_height) << "\"/><quality offsamples=\"0\" numslices=\"" << slices << "\" numstacks=\""
       << slices / 2 << "\"/></visual>\n"
       << "<default><geom contype=\"1\" conaffinity=\"3\" friction=\"1 0.005 0.0001\"/></default>\n"
       << "<worldbody>\n"
       << worldbody;
  }

  void wheel(const char* name, double ax, double ay) {
    x_ << "  <body name=\"" << name << "\" pos=\"" << vec3(ax, ay, 0) << "\">\n"
       << "   <joint name=\"" << name << "\" type=\"hinge\" axis=\"0 1 0\" damping=\"" << p_.wheel_damping
       << "\" armature=\"0.5\"/>\n"
       << "   <geom name=\"" << name << "_tyre\" type=\"sphere\" size=\"" << r_ << "\" mass=\"" << g_.wheel_mass_kg
       << "\" contype=\"2\" conaffinity=\"1\" rgba=\"" << kTyreColour << "\"/>\n  </body>\n";
  }

  /// The two side rails of a body's frame between x_from and x_to, each of half the mass.
  void frame(const std::string& name, double x_from, double x_to, double mass) {
    const double cx = 0.5 * (x_from + x_to), hx = 0.5 * std::abs(x_to - x_from);
    for (int side = -1; side <= 1; side += 2) {
      x_ << "  <geom name=\"" << name << (side > 0 ? "_left" : "_right") << "\" type=\"box\" pos=\""
         << vec3(cx, side * rail_y_, 0.9) << "\" size=\"" << vec3(hx, 0.06, 0.08) << "\" mass=\"" << 0.5 * mass
         << "\" contype=\"0\" conaffinity=\"0\" rgba=\"" << kFrameColour << "\"/>\n";
    }
  }

  /// Body frames sit at the wheels' centre height, pitched with the ground.
  void rearBody() {
    const double x0 = p_.start_x_m;
    const double bx = x0 - r_ * std::sin(th_), bz = x0 * std::tan(th_) + r_ * std::cos(th_) + 0.01;
    x_ << " <body name=\"rover_rear\" pos=\"" << vec3(bx, 0, bz) << "\" euler=\"0 " << -th_ << " 0\">\n"
       << "  <freejoint name=\"rover\"/>\n";
    frame("rear_frame", -g_.rear_length_m, 0.0, g_.rear_mass_kg);
    wheel(kRoverWheelNames[2], -g_.axle_to_joint_m, wy_);
    wheel(kRoverWheelNames[3], -g_.axle_to_joint_m, -wy_);
  }

  void frontBody() {
    x_ << "  <body name=\"rover_front\" pos=\"0 0 0\">\n"
       << "   <joint name=\"articulation\" type=\"hinge\" axis=\"0 0 1\" range=\""
       << -g_.articulation_limit_deg * kDegToRad << " " << g_.articulation_limit_deg * kDegToRad
       << "\" damping=\"20000\" armature=\"10\"/>\n";
    frame("front_frame", 0.0, g_.front_length_m, g_.front_mass_kg);
    // Top beam carrying the camera (above it: never in its view) and the arm's vertical mast.
    x_ << "   <geom name=\"camera_beam\" type=\"box\" pos=\"" << vec3(g_.camera_ahead_m, 0, cam_z_ + 0.12)
       << "\" size=\"" << vec3(0.06, rail_y_, 0.05) << "\" mass=\"20\" contype=\"0\" conaffinity=\"0\" rgba=\""
       << kFrameColour << "\"/>\n";
    const double mast_bottom = cam_z_ - g_.max_depth_m - 0.02, mast_top = cam_z_ + 0.07;
    x_ << "   <geom name=\"arm_mast\" type=\"box\" pos=\""
       << vec3(g_.camera_ahead_m + 0.12, -g_.arm_base_offset_m, 0.5 * (mast_bottom + mast_top)) << "\" size=\""
       << vec3(0.03, 0.03, 0.5 * (mast_top - mast_bottom)) << "\" mass=\"15\" contype=\"0\" conaffinity=\"0\" rgba=\""
       << kArmColour << "\"/>\n";
    wheel(kRoverWheelNames[0], g_.axle_to_joint_m, wy_);
    wheel(kRoverWheelNames[1], g_.axle_to_joint_m, -wy_);
  }

  /// The arm: the vertical axis carries the horizontal one; the end-effector slides along +y (camera x). Closes the
  /// front and rear bodies and the world body.
  void arm() {
    const double e = g_.effector_half_m, h = g_.effector_height_m;
    x_ << "   <body name=\"arm_carriage\" pos=\""
       << vec3(g_.camera_ahead_m, -g_.arm_base_offset_m, cam_z_ - g_.min_depth_m) << "\">\n"
       << "    <joint name=\"vertical\" type=\"slide\" axis=\"0 0 -1\" range=\"0 " << g_.max_depth_m - g_.min_depth_m
       << "\" damping=\"3000\" armature=\"5\"/>\n"
       << "    <geom name=\"arm_carriage_box\" type=\"box\" pos=\"0.08 0 -0.03\" size=\"0.04 0.05 0.04\" mass=\"8\" "
          "contype=\"0\" conaffinity=\"0\" rgba=\""
       << kArmColour << "\"/>\n"
       << "    <body name=\"end_effector\" pos=\"0 0 0\">\n"
       << "     <joint name=\"horizontal\" type=\"slide\" axis=\"0 1 0\" range=\"0 " << g_.horizontal_travel_m
       << "\" damping=\"3000\" armature=\"5\"/>\n"
       << "     <geom name=\"end_effector_housing\" type=\"box\" pos=\"" << vec3(0, 0, -0.5 * h) << "\" size=\""
       << vec3(e, e, 0.5 * h) << "\" mass=\"3\" contype=\"0\" conaffinity=\"" << housingContact() << "\" rgba=\""
       << kEffectorColour << "\"/>\n"
       << "     <geom name=\"horizontal_arm\" type=\"capsule\" fromto=\""
       << vec3(0, -e - 0.015, -0.03) + " " + vec3(0, -g_.horizontal_travel_m - 0.05, -0.03)
       << "\" size=\"0.015\" mass=\"2\" contype=\"0\" conaffinity=\"0\" rgba=\"" << kArmColour << "\"/>\n"
       << housingWalls() << "    </body>\n   </body>\n  </body>\n </body>\n</worldbody>\n";
  }

  void actuators() {
    x_ << "<actuator>\n";
    for (const char* w : kRoverWheelNames) x_ << " <motor name=\"" << w << "\" joint=\"" << w << "\" gear=\"1\"/>\n";
    // Datasheet: the steppers push the arm no harder than their force limit (a stem stops them, they lose steps).
    std::string limit;
    if (p_.realism == thorvald_sim::Realism::kDatasheet) {
      std::ostringstream f;
      f << " forcelimited=\"true\" forcerange=\"" << -p_.stepper_force_n << " " << p_.stepper_force_n << "\"";
      limit = f.str();
    }
    x_ << " <position name=\"articulation\" joint=\"articulation\" kp=\"200000\"/>\n"
       << " <position name=\"vertical\" joint=\"vertical\" kp=\"100000\"" << limit << "/>\n"
       << " <position name=\"horizontal\" joint=\"horizontal\" kp=\"100000\"" << limit << "/>\n"
       << "</actuator>\n</mujoco>\n";
  }

  /// The housing meets the datasheet plants; in ideal nothing. As a solid box (parts.hood_housing off) it meets
  /// leaves, stems and branches with its whole volume (stiff contacts: a stem does not let it sink in); as a hood
  /// (on) its box meets leaves only and its walls meet stems and branches, so a branch passes into its open mouth.
  std::string housingContact() const {
    if (p_.realism != thorvald_sim::Realism::kDatasheet) return "0";
    const int stems = p_.parts.hood_housing || !p_.parts.housing_meets_stems ? 0 : thorvald_sim::kStemContype;
    return std::to_string(thorvald_sim::kPlantContype | stems) + "\" solref=\"0.004 1\" solimp=\"0.95 0.99 0.001";
  }

  /// Datasheet: the housing's walls (invisible, 5 mm thick) meet the bolls (parts.housing_meets_bolls); its open
  /// mouth below does not, so a boll the nozzle comes down onto goes in while one the housing sweeps into is pushed.
  /// As a hood (parts.hood_housing) the housing is also open towards the boll, the way the arm extends to pick (the
  /// sideways pick of the paper, which takes bolls on the real rover, needs that intake), and its three walls meet
  /// stems and branches too.
  std::string housingWalls() const {
    if (p_.realism != thorvald_sim::Realism::kDatasheet) return "";
    const bool hood = p_.parts.hood_housing;
    const int bolls = p_.parts.housing_meets_bolls ? thorvald_sim::kBollContype : 0;
    const int affinity = bolls | (hood && p_.parts.housing_meets_stems ? thorvald_sim::kStemContype : 0);
    if (affinity == 0) return "";
    const double e = g_.effector_half_m, h = 0.5 * g_.effector_height_m, t = 0.0025;
    std::ostringstream w;
    w.precision(9);
    for (int k = 0; k < 4; ++k) {
      if (hood && k == 2) continue;  // the intake: the wall on the side the arm extends towards (+y, camera x)
      const bool along_x = k < 2;
      const double s = (k % 2 == 0 ? 1.0 : -1.0) * (e - t);
      w << "     <geom name=\"end_effector_wall" << k << "\" type=\"box\" pos=\""
        << (along_x ? vec3(s, 0, -h) : vec3(0, s, -h)) << "\" size=\"" << (along_x ? vec3(t, e, h) : vec3(e, t, h))
        << "\" mass=\"0.01\" contype=\"0\" conaffinity=\"" << affinity
        << (hood ? "\" solref=\"0.004 1\" solimp=\"0.95 0.99 0.001" : "") << "\" rgba=\"1 0.45 0.05 0\"/>\n";
    }
    return w.str();
  }

  const RoverSimParams& p_;
  const RoverGeometry& g_;
  const double th_;      ///< the ground's slope [rad]
  const double r_;       ///< wheel radius [m]
  const double wy_;      ///< the wheels' centres off the rover's middle [m]
  const double cam_z_;   ///< the camera above the body frames [m]
  const double rail_y_;  ///< the frame rails off the rover's middle [m]
  std::ostringstream x_;
};

}  // namespace

std::string RoverGeometry::check() const {
  const std::pair<const char*, double> lengths[] = {
      {"wheel_radius_m", wheel_radius_m},   {"front_length_m", front_length_m},
      {"rear_length_m", rear_length_m},     {"width_m", width_m},
      {"wheel_width_m", wheel_width_m},     {"axle_to_joint_m", axle_to_joint_m},
      {"camera_height_m", camera_height_m}, {"horizontal_travel_m", horizontal_travel_m},
      {"min_depth_m", min_depth_m},         {"max_depth_m", max_depth_m},
      {"effector_half_m", effector_half_m}, {"effector_height_m", effector_height_m},
      {"rear_mass_kg", rear_mass_kg},       {"front_mass_kg", front_mass_kg},
      {"wheel_mass_kg", wheel_mass_kg},     {"articulation_limit_deg", articulation_limit_deg}};
  for (const auto& [key, v] : lengths)
    if (!positive(v)) return std::string(key) + ": expected > 0";
  if (!(min_depth_m < max_depth_m)) return "min_depth_m: expected below max_depth_m";
  if (!(max_depth_m < camera_height_m)) return "max_depth_m: expected below camera_height_m";
  if (!(camera_height_m > 2.0 * wheel_radius_m)) return "camera_height_m: expected above the wheels";
  if (!(wheel_width_m < width_m)) return "wheel_width_m: expected below width_m";
  if (!(axle_to_joint_m < front_length_m && axle_to_joint_m < rear_length_m))
    return "axle_to_joint_m: expected inside the rover's length";
  if (!std::isfinite(camera_ahead_m) || !std::isfinite(arm_base_offset_m)) return "camera_ahead_m: expected finite";
  return "";
}

std::string RoverSimParams::check() const {
  if (auto bad = geometry.check(); !bad.empty()) return bad;
  if (const char* bad = drive.check(); bad && *bad) return bad;
  const std::pair<const char*, double> values[] = {{"timestep_s", timestep_s},
                                                   {"wheel_damping", wheel_damping},
                                                   {"vertical_speed_mps", vertical_speed_mps},
                                                   {"horizontal_speed_mps", horizontal_speed_mps},
                                                   {"capture_radius_m", capture_radius_m},
                                                   {"capture_time_s", capture_time_s},
                                                   {"fx", fx}};
  for (const auto& [key, v] : values)
    if (!positive(v)) return std::string(key) + ": expected > 0";
  if (timestep_s > 0.01) return "timestep_s: expected <= 0.01";
  if (camera_width < 16 || camera_height < 16 || camera_width > 4096 || camera_height > 4096)
    return "camera_width/height: expected 16..4096";
  if (!std::isfinite(start_x_m)) return "start_x_m: expected finite";
  if (!(leaf_push_max_m >= 0.0) || !std::isfinite(leaf_push_max_m)) return "leaf_push_max_m: expected >= 0";
  if (!(depth_noise_coeff >= 0.0) || !(depth_dropout >= 0.0 && depth_dropout < 1.0))
    return "depth_noise_coeff/depth_dropout: expected >= 0 (dropout < 1)";
  return "";
}

std::string roverSceneXml(const RoverSimParams& params, const std::string& worldbody) {
  return SceneWriter(params).write(worldbody);
}

}  // namespace sim
}  // namespace cotton_harvester
