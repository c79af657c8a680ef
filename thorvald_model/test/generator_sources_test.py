#!/usr/bin/python3
"""urdf_generator from the parameter server equals urdf_generator from the file; model.launch loads the model."""
import os
import subprocess
import tempfile
import unittest
import xml.etree.ElementTree as ET

import rosparam
import rospy
import rostest
import yaml


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

    def run_generator(self, *args):
        return subprocess.run(["rosrun", "thorvald_model", "urdf_generator"] + list(args), stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, universal_newlines=True)

    def test_command_line(self):
        result = self.run_generator("--help")
        self.assertEqual(result.returncode, 0)
        self.assertIn("--config", result.stdout)
        result = self.run_generator("--config", rospy.get_param("~robot_file"), "--no-such-option")
        self.assertEqual(result.returncode, 2)
        self.assertIn("--no-such-option", result.stderr)
        result = self.run_generator("--config")
        self.assertEqual(result.returncode, 2)

    def robot_text(self, extra="", node1=2):
        drive = ("{node: %d, x: %s, y: 0.3, r_wheel: 0.2, prp_gr_rt: 42, prp_enc_ppr: 1024, prp_max_rpm: 3000, "
                 "str_gr_rt: 42.86, str_enc_ppr: 1024, str_lim: 3.07}")
        return ("motor_drives: {drive0: %s, drive1: %s}\n" % (drive % (1, "-0.5"), drive % (node1, "0.5"))) + extra

    def write(self, text):
        f = tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False)
        f.write(text)
        f.close()
        self.addCleanup(os.unlink, f.name)
        return f.name

    def test_misspelt_group_is_warned_from_file_and_parameter_server(self):
        text = self.robot_text("caster: {c0: {x: -0.5, y: 0.0}}\n")
        result = self.run_generator("--config", self.write(text))
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("caster: unknown top-level key, ignored (did you mean 'casters'?)", result.stderr)
        rosparam.upload_params("/misspelt", yaml.safe_load(text))
        result = self.run_generator("--param-ns", "/misspelt")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("caster: unknown top-level key, ignored (did you mean 'casters'?)", result.stderr)

    def test_duplicate_node_ids_are_refused(self):
        result = self.run_generator("--config", self.write(self.robot_text(node1=1)))
        self.assertEqual(result.returncode, 1)
        self.assertIn("CAN node id 1 is already used by drive0", result.stderr)


if __name__ == "__main__":
    rospy.init_node("generator_sources_test")
    rostest.rosrun("thorvald_model", "generator_sources", GeneratorSources)
