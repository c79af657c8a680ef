// urdf_generator: writes a Thorvald robot's URDF from its robot file (a path, or the parameter server).
// Usable from a launch file: <param name="robot_description" command="$(find thorvald_model)/... --config f"/>.

#include <ros/ros.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstring>
#include <set>
#include <fstream>
#include <iostream>
#include <sstream>

#include "thorvald_common/command_line.h"
#include "thorvald_base/robot_config.h"
#include "thorvald_model/model_builder.h"
#include "thorvald_model/urdf_writer.h"
#include "thorvald_base/ros/base_calculator_loader.h"
#include "thorvald_base/ros/robot_config_params.h"

namespace {

struct Arguments {
  std::string config, param_ns, output;
  bool from_param_server = true;
  thorvald_model::ModelOptions model;
  thorvald_model::WriteOptions write;
  std::vector<std::string> extras;
};

/// Parses the command line (thorvald_common/command_line.h): --help exits 0, a usage error exits 2 naming it.
/// roslaunch's own arguments (__name:=, __log:=) and empty words that are no option's value are dropped first.
Arguments parseArguments(int argc, char** argv) {
  std::vector<std::string> words;
  ros::removeROSArgs(argc, argv, words);
  static const std::set<std::string> takes_value = {"--config",     "--param-ns", "--tf-prefix",
                                                    "--robot-name", "--extras",   "--output"};
  std::vector<std::string> kept;
  for (size_t i = 1; i < words.size(); ++i) {
    // An empty word is the value of an option left unset in a launch file; on its own it is dropped.
    if (!words[i].empty() || takes_value.count(words[i - 1])) kept.push_back(words[i]);
  }
  Arguments a;
  CLI::App app("Writes a Thorvald robot's URDF from its robot file (a path, or the parameter server).",
               "urdf_generator");
  app.add_option("--config", a.config,
                 "robot file; without it the robot file is read from the parameter server under --param-ns");
  app.add_option("--param-ns", a.param_ns,
                 "namespace of the robot file on the parameter server (default: this "
                 "process's namespace, e.g. ROS_NAMESPACE)");
  app.add_option("--tf-prefix", a.model.tf_prefix, "prefix of every link and joint name (as base_driver's tf_prefix)");
  app.add_option("--robot-name", a.model.robot_name, "<robot name=...>")->capture_default_str();
  app.add_option("--extras", a.extras, "URDF fragment merged into the model (repeatable; empty values are ignored)")
      ->take_all();
  app.add_option("--output", a.output, "file to write (default stdout)");
  app.add_flag("--mujoco", a.write.mujoco_compiler,
               "add MuJoCo compiler options (keep fixed links as bodies, drop visuals)");
  app.add_flag("--floating-base", a.model.floating_base, "add a `world` link and a floating joint to base_link");
  if (const auto code = thorvald_common::parseCommandLine(app, kept)) std::exit(*code);
  a.from_param_server = a.config.empty();
  a.extras.erase(std::remove(a.extras.begin(), a.extras.end(), std::string()), a.extras.end());
  while (!a.model.tf_prefix.empty() && a.model.tf_prefix.front() == '/') a.model.tf_prefix.erase(0, 1);
  while (!a.model.tf_prefix.empty() && a.model.tf_prefix.back() == '/') a.model.tf_prefix.pop_back();
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
    const Arguments args = parseArguments(argc, argv);
    const thorvald_base::RobotConfig config = args.from_param_server
                                                  ? readFromParameterServer(argc, argv, args.param_ns)
                                                  : thorvald_base::loadRobotConfigFile(args.config);
    for (const auto& w : config.warnings) std::cerr << "urdf_generator: " << w << "\n";
    thorvald_base::BaseCalculatorLoader().check(config);  // the kinematics plugin as base_driver would load it
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
  } catch (const std::exception& e) {
    std::cerr << "urdf_generator: " << e.what() << "\n";
  }
  return 1;
}
