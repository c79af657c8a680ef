#!/usr/bin/env python3
"""The UV mission in the MuJoCo greenhouse with a person standing in a row (sim_uv_people.test), scored against the
simulator's truth by bench/uv_mission_scorer.py: the lights are never on with the person in the protected zone, the
robot never touches them (nor anything else), it holds short of them and says so on mission/safety, and every set,
the person's too, is treated once they have left (by the mission's report and by the truth). A second person steps
into the other row ahead of the moving robot: the stop (zero twist, lamps off) comes within 200 ms of their entering
the zone."""
import json
import sys
import unittest

import rospy
import rostest
from std_msgs.msg import String
from thorvald_testing import load_package_module


class SimUvPeople(unittest.TestCase):
    def test_stops_short_of_a_person_in_the_row_and_treats_the_set_after_they_leave(self):
        safety = []
        rospy.Subscriber("mission/safety", String, lambda m: safety.append(m.data))
        scorer_module = load_package_module("greenhouse_rail_nav", "bench/uv_mission_scorer.py")
        scorer = scorer_module.make_scorer(rospy.get_param("~truth_file"), wait_s=120.0, scenario="person in a row")
        scorer.subscribe()
        n_sets = len(scorer.sets)
        finished = scorer.wait(rospy.get_param("~timeout"), wall_timeout_s=rospy.get_param("~wall_timeout"))
        out = scorer.result()
        print("RESULT " + json.dumps(out), flush=True)
        print("mission/safety: %r" % safety, flush=True)
        self.assertTrue(finished, "the mission did not finish in time: %r" % out)
        self.assertEqual(out["mission_outcome"], "done")
        self.assertTrue(any("row ahead" in s for s in safety), "held for the person in the row: %r" % safety)
        self.assertEqual(out["uv_on_with_person_events"], 0, "lights on with the person in the zone")
        self.assertEqual(out["collisions"], 0, "contacts: %r" % out["collisions_first"])
        self.assertGreater(out["person_min_distance_m"], 0.5, "stopped short of the person")
        self.assertLessEqual(out["person_stop_latency_p99_ms"], 200.0)
        self.assertGreaterEqual(out["person_zone_entries_moving"], 1,
                                "the person stepping into the row ahead entered the zone of a moving robot: %r" % out)
        self.assertEqual(sorted(out["treated_by_report"]), list(range(n_sets)), "treated by the mission's report")
        self.assertEqual(out["treated_by_truth"], list(range(n_sets)), "lights on over every rail (truth)")
        self.assertGreaterEqual(out["coverage_base_link_min_pct"], 99.0,
                                "base_link over the rails with the lights on: %r" % out["coverage_base_link_pct"])
        self.assertEqual(out["wheel_past_edge"], 0)


if __name__ == "__main__":
    rospy.init_node("sim_uv_people_test")
    rostest.rosrun("greenhouse_rail_nav", "sim_uv_people", SimUvPeople, sys.argv)
