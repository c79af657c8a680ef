#pragma once

#include <Eigen/Core>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <thorvald_sim/camera_renderer.h>
#include <thorvald_sim/daylight.h>
#include <thorvald_sim/mjcf_compiler.h>
#include <thorvald_sim/realism.h>
#include <thorvald_sim/stereo_models.h>
#include <thorvald_sim/world.h>

#include "cotton_harvester/control/hydrostatic_drive_model.h"

namespace cotton_harvester {
namespace sim {

/// The rover's build (paper §2.1). Lengths [m], masses [kg]. The camera frame: x across the row (towards the
/// rover's left, the direction the horizontal arm extends), y along the row (forward), z down.
struct RoverGeometry {
  double wheel_radius_m = 0.3048;
  double front_length_m = 1.45;   ///< articulation joint to the front end
  double rear_length_m = 1.95;    ///< articulation joint to the rear end
  double width_m = 2.12;          ///< outer width
  double wheel_width_m = 0.30;    ///< the wheels' centres lie half of it inside the outer width
  double axle_to_joint_m = 0.91;  ///< both axles to the articulation joint
  double articulation_limit_deg = 45.0;
  double camera_height_m = 2.20;      ///< above the ground, rover level and at rest
  double camera_ahead_m = 1.30;       ///< camera ahead of the articulation joint
  double arm_base_offset_m = 0.55;    ///< the arm's vertical axis is at camera x = -this
  double horizontal_travel_m = 0.70;  ///< horizontal axis (§2.1)
  double min_depth_m = 0.30;          ///< end-effector top face below the camera, highest position
  double max_depth_m = 1.93;          ///< lowest position: 27 cm of ground clearance (§2.1)
  double effector_half_m = 0.05;      ///< end-effector housing: a box of this half side ...
  double effector_height_m = 0.08;    ///< ... and this height
  double rear_mass_kg = 520.0, front_mass_kg = 380.0, wheel_mass_kg = 40.0;
  std::string check() const;  ///< empty when sound
};

/// The `datasheet` parts that can be switched off one at a time to measure what each costs the harvest (all on:
/// the datasheet profile). Ignored in `ideal`.
struct DatasheetParts {
  bool passive_stereo = true;       ///< the ZED's passive-stereo depth; off: ideal's active-stereo depth
  bool daylight = true;             ///< shading, texture and exposure of the day; off: flat colours (and no shadows)
  bool shadows = true;              ///< the sun's hard shadows (sunny days)
  bool housing_meets_bolls = true;  ///< the housing's side walls push bolls; off: they pass through them
  bool knock_off = true;            ///< a boll's springs break over the break force; off: they never do
  /// The housing is a hood, open below and towards the boll (the arm's extension), that meets stems and branches
  /// with its walls; off: a solid box that meets them with its whole volume and bolls with all four side walls.
  bool hood_housing = true;
  bool housing_meets_stems = true;  ///< the housing stops at stems and branches; off: it passes through them
};

/// The simulator's figures: physics, the actuators' speeds and the vacuum. None of these is known to the harvest
/// stack; it only sees the encoder, the potentiometer, the stepper counters and the camera.
struct RoverSimParams {
  RoverGeometry geometry;
  control::HydrostaticDriveParams drive;  ///< swashplate PWM -> pump flow with the deadband and lag
  double timestep_s = 0.002;
  double wheel_damping = 3000.0;  ///< wheel velocity servo gain [N m s/rad] (hydraulic motors are stiff)
  /// false: all four wheels turn at the pump's speed, as before (they scrub when the rover is articulated); true: the
  /// hydraulic motors share the flow as a differential would, each wheel at the speed of its track on the turning
  /// circle that the articulation angle gives (the axles' centres at the pump's speed).
  bool differential_wheels = false;
  double vertical_speed_mps = 0.365;   ///< stepper: 150 steps/s at 410.7 steps/m (eq. 7)
  double horizontal_speed_mps = 0.30;  ///< stepper: 2000 steps/s on a 20-tooth 3 mm belt
  double capture_radius_m = 0.05;      ///< a boll whose centre is this close to the nozzle is sucked in ...
  double capture_time_s = 0.3;         ///< ... after the vacuum ran this long with it there
  /// Leaves give way to the end-effector's housing: a leaf it meets while moving sideways is pushed ahead of it
  /// and stays bent where it was pushed, up to this far from where it grew [m]; further it slips past the housing.
  /// 0: leaves do not interact with the arm (the housing passes through them).
  double leaf_push_max_m = 0.15;
  double start_x_m = -0.6;            ///< articulation joint's start position along the row (world x)
  thorvald_sim::CottonRowParams row;  ///< the row of plants with bolls
  /// When set: a field of rows (thorvald_sim::makeCottonFieldWorld, its rows' profile from `realism`) instead of
  /// `row`; row() then holds the whole field's plants and bolls.
  std::optional<thorvald_sim::CottonFieldParams> field;
  int camera_width = 1280, camera_height = 720;
  double fx = 699.936, cx = 685.286, cy = 361.248;  ///< the ZED's calibration (paper eq. 1)
  double depth_noise_coeff = 0.001;                 ///< active-stereo noise coefficient [1/m]
  double depth_dropout = 0.005;
  unsigned seed = 1;
  /// kIdeal: today's row (flat-coloured plants fixed to the world, leaves pushed by leaf_push_max_m) and camera
  /// (flat colours, active-stereo noise depth_noise_coeff). kDatasheet: the row's datasheet plants (row.datasheet:
  /// lobed bolls on breaking springs, springy leaves, rigid stems the housing cannot pass, soil clods and weeds),
  /// the housing colliding with them through the steppers' force limit, daylight drawn from the seed (sun, hard
  /// shadows or overcast, texture, exposure) and the ZED's passive-stereo depth (`stereo`).
  thorvald_sim::Realism realism = thorvald_sim::Realism::kIdeal;
  thorvald_sim::PassiveStereoModel stereo;  ///< datasheet: the ZED (120 mm baseline)
  double stepper_force_n = 1500.0;          ///< datasheet: the arm's axes push no harder than this [N]
  DatasheetParts parts;                     ///< datasheet: which of its parts are on (all by default)
  std::string check() const;                ///< empty when sound
};

/// A boll the simulation knows (truth, for scoring only).
struct BollTruth {
  int geom = -1;
  int body = -1;  ///< datasheet: the boll's own body (-1: a geom of the world body)
  int plant = 0;
  bool knocked_off = false;  ///< datasheet: broke off its branch (its springs' force exceeded the break force)
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< world [m]
  bool captured = false;
  double captured_at_s = 0.0;
  double near_nozzle_s = 0.0;  ///< vacuum time with the boll within the capture radius
  /// Closest approach of the nozzle to the centre while the vacuum ran [m] (infinity: never).
  double closest_vacuum_m = std::numeric_limits<double>::infinity();
};

/// The cotton rover and a row of cotton in MuJoCo: a centre-articulated body on four wheels driven by a
/// hydrostatic pump (the swashplate servo's PWM, its slew, the 80-98 deadband and the flow lag from
/// HydrostaticDriveModel set the wheels' speed; the wheels then roll by contact physics on the sloped ground), an
/// articulation joint held by the valve and read by a potentiometer, a 2-axis Cartesian arm whose steppers move
/// at a fixed speed, an orange vacuum end-effector, and the downward ZED camera rendered by thorvald_sim's
/// CameraRenderer (colour and an organised cloud with stereo noise). A pick happens in the simulation: a boll whose
/// centre stays within the capture radius of the nozzle while the vacuum runs is sucked in and leaves the world.
/// Not thread-safe; the renderer's OpenGL context belongs to the constructing thread.
class RoverSim {
 public:
  /// Builds the world and the rover. Throws std::invalid_argument on bad parameters, thorvald_sim::ModelError or
  /// thorvald_sim::RenderError when MuJoCo or the renderer refuse.
  explicit RoverSim(const RoverSimParams& params);
  ~RoverSim();

