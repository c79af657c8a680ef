#!/usr/bin/env python3
"""The whole UV mission in the MuJoCo greenhouse (sim_uv_mission.launch, 2 short rail sets), scored against the
simulator's truth by bench/uv_mission_scorer.py: map_analyzer must mark every rail set of the robot's own map good,
the mission must treat each of them (by its report and by the truth: lights on over the rails; every plant of the rows
dosed), the frame must touch nothing, the lights must be
on only while the drive wheels are on the rails, no wheel may pass an edge (truth) nor any range finder see one
under a wheel, the speed with the lights on must be near 0.5 m/s, and the mission must end with `done`."""
import json
import sys
import unittest

import rospy
import rostest
from geometry_msgs.msg import PoseArray
from thorvald_testing import load_package_module


class SimUvMission(unittest.TestCase):
    def test_mission_treats_every_good_rail_set(self):
        scorer_module = load_package_module("greenhouse_rail_nav", "bench/uv_mission_scorer.py")
        scorer = scorer_module.make_scorer(rospy.get_param("~truth_file"), wait_s=120.0)
        scorer.subscribe()
        n_sets = len(scorer.sets)
        # The analyzer's verdict on the robot's own map: every set of the world must be good.
        good = rospy.wait_for_message("rail_targets", PoseArray, timeout=120.0)
        uncertain = rospy.wait_for_message("rail_targets_uncertain", PoseArray, timeout=30.0)
        self.assertEqual(len(good.poses), n_sets,
                         "map_analyzer marked %d of %d rail sets good (%d uncertain) on the robot's own map" %
                         (len(good.poses), n_sets, len(uncertain.poses)))
        finished = scorer.wait(rospy.get_param("~timeout"), wall_timeout_s=rospy.get_param("~wall_timeout"))
        out = scorer.result()
        print("RESULT " + json.dumps(out), flush=True)
        self.assertTrue(finished, "the mission did not finish in time: %r" % out)
        self.assertEqual(out["mission_outcome"], "done")
        self.assertEqual(out["rail_sets_in_report"], n_sets)
        self.assertEqual(sorted(out["treated_by_report"]), list(range(n_sets)), "treated by the mission's report")
        self.assertEqual(out["treated_by_truth"], list(range(n_sets)), "lights on over every rail (truth)")
        self.assertEqual(out["wheel_past_edge"], 0, "a wheel past an edge at %r" % (out["wheel_past_edge_first"],))
        self.assertLess(out["lights_off_rails_s"], 1e-6,
                        "lights on off the rails, first at %r" % (out["lights_off_rails_first"],))
        # A range finder's readings arriving late on a loaded machine engage the lock too (it does its job); only
        # an edge under a wheel counts against the mission here. uv_mission_bench reports every engagement.
        self.assertEqual(out["safety_events_edge"], 0, "lock reasons: %r" % out["safety_lock_reasons"])
        # Every plant of each set's row got the set dose (the plants' stretch from the truth), and the frame touched
        # nothing (walls included) on the way.
        self.assertGreaterEqual(out["coverage_min_pct"], 99.0,
                                "coverage %r, short %r" % (out["coverage_pct"], out["coverage_uncovered_m"]))
        self.assertEqual(out["collisions"], 0, "body contacts: %r" % (out.get("collisions_first"),))
        self.assertGreater(out["rail_speed_samples"], 10)
        self.assertLess(abs(out["rail_speed_mean_mps"] - 0.5), 0.05)


if __name__ == "__main__":
    rospy.init_node("sim_uv_mission_test")
    rostest.rosrun("greenhouse_rail_nav", "sim_uv_mission", SimUvMission, sys.argv)
