#include "cotton_harvester_sim/rover_sim.h"

#include "cotton_harvester_sim/rover_scene.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <thorvald_sim/ray_caster.h>
#include <thorvald_sim/sensors.h>

namespace cotton_harvester {
namespace sim {

namespace {

constexpr double kDegToRad = M_PI / 180.0;

}  // namespace

RoverSim::RoverSim(const RoverSimParams& params) : params_(params), drive_(params.drive), rng_(params.seed) {
  if (auto bad = params_.check(); !bad.empty()) throw std::invalid_argument("rover simulation: " + bad);
  params_.row.datasheet = params_.realism == thorvald_sim::Realism::kDatasheet;
  thorvald_sim::WorldDescription world;
  if (params_.field) {
    params_.field->row.datasheet = params_.row.datasheet;
    thorvald_sim::CottonFieldTruth field;
    world = thorvald_sim::makeCottonFieldWorld(*params_.field, &field);
    row_truth_ = field.plants;
  } else {
    world = thorvald_sim::makeCottonRowWorld(params_.row, &row_truth_);
  }
  xml_ = roverSceneXml(params_, world.worldbody);
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
    wheel_joint_[w] = id(mjOBJ_JOINT, kRoverWheelNames[w]);
    wheel_act_[w] = id(mjOBJ_ACTUATOR, kRoverWheelNames[w]);
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
  geom_boll_.assign(m->ngeom, -1);
  for (size_t i = 0; i < bolls_.size(); ++i) geom_boll_[bolls_[i].geom] = static_cast<int>(i);
  if (params_.row.datasheet) setupDatasheet();
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
  // Left wheels (0, 2) on the inside of a left turn (positive articulation): slower by the half track times the axles'
  // curvature tan(gamma / 2) / axle_to_joint.
  const RoverGeometry& g = params_.geometry;
  const double curvature =
      params_.differential_wheels ? std::tan(0.5 * potentiometerDeg() * kDegToRad) / g.axle_to_joint_m : 0.0;
  const double half_track = 0.5 * (g.width_m - g.wheel_width_m);
  for (int w = 0; w < 4; ++w) {
    const double side = w % 2 == 0 ? 1.0 : -1.0;
    d->ctrl[wheel_act_[w]] = params_.wheel_damping * wheel_rate * (1.0 - side * half_track * curvature);
  }
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
  if (params_.row.datasheet) updateBollBodies();
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
        hideBoll(b);
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
  thorvald_sim::DepthImage points;
  thorvald_sim::ColorImage rgb = thorvald_sim::colorFromView(rendered, m, colour);
  std::vector<float> z;
  if (params_.row.datasheet) datasheetCamera(rendered, pose, thorvald_sim::intrinsics(depth), &rgb, &z);
  if (!z.empty()) {
    points.width = depth.width;
    points.height = depth.height;
    points.points.resize(z.size());
    const thorvald_sim::Intrinsics k = thorvald_sim::intrinsics(depth);
    for (int v = 0; v < depth.height; ++v)
      for (int u = 0; u < depth.width; ++u) {
        const size_t i = static_cast<size_t>(v) * depth.width + u;
        const float zi = z[i];
        points.points[i] =
            Eigen::Vector3f(static_cast<float>(zi * (u - k.cx) / k.fx), static_cast<float>(zi * (v - k.cy) / k.fy), zi);
      }
  } else {
    const thorvald_sim::RayCaster caster(m, data_.get(), -1);
    thorvald_sim::depthFromView(rendered, caster, pose, depth, rng_, &points, 1);
  }
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
  for (int j : leaf_joints_) n += std::abs(data_->qpos[model_->jnt_qposadr[j]]) > 0.1 ? 1 : 0;
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
    visible += bollOfGeom(geom) == static_cast<int>(index) ? 1 : 0;
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
