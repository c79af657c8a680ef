#!/usr/bin/python3
"""The bench scorer's coverage (bench/uv_mission_scorer.py): the dose along a row in 5 cm bins from the lamps' lit
stretch (config/uv_lamps.yaml) and base_link's truth pose; a run that lights all of a row, none of it, half of it.
No ROS master needed."""
import os
import sys
import tempfile
import unittest

from thorvald_testing import load_package_module

scorer = load_package_module("greenhouse_rail_nav", "bench/uv_mission_scorer.py")
LAMPS = scorer.load_lamps(scorer.default_lamps_file())
REAR = LAMPS["lamp_offset"] - 0.5 * LAMPS["lamp_length"]  # the lit stretch's rear edge along base_link's x
FRONT = LAMPS["lamp_offset"] + 0.5 * LAMPS["lamp_length"]


def drive(row, s_from, s_to, speed=0.5, on=lambda s: True, dt=0.02):
    """base_link from s_from to s_to at `speed`, the lamps on where on(s)."""
    s = s_from
    while s < s_to - 1e-12:
        nxt = min(s_to, s + speed * dt)
        row.add(s, nxt, (nxt - s) / speed, on(s))
        s = nxt


class RowDoseBinsTest(unittest.TestCase):
    def test_the_placeholder_lamps_give_120_j_per_m_at_half_a_metre_per_second(self):
        self.assertAlmostEqual(LAMPS["lamp_power"] / 0.5, 120.0)
        self.assertAlmostEqual(LAMPS["target_dose"], 100.0)

    def test_lit_over_the_whole_row_at_the_treatment_speed_covers_all(self):
        row = scorer.RowDoseBins(LAMPS, 0.5, 5.5)
        drive(row, 0.5 - FRONT - 0.1, 5.5 - REAR + 0.1)
        self.assertEqual(row.coverage_pct(), 100.0)
        self.assertEqual(row.uncovered(), [])
        self.assertTrue(all(abs(d - 120.0) < 1.0 for d in row.dose), (min(row.dose), max(row.dose)))

    def test_lights_off_covers_none(self):
        row = scorer.RowDoseBins(LAMPS, 0.0, 5.0)
        drive(row, -1.0, 6.0, on=lambda s: False)
        self.assertEqual(row.coverage_pct(), 0.0)
        self.assertEqual(row.uncovered(), [[0.0, 5.0]])

    def test_lit_until_half_way_covers_the_first_half_less_the_lamps_last_stretch(self):
        # Lights off once the lit stretch's rear edge is at 2.5 m: the bins still under the lamps then got less than
        # the set dose (120 J/m needs the whole 0.75 m stretch to pass; 100 J/m 0.625 m of it).
        row = scorer.RowDoseBins(LAMPS, 0.0, 5.0)
        drive(row, -FRONT - 0.1, 6.0 - REAR, on=lambda s: s + REAR < 2.5)
        self.assertAlmostEqual(row.coverage_pct(), 100.0 * (2.5 + 0.125) / 5.0, delta=1.1)
        self.assertEqual(len(row.uncovered()), 1)
        self.assertAlmostEqual(row.uncovered()[0][1], 5.0)

    def test_too_fast_is_not_covered(self):
        row = scorer.RowDoseBins(LAMPS, 0.0, 5.0)
        drive(row, -FRONT - 0.1, 5.0 - REAR + 0.1, speed=0.7)  # 60 W / 0.7 m/s: 86 J/m
        self.assertEqual(row.coverage_pct(), 0.0)

    def test_stopping_with_the_lamps_front_edge_at_the_end_leaves_the_end_short(self):
        # Braking at 0.5 m/s^2 to a stop with the lamps' front edge at the row's end, lights off then: the last
        # ~0.39 m (sqrt(2 d / a) s under the lamps < 1.25 s) miss the set dose.
        row = scorer.RowDoseBins(LAMPS, 0.0, 5.0)
        drive(row, -FRONT - 0.1, 5.0 - FRONT - 0.25)
        s, v, dt = 5.0 - FRONT - 0.25, 0.5, 0.001
        while v > 0.0:
            nv = max(0.0, v - 0.5 * dt)
            row.add(s, s + 0.5 * (v + nv) * dt, dt, True)
            s, v = s + 0.5 * (v + nv) * dt, nv
        self.assertAlmostEqual(s + FRONT, 5.0, delta=0.01)
        self.assertAlmostEqual(row.coverage_pct(), 100.0 * (5.0 - 0.39) / 5.0, delta=1.1)


