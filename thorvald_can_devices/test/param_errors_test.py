#!/usr/bin/python3
"""The CAN plugin's parameters (read through base_driver's ParamReader) and can_device_sim's are strict: a wrong
value stops the node with exit code 1 naming the parameter, before any bus is opened."""
import os
import subprocess
import unittest

import rosparam
import rostest

DRIVE = {"node": 1, "x": 0.5, "y": -0.3, "r_wheel": 0.2, "prp_gr_rt": 42, "prp_enc_ppr": 1024,
         "prp_max_rpm": 3000, "str_gr_rt": 42.86, "str_enc_ppr": 1024, "str_lim": 3.07}


class ParamErrors(unittest.TestCase):
    def run_node(self, ns, package, node, args):
        rosparam.upload_params(ns, {"motor_drives": {"drive0": DRIVE, "drive1": dict(DRIVE, node=2, x=-0.5, y=0.3)}})
        env = dict(os.environ, ROS_NAMESPACE=ns)
        proc = subprocess.run(["rosrun", package, node, *args], env=env, capture_output=True, text=True, timeout=30)
        return proc.returncode, proc.stdout + proc.stderr

    def test_plugin_parameter_out_of_range(self):
        code, out = self.run_node("/perr1", "thorvald_base", "base_driver",
                                  ["_simple_sim:=false", "_can_interface_type:=virtual", "_can_feedback_timeout:=0.5"])
        self.assertEqual(code, 1, out)
        self.assertIn("parameter ~can_feedback_timeout: found the number 0.5", out)

    def test_plugin_parameter_wrong_type(self):
        code, out = self.run_node("/perr2", "thorvald_base", "base_driver",
                                  ["_simple_sim:=false", "_can_interface_type:=virtual",
                                   "_can_max_frames_per_cycle:=many"])
        self.assertEqual(code, 1, out)
        self.assertIn("parameter ~can_max_frames_per_cycle: found the string 'many'", out)

    def test_can_device_sim_rate(self):
        code, out = self.run_node("/perr3", "thorvald_can_devices", "can_device_sim", ["_rate:=fast"])
        self.assertEqual(code, 1, out)
        self.assertIn("parameter ~rate: found the string 'fast'", out)

    def test_can_device_sim_interface_type(self):
        code, out = self.run_node("/perr4", "thorvald_can_devices", "can_device_sim", ["_can_interface_type:=vcan"])
        self.assertEqual(code, 1, out)
        self.assertIn("parameter ~can_interface_type: found the string 'vcan'", out)


if __name__ == "__main__":
    rostest.rosrun("thorvald_can_devices", "param_errors", ParamErrors)
