#pragma once

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace YAML {
class Node;
}

namespace thorvald_base {

/// A robot file that cannot be turned into a robot: says which file, which module, which key, what was expected.
class ConfigError : public std::runtime_error {
 public:
  ConfigError(const std::string& source, const std::string& where, const std::string& what)
      : std::runtime_error(source + ": " + where + ": " + what), source_(source), where_(where), what_(what) {}
  const std::string& source() const { return source_; }
  /// Module and key, e.g. "motor_drives.drive2.r_wheel".
  const std::string& where() const { return where_; }
  const std::string& problem() const { return what_; }

 private:
  std::string source_, where_, what_;
};

/// One drive module (`motor_drives.driveN`). Units SI: metres, radians.
struct DriveConfig {
  int index = 0;                      ///< N of driveN
  int node = 0;                       ///< CAN node id
  double x = 0.0;                     ///< position in base_link [m]
  double y = 0.0;                     ///< position in base_link [m]
  int type = 0;                       ///< 0 steering + propulsion, 1 propulsion only
  int leg_mesh = 0;                   ///< leg geometry for the model (0-9)
  double r_wheel = 0.0;               ///< wheel radius [m]
  double w_wheel = 0.16;              ///< wheel width [m]
  double prp_gr_rt = 0.0;             ///< propulsion gear ratio (motor turns per wheel turn)
  double prp_enc_ppr = 0.0;           ///< propulsion encoder pulses per motor revolution
  double prp_max_rpm = 0.0;           ///< motor rpm mapped to a full-scale command
  double prp_sim_a = 1.5;             ///< simulated propulsion acceleration limit [m/s^2]
  double str_gr_rt = 0.0;             ///< steering gear ratio
  double str_enc_ppr = 0.0;           ///< steering encoder pulses per revolution
  double str_lim = 0.0;               ///< steering limit, symmetric [rad]
  double str_sim_v = 4.0;             ///< simulated steering rate [rad/s]
  std::string protocol = "thorvald";  ///< controller protocol (workspace key `protocol`): thorvald | cia402

  bool steered() const { return type == 0; }
};

/// Battery enclosure (`batteries.batN`).
struct BatteryConfig {
  std::string name;  ///< batN
  int id = -1;       ///< battery id on the bus; -1: no battery in this enclosure
  int type = 1;      ///< 0 empty enclosure, 1 battery
  double x = 0, y = 0, z = 0, yaw = 0;
  int bat_mesh = 0;
  bool with_battery = true;
  bool present() const { return type != 0 && with_battery && id >= 0; }
};

/// A frame tube pair between two points (`pipes.<name>`).
struct PipeConfig {
  std::string name;
  double x1 = 0, y1 = 0, x2 = 0, y2 = 0, height = 0, space = 0;
};

/// A frame corner (`corners.<name>`).
struct CornerConfig {
  std::string name;
  int type = 0, corner_mesh = 0;
  double x = 0, y = 0, z = 0, space = 0, susp_ang = 0;
};

/// A beam joining two drives (`beams.<name>`).
struct BeamConfig {
  std::string name, start, end;
};

/// A caster or a passive (unpowered, fixed) wheel.
struct PassiveWheelConfig {
  std::string name;
  double x = 0, y = 0, z_top = 0, r_wheel = 0.1, w_wheel = 0.05, offset = 0;
};

/// A relay board (`io.ioN`).
struct IoConfig {
  std::string name;
  int id = 0, type = 0, rl0_init_state = 0, rl1_init_state = 0;
};

/// Everything one robot file says. Drives are ordered by their index (drive0 first).
struct RobotConfig {
  std::string source;           ///< file or parameter namespace it came from
  std::string base_calculator;  ///< plugin name as written (normalised: ':' -> '::'), default standard
  std::vector<DriveConfig> drives;
  std::vector<BatteryConfig> batteries;
  std::vector<PipeConfig> pipes;
  std::vector<CornerConfig> corners;
  std::vector<BeamConfig> beams;
  std::vector<PassiveWheelConfig> casters;
  std::vector<PassiveWheelConfig> passive_wheels;
  std::vector<IoConfig> io;
  /// `implement_can_ids`: 11-bit CAN ids of implements on the base's bus (not drives or batteries); base_driver's
  /// relay lets users send these and no others.
  std::vector<int> implement_can_ids;
  std::vector<std::string> warnings;  ///< unknown keys and other things worth one log line each
};

/// Largest |x| or |y| of any module relative to base_link [m]; beyond it a position is a typing slip.
constexpr double kMaxModuleOffset_m = 10.0;
/// Most drives a robot file may declare (CAN node ids 1..127 must stay unique).
constexpr size_t kMaxDrives = 64;
/// Most modules in any other group (batteries, pipes, ...).
constexpr size_t kMaxModulesPerGroup = 256;

/// Highest standard (11-bit) CAN identifier.
constexpr int kMaxCanStdId = 0x7FF;

/// Plugin name used when a robot file names none.
constexpr const char* kDefaultBaseCalculator = "pltf_clc_std::PltfClcStd";

/// The module group a top-level key most likely means ("caster" -> "casters", "motor_drive" -> "motor_drives"),
/// the key itself when it is a group, "" when it resembles none.
std::string nearestRobotFileGroup(const std::string& key);

/// Parses a robot file already read into a YAML tree. `source` names it in errors. Throws ConfigError.
RobotConfig parseRobotConfig(const YAML::Node& root, const std::string& source);

/// Reads and parses a robot file. Throws ConfigError (also for an unreadable file or broken YAML).
RobotConfig loadRobotConfigFile(const std::string& path);

/// Checks the values of one drive against the physical range of every key (docs/robot_file.md). `where` prefixes the
/// key in errors. Throws ConfigError.
void validateDrive(const DriveConfig& drive, const std::string& source, const std::string& where);

/// Refuses CAN node ids used twice (a CiA 402 steered drive also uses node + 64), in every mode, so the mistake
/// shows before the robot. Only two consecutive type-1 drives of protocol `thorvald` may share a node id: the two
/// channels of one controller. parseRobotConfig calls it. Throws ConfigError.
void validateCanNodeIds(const std::vector<DriveConfig>& drives, const std::string& source);

/// Refuses implement CAN ids outside 0x001..0x7FF or listed twice. `where` names the list in errors (e.g.
/// "implement_can_ids"). Throws ConfigError.
void validateImplementCanIds(const std::vector<int>& ids, const std::string& source, const std::string& where);
/// Refuses drives closer to each other than their wheels allow (e.g. every drive at one point). Parsing and
/// every kinematics plugin's configure call it. Throws ConfigError.
void validateDriveSpacing(const std::vector<DriveConfig>& drives, const std::string& source);

/// Refuses drives and passive wheels whose equations leave (vx, vy, wz) undetermined, so odometry would report no
/// motion while the wheels turn (one drive alone, or one drive with passive wheels on its own axle line). The
/// kinematics plugins call it in configure. Throws ConfigError.
void validateObservability(const std::vector<DriveConfig>& drives, const std::vector<PassiveWheelConfig>& passive,
                           const std::string& source);

/// Sets one drive key by the name used in the robot file (aliases accepted). Returns false for a key that
/// cannot be changed this way. The caller validates the result with validateDrive.
bool setDriveKey(DriveConfig& drive, const std::string& key, double value);

}  // namespace thorvald_base
