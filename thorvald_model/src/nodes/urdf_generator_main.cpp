// urdf_generator: writes a Thorvald robot's URDF from its robot file (a path, or the parameter server).
// Usable from a launch file: <param name="robot_description" command="$(find thorvald_model)/... --config f"/>.

#include <ros/ros.h>

#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>

#include "thorvald_base/robot_config.h"
#include "thorvald_model/model_builder.h"
#include "thorvald_model/urdf_writer.h"
#include "thorvald_base/ros/robot_config_params.h"

namespace {

const char* kUsage =
    "usage: urdf_generator [--config <robot.yaml> | --param-ns <namespace>] [--tf-prefix <p>]\n"
    "                      [--robot-name <n>] [--extras <fragment.urdf>]... [--output <file>]\n"
    "                      [--mujoco] [--floating-base]\n"
    "  --config      robot file; without it the robot file is read from the parameter server under\n"
    "                --param-ns (default: this process's namespace, e.g. ROS_NAMESPACE)\n"
    "  --tf-prefix   prefix of every link and joint name (as base_driver's tf_prefix)\n"
    "  --robot-name  <robot name=...> (default thorvald)\n"
    "  --extras      URDF fragment merged into the model (repeatable; an empty value is ignored)\n"
    "  --output      file to write (default stdout)\n"
    "  --mujoco      add MuJoCo compiler options (keep fixed links as bodies, drop visuals)\n"
    "  --floating-base  add a `world` link and a floating joint to base_link\n";

struct Arguments {
  std::string config, param_ns, output;
  bool from_param_server = true;
  thorvald_model::ModelOptions model;
  thorvald_model::WriteOptions write;
  std::vector<std::string> extras;
};

/// Parses the command line; throws std::invalid_argument with the problem.
Arguments parseArguments(const std::vector<std::string>& args) {
  Arguments a;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& key = args[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= args.size()) throw std::invalid_argument(key + " needs a value");
      return args[++i];
    };
    if (key == "--config") {
      a.config = value();
      a.from_param_server = false;
    } else if (key == "--param-ns") {
      a.param_ns = value();
    } else if (key == "--tf-prefix") {
      a.model.tf_prefix = value();
      while (!a.model.tf_prefix.empty() && a.model.tf_prefix.front() == '/') a.model.tf_prefix.erase(0, 1);
      while (!a.model.tf_prefix.empty() && a.model.tf_prefix.back() == '/') a.model.tf_prefix.pop_back();
    } else if (key == "--robot-name") {
      a.model.robot_name = value();
    } else if (key == "--extras") {
      const std::string path = value();
      if (!path.empty()) a.extras.push_back(path);  // empty: a launch file's optional fragment left unset
    } else if (key == "--output") {
      a.output = value();
    } else if (key == "--mujoco") {
      a.write.mujoco_compiler = true;
    } else if (key == "--floating-base") {
      a.model.floating_base = true;
    } else if (key == "-h" || key == "--help") {
      std::cout << kUsage;
      std::exit(0);
    } else if (key.rfind("__", 0) == 0 || key.rfind("_", 0) == 0) {
      continue;  // roslaunch remappings (__name:=, __log:=) when started as a node
    } else if (key.empty()) {
      continue;  // an empty launch argument expands to ""
    } else {
      throw std::invalid_argument("unknown argument '" + key + "'");
    }
  }
  a.write.tf_prefix = a.model.tf_prefix;
  return a;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot read the file");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

thorvald_base::RobotConfig readFromParameterServer(int argc, char** argv, const std::string& ns_arg) {
  ros::init(argc, argv, "urdf_generator", ros::init_options::AnonymousName | ros::init_options::NoSigintHandler);
  if (!ros::master::check())
    throw std::runtime_error("no --config given and no ROS master to read the robot file from");
  const std::string ns = ns_arg.empty() ? ros::this_node::getNamespace() : ros::names::resolve(ns_arg);
  return thorvald_base::robotConfigFromParams(ros::NodeHandle(ns));
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Arguments args = parseArguments(std::vector<std::string>(argv + 1, argv + argc));
    const thorvald_base::RobotConfig config = args.from_param_server
                                                  ? readFromParameterServer(argc, argv, args.param_ns)
                                                  : thorvald_base::loadRobotConfigFile(args.config);
    const thorvald_model::UrdfTree tree = thorvald_model::buildModel(config, args.model);
    for (const auto& w : tree.warnings) std::cerr << "urdf_generator: " << config.source << ": " << w << "\n";
    std::vector<thorvald_model::UrdfFragment> fragments;
    for (const auto& path : args.extras) fragments.push_back({path, readFile(path)});
    const std::string urdf = thorvald_model::writeUrdf(tree, fragments, args.write);
    if (args.output.empty()) {
      std::cout << urdf;
    } else {
      std::ofstream out(args.output);
      out << urdf;
      if (!out) throw std::runtime_error(args.output + ": cannot write the file");
    }
    return 0;
  } catch (const std::invalid_argument& e) {
    std::cerr << "urdf_generator: " << e.what() << "\n" << kUsage;
  } catch (const std::exception& e) {
    std::cerr << "urdf_generator: " << e.what() << "\n";
  }
  return 1;
}