def score_set0_driven(sets_yaml, to_x, then=None):
    """The scorer's result for a truth file of 5 m rail sets (`sets_yaml`: its rail_sets lines) after base_link drove
    set 0's rails from their start to world x `to_x` at 0.5 m/s with the lights on; then(scorer, t) adds more."""
    with tempfile.TemporaryDirectory() as d:
        truth = os.path.join(d, "truth.yaml")
        with open(truth, "w") as f:
            f.write("rail_length: 5.0\nrail_sets:\n" + sets_yaml)
        sc = scorer.UvMissionScorer(truth)
        sc.lights = True
        t, x = 0.0, 0.03
        while x < to_x:
            sc.add_dose((t, x, 0.0), (t + 0.02, x + 0.01, 0.0))
            t, x = t + 0.02, x + 0.01
        if then:
            then(sc, t)
        return sc.result()


class ScorerCoverageTest(unittest.TestCase):
    def test_the_scorer_bins_the_truth_path_of_each_set(self):
        # set 0 driven over its whole rails with the lights on, set 1 never
        out = score_set0_driven("  - {index: 0, x: 0.03, y: 0.0, yaw: 0.0}\n  - {index: 1, x: 0.03, y: 1.6, yaw: 0.0}\n",
                                5.0)
        # a truth file without `plants` (written before thorvald_sim gave them): the old rows, 0.5 m past the start
        self.assertEqual(out["coverage_row_m"], {"0": [0.5, 5.5], "1": [0.5, 5.5]})
        self.assertEqual(out["coverage_pct"]["1"], 0.0)
        self.assertEqual(out["coverage_rails_pct"]["1"], 0.0)
        # The lit stretch's rear edge reached 4.97 + REAR in set coordinates: the rails' row up to 0.125 m past it.
        self.assertAlmostEqual(out["coverage_rails_pct"]["0"], 100.0 * (4.97 + REAR + 0.125) / 5.0, delta=1.1)
        self.assertAlmostEqual(out["coverage_pct"]["0"], 100.0 * (4.97 + REAR + 0.125 - 0.5) / 5.0, delta=1.1)
        self.assertEqual(out["coverage_interlock_pct"]["0"], out["coverage_rails_pct"]["0"])
        self.assertEqual(out["coverage_min_pct"], 0.0)

    def test_the_row_is_the_truths_plants_of_each_set(self):
        # set 0 driven with the lights on to 4.2 m, then on set 1's rails (no plants there: no figure)
        out = score_set0_driven("  - {index: 0, x: 0.03, y: 0.0, yaw: 0.0, plants: [1.0, 4.0]}\n"
                                "  - {index: 1, x: 0.03, y: 1.6, yaw: 0.0, plants: []}\n", 4.2,
                                lambda sc, t: sc.add_dose((t, 0.03, 1.6), (t + 0.02, 0.5, 1.6)))
        self.assertEqual(out["coverage_row_m"], {"0": [1.0, 4.0]})
        self.assertEqual(sorted(out["coverage_pct"]), ["0"])
        # The full dose needs target / (power / speed) of the lamps' length to pass: bins up to 4.2 - 0.03 + FRONT
        # - 0.625 m are covered, past the plants' end only when FRONT > 0.455 m.
        expect = min(4.0, 4.17 + FRONT - 0.75 * LAMPS["target_dose"] / (LAMPS["lamp_power"] / 0.5))
        self.assertAlmostEqual(out["coverage_pct"]["0"], 100.0 * (expect - 1.0) / 3.0, delta=2.0)