  // ---- What the rover's controllers command and read (the hardware interface) ----
  /// Swashplate servo PWM (65-120, neutral 90); clamped to the servo's range, NaN is ignored.
  void setSwashplatePwm(double pwm);
  /// Wheel encoder: whole pulses of metres_per_pulse travelled, from the simulated front wheels' rotation.
  std::int32_t encoderCount() const;
  /// Articulation potentiometer angle [deg] (the joint's angle; the valve holds it at the commanded angle).
  double potentiometerDeg() const;
  void setArticulationDeg(double angle_deg);
  /// Stepper targets: horizontal extension [0, travel] and end-effector depth below the camera [m]; clamped.
  void commandHorizontal(double extension_m);
  void commandVertical(double depth_m);
  /// Step counters as positions (open loop, like the steppers' controller reports them) [m].
  double horizontalPosition() const { return horizontal_now_; }
  double verticalPosition() const { return vertical_now_; }
  bool armMoving() const { return horizontal_now_ != horizontal_target_ || vertical_now_ != vertical_target_; }
  void setVacuum(bool on);
  bool vacuum() const { return vacuum_; }

  /// Advances the physics by `seconds` (whole time steps).
  void advance(double seconds);
  double time() const;

  /// Renders the camera: bgr CV_8UC3 and an organised CV_32FC3 cloud in the optical frame (NaN: no depth).
  void renderCamera(cv::Mat* bgr, cv::Mat* cloud);

