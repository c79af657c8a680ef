#!/usr/bin/python3
"""thorvald_sim refuses wrong parameters (exit 1, naming the parameter, what was found and what was expected) and
warns about private parameters it does not read."""
import unittest

import rosparam
import rostest
from thorvald_testing import run_until_line


def run_sim(name, params, wait_for=None, deadline_s=40.0):
    """Runs thorvald_sim as `name` with `params` as its private parameters. Without `wait_for`, waits for it to
    exit; with it, stops the node once a line contains `wait_for`. Returns (exit code or None, output)."""
    rosparam.upload_params("/" + name, params)
    return run_until_line(["rosrun", "thorvald_sim", "thorvald_sim", "__name:=" + name], wanted=wait_for,
                          deadline_s=deadline_s, stop_wait_s=15.0)


class BadParams(unittest.TestCase):
    def test_wrong_type_exits_1_naming_the_parameter(self):
        code, out = run_sim("sim_bad_rtf", {"real_time_factor": "fast", "robots": []})
        self.assertEqual(code, 1, out)
        self.assertIn("~real_time_factor: found the string 'fast', expected a number in [0, 1000]", out)

    def test_world_value_out_of_range(self):
        code, out = run_sim("sim_bad_sets", {"world": "greenhouse", "greenhouse": {"rail_sets": 0}, "robots": []})
        self.assertEqual(code, 1, out)
        self.assertIn("~greenhouse/rail_sets: found the integer 0, expected an integer in [1, 200]", out)

    def test_unknown_key_in_a_robot_entry(self):
        code, out = run_sim("sim_bad_robot", {"robots": [{"namespace": "r1", "x": 1.0, "yawn": 0.5}]})
        self.assertEqual(code, 1, out)
        self.assertIn("~robots[0]", out)
        self.assertIn("unknown key 'yawn'", out)

    def test_single_robot_keys_refused_next_to_robots(self):
        code, out = run_sim("sim_bad_both", {"robots": [], "x": 2.0})
        self.assertEqual(code, 1, out)
        self.assertIn("~x is not supported", out)

    def test_misspelt_parameter_is_warned_about(self):
        code, out = run_sim("sim_typo", {"world": "flat", "robots": [], "greenhous": {"rail_sets": 3}},
                            wait_for="thorvald_sim: parameters:")
        self.assertIn("~greenhous/rail_sets is set but nothing in this node reads it", out)
        self.assertIn("world=flat", out)  # the start-up line of effective values


if __name__ == "__main__":
    rostest.rosrun("thorvald_sim", "bad_params", BadParams)
