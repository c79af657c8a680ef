#pragma once

#include <mujoco/mujoco.h>

#include <memory>
#include <stdexcept>
#include <string>

namespace thorvald_sim {

/// Owns a compiled MuJoCo model.
struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;

/// Owns MuJoCo simulation state.
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

/// A model that MuJoCo refused, with MuJoCo's message.
class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Compiles MJCF or URDF text (MuJoCo tells them apart by the root element) held in memory. Throws ModelError.
ModelPtr compileXml(const std::string& xml, const std::string& what);

/// Prepares a robot's URDF for MuJoCo: a dummy `world` link with a floating joint `<prefix>root` to the root link
/// (so the robot moves freely instead of being welded to the world) and compiler options that keep every link
/// as a body. Returns the root link's name in `root_link`. Throws ModelError for text that is not a URDF robot.
std::string prepareUrdf(const std::string& urdf, std::string* root_link);

/// Compiles a robot's URDF through MuJoCo and returns the MJCF it wrote (mj_saveLastXML): bodies, joints,
/// geoms and inertias as MuJoCo understood them, ready to be combined with a world. Throws ModelError.
std::string urdfToMjcf(const std::string& urdf, std::string* root_link);

}  // namespace thorvald_sim
