#!/usr/bin/env python3
"""The greenhouse robot in the MuJoCo greenhouse (3 rail sets), started away from the map's origin with a rough
initial guess, localises on the headland map made by headland_mapper and reaches two rail-set targets in sequence
through the move_base action. Scored against the simulator's truth with the bench's own code."""
import importlib.machinery
import importlib.util
import math
import os
import sys
import unittest

import rospkg
import rospy
import rostest


def load_bench():
    path = os.path.join(rospkg.RosPack().get_path("thorvald_bringup"), "bench", "greenhouse_nav_bench")
    loader = importlib.machinery.SourceFileLoader("greenhouse_nav_bench", path)
    spec = importlib.util.spec_from_loader("greenhouse_nav_bench", loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


class Args:
    goals = 2
    seed = 3
    approach_x = -0.8
    jitter_xy = 0.05
    jitter_yaw = 0.05
    goal_timeout = 120.0  # simulated seconds: up to three corrections of the approach at 0.5 m/s
    odom_jump = 0.0  # no forced odometry jump
    odom_jump_every = 1
    odom_jump_delay = 3.0


class GreenhouseSimNavigation(unittest.TestCase):
    def test_two_rail_set_targets_in_sequence(self):
        bench = load_bench()
        args = Args()
        args.truth_file = rospy.get_param("~truth_file")
        tolerance_xy = rospy.get_param("~tolerance_xy")
        tolerance_yaw = rospy.get_param("~tolerance_yaw")
        out, results = bench.run(args)
        print("RESULT", out)
        self.assertEqual(len(results), 2)
        self.assertNotEqual(results[0]["set"], results[1]["set"], "the two targets are different rail sets")
        for r in results:
            self.assertTrue(r["ok"], "goal at rail set %d not reached: %r" % (r["set"], r))
            self.assertLess(r["err"], tolerance_xy, "truth position error at rail set %d" % r["set"])
            self.assertLess(r["err_yaw"], tolerance_yaw, "truth heading error at rail set %d" % r["set"])
        self.assertGreater(out["loc_samples"], 10)
        self.assertLess(out["loc_rms_m"], tolerance_xy)


if __name__ == "__main__":
    rospy.init_node("greenhouse_sim_nav_test")
    rostest.rosrun("thorvald_bringup", "greenhouse_sim_nav", GreenhouseSimNavigation, sys.argv)