class ScorerZoneTest(unittest.TestCase):
    """The protected zone the scorer times the stops against: the lamps' reach with the lights on, the swept path
    (the footprint's corridor to 1 s of travel plus 0.3 m past its leading edge) while driving, the row ahead on the
    rails."""

    def scorer_at(self, x, y, yaw=0.0):
        with tempfile.TemporaryDirectory() as d:
            truth = os.path.join(d, "truth.yaml")
            with open(truth, "w") as f:
                f.write("rail_length: 5.0\nrail_sets:\n  - {index: 0, x: 0.0, y: 0.0, yaw: 0.0}\n")
            sc = scorer.UvMissionScorer(truth)
        sc.pose = (0.0, x, y, yaw)
        return sc

    def test_a_person_in_the_plant_row_beside_a_robot_driving_in_with_the_lamps_off_is_not_in_its_path(self):
        sc = self.scorer_at(-1.0, 0.0)  # on the headland, facing the rails
        sc.people = [(0.0, 0.8, 0.25)]
        sc.cmd_v = 0.2
        self.assertFalse(sc.person_in_zone())
        sc.lights = True  # the lamps' reach
        self.assertTrue(sc.person_in_zone())

    def test_the_swept_path_runs_in_the_direction_of_motion_across_the_footprints_width(self):
        sc = self.scorer_at(-3.0, 0.0)
        sc.cmd_v = -0.2  # reversing: 0.85 m of frame behind base_link, then 0.2 m/s x 1 s + 0.3 m of path
        sc.people = [(-3.0 - 1.55, 0.3, 0.25)]
        self.assertTrue(sc.person_in_zone())
        sc.people = [(-3.0 - 1.65, 0.3, 0.25)]
        self.assertFalse(sc.person_in_zone(), "beyond the swept reach")
        sc.cmd_v = -0.5  # faster: 0.8 m of path
        self.assertTrue(sc.person_in_zone())
        sc.people = [(-3.0 - 1.5, 0.8, 0.25)]
        self.assertFalse(sc.person_in_zone(), "beside the path")
        sc.cmd_v = 0.2
        sc.people = [(-3.0 - 1.55, 0.3, 0.25)]
        self.assertFalse(sc.person_in_zone(), "behind a robot driving forwards")
        sc.cmd_v = 0.0
        sc.people = [(-3.0 + 0.6, 0.0, 0.25)]
        self.assertFalse(sc.person_in_zone(), "a robot standing still sweeps nothing")

    def test_a_person_stepping_into_the_row_ahead_of_a_robot_holding_there_is_an_entry_of_0_ms(self):
        sc = self.scorer_at(1.0, 0.0)  # on set 0's rails, stopped, lamps off
        sc.people = [(3.5, 0.0, 0.25)]
        self.assertFalse(sc.person_in_zone(), "a robot standing on the rails, not holding, has no row zone")
        sc.holding = True
        sc.update_zone(5.0)
        self.assertEqual(sc.latencies, [0.0])
        self.assertEqual(sc.result()["person_zone_entries_already_stopped"], 1)
        self.assertEqual(sc.result()["person_zone_entries_moving"], 0)
        sc.cmd_v, sc.holding = -0.2, False  # reversing out: the row ahead is behind the motion
        self.assertFalse(sc.person_in_zone())

    def test_a_person_stepping_into_the_row_ahead_enters_it_with_their_body_not_their_centre(self):
        sc = self.scorer_at(1.0, 0.0)  # on set 0's rails, driving in with the lamps lit
        sc.lights, sc.cmd_v = True, 0.5
        sc.people = [(4.0, 0.6, 0.25)]  # in the plant row's edge, 3 m ahead: body 0.35 m from the centre line
        self.assertFalse(sc.person_in_zone())
        sc.people = [(4.0, 0.5, 0.25)]  # their side 0.25 m from the centre line, their centre 0.5 m
        self.assertTrue(sc.person_in_zone())
        sc.people = [(-0.5, 0.0, 0.25)]  # on the centre line behind the robot: not ahead
        sc.lights = False
        self.assertFalse(sc.person_in_zone())

    def test_the_lights_on_with_a_person_in_the_zone_are_counted_and_timed(self):
        sc = self.scorer_at(1.0, 0.0)  # on set 0's rails, treating
        sc.lights, sc.cmd_v = True, 0.5
        sc.people = [(3.0, 0.8, 0.25)]  # in the plant row 2 m ahead
        sc.update_zone(20.0)
        sc.people = [(3.0, 0.4, 0.25)]  # steps in
        sc.update_zone(20.1)
        sc.update_zone(20.15)
        sc.lights, sc.cmd_v = False, 0.0  # the mission stops with the lights off
        sc.update_zone(20.18)
        self.assertEqual(sc.uv_person_any, 1)
        self.assertEqual(sc.uv_person_events, 0, "stopped within the reaction allowance (0.2 s)")
        self.assertEqual(len(sc.uv_person_ms), 1)
        self.assertAlmostEqual(sc.uv_person_ms[0], 80.0, places=6)
        self.assertEqual(len(sc.latencies), 1)
        self.assertAlmostEqual(sc.latencies[0], 0.08, places=6)
        self.assertEqual(sc.entries_moving, [True])
        # The same step with a robot that stops late: an event once the allowance has run out.
        sc.people = [(3.0, 0.8, 0.25)]
        sc.lights, sc.cmd_v = True, 0.5
        sc.update_zone(30.0)
        sc.people = [(3.0, 0.4, 0.25)]
        for t in (30.1, 30.2, 30.29):
            sc.update_zone(t)
        self.assertEqual(sc.uv_person_events, 0)
        sc.update_zone(30.31)
        self.assertEqual(sc.uv_person_events, 1)
        sc.update_zone(30.5)
        self.assertEqual(sc.uv_person_events, 1, "counted once")
        # The lamps coming on with a person standing in the zone: at once.
        sc.lights, sc.cmd_v = False, 0.0
        sc.update_zone(31.0)
        sc.holding = True  # holding on the rails: the row ahead is in the zone
        sc.update_zone(31.5)
        sc.lights = True
        sc.update_zone(31.52)
        self.assertEqual(sc.uv_person_events, 2)
        self.assertEqual(sc.uv_person_any, 3)

    def test_a_robot_that_stops_just_before_the_persons_body_is_in_the_zone_stopped_for_them(self):
        sc = self.scorer_at(1.0, 0.0)
        sc.lights, sc.cmd_v = True, 0.5
        sc.people = [(3.0, 0.8, 0.25)]
        sc.update_zone(40.0)
        sc.lights, sc.cmd_v, sc.holding = False, 0.0, True  # the mission saw their side and holds
        sc.update_zone(40.02)
        sc.people = [(3.0, 0.5, 0.25)]
        sc.update_zone(40.04)
        self.assertEqual(sc.entries_moving, [True])
        self.assertEqual(sc.latencies, [0.0])
        sc.people = [(3.0, 0.8, 0.25)]  # steps out and in again 3 s later: the robot stood all that time
        for t in (41.0, 42.0, 43.0):
            sc.update_zone(t)
        sc.people = [(3.0, 0.5, 0.25)]
        sc.update_zone(43.02)
        self.assertEqual(sc.entries_moving, [True, False])

    def test_a_zone_entry_is_timed_to_the_stop_once(self):
        sc = self.scorer_at(-3.0, 0.0)
        sc.cmd_v = 0.2
        sc.people = [(-3.0 + 0.8, 0.0, 0.25)]
        sc.update_zone(10.0)
        sc.update_zone(10.05)
        sc.cmd_v = 0.0
        sc.update_zone(10.12)
        sc.update_zone(10.2)
        self.assertEqual(len(sc.latencies), 1)
        self.assertAlmostEqual(sc.latencies[0], 0.12, places=6)