  // ---- Truth (scoring and tests only) ----
  const std::vector<BollTruth>& bolls() const { return bolls_; }
  int bollsCaptured() const;
  /// Share of rays from the camera to points spread over the boll's disc (as the camera sees it) that reach the
  /// boll before anything else (a leaf, the arm) [0, 1]. Uses the state of the last renderCamera().
  double bollVisibleFraction(size_t index) const;
  /// The largest share as above from the camera moved along the row by each of `offsets_m` from where it is now
  /// (height, pitch and heading kept), counting only positions whose image holds the boll's centre: whether any
  /// camera position on the row could see the boll in the leaves' present state [0, 1].
  double bestVisibleFractionAlongRow(size_t index, const std::vector<double>& offsets_m) const;
  /// Whether the boll's centre projects into the camera image.
  bool bollInView(size_t index) const;
  /// World position of the articulation joint and the nozzle [m].
  Eigen::Vector3d roverPosition() const;
  Eigen::Vector3d nozzlePosition() const;
  /// Camera-frame position of a world point [m] (optical frame: x right, y down, z forward).
  Eigen::Vector3d toCamera(const Eigen::Vector3d& world) const;
  const thorvald_sim::CottonRowTruth& row() const { return row_truth_; }
  const RoverSimParams& params() const { return params_; }
  /// Leaves the housing has pushed away from where they grew (datasheet: leaves bent over 0.1 rad now).
  int leavesPushed() const;
  /// Bolls knocked off their branch (datasheet).
  int bollsKnockedOff() const;
  /// The day drawn for this run (datasheet; ideal draws none and shades nothing).
  const thorvald_sim::Daylight& daylight() const { return daylight_; }
  void setDaylight(const thorvald_sim::Daylight& d) { daylight_ = d; }
  /// The last frame's true depth along the optical axis [m] (NaN: nothing) and what the camera reported.
  const std::vector<float>& lastTrueDepth() const { return true_depth_; }
  /// Which boll a geom belongs to (its lobes and core; -1: none).
  int bollOfGeom(int geom) const;
  /// Physics divergences (NaN) seen; the run is then not trusted.
  int divergences() const { return divergences_; }
  /// The compiled scene as MJCF (for viewing it in MuJoCo's simulate).
  const std::string& sceneXml() const { return xml_; }
  /// The MuJoCo model and state, read-only (the rover's sensors, rover_sensors.h, read their truth from them).
  const mjModel* model() const { return model_.get(); }
  const mjData* data() const { return data_.get(); }

 private:
  void stepOnce();
  void cameraPose(Eigen::Vector3d* origin, Eigen::Matrix3d* rotation) const;
  double visibleFractionFrom(size_t index, const Eigen::Vector3d& origin) const;
  /// Pushes the leaves the housing meets as it moves by `motion` (world [m]) this step.
  void pushLeaves(const Eigen::Vector3d& motion);
  /// Datasheet: bolls follow their bodies; one whose springs pull harder than the break force comes off.
  void updateBollBodies();
  void setupDatasheet();
  void hideBoll(const BollTruth& b);
  /// Datasheet: daylight and texture on `rgb`, passive-stereo depth from the true depth into `depth_z`.
  void datasheetCamera(const thorvald_sim::RenderedView& view, const thorvald_sim::SensorPose& pose,
                       const thorvald_sim::Intrinsics& k, thorvald_sim::ColorImage* rgb, std::vector<float>* depth_z);

  /// A leaf of the row: a flat ellipsoid geom of the world body that the housing can push aside.
  struct Leaf {
    int geom = -1;
    Eigen::Vector3d grown_at = Eigen::Vector3d::Zero();  ///< where it grew (world) [m]
    Eigen::Vector3d half = Eigen::Vector3d::Zero();      ///< semi-axes [m]
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  };
  std::vector<Leaf> leaves_;
  Eigen::Vector3d last_housing_ = Eigen::Vector3d::Zero();

  RoverSimParams params_;
  thorvald_sim::CottonRowTruth row_truth_;
  std::string xml_;
  thorvald_sim::ModelPtr model_;
  thorvald_sim::DataPtr data_;
  std::unique_ptr<thorvald_sim::CameraRenderer> renderer_;
  control::HydrostaticDriveModel drive_;
  std::mt19937 rng_;
  double pwm_command_ = 90.0;
  double articulation_target_deg_ = 0.0;
  double horizontal_target_ = 0.0, horizontal_now_ = 0.0;
  double vertical_target_ = 0.0, vertical_now_ = 0.0;
  bool vacuum_ = false;
  int divergences_ = 0;
  std::vector<BollTruth> bolls_;
  std::vector<int> geom_boll_;       ///< geom -> boll index (lobes and core), -1
  std::vector<float> texture_;       ///< datasheet: texture amplitude per geom
  std::vector<int> leaf_joints_;     ///< datasheet: the leaves' hinges
  thorvald_sim::Daylight daylight_;  ///< datasheet
  std::vector<float> true_depth_;
  thorvald_sim::ShadowMapCache shadows_;               ///< datasheet: the sun's view, kept while the plants stay still
  thorvald_sim::PassiveStereoScratch stereo_scratch_;  ///< datasheet
  // MuJoCo ids
  int front_body_ = -1, effector_body_ = -1, rear_body_ = -1;
  int wheel_joint_[4] = {-1, -1, -1, -1};
  int wheel_act_[4] = {-1, -1, -1, -1};
  int articulation_joint_ = -1, articulation_act_ = -1, horizontal_act_ = -1, vertical_act_ = -1;
  double wheel_start_angle_[4] = {0, 0, 0, 0};
};

}  // namespace sim
}  // namespace cotton_harvester
