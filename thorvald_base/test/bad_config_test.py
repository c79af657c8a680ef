#!/usr/bin/python3
"""base_driver with a broken robot file exits non-zero and says which key is wrong."""
import os
import signal
import subprocess
import time
import unittest

import rosgraph
import rosparam
import rospy
import rostest
from thorvald_testing import run_until_line


class BadConfig(unittest.TestCase):
    def run_driver(self, ns, params, args=()):
        rosparam.upload_params(ns, params)
        env = dict(os.environ, ROS_NAMESPACE=ns)
        proc = subprocess.run(["rosrun", "thorvald_base", "base_driver", *args], env=env, capture_output=True,
                              text=True, timeout=30)
        return proc.returncode, proc.stdout + proc.stderr

    def output_of_running_driver(self, ns, params, args, wanted, deadline_s=30.0, command=None):
        """Starts base_driver, collects its output until a line contains `wanted` (or the deadline), stops it."""
        rosparam.upload_params(ns, params)
        env = None if command else {"ROS_NAMESPACE": ns}
        _, out = run_until_line(command or ["rosrun", "thorvald_base", "base_driver", *args], wanted=wanted,
                                deadline_s=deadline_s, env=env)
        return out

    def good_robot(self):
        return {"motor_drives": {"drive0": self.drive(), "drive1": self.drive(node=2, x=-0.5, y=0.3)}}

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

    def test_wrong_parameter_types_are_refused(self):
        for ns, arg, name, found in (("/par1", "_simple_sim:=maybe", "~simple_sim", "the string 'maybe'"),
                                     ("/par2", "_rate:=fast", "~rate", "the string 'fast'"),
                                     ("/par3", "_rate:=0", "~rate", "the integer 0"),
                                     ("/par4", "_odometry_estimator:=magic", "~odometry_estimator", "the string 'magic'"),
                                     ("/par5", "_max_linear_speed:=fast", "~max_linear_speed", "the string 'fast'"),
                                     ("/par6", "_battery_lost_action:=explode", "~battery_lost_action",
                                      "the string 'explode'")):
            code, out = self.run_driver(ns, self.good_robot(), [arg])
            self.assertEqual(code, 1, out)
            self.assertIn("parameter " + name + ": found " + found, out)
            self.assertIn("base_driver", out)

    def test_relay_ids_outside_11_bits_are_refused(self):
        robot = self.good_robot()
        robot["base_driver"] = {"relay_allowed_ids": [0x123, 4096]}
        code, out = self.run_driver("/par7", robot)
        self.assertEqual(code, 1, out)
        self.assertIn("parameter ~relay_allowed_ids[1]: found the integer 4096", out)
        robot = self.good_robot()
        robot["implement_can_ids"] = [0x123, 0x800]
        code, out = self.run_driver("/par8", robot)
        self.assertEqual(code, 1, out)
        self.assertIn("implement_can_ids[1]", out)

    def test_misspelt_parameter_is_warned(self):
        out = self.output_of_running_driver("/par5", self.good_robot(), ["_cmd_vel_timout:=0.1"], "did you mean")
        self.assertIn("~cmd_vel_timout is set but nothing in this node reads it; did you mean ~cmd_vel_timeout?",
                      out)

    def test_misspelt_group_is_warned(self):
        robot = self.good_robot()
        robot["caster"] = {"c0": {"x": -0.5, "y": 0.0}}
        out = self.output_of_running_driver("/par6", robot, [], "caster")
        self.assertIn("caster: unknown top-level key, ignored (did you mean 'casters'?)", out)

    def test_duplicate_node_ids_are_refused_in_simulation(self):
        robot = {"motor_drives": {"drive0": self.drive(), "drive1": self.drive(x=-0.5)}}
        code, out = self.run_driver("/bad5", robot, ["_simple_sim:=true"])
        self.assertEqual(code, 1, out)
        self.assertIn("CAN node id 1 is already used by drive0", out)

    def test_ros2_parameters_file_is_named(self):
        code, out = self.run_driver("/bad6", {"base_driver": {"ros__parameters": self.good_robot()}})
        self.assertEqual(code, 1, out)
        self.assertIn("ROS 2 parameters file", out)
        self.assertIn("base_driver/ros__parameters", out)

    def test_alias_bomb_is_bounded(self):
        # What YAML aliases expand to: 12^4 = 20736 values under one drive, past the reader's bound.
        leaf = [1.0] * 12
        for _ in range(3):
            leaf = [leaf] * 12
        robot = self.good_robot()
        robot["motor_drives"]["drive0"]["lol"] = leaf
        start = time.monotonic()
        code, out = self.run_driver("/bad7", robot)
        self.assertEqual(code, 1, out)
        self.assertIn("expands to more than 20000 values", out)
        self.assertLess(time.monotonic() - start, 25.0)

    def test_misspelt_drives_group_is_named(self):
        code, out = self.run_driver("/bad8", {"motor_drive": self.good_robot()["motor_drives"]})
        self.assertEqual(code, 1, out)
        self.assertIn("motor_drives: not found in /bad8; did you mean motor_drive?", out)

    def test_group_larger_than_its_bound_is_refused_before_it_is_expanded(self):
        robot = self.good_robot()
        robot["motor_drives"]["drive0"]["lol"] = [1.0] * 60000  # about 2 MB XML-RPC encoded, past the 1 MiB bound
        code, out = self.run_driver("/bad9", robot)
        self.assertEqual(code, 1, out)
        self.assertIn("motor_drives: takes more than 1048576 bytes", out)

    def test_deep_nesting_is_refused(self):
        leaf = 1.0
        for _ in range(10):
            leaf = [leaf]
        robot = self.good_robot()
        robot["motor_drives"]["drive0"]["lol"] = leaf
        code, out = self.run_driver("/bad10", robot)
        self.assertEqual(code, 1, out)
        self.assertIn("motor_drives: nests deeper than 8 levels", out)

    def bomb_rows(self, rows):
        # What a half-loaded alias bomb leaves on the server: one list of `rows` references to a list of 1000.
        return [[1.0] * 1000] * rows

    def test_half_loaded_bomb_next_to_the_groups_is_not_read(self):
        # No motor_drives (rosparam load stopped half-way), 500000 values next to where it would be: base_driver
        # reads only the robot file's groups, never the namespace, and says what is missing.
        rosparam.upload_params("/bad11", {"lol": self.bomb_rows(500)})
        start = time.monotonic()
        code, out = self.run_driver("/bad11", {})
        self.assertEqual(code, 1, out)
        self.assertIn("motor_drives: not found in /bad11", out)
        self.assertLess(time.monotonic() - start, 20.0)

    def test_sigint_while_reading_a_bomb_stops_promptly(self):
        # A group of a million values: the master takes seconds to encode it. base_driver, stopped with SIGINT as
        # soon as it is up (it reads the robot file right away), exits within seconds, while it waits for the
        # reply ("reading interrupted") or once it has refused the group's size.
        robot = self.good_robot()
        robot["motor_drives"]["lol"] = self.bomb_rows(1000)
        rosparam.upload_params("/bad12", robot)
        proc = subprocess.Popen(["rosrun", "thorvald_base", "base_driver"], env=dict(os.environ, ROS_NAMESPACE="/bad12"),
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        master = rosgraph.Master("/bad_config_test")
        try:
            end = time.monotonic() + 30.0
            up = False
            while time.monotonic() < end and not up and proc.poll() is None:
                up = any("/bad12/base_driver" in nodes for _, nodes in master.getSystemState()[0])
                time.sleep(0.05)
            self.assertTrue(up or proc.poll() is not None, "base_driver did not come up")
            signalled = time.monotonic()
            proc.send_signal(signal.SIGINT)
            out, _ = proc.communicate(timeout=15)
            elapsed = time.monotonic() - signalled
            self.assertLess(elapsed, 5.0, out)
            self.assertNotEqual(proc.returncode, 0, out)
            self.assertNotIn("drives, model", out)  # it never started driving
            self.assertTrue("reading interrupted" in out or "motor_drives: takes more than" in out, out)
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()

    def test_launch_file_clears_a_robot_file_loaded_before(self):
        # A four-drive robot file left in the namespace, then the two-wheel differential robot through the launch
        # file: without clearing, the drives would merge and base_driver would refuse them ("found 4").
        four = {"motor_drives": {"drive%d" % i: self.drive(node=i + 1, x=(-0.5, 0.5)[i % 2], y=(-0.3, 0.3)[i // 2])
                                 for i in range(4)}}
        rosparam.upload_params("/leftover", four)
        diff = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "field_quirks.yaml")
        proc = subprocess.Popen(["roslaunch", "thorvald_base", "base_driver.launch", "robot_name:=leftover",
                                 "robot_model:=" + diff], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        master = rosgraph.Master("/bad_config_test")
        publishing = False
        try:
            end = time.monotonic() + 30.0
            while time.monotonic() < end and not publishing and proc.poll() is None:
                publishers = master.getSystemState()[0]
                publishing = any(topic == "/leftover/odometry/base_raw" for topic, _ in publishers)
                time.sleep(0.2)
            self.assertTrue(publishing, "base_driver did not come up with the second robot file")
            self.assertEqual(sorted(rosparam.get_param("/leftover/motor_drives").keys()), ["drive0", "drive1"])
        finally:
            proc.send_signal(signal.SIGINT)
            try:
                proc.wait(timeout=15)
            except subprocess.TimeoutExpired:
                proc.kill()

if __name__ == "__main__":
    rospy.init_node("bad_config_test", anonymous=True)
    rostest.rosrun("thorvald_base", "base_driver_bad_config", BadConfig)
