#include "cotton_harvester_sim/rover_sim.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <thorvald_sim/ray_caster.h>
#include <thorvald_sim/sensors.h>

namespace cotton_harvester {
namespace sim {

namespace {

constexpr double kDegToRad = M_PI / 180.0;
const char* const kWheelNames[4] = {"wheel_front_left", "wheel_front_right", "wheel_rear_left", "wheel_rear_right"};
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

RoverSim::RoverSim(const RoverSimParams& params) : params_(params), drive_(params.drive), rng_(params.seed) {
  if (auto bad = params_.check(); !bad.empty()) throw std::invalid_argument("rover simulation: " + bad);
  xml_ = buildXml();
  model_ = thorvald_sim::compileXml(xml_, "cotton rover scene");
  data_.reset(mj_makeData(model_.get()));
  const mjModel* m = model_.get();
  auto id = [m](mjtObj type, const std::string& name) {
    const int i = mj_name2id(m, type, name.c_str());
    if (i < 0) throw thorvald_sim::ModelError("cotton rover scene: no " + name);
    return i;
  };
  rear_body_ = id(mjOBJ_BODY, "rover_rear");
  front_body_ = id(mjOBJ_BODY, "rover_front");
  effector_body_ = id(mjOBJ_BODY, "end_effector");
  for (int w = 0; w < 4; ++w) {
    wheel_joint_[w] = id(mjOBJ_JOINT, kWheelNames[w]);
    wheel_act_[w] = id(mjOBJ_ACTUATOR, kWheelNames[w]);
  }
  articulation_joint_ = id(mjOBJ_JOINT, "articulation");
  articulation_act_ = id(mjOBJ_ACTUATOR, "articulation");
  horizontal_act_ = id(mjOBJ_ACTUATOR, "horizontal");
  vertical_act_ = id(mjOBJ_ACTUATOR, "vertical");
  for (size_t i = 0; i < row_truth_.bolls.size(); ++i) {
    BollTruth b;
    const int plant = row_truth_.boll_plant[i];
    int index = 0;
    for (size_t j = 0; j < i; ++j) index += row_truth_.boll_plant[j] == plant ? 1 : 0;
    b.geom = id(mjOBJ_GEOM, "plant" + std::to_string(plant) + "_boll" + std::to_string(index));
    b.plant = plant;
    b.centre = row_truth_.bolls[i];
    bolls_.push_back(b);
  }
  // The arm starts at its rest: half way out, above the plants.
  const RoverGeometry& g = params_.geometry;
  horizontal_target_ = horizontal_now_ = std::min(0.35, g.horizontal_travel_m);
  vertical_target_ = vertical_now_ = std::clamp(1.2, g.min_depth_m, g.max_depth_m);
  data_->qpos[m->jnt_qposadr[id(mjOBJ_JOINT, "horizontal")]] = horizontal_now_;
  data_->qpos[m->jnt_qposadr[id(mjOBJ_JOINT, "vertical")]] = vertical_now_ - g.min_depth_m;
  mj_forward(m, data_.get());
  if (params_.leaf_push_max_m > 0.0) {
    for (int g = 0; g < m->ngeom; ++g) {
      const char* name = mj_id2name(m, mjOBJ_GEOM, g);
      if (!name || m->geom_type[g] != mjGEOM_ELLIPSOID || m->geom_bodyid[g] != 0) continue;
      const std::string n(name);
      if (n.size() < 5 || n.find("_leaf") == std::string::npos) continue;
      Leaf leaf;
      leaf.geom = g;
      leaf.grown_at = Eigen::Vector3d(m->geom_pos[3 * g], m->geom_pos[3 * g + 1], m->geom_pos[3 * g + 2]);
      leaf.half = Eigen::Vector3d(m->geom_size[3 * g], m->geom_size[3 * g + 1], m->geom_size[3 * g + 2]);
      leaf.rotation = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(data_->geom_xmat + 9 * g);
      leaves_.push_back(leaf);
    }
  }
  last_housing_ = nozzlePosition();
  renderer_ = std::make_unique<thorvald_sim::CameraRenderer>(m);
  // Let the rover settle on its wheels before anyone looks.
  advance(1.0);
  for (int w = 0; w < 4; ++w) wheel_start_angle_[w] = data_->qpos[m->jnt_qposadr[wheel_joint_[w]]];
}

RoverSim::~RoverSim() = default;

std::string RoverSim::buildXml() {
  const RoverGeometry& g = params_.geometry;
  thorvald_sim::WorldDescription world = thorvald_sim::makeCottonRowWorld(params_.row, &row_truth_);
  const double th = params_.row.slope_deg * kDegToRad;
  const double r = g.wheel_radius_m;
  const double x0 = params_.start_x_m;
  // Body frames sit at the wheels' centre height, pitched with the ground.
  const double bx = x0 - r * std::sin(th), bz = x0 * std::tan(th) + r * std::cos(th) + 0.01;
  const double wy = 0.5 * (g.width_m - g.wheel_width_m);
  const double cam_z = g.camera_height_m - r;
  const double rail_y = wy - 0.5 * g.wheel_width_m - 0.08;
  std::ostringstream x;
  x.precision(9);
  x << "<mujoco model=\"cotton_rover_row\">\n"
    << "<compiler angle=\"radian\" autolimits=\"true\"/>\n"
    << "<option timestep=\"" << params_.timestep_s << "\" integrator=\"Euler\"/>\n"
    << "<visual><global offwidth=\"" << std::max(1280, params_.camera_width) << "\" offheight=\""
    << std::max(720, params_.camera_height)
    << "\"/><quality offsamples=\"0\" numslices=\"32\" numstacks=\"16\"/></visual>\n"
    << "<default><geom contype=\"1\" conaffinity=\"3\" friction=\"1 0.005 0.0001\"/></default>\n"
    << "<worldbody>\n"
    << world.worldbody;
  auto wheel = [&](const char* name, double ax, double ay) {
    x << "  <body name=\"" << name << "\" pos=\"" << vec3(ax, ay, 0) << "\">\n"
      << "   <joint name=\"" << name << "\" type=\"hinge\" axis=\"0 1 0\" damping=\"" << params_.wheel_damping
      << "\" armature=\"0.5\"/>\n"
      << "   <geom name=\"" << name << "_tyre\" type=\"sphere\" size=\"" << r << "\" mass=\"" << g.wheel_mass_kg
      << "\" contype=\"2\" conaffinity=\"1\" rgba=\"" << kTyreColour << "\"/>\n  </body>\n";
  };
  auto frame = [&](const std::string& name, double x_from, double x_to, double mass) {
    const double cx = 0.5 * (x_from + x_to), hx = 0.5 * std::abs(x_to - x_from);
    for (int side = -1; side <= 1; side += 2) {
      x << "  <geom name=\"" << name << (side > 0 ? "_left" : "_right") << "\" type=\"box\" pos=\""
        << vec3(cx, side * rail_y, 0.9) << "\" size=\"" << vec3(hx, 0.06, 0.08) << "\" mass=\"" << 0.5 * mass
        << "\" contype=\"0\" conaffinity=\"0\" rgba=\"" << kFrameColour << "\"/>\n";
    }
  };
  x << " <body name=\"rover_rear\" pos=\"" << vec3(bx, 0, bz) << "\" euler=\"0 " << -th << " 0\">\n"
    << "  <freejoint name=\"rover\"/>\n";
  frame("rear_frame", -g.rear_length_m, 0.0, g.rear_mass_kg);
  wheel(kWheelNames[2], -g.axle_to_joint_m, wy);
  wheel(kWheelNames[3], -g.axle_to_joint_m, -wy);
  x << "  <body name=\"rover_front\" pos=\"0 0 0\">\n"
    << "   <joint name=\"articulation\" type=\"hinge\" axis=\"0 0 1\" range=\"" << -g.articulation_limit_deg * kDegToRad
    << " " << g.articulation_limit_deg * kDegToRad << "\" damping=\"20000\" armature=\"10\"/>\n";
  frame("front_frame", 0.0, g.front_length_m, g.front_mass_kg);
  // Top beam carrying the camera (above it: never in its view) and the arm's vertical mast.
  x << "   <geom name=\"camera_beam\" type=\"box\" pos=\"" << vec3(g.camera_ahead_m, 0, cam_z + 0.12) << "\" size=\""
    << vec3(0.06, rail_y, 0.05) << "\" mass=\"20\" contype=\"0\" conaffinity=\"0\" rgba=\"" << kFrameColour << "\"/>\n";
  const double mast_bottom = cam_z - g.max_depth_m - 0.02, mast_top = cam_z + 0.07;
  x << "   <geom name=\"arm_mast\" type=\"box\" pos=\""
    << vec3(g.camera_ahead_m + 0.12, -g.arm_base_offset_m, 0.5 * (mast_bottom + mast_top)) << "\" size=\""
    << vec3(0.03, 0.03, 0.5 * (mast_top - mast_bottom)) << "\" mass=\"15\" contype=\"0\" conaffinity=\"0\" rgba=\""
    << kArmColour << "\"/>\n";
  wheel(kWheelNames[0], g.axle_to_joint_m, wy);
  wheel(kWheelNames[1], g.axle_to_joint_m, -wy);
  // The arm: the vertical axis carries the horizontal one; the end-effector slides along +y (camera x).
  const double e = g.effector_half_m, h = g.effector_height_m;
  x << "   <body name=\"arm_carriage\" pos=\"" << vec3(g.camera_ahead_m, -g.arm_base_offset_m, cam_z - g.min_depth_m)
    << "\">\n"
    << "    <joint name=\"vertical\" type=\"slide\" axis=\"0 0 -1\" range=\"0 " << g.max_depth_m - g.min_depth_m
    << "\" damping=\"3000\" armature=\"5\"/>\n"
    << "    <geom name=\"arm_carriage_box\" type=\"box\" pos=\"0.08 0 -0.03\" size=\"0.04 0.05 0.04\" mass=\"8\" "
       "contype=\"0\" conaffinity=\"0\" rgba=\""
    << kArmColour << "\"/>\n"
    << "    <body name=\"end_effector\" pos=\"0 0 0\">\n"
    << "     <joint name=\"horizontal\" type=\"slide\" axis=\"0 1 0\" range=\"0 " << g.horizontal_travel_m
    << "\" damping=\"3000\" armature=\"5\"/>\n"
    << "     <geom name=\"end_effector_housing\" type=\"box\" pos=\"" << vec3(0, 0, -0.5 * h) << "\" size=\""
    << vec3(e, e, 0.5 * h) << "\" mass=\"3\" contype=\"0\" conaffinity=\"0\" rgba=\"" << kEffectorColour << "\"/>\n"
    << "     <geom name=\"horizontal_arm\" type=\"capsule\" fromto=\""
    << vec3(0, -e - 0.015, -0.03) + " " + vec3(0, -g.horizontal_travel_m - 0.05, -0.03)
    << "\" size=\"0.015\" mass=\"2\" contype=\"0\" conaffinity=\"0\" rgba=\"" << kArmColour << "\"/>\n"
    << "    </body>\n   </body>\n  </body>\n </body>\n</worldbody>\n<actuator>\n";
  for (const char* w : kWheelNames) x << " <motor name=\"" << w << "\" joint=\"" << w << "\" gear=\"1\"/>\n";
  x << " <position name=\"articulation\" joint=\"articulation\" kp=\"200000\"/>\n"
    << " <position name=\"vertical\" joint=\"vertical\" kp=\"100000\"/>\n"
    << " <position name=\"horizontal\" joint=\"horizontal\" kp=\"100000\"/>\n"
    << "</actuator>\n</mujoco>\n";
  return x.str();
}

void RoverSim::setSwashplatePwm(double pwm) {
  if (!std::isfinite(pwm)) return;
  pwm_command_ = std::clamp(pwm, params_.drive.pwm_min, params_.drive.pwm_max);
}

std::int32_t RoverSim::encoderCount() const {
  const mjModel* m = model_.get();
  double angle = 0.0;
  for (int w = 0; w < 2; ++w) angle += data_->qpos[m->jnt_qposadr[wheel_joint_[w]]] - wheel_start_angle_[w];
  const double metres = 0.5 * angle * params_.geometry.wheel_radius_m;
  return static_cast<std::int32_t>(std::trunc(metres / params_.drive.metres_per_pulse));
}

double RoverSim::potentiometerDeg() const { return data_->qpos[model_->jnt_qposadr[articulation_joint_]] / kDegToRad; }

void RoverSim::setArticulationDeg(double angle_deg) {
  if (!std::isfinite(angle_deg)) return;
  const double lim = params_.geometry.articulation_limit_deg;
  articulation_target_deg_ = std::clamp(angle_deg, -lim, lim);
}

void RoverSim::commandHorizontal(double extension_m) {
  if (std::isfinite(extension_m))
    horizontal_target_ = std::clamp(extension_m, 0.0, params_.geometry.horizontal_travel_m);
}

void RoverSim::commandVertical(double depth_m) {
  if (std::isfinite(depth_m))
    vertical_target_ = std::clamp(depth_m, params_.geometry.min_depth_m, params_.geometry.max_depth_m);
}

double RoverSim::time() const { return data_->time; }

void RoverSim::advance(double seconds) {
  const long steps = std::lround(std::max(0.0, seconds) / params_.timestep_s);
  for (long i = 0; i < steps; ++i) stepOnce();
}

void RoverSim::stepOnce() {
  const mjModel* m = model_.get();
  mjData* d = data_.get();
  const double dt = params_.timestep_s;
  drive_.step(pwm_command_, false, false, dt);
  const double wheel_rate = drive_.speedMps() / params_.geometry.wheel_radius_m;
  for (int w = 0; w < 4; ++w) d->ctrl[wheel_act_[w]] = params_.wheel_damping * wheel_rate;
  d->ctrl[articulation_act_] = articulation_target_deg_ * kDegToRad;
  auto ramp = [dt](double now, double target, double speed) {
    const double stepm = speed * dt;
    return std::abs(target - now) <= stepm ? target : now + std::copysign(stepm, target - now);
  };
  horizontal_now_ = ramp(horizontal_now_, horizontal_target_, params_.horizontal_speed_mps);
  vertical_now_ = ramp(vertical_now_, vertical_target_, params_.vertical_speed_mps);
  d->ctrl[horizontal_act_] = horizontal_now_;
  d->ctrl[vertical_act_] = vertical_now_ - params_.geometry.min_depth_m;
  mj_step(m, d);
  for (int i = 0; i < m->nq; ++i) {
    if (!std::isfinite(d->qpos[i])) {
      ++divergences_;
      throw std::runtime_error("rover simulation diverged (NaN in the state) at t = " + std::to_string(d->time));
    }
  }
  // The vacuum: a boll that stays close enough to the nozzle is sucked in and leaves the world.
  const Eigen::Vector3d nozzle = nozzlePosition();
  if (!leaves_.empty()) pushLeaves(nozzle - last_housing_);
  last_housing_ = nozzle;
  for (BollTruth& b : bolls_) {
    if (b.captured) continue;
    const double dist = (b.centre - nozzle).norm();
    if (vacuum_) b.closest_vacuum_m = std::min(b.closest_vacuum_m, dist);
    if (vacuum_ && dist <= params_.capture_radius_m) {
      b.near_nozzle_s += dt;
      if (b.near_nozzle_s >= params_.capture_time_s) {
        b.captured = true;
        b.captured_at_s = d->time;
        model_->geom_rgba[4 * b.geom + 3] = 0.0f;  // the renderer leaves invisible geoms out
      }
    } else {
      b.near_nozzle_s = 0.0;
    }
  }
}

void RoverSim::cameraPose(Eigen::Vector3d* origin, Eigen::Matrix3d* rotation) const {
  const RoverGeometry& g = params_.geometry;
  const Eigen::Map<const Eigen::Vector3d> p(data_->xpos + 3 * front_body_);
  const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rm(data_->xmat + 9 * front_body_);
  const Eigen::Matrix3d rb = rm;
  *origin = p + rb * Eigen::Vector3d(g.camera_ahead_m, 0.0, g.camera_height_m - g.wheel_radius_m);
  Eigen::Matrix3d optical;  // columns: the optical axes in the body: x = +y (left), y = +x (forward), z = down
  optical << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  *rotation = rb * optical;
}

Eigen::Vector3d RoverSim::toCamera(const Eigen::Vector3d& world) const {
  Eigen::Vector3d o;
  Eigen::Matrix3d r;
  cameraPose(&o, &r);
  return r.transpose() * (world - o);
}

void RoverSim::renderCamera(cv::Mat* bgr, cv::Mat* cloud) {
  const mjModel* m = model_.get();
  mj_forward(m, data_.get());
  thorvald_sim::SensorPose pose;
  cameraPose(&pose.origin, &pose.rotation);
  thorvald_sim::DepthCameraSpec depth;
  depth.width = params_.camera_width;
  depth.height = params_.camera_height;
  depth.focal_px = params_.fx;
  depth.cx_px = params_.cx;
  depth.cy_px = params_.cy;
  depth.range_min_m = 0.3;
  depth.range_max_m = 20.0;
  depth.noise_coeff = params_.depth_noise_coeff;
  depth.dropout = params_.depth_dropout;
  thorvald_sim::ColorCameraSpec colour;
  colour.width = depth.width;
  colour.height = depth.height;
  colour.focal_px = depth.focal_px;
  colour.cx_px = depth.cx_px;
  colour.cy_px = depth.cy_px;
  thorvald_sim::CameraView view = thorvald_sim::cameraView(depth, true);
  thorvald_sim::RenderedView rendered;
  renderer_->render(data_.get(), pose, view, -1, &rendered);
  const thorvald_sim::RayCaster caster(m, data_.get(), -1);
  thorvald_sim::DepthImage points;
  thorvald_sim::depthFromView(rendered, caster, pose, depth, rng_, &points, 1);
  const thorvald_sim::ColorImage rgb = thorvald_sim::colorFromView(rendered, m, colour);
  cv::Mat rgb_mat(rgb.height, rgb.width, CV_8UC3, const_cast<uint8_t*>(rgb.rgb.data()));
  bgr->create(rgb.height, rgb.width, CV_8UC3);
  for (int v = 0; v < rgb.height; ++v) {
    const uint8_t* src = rgb_mat.ptr<uint8_t>(v);
    uint8_t* dst = bgr->ptr<uint8_t>(v);
    for (int u = 0; u < rgb.width; ++u) {
      dst[3 * u] = src[3 * u + 2];
      dst[3 * u + 1] = src[3 * u + 1];
      dst[3 * u + 2] = src[3 * u];
    }
  }
  cloud->create(points.height, points.width, CV_32FC3);
  for (int v = 0; v < points.height; ++v) {
    cv::Vec3f* row = cloud->ptr<cv::Vec3f>(v);
    for (int u = 0; u < points.width; ++u) {
      const Eigen::Vector3f& q = points.points[static_cast<size_t>(v) * points.width + u];
      row[u] = cv::Vec3f(q.x(), q.y(), q.z());
    }
  }
}

void RoverSim::pushLeaves(const Eigen::Vector3d& motion) {
  // Only sideways motion pushes: a leaf the housing moves down or up onto bends and springs back (not modelled).
  const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rm(data_->xmat + 9 * effector_body_);
  const Eigen::Matrix3d housing_rotation = rm;
  const Eigen::Vector3d up = housing_rotation.col(2);
  const Eigen::Vector3d sideways = motion - motion.dot(up) * up;
  const double moved = sideways.norm();
  if (!(moved > 1e-7)) return;
  const Eigen::Vector3d d = sideways / moved;
  const Eigen::Vector3d centre = last_housing_ + motion;  // the housing's centre now
  const double e = params_.geometry.effector_half_m, h = 0.5 * params_.geometry.effector_height_m;
  const Eigen::Vector3d box_half(e, e, h);
  mjModel* m = model_.get();
  for (Leaf& leaf : leaves_) {
    double* pos = m->geom_pos + 3 * leaf.geom;
    const Eigen::Vector3d at(pos[0], pos[1], pos[2]);
    if ((at - centre).norm() > box_half.norm() + leaf.half.maxCoeff()) continue;
    // The leaf as its centre and eight points of its rim (0.9 of the semi-axes); each point inside the housing's
    // box grown by the leaf's thickness is pushed out through the face the housing moves towards.
    double push = 0.0;
    for (int k = -1; k < 8; ++k) {
      const double phi = M_PI * k / 4.0;
      const Eigen::Vector3d local =
          k < 0 ? Eigen::Vector3d::Zero()
                : Eigen::Vector3d(0.9 * leaf.half.x() * std::cos(phi), 0.9 * leaf.half.y() * std::sin(phi), 0.0);
      const Eigen::Vector3d q = housing_rotation.transpose() * (at + leaf.rotation * local - centre);
      const Eigen::Vector3d grown = box_half + Eigen::Vector3d::Constant(leaf.half.z());
      if ((q.cwiseAbs() - grown).maxCoeff() > 0.0) continue;
      const Eigen::Vector3d dl = housing_rotation.transpose() * d;
      const double front = grown.cwiseProduct(dl.cwiseAbs()).sum();  // the leading face's distance along d
      push = std::max(push, front - q.dot(dl));
    }
    if (!(push > 0.0)) continue;
    const Eigen::Vector3d next = at + push * d;
    if ((next - leaf.grown_at).norm() > params_.leaf_push_max_m) continue;  // held by its stalk: slips past
    pos[0] = next.x();
    pos[1] = next.y();
    pos[2] = next.z();
  }
}

int RoverSim::leavesPushed() const {
  int n = 0;
  for (const Leaf& leaf : leaves_) {
    const double* pos = model_->geom_pos + 3 * leaf.geom;
    n += (Eigen::Vector3d(pos[0], pos[1], pos[2]) - leaf.grown_at).norm() > 1e-4 ? 1 : 0;
  }
  return n;
}

int RoverSim::bollsCaptured() const {
  return static_cast<int>(std::count_if(bolls_.begin(), bolls_.end(), [](const BollTruth& b) { return b.captured; }));
}

bool RoverSim::bollInView(size_t index) const {
  if (index >= bolls_.size()) return false;
  const Eigen::Vector3d c = toCamera(bolls_[index].centre);
  if (!(c.z() > 0.0)) return false;
  const double u = params_.cx + params_.fx * c.x() / c.z(), v = params_.cy + params_.fx * c.y() / c.z();
  return u >= 0.0 && v >= 0.0 && u < params_.camera_width && v < params_.camera_height;
}

double RoverSim::bollVisibleFraction(size_t index) const {
  if (index >= bolls_.size()) return 0.0;
  Eigen::Vector3d origin;
  Eigen::Matrix3d rotation;
  cameraPose(&origin, &rotation);
  return visibleFractionFrom(index, origin);
}

double RoverSim::bestVisibleFractionAlongRow(size_t index, const std::vector<double>& offsets_m) const {
  if (index >= bolls_.size()) return 0.0;
  Eigen::Vector3d origin;
  Eigen::Matrix3d rotation;
  cameraPose(&origin, &rotation);
  const Eigen::Vector3d forward = rotation.col(1);  // the optical frame's y is forward along the row
  double best = 0.0;
  for (double offset : offsets_m) {
    const Eigen::Vector3d o = origin + offset * forward;
    const Eigen::Vector3d c = rotation.transpose() * (bolls_[index].centre - o);
    if (!(c.z() > 0.0)) continue;
    const double u = params_.cx + params_.fx * c.x() / c.z(), v = params_.cy + params_.fx * c.y() / c.z();
    if (u < 0.0 || v < 0.0 || u >= params_.camera_width || v >= params_.camera_height) continue;
    best = std::max(best, visibleFractionFrom(index, o));
  }
  return best;
}

double RoverSim::visibleFractionFrom(size_t index, const Eigen::Vector3d& origin) const {
  const BollTruth& b = bolls_[index];
  const Eigen::Vector3d view = (b.centre - origin).normalized();
  // Two directions across the line of sight span the disc the camera sees.
  const Eigen::Vector3d a = view.unitOrthogonal(), c = view.cross(a);
  const double r = 0.7 * params_.row.boll_radius_m;
  int visible = 0, rays = 0;
  for (int k = -1; k < 8; ++k) {
    const double phi = 2.0 * M_PI * k / 8.0;
    const Eigen::Vector3d target =
        k < 0 ? b.centre : Eigen::Vector3d(b.centre + r * (std::cos(phi) * a + std::sin(phi) * c));
    const Eigen::Vector3d dir = target - origin;
    int geom = -1;
    const mjtNum pnt[3] = {origin.x(), origin.y(), origin.z()}, vec[3] = {dir.x(), dir.y(), dir.z()};
    mj_ray(model_.get(), data_.get(), pnt, vec, nullptr, 1, -1, &geom);
    ++rays;
    visible += geom == b.geom ? 1 : 0;
  }
  return static_cast<double>(visible) / rays;
}

Eigen::Vector3d RoverSim::roverPosition() const {
  return Eigen::Map<const Eigen::Vector3d>(data_->xpos + 3 * rear_body_);
}

Eigen::Vector3d RoverSim::nozzlePosition() const {
  const Eigen::Map<const Eigen::Vector3d> p(data_->xpos + 3 * effector_body_);
  const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rm(data_->xmat + 9 * effector_body_);
  return p + rm * Eigen::Vector3d(0.0, 0.0, -0.5 * params_.geometry.effector_height_m);
}

}  // namespace sim
}  // namespace cotton_harvester