class ScorerHoldCountTest(unittest.TestCase):
    def test_a_hold_whose_text_changes_is_one_hold_until_clear(self):
        with tempfile.TemporaryDirectory() as d:
            truth = os.path.join(d, "truth.yaml")
            with open(truth, "w") as f:
                f.write("rail_length: 5.0\nrail_sets:\n  - {index: 0, x: 0.0, y: 0.0, yaw: 0.0}\n")
            sc = scorer.UvMissionScorer(truth)
        sc.pose = (0.0, 1.0, 0.0, 0.0)
        sc.people = [(4.0, 0.3, 0.25)]

        class Msg:
            def __init__(self, data):
                self.data = data

        for text in ("holding: a person in the row ahead at (3.00, 0.30) m",
                     "holding: an obstacle in the row ahead at (3.00, 0.35) m",
                     "holding: a person in the row ahead at (3.00, 0.31) m", "clear",
                     "holding: a person in the row ahead at (3.00, 0.30) m"):
            sc.on_safety(Msg(text))
        self.assertEqual(sc.person_holds, 2)
        self.assertEqual(sc.phantom_holds, [])
        sc.on_safety(Msg("clear"))
        sc.on_safety(Msg("holding: a person near the robot at (0.00, 2.00) m"))  # nobody there
        self.assertEqual(sc.person_holds, 3)
        self.assertEqual(len(sc.phantom_holds), 1)


