#!/usr/bin/python3
"""base_driver with a broken robot file exits non-zero and says which key is wrong."""
import os
import subprocess
import unittest

import rosgraph
import rosparam
import rospy
import rostest


class BadConfig(unittest.TestCase):
    def run_driver(self, ns, params):
        rosparam.upload_params(ns, params)
        env = dict(os.environ, ROS_NAMESPACE=ns)
        proc = subprocess.run(["rosrun", "thorvald_base", "base_driver"], env=env, capture_output=True, text=True,
                              timeout=30)
        return proc.returncode, proc.stdout + proc.stderr

    def drive(self, **over):
        d = {"node": 1, "x": 0.5, "y": -0.3, "r_wheel": 0.2, "prp_gr_rt": 42, "prp_enc_ppr": 1024,
             "prp_max_rpm": 3000, "str_gr_rt": 42.86, "str_enc_ppr": 1024, "str_lim": 3.07}
        d.update(over)
        return d

    def test_negative_radius(self):
        code, out = self.run_driver("/bad1", {"motor_drives": {"drive0": self.drive(r_wheel=-0.2)}})
        self.assertNotEqual(code, 0)
        self.assertIn("motor_drives.drive0.r_wheel", out)

    def test_missing_robot_file(self):
        code, out = self.run_driver("/bad2", {})
        self.assertNotEqual(code, 0)
        self.assertIn("rosparam load", out)

    def test_unknown_plugin(self):
        code, out = self.run_driver("/bad3", {"base_calculator": "no_such::Model",
                                              "motor_drives": {"drive0": self.drive()}})
        self.assertNotEqual(code, 0)
        self.assertIn("no_such::Model", out)

    def test_model_cannot_drive_robot(self):
        code, out = self.run_driver("/bad4", {"base_calculator": "pltf_clc_2wdiff::PltfClc2WDiff",
                                              "motor_drives": {"drive0": self.drive()}})
        self.assertNotEqual(code, 0)
        self.assertIn("exactly 2 drives", out)


if __name__ == "__main__":
    rospy.init_node("bad_config_test", anonymous=True)
    rostest.rosrun("thorvald_base", "base_driver_bad_config", BadConfig)
