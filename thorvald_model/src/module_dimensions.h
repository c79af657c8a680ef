#pragma once

// Sizes [m] and effective densities [kg/m^3] of the Thorvald II modules as the model draws them. An effective
// density is the module's mass divided by the volume of the primitive that draws it, chosen so that a standard
// module weighs what the real one does: steering module 8 kg, leg 3.5 kg, drive module (motor and gear at the
// hub) 7 kg, a 0.2 m x 0.16 m wheel 4 kg (22.5 kg per steered drive), battery enclosure 25 kg with a battery
// and 10 kg empty, aluminium frame tubes 1.1 kg/m.

namespace thorvald_model {
namespace dims {

constexpr double kLegLength = 0.45;  ///< axle to the bottom of the steering module [m]

constexpr double kSteeringBoxX = 0.20, kSteeringBoxY = 0.20, kSteeringBoxZ = 0.16;
constexpr double kSteeringDensity = 8.0 / (kSteeringBoxX * kSteeringBoxY * kSteeringBoxZ);

constexpr double kFixedMountX = 0.20, kFixedMountY = 0.20, kFixedMountZ = 0.05;  ///< type-1 drive bracket
constexpr double kFixedMountDensity = 1000.0;

constexpr double kLegX = 0.06, kLegY = 0.08;  ///< leg section [m]
constexpr double kLegArmZ = 0.06;             ///< height of the arm from the steering axis to the leg [m]
constexpr double kLegDensity = 1100.0;        ///< hollow aluminium section and cable guide

constexpr double kDriveRadius = 0.07, kDriveLength = 0.14;  ///< motor and gear housing beside the wheel [m]
constexpr double kDriveDensity = 7.0 / (3.14159265358979 * kDriveRadius * kDriveRadius * kDriveLength);

constexpr double kWheelDensity = 4.0 / (3.14159265358979 * 0.2 * 0.2 * 0.16);  ///< tyre and rim

constexpr double kBatteryX = 0.58, kBatteryY = 0.38, kBatteryZ = 0.28;
constexpr double kBatteryFullDensity = 25.0 / (kBatteryX * kBatteryY * kBatteryZ);
constexpr double kBatteryEmptyDensity = 10.0 / (kBatteryX * kBatteryY * kBatteryZ);

constexpr double kTubeOuterRadius = 0.024, kTubeInnerRadius = 0.021;  ///< 48 x 3 mm aluminium tube
constexpr double kAluminiumDensity = 2700.0;

constexpr double kCornerSize = 0.20;  ///< cast corner piece, cube edge [m]
constexpr double kCornerDensity = 4.0 / (kCornerSize * kCornerSize * kCornerSize);

constexpr double kForkX = 0.04, kForkClearance = 0.02;  ///< caster fork / passive wheel bracket plates [m]
constexpr double kForkDensity = 2500.0;
constexpr double kCasterWheelDensity = 400.0;  ///< rubber tyre on a plastic rim
constexpr double kMinForkHeight = 0.05;        ///< swivel mount above the caster axle, at least [m]

}  // namespace dims
}  // namespace thorvald_model