class ScorerRailYawTest(unittest.TestCase):
    """How far the pipes let the robot turn: the truth heading off a set's line, with base_link 1.5 m or more along
    its rails (the rear wheels on the straight pipes) and short of its end; never on the headland or the start."""

    def test_the_heading_off_the_line_counts_only_on_the_straight_rails(self):
        with tempfile.TemporaryDirectory() as d:
            truth = os.path.join(d, "truth.yaml")
            with open(truth, "w") as f:
                f.write("rail_length: 5.0\nrail_sets:\n  - {index: 0, x: 0.0, y: 0.0, yaw: 0.0}\n"
                        "  - {index: 1, x: 0.0, y: 1.6, yaw: 3.1}\n")
            sc = scorer.UvMissionScorer(truth)
        sc.track_rail_yaw(-1.0, 0.0, 0.5)  # on the headland
        sc.track_rail_yaw(1.0, 0.0, 0.2)  # on the bent start pieces
        sc.track_rail_yaw(4.9, 0.0, 0.2)  # past the end's margin
        self.assertEqual(sc.result()["rail_yaw_max_abs_rad"], 0.0)
        sc.track_rail_yaw(3.0, 0.01, -0.03)
        sc.track_rail_yaw(3.5, 0.01, 0.02)
        self.assertEqual(sc.result()["rail_yaw_max_abs_rad"], 0.03)
        self.assertEqual(sc.result()["rail_yaw_max_where"], (0, 3.0))
        # set 1 runs the other way (yaw 3.1): a heading of -3.13 is 0.053 rad off its line, across the wrap
        sc.track_rail_yaw(-2.0 * 0.99917, 1.6 + 2.0 * 0.04158, -3.13)
        self.assertAlmostEqual(sc.result()["rail_yaw_max_abs_rad"], 2 * 3.141592653589793 - 6.23, places=3)
        self.assertEqual(sc.result()["rail_yaw_max_where"][0], 1)


if __name__ == "__main__":
    import rosunit

    rosunit.unitrun("greenhouse_rail_nav", "test_uv_scorer_coverage", "__main__")
