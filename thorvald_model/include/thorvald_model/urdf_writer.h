#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "thorvald_model/urdf_tree.h"

namespace thorvald_model {

/// A user URDF fragment (sensors, a custom frame, a tool) to merge into the generated model.
struct UrdfFragment {
  std::string source;  ///< file name, for errors
  std::string text;    ///< a <robot> element holding links, joints, materials, ... (any <robot> name)
};

/// A fragment that cannot be merged: names the fragment, the element and what is wrong.
class FragmentError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct WriteOptions {
  std::string tf_prefix;         ///< prefix applied to the fragments' link and joint names (as buildModel does)
  bool mujoco_compiler = false;  ///< add <mujoco><compiler .../></mujoco> for MuJoCo's URDF reader
};

/// Writes the model as URDF XML and merges the fragments into it. In a fragment, every link name, joint name
/// and joint parent/child link is prefixed "<tf_prefix>/" unless it already is, so one fragment serves every
/// robot; a fragment's joint may name any generated link as parent. Throws FragmentError for unreadable XML,
/// a duplicate link or joint name, a joint whose parent or child link does not exist, or a link with two parents.
std::string writeUrdf(const UrdfTree& tree, const std::vector<UrdfFragment>& fragments, const WriteOptions& options);

}  // namespace thorvald_model
