#!/usr/bin/python3
"""urdf_generator from the parameter server equals urdf_generator from the file; model.launch loads the model."""
import subprocess
import unittest
import xml.etree.ElementTree as ET

import rospy
import rostest


def summary(urdf_text):
    """Links with their masses and joints with type, parent, child and origin: order-independent."""
    robot = ET.fromstring(urdf_text)
    links = {}
    for link in robot.findall("link"):
        mass = link.find("inertial/mass")
        links[link.get("name")] = round(float(mass.get("value")), 9) if mass is not None else 0.0
    joints = {}
    for j in robot.findall("joint"):
        origin = j.find("origin")
        joints[j.get("name")] = (j.get("type"), j.find("parent").get("link"), j.find("child").get("link"),
                                 origin.get("xyz") if origin is not None else "")
    return links, joints


def generate(*args):
    return subprocess.run(["rosrun", "thorvald_model", "urdf_generator"] + list(args), check=True,
                          stdout=subprocess.PIPE, universal_newlines=True).stdout


class GeneratorSources(unittest.TestCase):
    def test_parameter_server_gives_the_file_model(self):
        robot_file = rospy.get_param("~robot_file")
        from_file = summary(generate("--config", robot_file, "--tf-prefix", "p"))
        from_params = summary(generate("--param-ns", "/from_params", "--tf-prefix", "p"))
        self.assertEqual(from_file, from_params)
        self.assertIn("p/caster0_swivel", from_file[1])
        self.assertIn("p/passive_wheel0", from_file[1])

    def test_missing_namespace_is_an_error(self):
        result = subprocess.run(["rosrun", "thorvald_model", "urdf_generator", "--param-ns", "/nobody_here"],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True)
        self.assertEqual(result.returncode, 1)
        self.assertIn("robot file in namespace '/nobody_here': motor_drives: not found on the parameter server",
                      result.stderr)

    def test_model_launch_loads_robot_description(self):
        links, joints = summary(rospy.get_param("/launched/robot_description"))
        self.assertIn("launched/base_link", links)
        self.assertEqual(joints["launched/steering1"][0], "revolute")
        self.assertEqual(joints["launched/wheel2"][1], "launched/leg_link2")
        expected = summary(generate("--config", rospy.get_param("~robot_file"), "--tf-prefix", "launched"))
        self.assertEqual((links, joints), expected)


if __name__ == "__main__":
    rospy.init_node("generator_sources_test")
    rostest.rosrun("thorvald_model", "generator_sources", GeneratorSources)
